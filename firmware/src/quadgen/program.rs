//! TIM9's register writes, and the index pin's, as data (see `regs`).
//!
//! Addresses: RM0383 §2.3 Table 1 (TIM9 0x4001_4000, GPIOA 0x4002_0000),
//! §14.4.13 (TIM9 register map), §8.4.11 (GPIO register map). Bits: the
//! register descriptions of §14.4 and §8.4.7. Both are `polyturn_regs`',
//! checked there against ST's SVD (stm32-metapac).

use super::period::Period;
pub use crate::regs::{apply, Bus, Op};
use polyturn_regs::bits::{ccer, ccmr, cr1, dier, egr, ocm, sr};

pub use polyturn_regs::addr::{
    TIM9, TIM9_ARR as ARR, TIM9_CCER as CCER, TIM9_CCMR1 as CCMR1, TIM9_CCR1 as CCR1, TIM9_CCR2 as CCR2,
    TIM9_CNT as CNT, TIM9_CR1 as CR1, TIM9_DIER as DIER, TIM9_EGR as EGR, TIM9_PSC as PSC, TIM9_SR as SR,
};

/// GPIOA_BSRR (§8.4.7): bit y sets ODRy, bit 16 + y resets it, atomically.
pub use polyturn_regs::addr::GPIOA_BSRR;
/// The index output: PA4.
pub const INDEX_PIN: u32 = 4;

// TIM9_CR1 (§14.4.1). CEN: counter enabled. URS: "only counter overflow
// generates an update interrupt", so the UG below raises none. OPM: "counter
// stops counting at the next update event (clearing the bit CEN)". ARPE:
// "TIMx_ARR register is buffered": the new ARR is taken at the update event.
const CEN: u32 = cr1::CEN.mask();
const URS: u32 = cr1::URS.mask();
const OPM: u32 = cr1::OPM.mask();
const ARPE: u32 = cr1::ARPE.mask();
const CR1_STOPPED: u32 = ARPE | URS;
// TIM9_DIER.UIE (§14.4.3): the update interrupt (vector TIM1_BRK_TIM9).
const UIE: u32 = dier::UIE.mask();
// TIM9_EGR.UG (§14.4.5): "re-initialize the counter and generates an update
// of the registers": PSC, ARR and (with OCxPE) CCRx shadows loaded, CNT = 0.
const UG: u32 = egr::UG.mask();
// TIM9_CCMR1, output mode (§14.4.6): OC1M bits 6:4, OC1PE bit 3, OC2M bits
// 14:12, OC2PE bit 11; CCxS = 00, output. OCxM = 011 toggle ("OC1REF toggles
// when TIMx_CNT = TIMx_CCR1"), 100 force inactive ("OC1REF is forced low").
// OCxPE: "TIMx_CCR1 preload value is loaded in the active register at each
// update event".
const OC1_TOGGLE: u32 = ccmr::OC1M.val(ocm::TOGGLE);
const OC2_TOGGLE: u32 = ccmr::OC2M.val(ocm::TOGGLE);
const OC1_LOW: u32 = ccmr::OC1M.val(ocm::FORCE_INACTIVE);
const OC2_LOW: u32 = ccmr::OC2M.val(ocm::FORCE_INACTIVE);
const PRELOADS: u32 = ccmr::OC1PE.mask() | ccmr::OC2PE.mask();
pub const CCMR1_LOW: u32 = OC1_LOW | OC2_LOW | PRELOADS;
pub const CCMR1_TOGGLE: u32 = OC1_TOGGLE | OC2_TOGGLE | PRELOADS;
// TIM9_CCER (§14.4.7): CC1E bit 0, CC2E bit 4 ("OC1 signal is output on the
// corresponding output pin"); CCxP = 0, active high.
const CC1E_CC2E: u32 = ccer::CC1E.mask() | ccer::CC2E.mask();

/// The index level for the period that just started.
pub const fn index(high: bool) -> Op {
    Op::Write(GPIOA_BSRR, if high { 1 << INDEX_PIN } else { 1 << (16 + INDEX_PIN) })
}

/// TIM9_SR.UIF (§14.4.4): "set by hardware on an update event".
pub const UIF: u32 = sr::UIF.mask();

/// Clears UIF (SR is rc_w0, §14.4.4: writing 0 clears every flag, and no
/// other flag is used).
pub const CLEAR_FLAGS: Op = Op::Write(SR, 0);

/// Starts the generator on `first` from TIM9 stopped (or at reset): both
/// outputs low, then the counter set one tick before its overflow, so that
/// the first counter tick is update event 0, which starts `first` (§14.3.2
/// "the counter counts from 0 to the auto-reload value, then restarts from
/// 0 and generates a counter overflow event"). Every compare match then
/// falls on a counter tick after an update event, never on a write (UG
/// sets CNT = 0 while the outputs are still forced low).
pub const fn init(first: &Period) -> [Op; 15] {
    let [c1, c2] = first.ccr();
    [
        Op::Write(CR1, CR1_STOPPED),
        Op::Write(DIER, 0),
        Op::Write(CCMR1, CCMR1_LOW),
        Op::Write(CCER, CC1E_CC2E),
        Op::Write(PSC, first.psc as u32),
        Op::Write(ARR, first.arr() as u32),
        Op::Write(CCR1, c1 as u32),
        Op::Write(CCR2, c2 as u32),
        Op::Write(EGR, UG),
        Op::Write(CNT, first.arr() as u32),
        // toggle mode keeps OCxREF low until the first match
        Op::Write(CCMR1, CCMR1_TOGGLE),
        CLEAR_FLAGS,
        index(false),
        Op::Write(DIER, UIE),
        Op::Write(CR1, CR1_STOPPED | CEN),
    ]
}

/// The period after the current one: PSC (always buffered, §14.3.1: "the
/// new prescaler ratio is taken into account at the next update event"),
/// ARR (ARPE) and CCR1/CCR2 (OCxPE) all take effect at the next update
/// event, together.
pub const fn next(p: &Period) -> [Op; 4] {
    let [c1, c2] = p.ccr();
    [
        Op::Write(PSC, p.psc as u32),
        Op::Write(ARR, p.arr() as u32),
        Op::Write(CCR1, c1 as u32),
        Op::Write(CCR2, c2 as u32),
    ]
}

/// No period after the current one: the counter stops at the next update
/// event (OPM), before the next period's first edge.
pub const FINISH: Op = Op::Write(CR1, CR1_STOPPED | OPM | CEN);

/// After the last update event: no more interrupts, index low.
pub const DONE: [Op; 3] = [index(false), CLEAR_FLAGS, Op::Write(DIER, 0)];

/// Aborts at once: the counter stops, so no compare match changes an output
/// (toggle acts only on a match); A and B keep their levels. They are not
/// forced low: at an update event A = B, and both falling together is a
/// transition the encoder interface does not define (§13.3.12, Table 53
/// "assuming TI1 and TI2 do not switch at the same time").
pub const STOP: [Op; 4] = [Op::Write(CR1, CR1_STOPPED), Op::Write(DIER, 0), CLEAR_FLAGS, index(false)];
