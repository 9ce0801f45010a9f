//! The BLDC drive's command: TIM10_CH1 (PB8) in PWM mode 1, and
//! the cutter's sense on BLDC_DIR (PB1). One timer makes every interface
//! `bldc-out` offers; only its frame and pulse range differ:
//!
//! | `bldc-out` | frame | stop | full speed |
//! |---|---|---|---|
//! | `esc50` | 20 ms | 1 000 µs | 2 000 µs |
//! | `esc400` | 2.5 ms | 1 000 µs | 2 000 µs |
//! | `oneshot125` | 500 µs | 125 µs | 250 µs |
//! | `pwm` | 1 / `pwm-hz` | duty 0 (no pulse) | duty 100 % |
//!
//! PWM mode 1 (OC1M = 110, TIM10_CCMR1, RM0383 §14.5.5): OC1REF is high
//! while CNT < CCR1, so the pulse is CCR1 counts of f_CK_CNT = 96 MHz /
//! (PSC + 1) (TIMx_PSC, §14.5.8) every ARR + 1 counts; CCR1 = 0 never goes
//! high, and CCR1 > ARR is high throughout ("OCxREF is held at 1", §14.3.9
//! PWM mode). "TIMx_CNT and TIMx_CCRx are always compared" (§14.3.9): a
//! CCR1 raised after the pulse fell would start a second, short one in the
//! same frame, so CCR1 is preloaded (OC1PE = 1: taken at the next update,
//! one whole pulse a frame), as §14.3.9 asks of PWM mode ("You must enable
//! the corresponding preload register by setting the OCxPE bit"), at all
//! times but the stop's one write and the set-up's head (with the counter
//! stopped from its fourth word): the stop turns the preload off to write
//! CCR1 = 0 in force at once ("the new value is taken in account immediately",
//! TIMx_CCMR1 OC1PE, §14.5.5), ending the pulse under way, and turns it on
//! again. Keeping that window short matters: the OC1PE note
//! guarantees PWM mode without the preload only in one-pulse mode, which
//! TIM10 does not have (TIM10_CR1 has no OPM, §14.5.1). `program` and the
//! stop are register writes as data; the model runs them
//! (`tests/bldcout.rs` in the model crate), and [`Interlock`] orders the tick's
//! command against a stop that pre-empts it.
//!
//! The sense: every interface drives the cutter only its wired way (the
//! `dir` setting: `same` counts up). A speed the other way, the phase loop
//! asking to slow past zero, is the stop: an ESC cannot reverse, and a
//! spindle driver's stop brakes. BLDC_DIR gives drivers that have a DIR
//! input the wired sense, so `dir` can change without rewiring.

use crate::regs::Op;
use polyturn_regs::bits::{ccer, ccmr, cr1, egr, ocm};
use polyturn_sync::config::bldc_out::{pwm_prescaler, TIMER_HZ};
use polyturn_sync::config::{BldcOut, Config};

/// TIM10 (RM0383 §2.3 Table 1); its registers (§14.5.12) sit at the
/// offsets TIM1's have.
pub use polyturn_regs::addr::{off, TIM10};

/// The timer's setting for one interface, and its command's scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Out {
    pub psc: u32,
    pub arr: u32,
    /// CCR1 of the stop
    pub stop: u32,
    /// CCR1 at full speed less `stop`
    pub span: u32,
    /// full scale, Q16 counts per tick
    max: u32,
    /// ⌈span × 2^32 / max⌉: the tick multiplies, never divides
    scale: u64,
}

/// CK_CNT at 1 MHz: the RC pulses in whole µs.
const US_PSC: u32 = TIMER_HZ / 1_000_000 - 1;

impl Out {
    /// `max_q16`: the core's full scale (`max-rate`, Q16 counts per tick).
    pub fn new(c: &Config, max_q16: i64) -> Out {
        let (psc, arr, stop, full) = match c.bldc_out {
            BldcOut::Esc50 => (US_PSC, 19_999, 1_000, 2_000),
            BldcOut::Esc400 => (US_PSC, 2_499, 1_000, 2_000),
            // 48 counts a µs: 125 µs = 6 000, 250 µs = 12 000 (PSC 1, not
            // 0: a PWM at 2 kHz has PSC 0 and the same frame, and the
            // emulator tells the two apart by PSC)
            BldcOut::OneShot125 => (1, TIMER_HZ / 2 / 2_000 - 1, 6_000, 12_000),
            BldcOut::Pwm => {
                let psc = pwm_prescaler(c.pwm_hz);
                let arr = TIMER_HZ / (psc + 1) / c.pwm_hz.max(1) - 1;
                (psc, arr, 0, arr + 1)
            }
        };
        let max = max_q16.clamp(1, 4_000_000) as u32;
        let span = full - stop;
        Out { psc, arr, stop, span, max, scale: ((span as u64) << 32).div_ceil(max as u64) }
    }

    /// CCR1 for a speed of `speed_q16` the wired way, up to full scale.
    /// (At most max × scale < (span + 1) × 2^32 ≤ 2^48: one 64-bit
    /// multiply, no division.)
    #[inline]
    pub fn ccr(&self, speed_q16: u32) -> u32 {
        let v = ((speed_q16.min(self.max) as u64 * self.scale) >> 32).min(self.span as u64);
        self.stop + v as u32
    }

    /// This tick's CCR1: a speed while the drive runs and nothing halts
    /// it, only the wired way (`forward`: `dir same`); else the stop.
    #[inline]
    pub fn command(&self, run: bool, speed_q16: i32, forward: bool) -> u32 {
        let wired = if forward { speed_q16 > 0 } else { speed_q16 < 0 };
        if run && wired {
            self.ccr(speed_q16.unsigned_abs())
        } else {
            self.stop
        }
    }

    /// Whether `other` needs TIM10 set up again (its frame or its stop
    /// differs: a new scale alone does not).
    pub fn same_frame(&self, other: &Out) -> bool {
        (self.psc, self.arr, self.stop) == (other.psc, other.arr, other.stop)
    }

    /// TIM10's set-up, stopped. CCR1 = 0 first, around the preload's
    /// turning off (as `stop_ops`): the pin falls at once whatever the old
    /// frame was doing (a pulse under way must not be stretched by the
    /// stop that follows into a throttle). Then the counter off, the
    /// frame, the output on, the preload on again (§14.3.9 asks for it
    /// before the update that starts PWM), an update event (UG, TIMx_EGR
    /// §14.5.4) so PSC, ARR and CCR1 = 0 take effect now (PSC is otherwise
    /// loaded only at an update, §14.3.1), counting with ARR preloaded
    /// (ARPE, TIMx_CR1 §14.5.1), and the stop last, into the preload:
    /// CCR1 = 0 stays in force for the whole first frame, so the pin is low
    /// a full frame between the cut pulse and the first stop pulse, which
    /// an ESC cannot read as one pulse.
    pub fn program(&self) -> [Op; 11] {
        let t = |o: u32, v: u32| Op::Write(TIM10 + o, v);
        [
            t(off::CCR1, 0),
            t(off::CCMR1, CCMR1_STOPPED),
            t(off::CCR1, 0),
            t(off::CR1, 0),
            t(off::PSC, self.psc),
            t(off::ARR, self.arr),
            t(off::CCER, ccer::CC1E.mask()),
            t(off::CCMR1, CCMR1_LIVE),
            t(off::EGR, egr::UG.mask()),
            t(off::CR1, cr1::ARPE.mask() | cr1::CEN.mask()),
            t(off::CCR1, self.stop),
        ]
    }
}

/// The tick's running command: one word, CCR1 into the preload (taken at
/// the frame's next update, one whole pulse a frame). One word, so a stop
/// cannot land inside it.
pub fn run_ops(ccr: u32) -> [Op; 1] {
    [Op::Write(TIM10 + off::CCR1, ccr)]
}

/// The stop at once: CCR1 = 0 into the preload (replacing a command
/// waiting there), the preload off, CCR1 = 0 again (in force at once: the
/// pulse under way ends, and none can start), the preload on again, and
/// the stop into the preload, in force from the next frame. The pin falls
/// and never rises before that frame, whatever the frame was doing (in
/// the first frame after `program` too, where 0 is in force). An ESC reads
/// the cut pulse as no more than its command, or below its stop. The first
/// word matters if clearing OC1PE puts a waiting value in force, the third
/// if it does not: the manual does not say which at that instant
/// (`PreloadClear` in the model crate; the tests run both).
pub fn stop_ops(stop: u32) -> [Op; 5] {
    let t = |o: u32, v: u32| Op::Write(TIM10 + o, v);
    [t(off::CCR1, 0), t(off::CCMR1, CCMR1_STOPPED), t(off::CCR1, 0), t(off::CCMR1, CCMR1_LIVE), t(off::CCR1, stop)]
}

/// TIM10_CCMR1 (§14.5.5) for one write of the stop and the set-up's head:
/// PWM mode 1, CCR1 not preloaded (a write takes effect at once).
pub const CCMR1_STOPPED: u32 = ccmr::OC1M.val(ocm::PWM1);
/// At all other times: PWM mode 1, CCR1 preloaded (OC1PE, taken at each
/// update: one whole pulse a frame).
pub const CCMR1_LIVE: u32 = CCMR1_STOPPED | ccmr::OC1PE.mask();

mod interlock;
pub use interlock::Interlock;

#[cfg(test)]
mod tests;
