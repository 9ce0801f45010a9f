//! Timer bit fields, built with `stm32-metapac`'s setters (ST's SVD data as curated
//! by the embassy project) and compared with `bits`.
use polyturn_regs::addr::off;
use polyturn_regs::bits::*;
use stm32_metapac::timer::regs;
use stm32_metapac::timer::vals;

#[macro_use]
mod build_bits;

#[test]
fn timer_bit_fields_match_metapac() {
    use regs::{
        BdtrAdv, CcerAdv, CcmrOutputGp16, Cr1Gp16, Cr2Adv, Dcr1chCmp, DierAdv, EgrAdv, RcrAdv, SmcrGp16, SrAdv,
    };
    assert_eq!(bits!(Cr1Gp16, |r| r.set_cen(true)), cr1::CEN.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_udis(true)), cr1::UDIS.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_urs(vals::Urs::COUNTER_ONLY)), cr1::URS.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_opm(true)), cr1::OPM.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_dir(vals::Dir::DOWN)), cr1::DIR.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_cms(vals::Cms::CENTER_ALIGNED3)), cr1::CMS.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_arpe(true)), cr1::ARPE.mask());
    assert_eq!(bits!(Cr1Gp16, |r| r.set_ckd(vals::Ckd::from_bits(3))), cr1::CKD.mask());

    assert_eq!(bits!(Cr2Adv, |r| r.set_ccpc(true)), cr2::CCPC.mask());
    assert_eq!(bits!(Cr2Adv, |r| r.set_ccus(true)), cr2::CCUS.mask());
    assert_eq!(bits!(Cr2Adv, |r| r.set_ccds(vals::Ccds::ON_UPDATE)), cr2::CCDS.mask());
    assert_eq!(bits!(Cr2Adv, |r| r.set_ti1s(vals::Ti1s::XOR)), cr2::TI1S.mask());
    let mms = [
        (vals::Mms::RESET, cr2::MMS_RESET),
        (vals::Mms::ENABLE, cr2::MMS_ENABLE),
        (vals::Mms::UPDATE, cr2::MMS_UPDATE),
        (vals::Mms::COMPARE_PULSE, cr2::MMS_COMPARE_PULSE),
        (vals::Mms::COMPARE_OC1, cr2::MMS_OC1REF),
        (vals::Mms::COMPARE_OC2, cr2::MMS_OC2REF),
        (vals::Mms::COMPARE_OC4, 0b111),
    ];
    for (v, ours) in mms {
        assert_eq!(bits!(Cr2Adv, |r| r.set_mms(v)), cr2::MMS.val(ours));
    }
    for c in 0..4 {
        assert_eq!(bits!(Cr2Adv, |r| r.set_ois(c, true)), cr2::ois(c as u32).mask());
    }
    for c in 0..3 {
        assert_eq!(bits!(Cr2Adv, |r| r.set_oisn(c, true)), cr2::oisn(c as u32).mask());
    }

    assert_eq!(bits!(SmcrGp16, |r| r.set_sms(vals::Sms::EXT_CLOCK_MODE)), smcr::SMS.val(smcr::SMS_EXT_CLOCK_1));
    assert_eq!(bits!(SmcrGp16, |r| r.set_sms(vals::Sms::EXT_CLOCK_MODE)), smcr::SMS.mask());
    assert_eq!(bits!(SmcrGp16, |r| r.set_ts(vals::Ts::ETRF)), smcr::TS.mask());
    assert_eq!(bits!(SmcrGp16, |r| r.set_ts(vals::Ts::ITR0)), smcr::TS.val(smcr::TS_ITR0));
    assert_eq!(bits!(SmcrGp16, |r| r.set_ts(vals::Ts::ITR1)), smcr::TS.val(smcr::TS_ITR1));
    assert_eq!(bits!(SmcrGp16, |r| r.set_sms(vals::Sms::ENCODER_MODE_3)), smcr::SMS.val(smcr::SMS_ENCODER_3));
    assert_eq!(bits!(SmcrGp16, |r| r.set_msm(vals::Msm::SYNC)), smcr::MSM.mask());
    assert_eq!(bits!(SmcrGp16, |r| r.set_etf(vals::FilterValue::from_bits(15))), smcr::ETF.mask());
    assert_eq!(bits!(SmcrGp16, |r| r.set_etps(vals::Etps::DIV8)), smcr::ETPS.mask());
    assert_eq!(bits!(SmcrGp16, |r| r.set_ece(true)), smcr::ECE.mask());
    assert_eq!(bits!(SmcrGp16, |r| r.set_etp(vals::Etp::INVERTED)), smcr::ETP.mask());

    assert_eq!(bits!(DierAdv, |r| r.set_uie(true)), dier::UIE.mask());
    assert_eq!(bits!(DierAdv, |r| r.set_comie(true)), dier::COMIE.mask());
    assert_eq!(bits!(DierAdv, |r| r.set_tie(true)), dier::TIE.mask());
    assert_eq!(bits!(DierAdv, |r| r.set_bie(true)), dier::BIE.mask());
    assert_eq!(bits!(DierAdv, |r| r.set_ude(true)), dier::UDE.mask());
    assert_eq!(bits!(DierAdv, |r| r.set_comde(true)), dier::COMDE.mask());
    assert_eq!(bits!(DierAdv, |r| r.set_tde(true)), dier::TDE.mask());
    for c in 0..4 {
        assert_eq!(bits!(DierAdv, |r| r.set_ccie(c, true)), dier::ccie(c as u32).mask());
        assert_eq!(bits!(DierAdv, |r| r.set_ccde(c, true)), dier::ccde(c as u32).mask());
        assert_eq!(bits!(SrAdv, |r| r.set_ccif(c, true)), sr::ccif(c as u32).mask());
        assert_eq!(bits!(SrAdv, |r| r.set_ccof(c, true)), sr::ccof(c as u32).mask());
        assert_eq!(bits!(EgrAdv, |r| r.set_ccg(c, true)), egr::ccg(c as u32).mask());
        assert_eq!(bits!(CcerAdv, |r| r.set_cce(c, true)), ccer::cce(c as u32).mask());
        assert_eq!(bits!(CcerAdv, |r| r.set_ccp(c, true)), ccer::ccp(c as u32).mask());
    }
    for c in 0..3 {
        assert_eq!(bits!(CcerAdv, |r| r.set_ccne(c, true)), ccer::ccne(c as u32).mask());
        assert_eq!(bits!(CcerAdv, |r| r.set_ccnp(c, true)), ccer::ccnp(c as u32).mask());
    }
    assert_eq!(bits!(SrAdv, |r| r.set_uif(true)), sr::UIF.mask());
    assert_eq!(bits!(SrAdv, |r| r.set_comif(true)), sr::COMIF.mask());
    assert_eq!(bits!(SrAdv, |r| r.set_tif(true)), sr::TIF.mask());
    assert_eq!(bits!(SrAdv, |r| r.set_bif(0, true)), sr::BIF.mask());
    assert_eq!(bits!(EgrAdv, |r| r.set_ug(true)), egr::UG.mask());
    assert_eq!(bits!(EgrAdv, |r| r.set_comg(true)), egr::COMG.mask());
    assert_eq!(bits!(EgrAdv, |r| r.set_tg(true)), egr::TG.mask());
    assert_eq!(bits!(EgrAdv, |r| r.set_bg(0, true)), egr::BG.mask());

    let modes = [
        (vals::Ocm::FROZEN, ocm::FROZEN),
        (vals::Ocm::ACTIVE_ON_MATCH, ocm::ACTIVE_ON_MATCH),
        (vals::Ocm::INACTIVE_ON_MATCH, ocm::INACTIVE_ON_MATCH),
        (vals::Ocm::TOGGLE, ocm::TOGGLE),
        (vals::Ocm::FORCE_INACTIVE, ocm::FORCE_INACTIVE),
        (vals::Ocm::FORCE_ACTIVE, ocm::FORCE_ACTIVE),
        (vals::Ocm::PWM_MODE1, ocm::PWM1),
        (vals::Ocm::PWM_MODE2, ocm::PWM2),
    ];
    for c in 0..2 {
        let cu = c as u32;
        for (v, ours) in modes {
            assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocm(c, v)), ccmr::ocm(cu).val(ours));
        }
        assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocm(c, vals::Ocm::PWM_MODE2)), ccmr::ocm(cu).mask());
        assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocpe(c, true)), ccmr::ocpe(cu).mask());
        assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocfe(c, true)), ccmr::ocfe(cu).mask());
        assert_eq!(bits!(CcmrOutputGp16, |r| r.set_occe(c, true)), ccmr::occe(cu).mask());
        assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ccs(c, vals::CcmrOutputCcs::from_bits(3))), ccmr::ccs(cu).mask());
    }

    use regs::CcmrInput2ch;
    let inputs = [
        (vals::CcmrInputCcs::TI4, ccmr_in::CCS_TI),
        (vals::CcmrInputCcs::TI3, ccmr_in::CCS_TI_OTHER),
        (vals::CcmrInputCcs::TRC, ccmr_in::CCS_TRC),
    ];
    for c in 0..2 {
        let cu = c as u32;
        for (v, ours) in inputs {
            assert_eq!(bits!(CcmrInput2ch, |r| r.set_ccs(c, v)), ccmr::ccs(cu).val(ours));
        }
        assert_eq!(bits!(CcmrInput2ch, |r| r.set_icpsc(c, 3)), ccmr_in::icpsc(cu).mask());
        assert_eq!(bits!(CcmrInput2ch, |r| r.set_icf(c, vals::FilterValue::from_bits(15))), ccmr_in::icf(cu).mask());
        let n8 = bits!(CcmrInput2ch, |r| r.set_icf(c, vals::FilterValue::FCK_INT_N8));
        assert_eq!(n8, ccmr_in::icf(cu).val(ccmr_in::ICF_CK_INT_N8));
    }

    assert_eq!(bits!(BdtrAdv, |r| r.set_dtg(0xFF)), bdtr::DTG.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_lock(vals::Lock::LEVEL3)), bdtr::LOCK.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_ossi(vals::Ossi::IDLE_LEVEL)), bdtr::OSSI.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_ossr(vals::Ossr::IDLE_LEVEL)), bdtr::OSSR.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_bke(0, true)), bdtr::BKE.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_bkp(0, vals::Bkp::ACTIVE_HIGH)), bdtr::BKP.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_aoe(true)), bdtr::AOE.mask());
    assert_eq!(bits!(BdtrAdv, |r| r.set_moe(true)), bdtr::MOE.mask());

    assert_eq!(bits!(Dcr1chCmp, |r| r.set_dba(0x1F)), dcr::DBA.mask());
    assert_eq!(bits!(Dcr1chCmp, |r| r.set_dbl(0x1F)), dcr::DBL.mask());
    assert_eq!(bits!(Dcr1chCmp, |r| r.set_dba(11)), dcr::DBA.val(off::ARR / 4));
    assert_eq!(bits!(RcrAdv, |r| r.set_rep(0xFF)), dcr::REP.mask());
}

#[test]
fn tim9_ccmr1_fields_match_metapac() {
    use stm32_metapac::timer::regs::CcmrOutput2ch;
    for c in 0..2 {
        let mut r = CcmrOutput2ch::default();
        r.set_ocm(c, vals::Ocm::TOGGLE);
        r.set_ocpe(c, true);
        assert_eq!(r.0, ccmr::ocm(c as u32).val(ocm::TOGGLE) | ccmr::ocpe(c as u32).mask());
    }
}

/// The constants named after a channel, as the register programs spell their words.
#[test]
fn the_named_channel_fields_match_metapac() {
    use regs::{CcerAdv, CcmrInput2ch, CcmrOutputGp16, SrAdv, SrGp16};
    assert_eq!(bits!(SrAdv, |r| r.set_ccif(0, true)), sr::CC1IF.mask());
    assert_eq!(bits!(SrAdv, |r| r.set_ccif(2, true)), sr::CC3IF.mask());
    assert_eq!(bits!(SrAdv, |r| r.set_ccof(0, true)), sr::CC1OF.mask());
    let every = bits!(SrGp16, |r| {
        r.set_uif(true);
        r.set_tif(true);
        for c in 0..4 {
            r.set_ccif(c, true);
            r.set_ccof(c, true);
        }
    });
    assert_eq!(every, sr::GP_FLAGS, "TIM2-5 have no COMIF or BIF (§13.4.5)");
    assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocpe(0, true)), ccmr::OC1PE.mask());
    assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocm(0, vals::Ocm::PWM_MODE2)), ccmr::OC1M.mask());
    assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocpe(1, true)), ccmr::OC2PE.mask());
    assert_eq!(bits!(CcmrOutputGp16, |r| r.set_ocm(1, vals::Ocm::PWM_MODE2)), ccmr::OC2M.mask());
    let ccs = vals::CcmrInputCcs::from_bits(3);
    assert_eq!(bits!(CcmrInput2ch, |r| r.set_ccs(0, ccs)), ccmr_in::CC1S.mask());
    assert_eq!(bits!(CcmrInput2ch, |r| r.set_icpsc(0, 3)), ccmr_in::IC1PSC.mask());
    assert_eq!(bits!(CcmrInput2ch, |r| r.set_icf(0, vals::FilterValue::from_bits(15))), ccmr_in::IC1F.mask());
    assert_eq!(bits!(CcmrInput2ch, |r| r.set_ccs(1, ccs)), ccmr_in::CC2S.mask());
    assert_eq!(bits!(CcmrInput2ch, |r| r.set_icf(1, vals::FilterValue::from_bits(15))), ccmr_in::IC2F.mask());
    assert_eq!(bits!(CcerAdv, |r| r.set_cce(0, true)), ccer::CC1E.mask());
    assert_eq!(bits!(CcerAdv, |r| r.set_cce(1, true)), ccer::CC2E.mask());
    assert_eq!(bits!(CcerAdv, |r| r.set_cce(2, true)), ccer::CC3E.mask());
}
