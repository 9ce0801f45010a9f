//! The commanded cutter position follows the target within a maximum step
//! rate and acceleration: feed-forward of the target's speed plus a
//! proportional pull, with a braking check (v² ≥ 2·a·|e|) so catching up to
//! the exact phase never overshoots by more than the limits force. While
//! tracking, a change of speed within the motor's start rate
//! (`start-rate`, 0 by default), between two speeds within it, is taken at
//! once, as a stepper starts below its pull-in rate. Ramping down (stop,
//! faults) keeps to the acceleration limit: ENABLE goes off only once the
//! cutter is at rest.
//! All in Q16 steps, Q16 steps/tick and Q16 steps/tick²; adds, multiplies
//! and compares only.

/// Proportional pull: 1/16 of the position error per tick.
const KF_SHIFT: u32 = 4;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Limits {
    /// Q16 steps per tick
    pub max_velocity: i64,
    /// Q16 steps per tick per tick
    pub max_accel: i64,
    /// Q16 steps per tick: while tracking, a change of speed within it
    /// between two speeds within it is taken at once (0: every change at
    /// `max_accel`)
    pub start_velocity: i64,
}

impl Limits {
    /// Per-tick Q16 limits from steps/s and steps/s² at `tick_hz` (low
    /// priority: divides). The speed rounds up, the acceleration down (≥ 1).
    pub fn from_rates(rate_hz: u64, accel: u64, tick_hz: u64) -> Limits {
        let hz = tick_hz.max(1);
        Limits {
            max_velocity: (rate_hz << 16).div_ceil(hz) as i64,
            max_accel: ((accel << 16) / (hz * hz)).max(1) as i64,
            start_velocity: 0,
        }
    }

    /// With a start rate of `rate_hz` steps/s at `tick_hz` (low priority:
    /// divides), rounded down: never faster than the rate set.
    pub fn with_start(self, rate_hz: u64, tick_hz: u64) -> Limits {
        Limits { start_velocity: ((rate_hz << 16) / tick_hz.max(1)) as i64, ..self }
    }

    /// Whether `velocity` (Q16 steps per tick) is within the start rate
    /// (asked only with one set: `track` tests that first).
    #[inline]
    fn startable(&self, velocity: i64) -> bool {
        velocity.abs() <= self.start_velocity
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub struct Follower {
    /// Q16 steps
    pub position: i64,
    /// Q16 steps per tick
    pub velocity: i64,
}

impl Follower {
    /// Moves one tick toward `target`, the target's position at the end of
    /// this tick (moving at `target_velocity`). The error is what would
    /// remain after moving at the target's own speed for the tick.
    #[inline]
    pub fn track(&mut self, target: i64, target_velocity: i64, lim: &Limits) {
        let error = target - self.position - target_velocity;
        let relative = self.velocity - target_velocity;
        let want = target_velocity + (error >> KF_SHIFT) - self.velocity;
        // (one compare on the tick without a start rate, the default)
        if lim.start_velocity != 0 && self.started(want, lim) {
            return;
        }
        let mut dv = crate::q16::bound(want, lim.max_accel);
        // Closing in faster than we can brake: brake at the limit.
        // (relative > 0) == (error > 0), as one test of the sign bits: for
        // every v but i64::MIN, v > 0 exactly when v − 1 ≥ 0, and both are
        // far inside ±2^63 here. Two 64-bit compares cost the tick 11
        // instructions more on average (counted on an emulated Cortex-M4).
        if relative != 0 && (relative.wrapping_sub(1) ^ error.wrapping_sub(1)) >= 0 {
            // Q16 units on both sides: v² and 2·a·e both carry 2^32. With
            // r < 2^31 and |e| ≤ 2^40, a < 2^20 neither product overflows, so
            // plain multiplies do (no overflow checks on the tick).
            let r = relative.unsigned_abs().min(1 << 31);
            let brake = 2 * (lim.max_accel as u64).min(0xF_FFFF) * error.unsigned_abs().min(1 << 40);
            if r * r >= brake {
                // At the limit, but never past stopping the relative motion:
                // with a generous limit and a tiny error, a full-limit brake
                // would overshoot by far more than the error it corrects.
                let stop = lim.max_accel.min(r as i64);
                dv = if relative > 0 { -stop } else { stop };
            }
        }
        self.step(dv, lim);
    }

    /// A change of speed within the start rate, from and to speeds within
    /// it: at once, as the motor can (a cutter engaged at rest takes the
    /// lathe's speed at its first count instead of catching up at
    /// `max_accel`: docs/src/performance.md, "From rest"). No more than
    /// the start rate at once: +S to −S is a reversal of 2S. True if it
    /// moved so.
    #[inline(never)]
    fn started(&mut self, want: i64, lim: &Limits) -> bool {
        let v = self.velocity;
        let within = lim.startable(want) && lim.startable(v) && lim.startable(v + want);
        if within {
            self.step(want, lim);
        }
        within
    }

    /// Ramps the speed to zero at the acceleration limit, whatever the
    /// start rate: the controller drops ENABLE when the speed reaches 0,
    /// with two ticks of steps still in flight (`steps::pipe`), so the
    /// speed must be all but 0 by then, and a rotor left unpowered at
    /// speed would coast off its phase.
    #[inline]
    pub fn ramp_down(&mut self, lim: &Limits) {
        let dv = crate::q16::bound(-self.velocity, lim.max_accel);
        self.step(dv, lim);
    }

    fn step(&mut self, dv: i64, lim: &Limits) {
        self.velocity = crate::q16::bound(self.velocity + dv, lim.max_velocity);
        self.position += self.velocity;
    }

    /// On its target: within half a step of it, and moving within four
    /// ticks' acceleration of its speed. Every axis (cutter and X) must be
    /// on its target for the controller to call itself synchronised.
    #[inline]
    pub fn arrived(&self, target: i64, target_velocity: i64, lim: &Limits) -> bool {
        (target - self.position).abs() < crate::q16::HALF
            && (self.velocity - target_velocity).abs() <= 4 * lim.max_accel
    }

    /// Whole steps (rounded) of the commanded position.
    pub fn whole_steps(&self) -> i64 {
        crate::q16::round(self.position)
    }
}

#[cfg(test)]
mod pinned_tests;
#[cfg(test)]
mod tests;
