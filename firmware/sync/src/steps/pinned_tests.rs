//! Fixed cases of the planner's limits that the property tests reach only
//! by chance: the most steps a tick holds, forward and after a reversal.

use super::*;

const T: StepTiming = StepTiming { tick_len: 4000, min_period: 500, dir_setup: 500, pulse: 250 };

#[test]
fn a_tick_holds_at_most_one_step_per_min_period_from_the_first() {
    // 20 steps wanted in a tick: the first at its crossing (½ step of 20
    // is 1/40 of the tick: 100), then every 500: 100 ... 3600, the ninth
    // would rise at 4100
    for dir in [1i64, -1] {
        let last = if dir > 0 { Dir::Forward } else { Dir::Reverse };
        let p = plan(0, dir * (20 << 16), 0, &Prev::idle(last), &T);
        assert_eq!((p.count, p.dir, p.first, p.period, p.frac), (8, last, 100, 500, 0), "{dir}");
        assert_eq!(p.at(7), 3_600);
    }
}

#[test]
fn after_a_reversal_the_tick_holds_one_step_fewer() {
    // DIR turns at the tick's start: the first step waits 500, then
    // 500 ... 3500; the eighth would rise at 4000, past the last cycle (3999)
    let p = plan(0, -(20 << 16), 0, &Prev::idle(Dir::Forward), &T);
    assert_eq!((p.count, p.dir, p.first, p.period), (7, Dir::Reverse, 500, 500));
    assert_eq!(p.at(6), 3_500);
}
