//! An encoder on the stepper's shaft (the lost-step alarm's, `cutter-cpr`):
//! whole counts of the rotor's real angle, as TIM4 takes them. The rotor's
//! angle is the stepper's smooth position plus each step's own error (a
//! real motor's steps are not evenly spaced: ±5 % of a step is typical of
//! a 1.8° hybrid), fixed per step position and drawn from the run's seed.

use super::rng::Rng;

#[derive(Clone, Debug)]
pub struct ShaftEncoder {
    /// counts per cutter revolution; 0: no encoder
    pub cpr: u32,
    steps_per_rev: u32,
    /// largest step-position error, fraction of a step
    pub step_error: f64,
    seed: u64,
    /// the count at the last update
    pub count: i64,
}

impl ShaftEncoder {
    pub fn new(cpr: u32, steps_per_rev: u32, step_error: f64, seed: u64) -> ShaftEncoder {
        ShaftEncoder { cpr, steps_per_rev, step_error, seed, count: 0 }
    }

    /// The error of the step position `s`, in steps: the same every time
    /// the rotor comes back to it (it is the motor's, not noise).
    fn error_at(&self, s: i64) -> f64 {
        if self.step_error == 0.0 {
            return 0.0;
        }
        let step = s.rem_euclid(self.steps_per_rev as i64) as u64;
        let u = Rng::new(self.seed ^ step.wrapping_mul(0x2545_F491_4F6C_DD1D)).uniform();
        (2.0 * u - 1.0) * self.step_error
    }

    /// Takes the rotor's position (steps, smooth) and returns the count.
    pub fn update(&mut self, steps: f64) -> i64 {
        if self.cpr == 0 {
            return 0; // no encoder: nothing counts
        }
        let angle = steps + self.error_at(steps.round() as i64);
        self.count = (angle * self.cpr as f64 / self.steps_per_rev as f64).floor() as i64;
        self.count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_whole_turns_exactly_and_the_step_error_stays_within_its_bound() {
        let mut e = ShaftEncoder::new(1000, 3200, 0.05, 7);
        assert_eq!(e.update(3200.0 * 5.0), 5000);
        for s in -5000..5000 {
            let err = e.error_at(s);
            assert!(err.abs() <= 0.05, "{s}: {err}");
            assert_eq!(err, e.error_at(s + 3200), "a step's error is the motor's: it repeats each turn");
        }
    }
}
