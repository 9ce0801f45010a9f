use super::*;
use proptest::prelude::*;
use std::vec::Vec;

const T: StepTiming = StepTiming { tick_len: 4000, min_period: 500, dir_setup: 500, pulse: 250 };

/// Runs a constant-velocity command through the planner and a perfect
/// generator; returns the absolute times of all steps.
fn run(v_q16: i64, ticks: i64) -> (Vec<i64>, i64) {
    let (mut pos, mut emitted, mut prev) = (0i64, 0i64, Prev::idle(Dir::Forward));
    let mut times = std::vec::Vec::new();
    for k in 0..ticks {
        let p = plan(pos, pos + v_q16, emitted, &prev, &T);
        prev = prev.after(&p, &T);
        for i in 0..p.count as i64 {
            times.push(k * T.tick_len as i64 + p.at(i as u32) as i64);
        }
        emitted += if p.dir == Dir::Forward { p.count as i64 } else { -(p.count as i64) };
        pos += v_q16;
    }
    (times, emitted)
}

#[test]
fn steps_are_evenly_spaced_across_tick_boundaries() {
    // 1.37 and 4.94 steps per tick: every step within half a timer tick
    // (and a little for the 1/256 fraction) of its exact instant, so gaps
    // differ from the ideal by at most one tick
    // (523 974 Q16 steps: a period of 500.3 ticks, just over min_period)
    for v in [(1.37 * 65536.0) as i64, (4.94 * 65536.0) as i64, 523_974] {
        let (times, emitted) = run(v, 2000);
        assert_eq!(emitted, (v * 2000 + (1 << 15)) >> 16);
        for (n, t) in times.iter().enumerate() {
            let exact = ((n as f64 + 0.5) * 65536.0) / v as f64 * 4000.0;
            assert!((*t as f64 - exact).abs() <= 0.55, "step {n} at {t}, exact {exact}");
        }
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
    let p = plan(0, 1 << 15, 0, &Prev::idle(Dir::Forward), &T);
    assert_eq!(p.count, 0);
    // ...and goes out at once in the next tick.
    let q = plan(1 << 15, (1 << 15) + 100, 0, &Prev::idle(Dir::Forward), &T);
    assert_eq!((q.count, q.first), (1, 0));
}

#[test]
fn a_reversal_waits_for_the_dir_setup_time() {
    let p = plan(0, -(3 << 16), 0, &Prev::idle(Dir::Forward), &T);
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
        let p = plan(from, to, emitted, &Prev::idle(last), &T);
        if p.count > 0 {
            prop_assert!(p.period >= T.min_period);
            prop_assert!(p.at(p.count as u32 - 1) <= T.tick_len);
            if p.dir != last { prop_assert!(p.first >= T.dir_setup); }
            let wanted = ((to + (1 << 15)) >> 16) - emitted;
            prop_assert!(p.count as i64 <= wanted.abs());
            prop_assert_eq!(p.dir == Dir::Forward, wanted > 0);
        }
    }
}

/// The step after a tick boundary keeps the minimum spacing from the last
/// step of the tick before (a late plan started at once would put it 30
/// timer cycles after the previous pulse).
#[test]
fn a_late_step_keeps_its_spacing_from_the_previous_tick() {
    // the previous tick's last step rose 100 ticks before this tick began
    let prev = Prev { dir: Dir::Forward, rise: -100, end: -100 + T.pulse as i32, dir_since: FAR };
    // two steps behind and standing: the late path would put the first at 0
    let p = plan(0, 0, -2, &prev, &T);
    assert_eq!(p.count, 2);
    assert_eq!(p.first, T.min_period - 100, "first step {} ticks after the previous", p.first + 100);
}

/// A reversal waits for DIR's setup time after the last pulse has ended
/// (DIR changes only while STEP is low), even when that pulse was in the
/// tick before.
#[test]
fn a_reversal_after_a_step_near_the_boundary_waits_setup_after_its_end() {
    let prev = Prev { dir: Dir::Forward, rise: -50, end: -50 + T.pulse as i32, dir_since: FAR };
    // fast enough that its first crossing (250) comes before DIR is ready
    let p = plan(0, -(8 << 16), 0, &prev, &T);
    assert_eq!(p.dir, Dir::Reverse);
    assert_eq!(p.first as i32, prev.end + T.dir_setup as i32);
}

/// The first step lands exactly on its half-step crossing: at 1/8 step
/// per 500 ticks from 3/8, the crossing of 1/2 is 500 ticks in.
#[test]
fn the_first_step_lands_on_its_half_step_crossing() {
    let from = 3 << 13; // 3/8 step
    let to = from + (1 << 16); // one step per tick: 4000 ticks per step
    let p = plan(from, to, 0, &Prev::idle(Dir::Forward), &T);
    assert_eq!((p.count, p.at(0), p.period), (1, 500, 4000));
    // backwards from -3/8: the crossing of -1/2 is 500 ticks in as well
    let q = plan(-from, -to, 0, &Prev::idle(Dir::Reverse), &T);
    assert_eq!((q.count, q.dir, q.at(0)), (1, Dir::Reverse, 500));
}

/// Seen from the next tick, the last step of a plan moves back a tick; a
/// tick whose last pulse ends at least a pulse before its end, and an empty
/// tick, are filled to their end, so DIR may change at the boundary; a
/// pulse ending closer to it is where DIR may change.
#[test]
fn prev_after_a_plan_and_after_an_empty_tick() {
    let p = StepPlan { count: 3, dir: Dir::Reverse, first: 100, period: 1000, ..StepPlan::default() };
    let a = Prev::idle(Dir::Forward).after(&p, &T);
    assert_eq!(a, Prev { dir: Dir::Reverse, rise: 2100 - 4000, end: 0, dir_since: -4000 });
    // a pulse ending 1 cycle less than a pulse before the boundary: not filled
    let late = StepPlan { count: 1, dir: Dir::Reverse, first: 4000 - 2 * 250 + 1, ..StepPlan::default() };
    assert_eq!(Prev::idle(Dir::Reverse).after(&late, &T).end, -250 + 1);
    let filled = StepPlan { first: 4000 - 2 * 250, ..late };
    assert_eq!(Prev::idle(Dir::Reverse).after(&filled, &T).end, 0);
    let b = a.after(&StepPlan { dir: Dir::Reverse, ..StepPlan::default() }, &T);
    assert_eq!(b, Prev { dir: Dir::Reverse, rise: 2100 - 8000, end: 0, dir_since: -8000 });
    assert_eq!(Prev::idle(Dir::Forward).after(&StepPlan::default(), &T).rise, FAR);
}

proptest! {
    /// Across tick boundaries too: every rising edge at least min_period
    /// after the one before, DIR never changing while STEP is high, and a
    /// step in a new direction at least dir_setup after DIR changed, whatever
    /// the command does. DIR changes where the step output puts it: at the
    /// start of the first tick whose plan has the new direction, from where
    /// the tick before left off (`Prev::end`: the last pulse's end, or the
    /// boundary when silence fills the tick).
    #[test]
    fn spacing_and_dir_setup_hold_across_ticks(moves in proptest::collection::vec(-300_000i64..300_000, 1..200)) {
        let (mut pos, mut emitted, mut prev) = (0i64, 0i64, Prev::idle(Dir::Forward));
        let (mut last_rise, mut last_end) = (i64::MIN / 2, i64::MIN / 2);
        let (mut dir, mut dir_at, mut stepped_since) = (Dir::Forward, i64::MIN / 2, true);
        for (k, dv) in moves.iter().enumerate() {
            let p = plan(pos, pos + dv, emitted, &prev, &T);
            let t0 = k as i64 * T.tick_len as i64;
            if p.dir != dir {
                (dir, dir_at, stepped_since) = (p.dir, t0 + prev.end as i64, false);
                prop_assert!(dir_at >= last_end, "DIR changed {} before the pulse ended", last_end - dir_at);
            }
            prev = prev.after(&p, &T);
            for i in 0..p.count as i64 {
                let rise = t0 + p.at(i as u32) as i64;
                prop_assert!(rise - last_rise >= T.min_period as i64, "spacing {} at tick {k}", rise - last_rise);
                if !stepped_since {
                    prop_assert!(rise - dir_at >= T.dir_setup as i64, "setup {} at tick {k}", rise - dir_at);
                    stepped_since = true;
                }
                last_rise = rise;
                last_end = rise + T.pulse as i64;
            }
            emitted += if p.dir == Dir::Forward { p.count as i64 } else { -(p.count as i64) };
            pos += dv;
        }
    }
}

/// Backwards from step 5: the first crossing (of 4½) is where it belongs
/// (the reverse boundary arithmetic with a non-zero count).
#[test]
fn a_reverse_step_from_a_later_position_lands_on_its_crossing() {
    let from = (5 << 16) - (1 << 13); // 4⅞ steps
    let p = plan(from, from - (1 << 16), 5, &Prev::idle(Dir::Reverse), &T);
    // 4⅞ → 4½ is ⅜ of a step at one step per tick: 1500 ticks in
    assert_eq!((p.count, p.dir, p.at(0)), (1, Dir::Reverse, 1500));
}

/// A DIR setup longer than a tick puts the reversal off by whole ticks.
#[test]
fn a_dir_setup_longer_than_a_tick_delays_the_reversal() {
    let t = StepTiming { dir_setup: 5_000, ..T };
    let prev = Prev { dir: Dir::Forward, rise: -300, end: -50, dir_since: FAR };
    // nothing fits, but DIR turns now, at the end of the last pulse
    let p = plan(0, -(1 << 16), 0, &prev, &t);
    assert_eq!((p.count, p.dir), (0, Dir::Reverse));
    let next = prev.after(&p, &t);
    // 5000 cycles after the pulse's end: 950 into the next tick
    let q = plan(0, -(8 << 16), 0, &next, &t);
    assert_eq!((q.count, q.dir, q.at(0)), (7, Dir::Reverse, 950));
}

/// A step due at the tick's last cycle goes out in this tick.
#[test]
fn a_step_due_at_the_last_cycle_is_not_put_off() {
    // one step per tick; from −0.49975 steps the crossing of ½ is 3999 in
    let from = -32_752;
    let p = plan(from, from + (1 << 16), 0, &Prev::idle(Dir::Forward), &T);
    assert_eq!((p.count, p.at(0)), (1, 3_999));
}

/// Catching up spreads the steps behind evenly over the tick.
#[test]
fn catching_up_spreads_the_missing_steps_over_the_tick() {
    let p = plan(0, 0, -2, &Prev::idle(Dir::Forward), &T);
    assert_eq!((p.count, p.first, p.period), (2, 0, 4_000 / 3));
}

/// A reversal that must wait late into the tick emits what fits before
/// its end, and never lets the fractions carry a step past it.
#[test]
fn a_late_reversal_emits_only_what_fits() {
    let t = StepTiming { dir_setup: 2_999, ..T };
    let prev = Prev { dir: Dir::Forward, rise: -250, end: 0, dir_since: FAR };
    // eight steps a tick backwards: period 500.9 ticks
    let p = plan(0, -523_346, 0, &prev, &t);
    assert_eq!((p.dir, p.first, p.period), (Dir::Reverse, 2_999, 500));
    assert!(p.frac > 200);
    // three whole periods fit after 2999; with the fraction the third
    // would rise at 4001
    assert_eq!(p.count, 2);
    assert!(p.at(1) <= t.tick_len);
    // and a slower one: after a late first, the rest wait for the next tick
    let t = StepTiming { dir_setup: 3_000, ..T };
    let p = plan(0, -3 << 16, 0, &prev, &t);
    assert_eq!((p.count, p.at(0), p.period), (1, 3_000, 4_000 / 3));
}

#[test]
fn q8_ratios_round_to_the_nearest_256th() {
    assert_eq!(q8_ratio(1, 3), (0, 85));
    assert_eq!(q8_ratio(2, 3), (0, 171));
    assert_eq!(q8_ratio(255, 256), (0, 255));
    assert_eq!(q8_ratio(511, 512), (1, 0));
    assert_eq!(q8_ratio(7, 2), (3, 128));
}

#[test]
fn a_tick_without_steps_leaves_dir_where_it_was() {
    let prev = Prev::idle(Dir::Reverse);
    let p = plan(-(3 << 16), -(3 << 16), -3, &prev, &T);
    assert_eq!((p.count, p.dir), (0, Dir::Reverse));
}

#[test]
fn a_step_allowed_only_at_the_last_cycle_still_goes() {
    let t = StepTiming { dir_setup: 3_999, ..T };
    let prev = Prev { dir: Dir::Forward, rise: -300, end: 0, dir_since: FAR };
    let p = plan(0, -(8 << 16), 0, &prev, &t);
    assert_eq!((p.count, p.dir, p.at(0)), (1, Dir::Reverse, 3_999));
}

#[test]
fn catching_up_after_a_late_first_step_fits_the_rest_before_the_tick_ends() {
    // twenty steps behind, the first allowed at 2000: ten would fit at the
    // shortest period, so they are spread at 4000/11; six of those fit
    let t = StepTiming { tick_len: 4_000, min_period: 200, dir_setup: 2_000, pulse: 100 };
    let prev = Prev { dir: Dir::Reverse, rise: -100, end: 0, dir_since: FAR };
    let p = plan(0, 0, -20, &prev, &t);
    assert_eq!((p.count, p.dir, p.first, p.period), (6, Dir::Forward, 2_000, 363));
}
