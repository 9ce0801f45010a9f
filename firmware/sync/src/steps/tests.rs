use super::*;
use proptest::prelude::*;
use std::vec::Vec;

const T: StepTiming = StepTiming { tick_len: 4000, min_period: 500, dir_setup: 500, pulse: 250 };

/// Runs a constant-velocity command through the planner and a perfect
/// generator; returns the absolute times of all steps.
fn run(v_q16: i64, ticks: i64) -> (Vec<i64>, i64) {
    let (mut pos, mut emitted, mut dir) = (0i64, 0i64, Dir::Forward);
    let mut times = std::vec::Vec::new();
    for k in 0..ticks {
        let p = plan(pos, pos + v_q16, emitted, dir, &T);
        for i in 0..p.count as i64 {
            times.push(k * T.tick_len as i64 + p.first as i64 + i * p.period as i64);
        }
        emitted += if p.dir == Dir::Forward { p.count as i64 } else { -(p.count as i64) };
        if p.count > 0 {
            dir = p.dir;
        }
        pos += v_q16;
    }
    (times, emitted)
}

#[test]
fn steps_are_evenly_spaced_across_tick_boundaries() {
    // 1.37 steps per tick: the gaps between steps may differ by rounding only.
    let (times, emitted) = run((1.37 * 65536.0) as i64, 2000);
    assert_eq!(emitted, ((1.37 * 65536.0) as i64 * 2000 + (1 << 15)) >> 16);
    let gaps: std::vec::Vec<i64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    let ideal = 4000.0 / 1.37;
    for g in &gaps {
        assert!((*g as f64 - ideal).abs() <= 2.0, "gap {g} vs {ideal}");
    }
}

#[test]
fn slow_motion_puts_steps_at_their_half_step_crossings() {
    // 0.1 step per tick: one step every 10 ticks, at the crossing of n + 1/2.
    let (times, _) = run(6554, 100);
    for (n, t) in times.iter().enumerate() {
        let crossing = (n as f64 + 0.5) / (6554.0 / 65536.0) * 4000.0;
        assert!((*t as f64 - crossing).abs() < 8.0, "step {n} at {t}, crossing {crossing}");
    }
}

#[test]
fn a_step_that_would_fall_past_the_tick_waits_for_the_next() {
    // The half-step crossing is exactly at the tick's end: no step now.
    let p = plan(0, 1 << 15, 0, Dir::Forward, &T);
    assert_eq!(p.count, 0);
    // ...and goes out at once in the next tick.
    let q = plan(1 << 15, (1 << 15) + 100, 0, Dir::Forward, &T);
    assert_eq!((q.count, q.first), (1, 0));
}

#[test]
fn a_reversal_waits_for_the_dir_setup_time() {
    let p = plan(0, -(3 << 16), 0, Dir::Forward, &T);
    assert_eq!(p.dir, Dir::Reverse);
    assert!(p.first >= T.dir_setup);
}

proptest! {
    #[test]
    fn every_plan_fits_its_tick_and_respects_the_minimum_period(
        from in -1_000_000i64..1_000_000, dv in -600_000i64..600_000, lag in -20i64..20, rev in any::<bool>(),
    ) {
        let to = from + dv;
        let emitted = ((from + (1 << 15)) >> 16) + lag;
        let last = if rev { Dir::Reverse } else { Dir::Forward };
        let p = plan(from, to, emitted, last, &T);
        if p.count > 0 {
            prop_assert!(p.period >= T.min_period);
            prop_assert!(p.first + p.period * (p.count as u32 - 1) < T.tick_len);
            if p.dir != last { prop_assert!(p.first >= T.dir_setup); }
            let wanted = ((to + (1 << 15)) >> 16) - emitted;
            prop_assert!(p.count as i64 <= wanted.abs());
            prop_assert_eq!(p.dir == Dir::Forward, wanted > 0);
        }
    }
}
