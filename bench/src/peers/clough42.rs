//! Clough42's Electronic Leadscrew (clough42/electronic-leadscrew at
//! 8e8e0de, `els-f280049c/Core.h` L97-137, `StepperDrive.h` L162-211): a
//! 5 µs timer interrupt samples the count, sets the desired position to
//! trunc(count · ratio) (f32, or u64 integer with `USE_FLOATING_POINT`
//! undefined) and takes one transition of a STEP/DIR state machine
//! toward it. A step rises at one interrupt and ends at the next (≤ 100
//! kHz); DIR is written one interrupt ahead of a reversed step. No speed
//! or acceleration limit: the drive chases the target.

/// Interrupt period, s (`STEPPER_CYCLE_US 5`).
pub const TICK_S: f64 = 5e-6;

pub struct Clough42 {
    /// steps per count as f32 (`feed = (float)num / den`), with the sense
    feed: f32,
    /// the integer variant: num/den steps per count, signed
    int: Option<(i64, i64)>,
    current: i32,
    /// bit 0: STEP high; bit 1: DIR forward
    state: u8,
}

impl Clough42 {
    /// `num/den` steps per count; `sense` ±1 (the reverse key).
    pub fn new(num: u64, den: u64, sense: i32, integer: bool) -> Clough42 {
        let feed = (num as f32 / den as f32) * sense as f32;
        let int = integer.then_some((num as i64 * sense as i64, den as i64));
        Clough42 { feed, int, current: 0, state: 0 }
    }

    fn desired(&self, count: i64) -> i32 {
        match self.int {
            // (floor of the u64 product in the firmware; ours are positive
            // or negated after, as its ×(−1) does)
            Some((num, den)) => ((count * num.abs()) / den * num.signum()) as i32,
            None => (count as f32 * self.feed) as i32,
        }
    }

    /// One interrupt with the count sampled now: the step it raises, if
    /// any (+1 forward, −1 back).
    pub fn tick(&mut self, count: i64) -> Option<i32> {
        let desired = self.desired(count);
        let cur = self.current;
        match self.state {
            0 if desired < cur => {
                self.state = 2;
                Some(-1)
            }
            0 if desired > cur => {
                self.state = 1; // DIR first, the step at the next interrupt
                None
            }
            1 if desired > cur => {
                self.state = 3;
                Some(1)
            }
            1 if desired < cur => {
                self.state = 0;
                None
            }
            2 => {
                (self.state, self.current) = (0, cur - 1);
                None
            }
            3 => {
                (self.state, self.current) = (1, cur + 1);
                None
            }
            _ => None,
        }
    }
}
