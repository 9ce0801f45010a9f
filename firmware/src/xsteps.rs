//! X-axis steps on two plain GPIO pins, driven from the control tick: all
//! the advanced timers are taken (TIM1 cutter steps, TIM2 their count), and
//! a cross-slide needs far fewer steps than the cutter. A pulse is one tick
//! high (50 µs at 20 kHz), then at least one tick low; DIR changes only
//! while STEP is low and a step never leaves in the tick DIR changed (≥ a
//! tick of setup). So at most one step per two ticks (10 kHz at the
//! board's 20 kHz tick), the limit `fit_cam` enforces.
//! The count of steps really emitted goes back to the core, which plans
//! anything not yet emitted again (nothing is lost, only delayed a tick).

use polyturn_sync::steps::{Dir, StepPlan};

/// What to put on the pins this tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct XPins {
    pub step_high: bool,
    pub dir: Dir,
}

#[derive(Clone, Copy, Debug, Default)]
pub struct XSteps {
    step_high: bool,
    dir: Dir,
    /// DIR changed this tick: no step until the next
    settling: bool,
    /// free-running count of pulses emitted (what the core reads)
    pub emitted: u16,
}

impl XSteps {
    /// One tick: the core's plan for this tick in, the pin levels out.
    pub fn tick(&mut self, plan: &StepPlan, halt: bool) -> XPins {
        if self.step_high || halt {
            self.step_high = false; // end of the pulse (or stop at once)
        } else if plan.count > 0 {
            if plan.dir != self.dir {
                (self.dir, self.settling) = (plan.dir, true);
            } else if !self.settling {
                self.step_high = true;
                self.emitted = self.emitted.wrapping_add(1);
            } else {
                self.settling = false;
            }
        }
        XPins { step_high: self.step_high, dir: self.dir }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(count: u16, dir: Dir) -> StepPlan {
        StepPlan { count, dir, ..StepPlan::default() }
    }

    /// The core's side: it asks for what is not yet emitted, each tick.
    #[test]
    fn every_requested_step_is_emitted_with_dir_set_up_and_pulses_apart() {
        let mut x = XSteps::default();
        let (mut want, mut last) = (0i64, XPins { step_high: false, dir: Dir::Forward });
        let mut at = 0i64;
        for t in 0..20_000u32 {
            // a target sweeping back and forth at up to 0.45 step per tick
            want += if (t / 2_000) % 2 == 0 { ((t % 9) < 4) as i64 } else { -(((t % 9) < 4) as i64) };
            let owed = want - at;
            let dir = if owed >= 0 { Dir::Forward } else { Dir::Reverse };
            let pins = x.tick(&plan(owed.unsigned_abs().min(3) as u16, dir), false);
            if pins.step_high {
                assert!(!last.step_high, "a pulse is followed by a low tick");
                assert_eq!(pins.dir, last.dir, "DIR was set a tick before the step");
                at += if pins.dir == Dir::Forward { 1 } else { -1 };
            }
            if pins.dir != last.dir {
                assert!(!pins.step_high && !last.step_high, "DIR changes only while STEP is low");
            }
            assert!((want - at).abs() <= 4, "falls behind by at most a few steps");
            last = pins;
        }
        for _ in 0..10 {
            let owed = want - at;
            let dir = if owed >= 0 { Dir::Forward } else { Dir::Reverse };
            if x.tick(&plan(owed.unsigned_abs() as u16, dir), false).step_high {
                at += if dir == Dir::Forward { 1 } else { -1 };
            }
        }
        assert_eq!(at, want, "caught up once the target rests");
    }

    #[test]
    fn halt_ends_the_pulse_at_once() {
        let mut x = XSteps::default();
        assert!(x.tick(&plan(1, Dir::Forward), false).step_high);
        assert!(!x.tick(&plan(1, Dir::Forward), true).step_high);
        assert!(!x.tick(&plan(0, Dir::Forward), true).step_high);
    }
}
