//! The same plant and the same measurement for every controller: a rotor
//! after `sim::stepper`'s (it passes through the middle of each step at
//! the step's instant, straight between two steps' middles, and sits on
//! its step when the next is over 2 ms away), read at every polyturn tick
//! (50 µs) against the exact gear. Read between ticks, a burst's peak can
//! fall between two readings: that flatters the bursty peers.
//!
//! The rotor follows every pulse: no stall is modelled (the simulator's
//! stall model would pass the peers' starts too: they jump to speeds a
//! motor starts at).

use super::trace::Instant;

/// The rotor's position (steps) at each instant, from step times.
pub fn rotor(steps: &[(f64, i32)], instants: &[Instant]) -> Vec<f64> {
    let (mut i, mut here) = (0usize, 0i64);
    let mut last: Option<(f64, i32)> = None;
    instants
        .iter()
        .map(|at| {
            while i < steps.len() && steps[i].0 <= at.t {
                here += steps[i].1 as i64;
                last = Some(steps[i]);
                i += 1;
            }
            match (last, steps.get(i)) {
                (Some((tp, sp)), Some(&(tn, sn))) if tn - tp < 2e-3 => {
                    let (pp, pn) = (here as f64 - 0.5 * sp as f64, here as f64 + 0.5 * sn as f64);
                    pp + (pn - pp) * ((at.t - tp) / (tn - tp)).clamp(0.0, 1.0)
                }
                _ => here as f64,
            }
        })
        .collect()
}

/// The largest change of one step interval to the next, as a fraction of
/// the shorter of the two, over the steps taken while cutting
/// (`from`..`to`, s).
pub fn interval_jerk(steps: &[(f64, i32)], (from, to): (f64, f64)) -> f64 {
    let times: Vec<f64> = steps.iter().map(|s| s.0).filter(|t| (from..to).contains(t)).collect();
    times
        .windows(3)
        .map(|w| {
            let (d0, d1) = (w[1] - w[0], w[2] - w[1]);
            (d1 - d0).abs() / d0.min(d1).max(1e-9)
        })
        .fold(0.0, f64::max)
}
