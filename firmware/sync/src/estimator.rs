//! Lathe speed estimate and sub-count interpolation: a type-2 tracking loop
//! in fixed point. It shapes *timing* only: its output is an offset from the
//! measured count, clamped to ±1 count and snapped to 0 at rest, so the
//! exact gear (not this filter) owns position and nothing can drift.
//!
//! Continuous equivalent: K1 = 2^−KP·f, K2 = 2^−KI·f². At f = 20 kHz:
//! ω_n = 2^−5.5·f ≈ 440 rad/s, ζ ≈ 0.7; the acceleration error a/ω_n² is
//! ≈ 0.1 count for 5 % once-per-rev ripple at 300 rpm on 2400 counts.

use fixed::types::I32F32;

/// Proportional shift (K1·T = 2^−5).
const KP: u32 = 4;
/// Integral shift (K2·T² = 2^−11).
const KI: u32 = 9;
/// The shifts on a timed edge's measurement: K1·T = 2^−4, K2·T² = 2^−8,
/// ω_n·T = 2^−4 (1 250 rad/s at 20 kHz), ζ = 0.5. Wider than the count's
/// loop: the measurement's noise is the stamp's ±½ µs, not ±½ count. No
/// wider: at 64 000 steps/s that ±½ µs is 3 % of a step's period, and the
/// loop's filtering is what keeps the steps' spacing within 1 %
/// (`hwsim::steady_lathe`).
const KP_EDGE: u32 = 4;
const KI_EDGE: u32 = 8;

#[derive(Clone, Copy, Debug, Default)]
pub struct Estimator {
    /// estimate − measured count, Q32 counts, within ±1 count
    offset: I32F32,
    /// Q32 counts per tick
    velocity: I32F32,
    still_ticks: u32,
    still_limit: u32,
}

impl Estimator {
    /// `still_limit`: ticks without a count after which the lathe is at rest.
    pub fn new(still_limit: u32) -> Estimator {
        Estimator { still_limit, ..Estimator::default() }
    }

    /// An estimate that starts at rest: a board that has just started has
    /// seen no count, and takes the lathe at rest until one comes (as
    /// 0.1 s after the last).
    pub fn resting(still_limit: u32) -> Estimator {
        Estimator { still_ticks: still_limit, ..Estimator::new(still_limit) }
    }

    /// A new estimate (no speed, no offset: measured afresh) that keeps the
    /// ticks since the last count: they are the encoder's, not the
    /// estimate's, so a lathe at rest stays at rest.
    pub fn restarted(&self, still_limit: u32) -> Estimator {
        Estimator { still_ticks: self.still_ticks, ..Estimator::new(still_limit) }
    }

    /// One tick with the measured count change `delta`.
    #[inline]
    pub fn update(&mut self, delta: i32) {
        self.update_measured(delta, None);
    }

    /// One tick with the count change `delta` and, where an edge's time
    /// places the lathe (`edges`), its offset from the count (Q16 counts).
    /// A timed measurement is far finer than the count's ±½, so it is
    /// followed with a wider loop (`KP_EDGE`, `KI_EDGE`).
    #[inline]
    pub fn update_measured(&mut self, delta: i32, measured_q16: Option<i64>) {
        if delta == 0 {
            self.still_ticks = self.still_ticks.saturating_add(1);
            if self.still_ticks >= self.still_limit {
                self.offset = I32F32::ZERO;
                self.velocity = I32F32::ZERO;
                return;
            }
        } else {
            self.still_ticks = 0;
        }
        // predict, then correct on the error (measured − estimate)
        let predicted = self.offset + self.velocity - I32F32::from(delta);
        let corrected = match measured_q16 {
            Some(m) => {
                let error = I32F32::from_bits(m << 16) - predicted;
                self.velocity += error >> KI_EDGE;
                predicted + (error >> KP_EDGE)
            }
            // the count's middle: the error is −predicted
            None => {
                self.velocity -= predicted >> KI;
                predicted - (predicted >> KP)
            }
        };
        self.offset = corrected.max(-I32F32::ONE).min(I32F32::ONE);
    }

    /// Sub-count offset of the estimate from the measured count, Q16 counts.
    pub fn offset_q16(&self) -> i32 {
        (self.offset.to_bits() >> 16) as i32
    }
    /// Q32 counts per tick.
    pub fn velocity_q32(&self) -> i64 {
        self.velocity.to_bits()
    }
    pub fn at_rest(&self) -> bool {
        self.still_ticks >= self.still_limit
    }
    /// Ticks since the last count (saturating).
    pub fn still_ticks(&self) -> u32 {
        self.still_ticks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds a true position (in counts, f64 reference model) sampled by a
    /// quantising counter; returns the worst |estimate − truth| after settling.
    fn track(speed: impl Fn(f64) -> f64, ticks: usize) -> f64 {
        let mut e = Estimator::new(2500);
        let (mut x, mut last) = (0.3f64, 0i64);
        let mut worst: f64 = 0.0;
        for k in 0..ticks {
            x += speed(k as f64);
            let c = x.round() as i64;
            e.update((c - last) as i32);
            last = c;
            if k > ticks / 4 {
                let est = c as f64 + e.offset_q16() as f64 / 65536.0;
                worst = worst.max((est - x).abs());
            }
        }
        worst
    }

    #[test]
    fn steady_speed_is_interpolated_well_inside_a_count() {
        for v in [0.05, 0.37, 0.96, 1.2, 3.7] {
            let w = track(|_| v, 40_000);
            assert!(w < 0.25, "v {v}: worst {w}");
        }
    }

    #[test]
    fn five_percent_ripple_is_tracked_within_a_few_tenths() {
        // 300 rpm, 2400 counts: 0.6 counts per tick at 20 kHz, ripple once
        // per rev (4 000 ticks)
        let hz = crate::Timing::FIRMWARE.tick_hz as f64;
        let (v, rev) = (12_000.0 / hz, hz / 5.0);
        let w = track(|k| v * (1.0 + 0.05 * (k * core::f64::consts::TAU / rev).sin()), 60_000);
        assert!(w < 0.3, "worst {w}");
    }

    #[test]
    fn at_rest_the_offset_is_exactly_zero() {
        let mut e = Estimator::new(100);
        for _ in 0..1000 {
            e.update(1);
        }
        for _ in 0..100 {
            e.update(0);
        }
        assert!(e.at_rest());
        assert_eq!((e.offset_q16(), e.velocity_q32()), (0, 0));
    }
}

#[cfg(test)]
mod measured_tests {
    use super::*;

    /// Fed the true offset from the count (as an edge's time gives it), the
    /// loop settles on it and on the speed within a few hundred ticks; the
    /// bare count's loop, fed the same steady lathe, interpolates it only
    /// to a few hundredths of a count.
    #[test]
    fn a_timed_measurement_is_followed_to_its_own_resolution() {
        let run = |timed: bool| {
            let mut e = Estimator::new(2500);
            let (mut x, mut last, mut worst) = (0.3f64, 0i64, 0.0f64);
            for k in 0..4000 {
                x += 0.37;
                let c = x.round() as i64;
                let m = timed.then_some(((x - c as f64) * 65536.0) as i64);
                e.update_measured((c - last) as i32, m);
                last = c;
                if k > 500 {
                    worst = worst.max((c as f64 + e.offset_q16() as f64 / 65536.0 - x).abs());
                }
            }
            (worst, e.velocity_q32() as f64 / 4_294_967_296.0)
        };
        let (timed, v) = run(true);
        assert!(timed < 0.001, "{timed}");
        assert!((v - 0.37).abs() < 1e-4, "{v}");
        let (bare, _) = run(false);
        assert!(bare > 0.02, "{bare}");
    }

    /// A step in the measurement is taken at the edge loop's gains: a
    /// sixteenth at once, the rest over the following ticks.
    #[test]
    fn the_edge_loop_takes_a_sixteenth_of_an_error_at_once() {
        let mut e = Estimator::new(2500);
        e.update_measured(0, Some(1 << 15));
        assert_eq!(e.offset_q16(), (1 << 15) >> KP_EDGE);
        assert_eq!(e.velocity_q32(), (1i64 << 31) >> KI_EDGE);
    }
}
