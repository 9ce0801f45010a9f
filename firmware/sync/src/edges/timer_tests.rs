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
                // the stamps' whole µs: the edge's own (±½ µs), and the
                // interval's (±1 µs in 4/speed) carried over up to an
                // interval, with the truncations: 2 µs of travel
                let bound = speed.abs() * 2.0 + 0.005;
                assert!(n > 2000, "speed {speed}: only {n} ticks measured");
                assert!(worst < bound, "speed {speed} after {after} k0 {k0}: worst {worst} > {bound}");
            }
        }
    }
}

#[test]
fn no_measurement_before_two_crossings_and_a_stopped_lathe_runs_on_only_to_its_counts_edge() {
    // a count every 1 000 µs (25 ticks)
    let rig = Rig { x0: 0.0, speed: 0.001, k0: 0, after: true, t0: 0.0 };
    let clock = EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false };
    let mut timer = EdgeTimer::new(clock);
    let mut lathe = Extender::new(0);
    let mut first = None;
    for k in 1..=400u32 {
        let t = 40.0 * k as f64;
        lathe.update(rig.count(t) as u16);
        let regs = rig.last_rise(t).map(|(c, at)| EdgeRegs { count: c as u16, stamp: at.floor() as u16 });
        if let (Some(m), None) = (timer.measure(regs, &lathe), first) {
            first = Some(t);
            // the boundary crossed (1.5), in the middle of its tick, run
            // on at one count a ms: the lathe's own place to the count's
            // change's ±½ tick
            let at = lathe.position() as f64 + m as f64 / 65536.0;
            assert!((at - rig.x(t)).abs() < 0.005, "{at} against {}", rig.x(t));
        }
    }
    // the count changes at 0.5 (500 µs) and 1.5 (1 500 µs): measured from
    // the second (A rises only at 0.5 and 4.5)
    assert_eq!(first, Some(1520.0));
    // then it stops: the same registers and count for ever after. The
    // position runs on to its count's edge and stays there: it neither
    // runs away nor turns back
    let still = rig.last_rise(16_000.0).map(|(c, at)| EdgeRegs { count: c as u16, stamp: at.floor() as u16 });
    let seen: std::vec::Vec<i64> = (0..200).filter_map(|_| timer.measure(still, &lathe)).collect();
    assert_eq!(seen.len(), 200);
    assert!(seen.windows(2).all(|w| w[1] >= w[0]), "turned back");
    assert!(seen[100..].iter().all(|&m| m == seen[199]), "ran on");
    // run on to its count's edge and a 32nd of a count past it (the count
    // is read a little after the instant)
    assert_eq!(seen[199], crate::q16::HALF + (1 << 11));
}

/// A lathe moving as `x(t)` (counts, t in µs, one way at a time), its A
/// rises latched (the count after, k0 = 0), ticked every 40 µs from t = 40:
/// the measured positions (counts) beside the true ones.
fn follow(x: &dyn Fn(f64) -> f64, ticks: u32) -> std::vec::Vec<(f64, Option<f64>)> {
    let clock = EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false };
    let mut timer = EdgeTimer::new(clock);
    let mut lathe = Extender::new(x(0.0).round() as u16);
    let mut rise: Option<EdgeRegs> = None;
    let mut out = std::vec::Vec::new();
    for k in 1..=ticks {
        let t = 40.0 * k as f64;
        let (u0, u1) = (x(t - 40.0), x(t));
        let up = u1 >= u0;
        let phase = if up { 0.5 } else { 2.5 };
        let mut b = ((u0.min(u1) - phase) / 4.0).floor() * 4.0 + phase;
        while b <= u0.max(u1) {
            if b > u0.min(u1) {
                // the crossing's time, by bisection (x is monotone in a tick)
                let (mut lo, mut hi) = (t - 40.0, t);
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if (x(mid) >= b) == up {
                        hi = mid
                    } else {
                        lo = mid
                    }
                }
                let count = if up { b + 0.5 } else { b - 0.5 };
                rise = Some(EdgeRegs { count: count.round() as i64 as u16, stamp: hi.floor() as i64 as u16 });
            }
            b += 4.0;
        }
        lathe.update(u1.round() as i64 as u16);
        let m = timer.measure(rise, &lathe);
        let base = x(0.0).round() + lathe.position() as f64;
        out.push((u1, m.map(|m| base + m as f64 / 65536.0)));
    }
    out
}

/// From rest at 48 000 counts/s² (a lathe reaching 600 rpm in half a
/// second): once A has risen three times the acceleration places it to a
/// hundredth of a count; without it (the last interval's mean speed) it
/// would lag by a·T/2 over an interval, a tenth of a count and more.
#[test]
fn a_lathe_starting_from_rest_is_placed_with_its_acceleration() {
    let acc = 48_000e-12;
    let x = |t: f64| 0.3 + 0.5 * acc * t * t;
    let seen = follow(&x, 1500);
    // between the second and third rise the count's changes tell
    let second_rise = (2.0 * (4.5 - 0.3) / acc).sqrt();
    let third_rise = (2.0 * (8.5 - 0.3) / acc).sqrt();
    let between =
        seen.iter().enumerate().filter(|(k, _)| (second_rise..third_rise).contains(&(40.0 * (*k + 1) as f64)));
    let worst = between.map(|(_, (truth, m))| m.map_or(1.0, |m| (m - truth).abs())).fold(0.0, f64::max);
    assert!(worst < 0.1, "between the second and third rises: {worst}");
    let after: std::vec::Vec<_> =
        seen.iter().enumerate().filter(|(k, _)| 40.0 * (*k + 1) as f64 > third_rise + 40.0).collect();
    assert!(after.len() > 1000);
    for (k, (truth, m)) in after {
        let m = m.unwrap_or_else(|| panic!("tick {k}: no measurement"));
        assert!((m - truth).abs() < 0.012, "tick {k}: {m} against {truth}");
    }
}

/// A lathe at 0.3 count slowing from 0.006 count/µs to a stop at 48 000
/// counts/s², `sense` +1 counting up, −1 down; still after its stop.
fn running_down(sense: f64) -> impl Fn(f64) -> f64 + Copy {
    let (acc, v0) = (48_000e-12, 0.006);
    let stop = v0 / acc;
    move |t: f64| {
        let t = t.min(stop);
        0.3 + sense * (v0 * t - 0.5 * acc * t * t)
    }
}

/// Running down to a stop at 48 000 counts/s²: the measurement follows
/// the slowing lathe, never turns back, and holds where the lathe stops.
#[test]
fn a_lathe_running_down_is_followed_to_its_stop_and_held_without_turning_back() {
    let x = running_down(1.0);
    let seen = follow(&x, 5000);
    let measured: std::vec::Vec<(f64, f64)> = seen.iter().filter_map(|&(t, m)| m.map(|m| (t, m))).collect();
    assert!(measured.len() > 4000);
    assert!(measured.windows(2).all(|w| w[1].1 >= w[0].1 - 1e-9), "turned back");
    let worst = measured.iter().map(|(t, m)| (m - t).abs()).fold(0.0, f64::max);
    assert!(worst < 0.1, "worst {worst}");
    let last = measured[measured.len() - 1];
    assert!((last.1 - last.0).abs() < 0.1, "held at {} against {}", last.1, last.0);
}

/// An edge after the tick's instant (while the interrupt was on its way to
/// the registers): its age is negative, and the lathe is placed before it.
#[test]
fn an_edge_after_the_instant_places_the_lathe_before_it() {
    // 0.005 counts a µs (steady), A rising at 43 + 800j µs, 3 µs after
    // the instant 40 + 800j; the tick at that instant reads the rise's
    // registers and the count after it, as an interrupt 4 µs late would
    let clock = EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false };
    let mut timer = EdgeTimer::new(clock);
    let x = |t: f64| 0.5 + 0.005 * (t - 43.0);
    let mut lathe = Extender::new(0);
    let mut checked = 0;
    for k in 1..=400u32 {
        let t = 40.0 * k as f64;
        let early = (t - 40.0) % 800.0 == 0.0;
        let j = ((t - 43.0) / 800.0).floor() + if early { 1.0 } else { 0.0 };
        let count = if early { 1.0 + 4.0 * j } else { x(t).round() };
        let regs = (j >= 0.0).then_some(EdgeRegs { count: (1.0 + 4.0 * j) as u16, stamp: (43.0 + 800.0 * j) as u16 });
        lathe.update(count as i64 as u16);
        let m = timer.measure(regs, &lathe);
        if let (true, Some(m), true) = (early, m, k > 100) {
            let at = lathe.position() as f64 + m as f64 / 65536.0;
            assert!((at - x(t)).abs() < 0.005, "t {t}: {at} against {}", x(t));
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked}");
}

/// Slowing from fast rises (133 µs apart) through the 200 µs from which the
/// acceleration counts, to a stop: the measurement never lapses on the way.
#[test]
fn a_lathe_slowing_through_the_acceleration_limit_keeps_its_measurement() {
    let (acc, v0) = (480_000e-12, 0.03);
    let stop = v0 / acc;
    let x = move |t: f64| {
        let t = t.min(stop);
        0.3 + v0 * t - 0.5 * acc * t * t
    };
    let seen = follow(&x, 1700);
    for (k, (truth, m)) in seen.iter().enumerate().skip(20) {
        let m = m.unwrap_or_else(|| panic!("tick {k}: no measurement"));
        assert!((m - truth).abs() < 0.1, "tick {k}: {m} against {truth}");
    }
}

/// The same run-down the other way: the lathe is followed down to its
/// stop and never turned back up.
#[test]
fn a_lathe_running_down_backwards_is_never_turned_back() {
    let x = running_down(-1.0);
    let seen = follow(&x, 5000);
    let measured: std::vec::Vec<(f64, f64)> = seen.iter().filter_map(|&(t, m)| m.map(|m| (t, m))).collect();
    assert!(measured.len() > 4000);
    assert!(measured.windows(2).all(|w| w[1].1 <= w[0].1 + 1e-9), "turned back");
    let worst = measured.iter().map(|(t, m)| (m - t).abs()).fold(0.0, f64::max);
    assert!(worst < 0.1, "worst {worst}");
}

/// Two rises thousands of counts apart (a count jump no lathe makes, or a
/// fast high-resolution encoder seen once a tick): no speed from them,
/// and no overflow on the way.
#[test]
fn rises_too_far_apart_give_no_speed_and_no_overflow() {
    let clock = EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false };
    let mut timer = EdgeTimer::new(clock);
    let mut lathe = Extender::new(0);
    lathe.update(1);
    assert_eq!(timer.measure(Some(EdgeRegs { count: 1, stamp: 30 }), &lathe), None);
    lathe.update(30_001);
    assert_eq!(timer.measure(Some(EdgeRegs { count: 30_001, stamp: 70 }), &lathe), None);
}

/// A slow lathe's next rise can come a whole wrap of the stamps later, at
/// the same stamp with another count: still a new pair.
#[test]
fn each_pair_of_registers_packs_to_its_own_word() {
    let a = EdgeRegs { count: 5, stamp: 700 };
    assert_ne!(packed(&a), packed(&EdgeRegs { count: 9, stamp: 700 }), "the count alone differs");
    assert_ne!(packed(&a), packed(&EdgeRegs { count: 5, stamp: 701 }), "the stamp alone differs");
    assert_ne!(packed(&EdgeRegs { count: 0xFFFF, stamp: 0xFFFF }), NONE_YET);
    assert_eq!(packed(&a), packed(&EdgeRegs { count: 5, stamp: 700 }));
}
