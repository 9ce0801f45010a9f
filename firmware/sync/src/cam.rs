//! The electronic cam: an axis position (X steps) as a function of the
//! lathe's angle, from a table of `N` evenly spaced points over `P` lathe
//! counts (one or more revolutions, the pattern's period). Synchronised to
//! the same encoder as the gear and, like it, exact: the table index is a
//! DDA on whole counts (adds and compares), so the cam comes back to exactly
//! the same point whenever the lathe does. Between points and between
//! counts it interpolates linearly in fixed point (bounded, never drifts).

/// Largest table the core holds (4 KiB of i32).
pub const CAM_POINTS: usize = 1024;

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CamError {
    /// fewer than 2 points, or more than [`CAM_POINTS`]
    Points,
    /// the period must be at least one count per point
    Period,
    /// two neighbouring points 2^23 steps or more apart
    Step,
}

/// The table is borrowed for the program's life: in the firmware it sits in
/// flash, so the controller stays small (fields within short load offsets).
#[derive(Clone, Copy, Debug)]
pub struct Cam {
    table: &'static [i32],
    /// lathe counts per table period
    period: u32,
    /// floor(2^40 / period): acc/period in Q24 is (acc·2^16 · inv) >> 32
    inv: u64,
    index: u32,
    /// (counts into the segment) × N, in [0, period)
    acc: u32,
}

const _: () = assert!(CAM_POINTS == 1024, "CamError::describe names 1024 points");

/// Neighbouring points must be less than this apart: |b − a| < 2^23 keeps
/// (b − a) · (Q24 fraction) inside i64.
pub const STEP_SPAN: i64 = 1 << 23;

impl CamError {
    pub fn describe(self) -> &'static str {
        match self {
            CamError::Points => "cam table: 2 to 1024 points",
            CamError::Period => "cam table: the period must be at least one count per point",
            CamError::Step => "cam table: neighbouring points must be less than 2^23 steps apart",
        }
    }
}

impl Cam {
    /// A cam over `period` lathe counts (revolutions × counts per rev).
    pub fn new(points: &'static [i32], period: u32) -> Result<Cam, CamError> {
        Cam::check(points, period)?;
        Ok(Cam { table: points, period, inv: (1u64 << 40) / period as u64, index: 0, acc: 0 })
    }

    /// Every check `new` applies, on any table (an upload before it is
    /// stored: nothing is saved or replaced that `new` would refuse).
    pub fn check(points: &[i32], period: u32) -> Result<(), CamError> {
        if points.len() < 2 || points.len() > CAM_POINTS {
            return Err(CamError::Points);
        }
        if (period as usize) < points.len() {
            return Err(CamError::Period);
        }
        match Cam::wide_step(points) {
            Some(_) => Err(CamError::Step),
            None => Ok(()),
        }
    }

    /// The first point `i` whose step to the next (point 0 after the last:
    /// the table repeats) is `STEP_SPAN` or more, which the interpolation
    /// cannot take; None if every step is shorter.
    pub fn wide_step(points: &[i32]) -> Option<usize> {
        let n = points.len();
        (0..n).find(|&i| (points[(i + 1) % n] as i64 - points[i] as i64).abs() >= STEP_SPAN)
    }

    /// Moves to an absolute lathe count (low priority: divides).
    pub fn seek(&mut self, count: i64) {
        let p = count.rem_euclid(self.period as i64) as u64 * self.table.len() as u64;
        self.index = (p / self.period as u64) as u32;
        self.acc = (p % self.period as u64) as u32;
    }

    /// Follows the lathe by `delta` counts: adds and compares only. Each
    /// count moves N/period < 1 segment, so one compare per count suffices.
    #[inline]
    pub fn advance(&mut self, delta: i32) {
        let n = self.table.len() as u32;
        for _ in 0..delta.unsigned_abs() {
            if delta > 0 {
                self.acc += n;
                if self.acc >= self.period {
                    self.acc -= self.period;
                    self.index = if self.index + 1 == n { 0 } else { self.index + 1 };
                }
            } else if self.acc >= n {
                self.acc -= n;
            } else {
                self.acc += self.period - n;
                self.index = if self.index == 0 { n - 1 } else { self.index - 1 };
            }
        }
    }

    /// The axis position in Q16 steps, `offset_q16` counts past the current
    /// count (the lathe estimator's sub-count interpolation).
    #[inline]
    pub fn position_q16(&self, offset_q16: i32) -> i64 {
        let n = self.table.len();
        let i = self.index as usize;
        let j = if i + 1 >= n { 0 } else { i + 1 };
        // `get`: no panic path in the tick (index < n always holds).
        let at = |k: usize| self.table.get(k).copied().unwrap_or(0) as i64;
        let (a, b) = (at(i), at(j));
        // fraction of the segment in Q24: (acc + offset·N) / period; Q24 keeps
        // the rounding under span / 2^24 even for a steep, coarse table.
        let acc_q16 = ((self.acc as i64) << 16) + offset_q16 as i64 * n as i64;
        let frac_q24 = (acc_q16 * self.inv as i64) >> 32; // |product| < 2^57
        (a << 16) + (((b - a) * frac_q24) >> 8)
    }

    pub fn points(&self) -> &[i32] {
        self.table
    }
    pub fn period(&self) -> u32 {
        self.period
    }
}

#[cfg(test)]
mod pinned_tests;
#[cfg(test)]
mod tests;
