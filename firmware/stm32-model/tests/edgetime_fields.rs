//! The fields the edge times' words are spelt in (`polyturn_firmware::regs::
//! fields`, beyond those `tests/register_fields.rs` at the root checks) are
//! the model's, which `metapac_timer_bits.rs` checks against ST's SVD.

use polyturn_firmware::regs::fields as fw;
use polyturn_stm32_model::bits as svd;

fn same(name: &str, ours: fw::Field, theirs: svd::Field) {
    assert_eq!(ours.mask(), theirs.mask(), "{name}: ours {ours:?}");
}

#[test]
fn every_field_of_the_edge_times_is_the_svds() {
    assert_eq!(fw::cr2::MMS_COMPARE_PULSE, svd::cr2::MMS_COMPARE_PULSE);
    assert_eq!(fw::smcr::SMS_ENCODER_3, svd::smcr::SMS_ENCODER_3);
    assert_eq!(fw::smcr::TS_ITR1, svd::smcr::TS_ITR1);
    same("SR.CC1IF", fw::sr::CC1IF, svd::sr::ccif(0));
    same("SR.CC3IF", fw::sr::CC3IF, svd::sr::ccif(2));
    same("SR.CC1OF", fw::sr::CC1OF, svd::sr::ccof(0));
    let flags = (0..4)
        .fold(svd::sr::UIF.mask() | svd::sr::TIF.mask(), |m, c| m | svd::sr::ccif(c).mask() | svd::sr::ccof(c).mask());
    assert_eq!(fw::sr::GP_FLAGS, flags, "TIM2-5 have no COMIF or BIF (§13.4.5)");
    // input mode: channel 1's and 2's fields (CCMR2's 3 and 4 sit the same)
    same("CCMR1.CC1S", fw::ccmr_in::CC1S, svd::ccmr::ccs(0));
    same("CCMR1.IC1PSC", fw::ccmr_in::IC1PSC, svd::ccmr_in::icpsc(0));
    same("CCMR1.IC1F", fw::ccmr_in::IC1F, svd::ccmr_in::icf(0));
    same("CCMR1.CC2S", fw::ccmr_in::CC2S, svd::ccmr::ccs(1));
    same("CCMR1.IC2F", fw::ccmr_in::IC2F, svd::ccmr_in::icf(1));
    assert_eq!(fw::ccmr_in::CCS_TI, svd::ccmr_in::CCS_TI);
    assert_eq!(fw::ccmr_in::CCS_TRC, svd::ccmr_in::CCS_TRC);
    assert_eq!(fw::ccmr_in::ICF_CK_INT_N8, svd::ccmr_in::ICF_CK_INT_N8);
    same("CCER.CC3E", fw::ccer::CC3E, svd::ccer::cce(2));
}
