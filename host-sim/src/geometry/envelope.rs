//! The lower envelope of cut curves in polar form: at each bin angle, the
//! smallest radius any cut reached, capped by the stock.

use crate::round::{ceil, floor};
use std::f64::consts::TAU;

/// Radii at `bins` evenly spaced angles from `start` over `span`, repeating
/// every `period` (2π for a whole section, 2π/N for one flat's sector).
#[derive(Clone, Debug)]
pub struct Envelope {
    pub start: f64,
    pub span: f64,
    pub period: f64,
    pub radius: Vec<f64>,
}

impl Envelope {
    /// An envelope filled with the stock radius. `span` is split into
    /// `bins` steps so that bin 0 sits on `start` exactly.
    pub fn new(start: f64, span: f64, period: f64, bins: usize, stock: f64) -> Envelope {
        Envelope { start, span, period, radius: vec![stock; bins.max(2)] }
    }

    pub fn bins(&self) -> usize {
        self.radius.len()
    }
    pub fn step(&self) -> f64 {
        self.span / self.bins() as f64
    }
    pub fn angle(&self, i: usize) -> f64 {
        self.start + self.step() * i as f64
    }

    /// Adds the straight polar segment (θ0, r0)–(θ1, r1) (θ unwrapped) to
    /// every copy of it shifted by multiples of the period.
    pub fn add_segment(&mut self, t0: f64, r0: f64, t1: f64, r1: f64) {
        let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let step = self.step();
        let (m_lo, m_hi) =
            (floor((lo - self.start - self.span) / self.period) as i64, ceil((hi - self.start) / self.period) as i64);
        for m in m_lo..=m_hi {
            let shift = m as f64 * self.period;
            let (a, b) = (lo - shift - self.start, hi - shift - self.start);
            let first = ceil(a / step).max(0.0) as usize;
            let last = floor(b / step).min(self.bins() as f64 - 1.0);
            if last < 0.0 {
                continue;
            }
            // (the slope once a segment: a bin's division is the envelope's
            // cost when a 50 µm piece covers hundreds of 0.24 µm bins)
            let slope = if hi > lo { (r1 - r0) / (t1 - t0) } else { 0.0 };
            let Some(bins) = self.radius.get_mut(first..=last as usize) else { continue };
            // (a straight loop over the slice, the index as i32 and `min`:
            // one the compiler vectorises; the bins stay below 2^31)
            for (k, radius) in bins.iter_mut().enumerate() {
                let t = self.start + step * (first + k) as i32 as f64 + shift;
                let r = if hi > lo { r0 + slope * (t - t0) } else { r0.min(r1) };
                *radius = radius.min(r);
            }
        }
    }

    /// Adds a polyline of work-frame points (x, y), unwrapping its angle.
    pub fn add_polyline(&mut self, points: &[(f64, f64)]) {
        let mut prev: Option<(f64, f64)> = None;
        for &(x, y) in points {
            // (no overflow to guard against at a lathe's millimetres: the
            // square root, not `hypot`'s care)
            let r = (x * x + y * y).sqrt();
            let mut t = y.atan2(x);
            if let Some((pt, pr)) = prev {
                t += ((pt - t) / TAU).round() * TAU;
                self.add_segment(pt, pr, t, r);
            }
            prev = Some((t, r));
        }
    }

    /// Radius at any angle, linear between bins, using the periodicity.
    pub fn at(&self, angle: f64) -> f64 {
        let rel = (angle - self.start).rem_euclid(self.period);
        let mut x = rel / self.step();
        let n = self.bins();
        if x >= n as f64 && (self.span - self.period).abs() < 1e-12 {
            // a hair short of a whole period, rounded onto it: that is bin 0
            // (not the last bin, which the clamping below would read)
            x -= n as f64;
        }
        let i = x.floor() as usize;
        let (r0, r1) = (self.radius[i.min(n - 1)], self.radius[(i + 1).min(n - 1)]);
        if i + 1 >= n && (self.span - self.period).abs() < 1e-12 {
            // whole-period envelope: the bin after the last is bin 0
            let f = x - i as f64;
            return r0 + (self.radius[0] - r0) * f;
        }
        r0 + (r1 - r0) * (x - i as f64).min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An angle a hair short of a whole turn past the start, which rounds onto
    /// the period, is bin 0, not the last bin: the corner after the last flat
    /// (flat 2 of 3, 256 bins per flat) read the wrong bin.
    #[test]
    fn the_envelope_wraps_a_hair_short_of_a_turn_to_bin_0() {
        let sector = TAU / 3.0;
        let mut env = Envelope::new(-sector / 2.0, TAU, TAU, 768, 10.0);
        env.radius[0] = 9.0;
        env.radius[767] = 8.0;
        let corner = TAU * 2.0 / 3.0 + env.step() * 128.0;
        assert_eq!(((corner - env.start).rem_euclid(TAU) / env.step()), 768.0, "the rounding this test is about");
        assert!((env.at(corner) - 9.0).abs() < 1e-9, "{}", env.at(corner));
    }
}
