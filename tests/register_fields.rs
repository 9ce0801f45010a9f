//! The fields the register programs are spelt in (`polyturn_firmware::
//! regs::fields`) are the manual's: each equals the model's field of the
//! same name, and the model's field table is checked against ST's SVD
//! (stm32-metapac, `firmware/stm32-model/tests/metapac*.rs`). So a program
//! word is right to the bit, or a test says which field is not.

use polyturn_firmware::regs::fields as fw;
use polyturn_stm32_model::bits as svd;

fn same(name: &str, ours: fw::Field, theirs: svd::Field) {
    assert_eq!(ours.mask(), theirs.mask(), "{name}: ours {ours:?}");
}

#[test]
fn every_timer_field_the_programs_write_is_the_svds() {
    same("CR1.CEN", fw::cr1::CEN, svd::cr1::CEN);
    same("CR1.URS", fw::cr1::URS, svd::cr1::URS);
    same("CR1.OPM", fw::cr1::OPM, svd::cr1::OPM);
    same("CR1.ARPE", fw::cr1::ARPE, svd::cr1::ARPE);
    same("CR2.MMS", fw::cr2::MMS, svd::cr2::MMS);
    assert_eq!(fw::cr2::MMS_OC1REF, svd::cr2::MMS_OC1REF);
    same("SMCR.SMS", fw::smcr::SMS, svd::smcr::SMS);
    same("SMCR.TS", fw::smcr::TS, svd::smcr::TS);
    assert_eq!(fw::smcr::SMS_EXT_CLOCK_1, svd::smcr::SMS_EXT_CLOCK_1);
    same("DIER.UIE", fw::dier::UIE, svd::dier::UIE);
    same("DIER.UDE", fw::dier::UDE, svd::dier::UDE);
    same("SR.UIF", fw::sr::UIF, svd::sr::UIF);
    same("EGR.UG", fw::egr::UG, svd::egr::UG);
    // the model numbers channels from 0
    same("CCMR1.OC1PE", fw::ccmr1::OC1PE, svd::ccmr::ocpe(0));
    same("CCMR1.OC1M", fw::ccmr1::OC1M, svd::ccmr::ocm(0));
    same("CCMR1.OC2PE", fw::ccmr1::OC2PE, svd::ccmr::ocpe(1));
    same("CCMR1.OC2M", fw::ccmr1::OC2M, svd::ccmr::ocm(1));
    let modes = [fw::ccmr1::TOGGLE, fw::ccmr1::FORCE_INACTIVE, fw::ccmr1::PWM1, fw::ccmr1::PWM2];
    assert_eq!(modes, [svd::ocm::TOGGLE, svd::ocm::FORCE_INACTIVE, svd::ocm::PWM1, svd::ocm::PWM2]);
    same("CCER.CC1E", fw::ccer::CC1E, svd::ccer::cce(0));
    same("CCER.CC2E", fw::ccer::CC2E, svd::ccer::cce(1));
    same("BDTR.MOE", fw::bdtr::MOE, svd::bdtr::MOE);
    same("DCR.DBA", fw::dcr::DBA, svd::dcr::DBA);
    same("DCR.DBL", fw::dcr::DBL, svd::dcr::DBL);
}

#[test]
fn every_dma_field_the_programs_write_is_the_svds() {
    use svd::{dma_cr, dma_isr};
    same("SxCR.EN", fw::dma_cr::EN, dma_cr::EN);
    same("SxCR.DIR", fw::dma_cr::DIR, dma_cr::DIR);
    same("SxCR.CIRC", fw::dma_cr::CIRC, dma_cr::CIRC);
    same("SxCR.MINC", fw::dma_cr::MINC, dma_cr::MINC);
    same("SxCR.PSIZE", fw::dma_cr::PSIZE, dma_cr::PSIZE);
    same("SxCR.MSIZE", fw::dma_cr::MSIZE, dma_cr::MSIZE);
    same("SxCR.PL", fw::dma_cr::PL, dma_cr::PL);
    same("SxCR.CHSEL", fw::dma_cr::CHSEL, dma_cr::CHSEL);
    assert_eq!((fw::dma_cr::DIR_M2P, fw::dma_cr::SIZE_WORD), (dma_cr::DIR_M2P, dma_cr::SIZE_WORD));
    same("HIFCR.CFEIF5", fw::hifcr::CFEIF5, dma_isr::feif(5));
    let five = dma_isr::dmeif(5).mask() | dma_isr::teif(5).mask() | dma_isr::htif(5).mask() | dma_isr::tcif(5).mask();
    assert_eq!(fw::hifcr::CDMEIF5_TO_CTCIF5.mask(), five, "stream 5's DME, TE, HT and TC flags");
}

#[test]
fn a_value_wider_than_its_field_is_refused() {
    assert_eq!(fw::dma_cr::CHSEL.val(7), 7 << 25);
    assert!(std::panic::catch_unwind(|| fw::dma_cr::CHSEL.val(8)).is_err());
}
