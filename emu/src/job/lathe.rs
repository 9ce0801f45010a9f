//! The lathe, as the host simulator models it (`polyturn_host::sim::lathe`: the
//! speed profile with ripple and wander), turned into pin levels: quadrature A/B on
//! PA6/PA7 and the index on PB0. The count is the host encoder's
//! (`sim::encoder`: round(angle · counts / 2π)); A/B follow it in Gray code, one
//! pin edge per count, and the index is high while the count is a whole turn.

use polyturn_host::sim::encoder::Encoder;
use polyturn_host::sim::lathe::{Lathe, LatheProfile};

/// The lathe model's step: the host simulator's, one control tick (40 µs), so the
/// lathe turns exactly as in `polyturn simulate` with the same seed. Within a step
/// the angle is taken as linear: each count's edge is put where the angle crosses
/// the count's boundary (half-way between two counts, as `sim::encoder` rounds).
const STEP_S: f64 = 1.0 / polyturn_sync::Timing::FIRMWARE.tick_hz as f64;

/// What turns the spindle: the host simulator's motor-driven lathe, or a hand
/// rocking the chuck (±`amp_counts` at `hz`, for `secs`).
pub enum Motion {
    Motor(Box<Lathe>),
    Rock { amp_counts: f64, hz: f64, secs: f64, t: f64 },
}

impl Motion {
    fn advance(&mut self, dt: f64) {
        match self {
            Motion::Motor(l) => l.advance(dt),
            Motion::Rock { t, .. } => *t += dt,
        }
    }
    fn angle(&self, cpr: u32) -> f64 {
        match self {
            Motion::Motor(l) => l.angle,
            Motion::Rock { amp_counts, hz, t, .. } => {
                amp_counts * std::f64::consts::TAU / cpr as f64 * (std::f64::consts::TAU * *hz * *t).sin()
            }
        }
    }
    fn finished(&self) -> bool {
        match self {
            Motion::Motor(l) => l.finished(),
            Motion::Rock { secs, t, .. } => t >= secs,
        }
    }
}

pub struct LatheDrive {
    lathe: Motion,
    cpr: u32,
    encoder: Encoder,
    /// CPU cycle of the lathe's time 0 (before 0 once a reset restarted the
    /// CPU's count while the lathe kept turning), and cycles per model step
    start: i64,
    per_step: u64,
    steps: u64,
    pub count: i64,
    /// the level changes of the step being played: (cycle, count), in order
    next: std::collections::VecDeque<(u64, i64)>,
    /// the angle at the end of the last step
    angle: f64,
}

/// Levels of (A, B, index) at count `c` (positive turning counts up, RM0383 §13.3.12
/// table 53 with both inputs: A rises while B is low).
pub fn levels(c: i64, cpr: u32) -> [bool; 3] {
    let s = c.rem_euclid(4);
    [s == 1 || s == 2, s >= 2, c.rem_euclid(cpr as i64) == 0]
}

impl LatheDrive {
    pub fn motor(profile: LatheProfile, seed: u64, cpr: u32, start: u64, sysclk: u64) -> LatheDrive {
        LatheDrive::new(Motion::Motor(Box::new(Lathe::new(profile, seed))), cpr, start, sysclk)
    }

    pub fn new(lathe: Motion, cpr: u32, start: u64, sysclk: u64) -> LatheDrive {
        let encoder = Encoder::new(cpr);
        LatheDrive {
            lathe,
            cpr,
            encoder,
            start: start as i64,
            per_step: (sysclk as f64 * STEP_S) as u64,
            steps: 0,
            count: 0,
            next: Default::default(),
            angle: 0.0,
        }
    }

    pub fn finished(&self) -> bool {
        self.lathe.finished()
    }

    /// The cycle of the next count change (looking ahead at most `horizon` cycles).
    pub fn next_edge(&mut self, horizon: u64) -> Option<u64> {
        while self.next.is_empty() && self.step_start() < horizon && !self.lathe.finished() {
            self.step();
        }
        self.next.front().map(|n| n.0)
    }

    /// One model step: its count changes, each at its crossing time.
    fn step(&mut self) {
        let t0 = self.step_start();
        let a0 = self.angle;
        self.lathe.advance(STEP_S);
        self.steps += 1;
        self.angle = self.lathe.angle(self.cpr);
        let last = self.next.back().map_or(self.count, |n| n.1);
        let c1 = self.encoder.count(self.angle, self.steps);
        let per_count = std::f64::consts::TAU / self.cpr as f64;
        let dir = (c1 - last).signum();
        let mut c = last;
        while c != c1 {
            // count c + dir begins half a count from c, towards it
            let boundary = (c as f64 + 0.5 * dir as f64) * per_count;
            let f = ((boundary - a0) / (self.angle - a0)).clamp(0.0, 1.0);
            c += dir;
            self.next.push_back((t0 + (f * self.per_step as f64).ceil() as u64, c));
        }
    }

    /// The CPU cycle the next model step starts at.
    fn step_start(&self) -> u64 {
        (self.start + (self.steps * self.per_step) as i64).max(0) as u64
    }

    /// The CPU's cycle count restarted (a reset) `by` cycles after the lathe's
    /// clock: the lathe turns on, its edges due at the same moments of the wall.
    pub fn rebase(&mut self, by: u64) {
        self.start -= by as i64;
        for n in self.next.iter_mut() {
            n.0 = n.0.saturating_sub(by);
        }
    }

    /// The count due at or before `now`, one count at a time.
    pub fn take_due(&mut self, now: u64) -> Option<i64> {
        let &(at, c) = self.next.front()?;
        if at > now {
            return None;
        }
        self.next.pop_front();
        self.count = c;
        Some(c)
    }
}

#[cfg(test)]
mod tests {
    use super::levels;

    #[test]
    fn each_count_moves_one_quadrature_pin_and_the_index_marks_whole_turns() {
        for c in -10i64..10 {
            let (a, b) = (levels(c, 8), levels(c + 1, 8));
            let changed = (a[0] != b[0]) as u32 + (a[1] != b[1]) as u32;
            assert_eq!(changed, 1, "count {c}");
        }
        assert_eq!(levels(1, 8)[..2], [true, false], "A leads B going up (table 53 counts up)");
        assert!(levels(16, 8)[2] && levels(-8, 8)[2] && !levels(3, 8)[2]);
    }
}
