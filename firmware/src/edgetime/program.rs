//! TIM3's and TIM5's configuration for the edge times, as data (see
//! `regs`): `app::drivers` applies `CONFIG` verbatim once embassy has set up
//! TIM3 (`Qei`: pins, clock) and TIM5 (its time driver).
//!
//! TIM3's words are whole: every input-channel bit the lathe encoder needs
//! is here (the A/B filters, the index on channel 3, the count captured on
//! channel 1), so the model sees exactly what the MCU has. Bits: §13.4.1 to
//! §13.4.9; `polyturn_regs`' tests check the fields against ST's SVD.

use super::{off, TIM3, TIM5};
pub use crate::regs::{apply, Bus, Op};
use polyturn_regs::bits::{ccer, ccmr_in, cr1, cr2, smcr, sr};

// TIM3_SMCR (§13.4.3): SMS = 011, encoder mode 3 (both inputs counted),
// TS unused (000).
const TIM3_SMCR: u32 = smcr::SMS.val(smcr::SMS_ENCODER_3);
// TIM3_CCMR1 (§13.4.7): CC1S = CC2S = 01, IC1 on TI1 (A), IC2 on TI2 (B),
// as the encoder interface needs; IC1F = IC2F = 0011, 8 samples at 96 MHz,
// rejecting glitches under 83 ns and passing edges over 1 MHz. ("CC1S bits
// are writable only when the channel is OFF": embassy's Qei has set both to
// 01 with the channels on, so the word rewrites them unchanged.)
const TIM3_CCMR1: u32 = ccmr_in::CC1S.val(ccmr_in::CCS_TI)
    | ccmr_in::IC1F.val(ccmr_in::ICF_CK_INT_N8)
    | ccmr_in::CC2S.val(ccmr_in::CCS_TI)
    | ccmr_in::IC2F.val(ccmr_in::ICF_CK_INT_N8);
// TIM3_CCMR2 (§13.4.8): CC3S = 01, IC3 on TI3 (the index, PB0), the same
// filter (CCMR2's fields sit where CCMR1's do).
const TIM3_CCMR2: u32 = ccmr_in::CC1S.val(ccmr_in::CCS_TI) | ccmr_in::IC1F.val(ccmr_in::ICF_CK_INT_N8);
// TIM3_CCER (§13.4.9): captures enabled on channels 1 (A: the edge's
// count), 2 (B: unused, as embassy's Qei left it) and 3 (the index), all
// on the rising edge and non-inverted (CCxP = CCxNP = 0), which is also
// the encoder interface's polarity (§13.3.12: "TI1FP1 ... not inverted").
const TIM3_CCER: u32 = ccer::CC1E.mask() | ccer::CC2E.mask() | ccer::CC3E.mask();
// TIM3_CR2.MMS = 011 (§13.4.2): TRGO pulses at every CC1 capture.
const TIM3_CR2: u32 = cr2::MMS.val(cr2::MMS_COMPARE_PULSE);
// TIM3_SR (§13.4.5, rc_w0): CC1IF and CC1OF cleared, every other flag
// written 1, which leaves it (the index's CC3IF above all).
const TIM3_SR_CLEAR_CC1: u32 = sr::GP_FLAGS & !(sr::CC1IF.mask() | sr::CC1OF.mask());

// TIM5_SMCR (§13.4.3): TS = 001, ITR1 = TIM3's TRGO; SMS = 000, no slave
// mode ("TS bits must be changed only when they are not used (e.g. when
// SMS=000)": they are written while SMS is 000 and stays so).
const TIM5_SMCR: u32 = smcr::TS.val(smcr::TS_ITR1);
// TIM5_CCMR2 (§13.4.8): CC3S = 11, "IC3 is mapped on TRC", no prescaler
// (IC3PSC = 00: every edge), no filter (TRC is internal); channel 4 left an
// output, frozen, as at reset. Written while CC3E = 0 ("CC3S bits are
// writable only when the channel is OFF").
const TIM5_CCMR2: u32 = ccmr_in::CC1S.val(ccmr_in::CCS_TRC);
// TIM5_CCER (§13.4.9): CC3E = 1, capture on TRC's rising edge (the pulse);
// channels 1 and 2, embassy's compares, drive no pin (CC1E = CC2E = 0).
const TIM5_CCER: u32 = ccer::CC3E.mask();

/// TIM3_SR.CC1IF: a capture on channel 1 since CCR1 was last read.
pub const CC1IF: u32 = sr::CC1IF.mask();
/// TIM3_SR.CC3IF: the index latched a count since CCR3 was last read.
pub const CC3IF: u32 = sr::CC3IF.mask();

/// The configuration, in order: TIM5's capture first, so that from TIM3's
/// first compare pulse every CC1 capture has its stamp; then TIM3 whole,
/// its counter running as embassy left it (ARR = 0xFFFF, CEN); last, CC1IF
/// cleared, so a capture made before the pulse reached TIM5 (embassy's Qei
/// enables channel 1) is not taken for a timed one (`read::Gate`).
pub const CONFIG: [Op; 11] = [
    Op::Write(TIM5 + off::SMCR, TIM5_SMCR),
    Op::Write(TIM5 + off::CCMR2, TIM5_CCMR2),
    Op::Write(TIM5 + off::CCER, TIM5_CCER),
    Op::Write(TIM3 + off::ARR, 0xFFFF),
    Op::Write(TIM3 + off::SMCR, TIM3_SMCR),
    Op::Write(TIM3 + off::CCMR1, TIM3_CCMR1),
    Op::Write(TIM3 + off::CCMR2, TIM3_CCMR2),
    Op::Write(TIM3 + off::CCER, TIM3_CCER),
    Op::Write(TIM3 + off::CR2, TIM3_CR2),
    Op::Write(TIM3 + off::CR1, cr1::CEN.mask()),
    Op::Write(TIM3 + off::SR, TIM3_SR_CLEAR_CC1),
];
