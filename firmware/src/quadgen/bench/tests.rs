//! The glue between the judge's plan and the generator.

use super::*;
use crate::quadgen::{max_rpm, program, MAX_COUNT_RATE};
use polyturn_sync::selftest::{generator_max_rpm, GENERATOR_MAX_COUNT_RATE};

#[test]
fn the_judge_knows_the_generators_speed_limit() {
    assert_eq!(GENERATOR_MAX_COUNT_RATE, MAX_COUNT_RATE);
    for cpr in [4, 100, 1000, 2400, 4096, 65_534] {
        assert_eq!(generator_max_rpm(cpr), max_rpm(cpr), "{cpr}");
    }
}

#[test]
fn every_plan_the_judge_allows_the_generator_plays() {
    for cpr in [4, 2400, 10_000, 65_534] {
        let rpm = generator_max_rpm(cpr);
        let plan = Plan::new(rpm, cpr, 1_000);
        assert!(start(&plan).is_some(), "{cpr} at {rpm}");
        let too_fast = Plan::new(rpm + 1, cpr, 1_000);
        assert!(start(&too_fast).is_none(), "{cpr} at {}", rpm + 1);
    }
    assert!(start(&Plan::new(10, 2401, 1_000)).is_none(), "odd cpr");
}

#[test]
fn each_leg_is_one_segment_and_a_rest_is_a_hold_at_zero() {
    let plan = Plan::new(300, 2400, 1_500);
    let segs = segments(&plan);
    assert_eq!(segs[0], Segment::Hold { rpm: 0, ms: 2_000 });
    assert_eq!(segs[1], Segment::Ramp { from: 0, to: 300, ms: 1_500 });
    assert_eq!(segs[2], Segment::Hold { rpm: 300, ms: 2_000 });
    assert_eq!(segs[5], Segment::Ramp { from: 0, to: -300, ms: 1_500 });
    assert_eq!(segs[8], Segment::Hold { rpm: 0, ms: 600 });
}

/// Plays a whole plan through the interrupt's work: the books end where
/// they began (forward and back the same), with the plan's length in
/// TIM9's clock, and then say the generator has stopped.
#[test]
fn the_books_of_a_whole_plan_come_back_to_zero_and_end_stopped() {
    let plan = Plan::new(300, 2400, 1_000);
    let (mut g, _) = start(&plan).unwrap();
    let (mut max, mut indexes) = (0i64, 0u32);
    let mut rest2 = None;
    while g.running() {
        let p = g.current();
        indexes += g.ledger().index_in(&p) as u32;
        assert_eq!(g.index_op(), g.on_update()[0], "the handler's first write is on_update's");
        let b = books(&g);
        max = max.max(b.counts);
        if b.ms >= plan.end_of(4) - 100 && rest2.is_none() {
            rest2 = Some(b);
        }
    }
    let end = books(&g);
    assert!(!end.running);
    assert_eq!(end.counts, 0, "back where it started");
    assert_eq!(end.indexes, indexes);
    assert!(end.ms.abs_diff(plan.total_ms()) <= 1, "{} ms", end.ms);
    // at the second rest: all of the forward run, none of the backward
    let rest2 = rest2.unwrap();
    assert_eq!(rest2.counts, max);
    assert_eq!(rest2.indexes * 2, end.indexes);
    assert_eq!(g.index_op(), program::index(false));
}

/// The handler prepares the next update's work after its writes; a
/// generator that is never prepared computes it on the spot: both give
/// the same writes at every update event, so preparing moves work, not
/// results.
#[test]
fn preparing_ahead_changes_no_write() {
    let plan = Plan::new(super::super::max_rpm(2400), 2400, 1_000);
    let (mut ahead, _) = start(&plan).unwrap();
    let (mut late, _) = start(&plan).unwrap();
    let mut updates = 0;
    while ahead.running() {
        assert_eq!(ahead.index_op(), late.index_op());
        assert_eq!(ahead.on_update(), late.on_update(), "update {updates}");
        ahead.prepare();
        updates += 1;
    }
    assert!(!late.running());
    assert!(updates > 10_000, "{updates}");
}
