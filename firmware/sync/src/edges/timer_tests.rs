//! The edge timer against an exact encoder: a lathe at a known position at
//! every instant, A rising where Table 53's cycle puts it, the capture
//! taking either count, stamps the whole µs they fall in.

use super::*;

/// A lathe turning at `counts_per_us` from `x0` counts; k0 = `k0`.
struct Rig {
    x0: f64,
    speed: f64,
    k0: i64,
    after: bool,
    /// start at this tick's instant (µs); ticks every 40
    t0: f64,
}

impl Rig {
    fn x(&self, t: f64) -> f64 {
        self.x0 + self.speed * t
    }
    fn count(&self, t: f64) -> i64 {
        self.x(t).round() as i64
    }
    /// The last A rise at or before `t`: (count latched, its time).
    fn last_rise(&self, t: f64) -> Option<(i64, f64)> {
        let mut best: Option<(i64, f64)> = None;
        let (lo, hi) = (self.x(0.0).min(self.x(t)), self.x(0.0).max(self.x(t)));
        let up = self.speed > 0.0;
        // A rises at k0 + ½ (mod 4) counting up, k0 + 2½ counting down
        let phase = if up { 0.5 } else { 2.5 };
        let mut b = ((lo - self.k0 as f64 - phase) / 4.0).floor() * 4.0 + self.k0 as f64 + phase;
        while b <= hi {
            if b > lo {
                let at = (b - self.x0) / self.speed;
                let (below, above) = ((b - 0.5) as i64, (b + 0.5) as i64);
                let count = if up == self.after { above } else { below };
                if best.is_none_or(|(_, t0)| at > t0) {
                    best = Some((count, at));
                }
            }
            b += 4.0;
        }
        best
    }
}

/// Runs `ticks` ticks; returns the worst |measured − true| (counts) over
/// the ticks that had a measurement, and how many did.
fn run(rig: &Rig, ticks: u32) -> (f64, u32) {
    let first_instant = (rig.t0 + 40.0) as i64 as u16;
    let clock = EdgeClock { first_instant, stamps_per_tick: 40, low_low_odd: rig.k0 & 1 == 1 };
    let mut timer = EdgeTimer::new(clock);
    let mut lathe = Extender::new(rig.count(0.0) as u16);
    let (mut worst, mut measured) = (0.0f64, 0u32);
    for k in 1..=ticks {
        let t = 40.0 * k as f64;
        lathe.update(rig.count(t) as u16);
        let regs =
            rig.last_rise(t).map(|(c, at)| EdgeRegs { count: c as u16, stamp: (rig.t0 + at).floor() as i64 as u16 });
        let off = timer.measure(regs, &lathe);
        // judged once A has risen three times (before, the count's changes)
        if let Some(off) = off.filter(|_| t * rig.speed.abs() > 13.0) {
            let est = (rig.count(0.0) + lathe.position()) as f64 + off as f64 / 65536.0;
            worst = worst.max((est - rig.x(t)).abs());
            measured += 1;
        }
    }
    (worst, measured)
}

#[test]
fn a_steady_lathe_is_placed_to_the_stamps_resolution_both_ways_and_either_capture() {
    for speed in [0.002, 0.013, 0.031, 0.1, -0.013, -0.1] {
        for after in [false, true] {
            for k0 in [0, 1, 3] {
                let rig = Rig { x0: 17.3, speed, k0, after, t0: 65_000.0 };
                let (worst, n) = run(&rig, 4000);
                // ±½ µs of stamp, and the speed's ±1 µs in an interval of
                // 4/speed carried over up to that interval: 1.5 µs of travel
                let bound = speed.abs() * 1.5 + 0.005;
                assert!(n > 2000, "speed {speed}: only {n} ticks measured");
                assert!(worst < bound, "speed {speed} after {after} k0 {k0}: worst {worst} > {bound}");
            }
        }
    }
}

#[test]
fn no_measurement_before_two_crossings_and_a_stopped_lathe_is_held_not_run_on() {
    let rig = Rig { x0: 0.0, speed: 0.01, k0: 0, after: true, t0: 0.0 };
    let clock = EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false };
    let mut timer = EdgeTimer::new(clock);
    let mut lathe = Extender::new(0);
    let mut first = None;
    for k in 1..=200u32 {
        let t = 40.0 * k as f64;
        lathe.update(rig.count(t) as u16);
        let regs = rig.last_rise(t).map(|(c, at)| EdgeRegs { count: c as u16, stamp: at.floor() as u16 });
        if timer.measure(regs, &lathe).is_some() && first.is_none() {
            first = Some(t);
        }
    }
    // the count changes at 0.5 (50 µs) and 1.5 (150 µs): measured from
    // the second (A rises only at 0.5 and 4.5)
    assert_eq!(first, Some(160.0));
    // then it stops: the same registers and count for ever after. The
    // position runs on for twice the last interval, then holds: it neither
    // runs away nor turns back
    let still = rig.last_rise(8000.0).map(|(c, at)| EdgeRegs { count: c as u16, stamp: at.floor() as u16 });
    let seen: std::vec::Vec<i64> = (0..200).filter_map(|_| timer.measure(still, &lathe)).collect();
    assert_eq!(seen.len(), 200);
    assert!(seen.windows(2).all(|w| w[1] >= w[0]), "turned back");
    assert!(seen[100..].iter().all(|&m| m == seen[199]), "ran on");
    assert!(seen[199].abs() <= crate::q16::HALF + SLACK_Q16_TEST);
}

const SLACK_Q16_TEST: i64 = 1 << 11;
