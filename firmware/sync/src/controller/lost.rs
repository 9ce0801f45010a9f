//! The lost-step alarm: with an encoder on a stepper's (or step/dir
//! servo's) shaft, on TIM4 (`cutter-cpr`), every tick compares the steps
//! sent so far (the pulses counted, signed by the books' windows:
//! `StepPipe::emitted`, not the plans still in flight) with where the
//! encoder says the shaft is. Both are integers and the scale is exact:
//! steps × cpr against counts × steps per rev, a multiply each, no
//! division in the tick. Beyond `lost-steps`
//! steps: `Fault::LostSteps`, which stops at once like the E-stop.
//!
//! Why a few steps of slack, not one: a loaded rotor lags its command by up
//! to one full step (a quarter of the electrical cycle) before it slips,
//! and a slip loses a whole cycle, four full steps; the encoder is read to
//! one count. The default, 32 steps, is two full steps at 1/16.
//!
//! Measured only while the motor is energised and settled: with ENABLE off
//! the shaft turns by hand, and on ENABLE the rotor jumps to its nearest
//! full step (up to two full steps away). The reference follows until
//! `SETTLE_TICKS` after ENABLE.

use super::{Controller, Fault};
use crate::encoder::Extender;

/// Ticks after ENABLE before the comparison starts: 10 ms of the board's.
pub const SETTLE_TICKS: u32 = crate::Timing::FIRMWARE.tick_hz / 100;

/// (No `start`: the first ticks are never energised, so the reference
/// takes whatever the encoder first reads.)
#[derive(Clone, Copy, Debug, Default)]
pub struct LostSteps {
    encoder: Extender,
    /// the books' steps and the encoder's counts at the reference
    steps0: i64,
    counts0: i64,
    /// ticks energised, up to `SETTLE_TICKS`
    settled: u32,
    /// steps × cpr − counts × steps-per-rev since the reference
    pub diff: i64,
}

impl LostSteps {
    /// One tick: true when the shaft is further than `limit` steps from
    /// the books. `energised`: ENABLE as the last tick left it.
    #[inline]
    pub fn tick(&mut self, raw: u16, steps: i64, energised: bool, (cpr, spr, limit): (i64, i64, i64)) -> bool {
        self.encoder.update(raw);
        let counts = self.encoder.position();
        if !energised || self.settled < SETTLE_TICKS {
            self.settled = if energised { self.settled + 1 } else { 0 };
            (self.steps0, self.counts0, self.diff) = (steps, counts, 0);
            return false;
        }
        self.diff = (steps - self.steps0) * cpr - (counts - self.counts0) * spr;
        self.diff.abs() > limit * cpr
    }
}

impl Controller {
    /// With a cutter encoder on a stepper: trips `LostSteps` when the shaft
    /// is not where the steps put it. (Without one, the tick pays a compare.)
    #[inline(always)]
    pub(super) fn check_lost_steps(&mut self, raw: u16) {
        if self.config.cutter_encoder_cpr != 0 {
            self.compare_shaft(raw);
        }
    }

    /// Out of line: a cutter without a shaft encoder pays only the call's
    /// test above.
    #[inline(never)]
    fn compare_shaft(&mut self, raw: u16) {
        let cpr = self.config.cutter_encoder_cpr as i64;
        let scale = (cpr, self.config.motor_steps_per_rev as i64, self.config.lost_step_limit_steps as i64);
        // (the state is still the last tick's: ENABLE as it left it)
        let energised = self.enable_and_halt().0;
        if self.lost.tick(raw, self.steps.emitted(), energised, scale) {
            self.trip(Fault::LostSteps);
        }
    }

    /// The shaft's distance from the books, as the books hold it (a copy:
    /// `ShaftGap::milli_steps` divides, outside any lock), with a cutter
    /// encoder on a stepper.
    pub fn shaft_gap(&self) -> Option<ShaftGap> {
        let cpr = self.config.cutter_encoder_cpr;
        let stepper = self.config.drive == crate::config::DriveKind::Stepper;
        (cpr != 0 && stepper).then_some(ShaftGap { diff: self.lost.diff, cpr })
    }

    /// `shaft_gap` in thousandths of a step (a division, so not for the tick).
    pub fn lost_milli_steps(&self) -> Option<i64> {
        self.shaft_gap().map(|g| g.milli_steps())
    }
}

/// The shaft's distance from the steps sent, in the books' units (steps ×
/// cpr − counts × motor steps, `LostSteps::diff`), with the cutter encoder's
/// cpr that turns it into steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaftGap {
    pub diff: i64,
    pub cpr: u32,
}

impl ShaftGap {
    /// Thousandths of a step.
    pub fn milli_steps(&self) -> i64 {
        // (clamped to ±2^52 so ×1000 fits an i64: a shaft that far off has
        // tripped long before; max(1): no division by zero)
        self.diff.clamp(-(1 << 52), 1 << 52) * 1000 / (self.cpr.max(1) as i64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCALE: (i64, i64, i64) = (1000, 3200, 32); // 1000 counts, 3200 steps, 32 allowed

    /// The encoder's raw count for `steps` of shaft (3.2 steps a count).
    fn raw(steps: i64) -> u16 {
        (steps * 1000 / 3200) as u16
    }

    #[test]
    fn a_shaft_that_follows_never_trips_and_one_that_stops_does_past_the_limit() {
        let mut l = LostSteps::default();
        for t in 0..SETTLE_TICKS as i64 + 1000 {
            assert!(!l.tick(raw(t * 7), t * 7, true, SCALE), "tick {t}");
        }
        // the rotor stops (a jam); the books go on 7 steps a tick
        let (s, r) = ((SETTLE_TICKS as i64 + 1000) * 7, raw((SETTLE_TICKS as i64 + 1000) * 7));
        let trips: [bool; 6] = core::array::from_fn(|k| l.tick(r, s + 7 * (k as i64 + 1), true, SCALE));
        assert_eq!(trips, [false, false, false, false, true, true], "33 steps off at the 5th tick");
    }

    #[test]
    fn moves_while_unpowered_or_settling_are_not_lost_steps() {
        let mut l = LostSteps::default();
        assert!(!l.tick(raw(500), 0, false, SCALE), "turned by hand, disabled");
        for _ in 0..SETTLE_TICKS {
            // the rotor jumps 2 full steps on enable
            assert!(!l.tick(raw(532), 0, true, SCALE));
        }
        assert!(!l.tick(raw(532), 0, true, SCALE));
        assert_eq!(l.diff, 0);
    }

    #[test]
    fn the_comparison_starts_on_the_tick_after_settling_and_the_limit_itself_is_within() {
        // one count a step: 32 steps off is within, 33 is not; and the
        // first compared tick is the one after SETTLE_TICKS energised
        let scale = (1, 1, 32);
        for (off, trips) in [(32, false), (33, true)] {
            let mut l = LostSteps::default();
            for _ in 0..SETTLE_TICKS {
                assert!(!l.tick(100, 0, true, scale));
            }
            assert_eq!(l.tick(100, off, true, scale), trips, "{off} steps off");
        }
    }

    #[test]
    fn the_comparison_is_exact_over_a_long_run() {
        // 10^9 steps at 3 steps per 7 counts...: still exact, no drift
        let mut l = LostSteps::default();
        let scale = (7, 3, 1);
        let mut counts: i64 = 0;
        for t in 0..SETTLE_TICKS as i64 + 2 {
            assert!(!l.tick(counts as u16, t * 3, true, scale));
            counts += 7;
        }
        assert_eq!(l.diff, 0);
    }
}
