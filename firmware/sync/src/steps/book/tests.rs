//! The X axis's step books: pulses count the way of the plan that asked
//! for them, from the counter's value at `start`; `hold` is where the next
//! plan starts from.

use super::*;
use crate::config::Config;
use crate::derived::Derived;
use crate::timing::Timing;

fn timing() -> StepTiming {
    Derived::new(&Config::default(), Timing::FIRMWARE).steps
}

#[test]
fn pulses_after_a_reverse_plan_count_backwards() {
    let t = timing();
    let mut b = StepBook::default();
    let p = b.plan(-3 << 16, &t);
    assert_eq!((p.count, p.dir), (3, Dir::Reverse));
    assert_eq!(b.read(3), -3);
    // and forward again
    let p = b.plan(-1 << 16, &t);
    assert_eq!((p.count, p.dir), (2, Dir::Forward));
    assert_eq!(b.read(5), -1);
    assert_eq!(b.emitted(), -1);
}

#[test]
fn steps_not_emitted_are_planned_again() {
    let t = timing();
    let mut b = StepBook::default();
    assert_eq!(b.plan(4 << 16, &t).count, 4);
    assert_eq!(b.read(1), 1, "only one went out");
    assert_eq!(b.plan(4 << 16, &t).count, 3);
}

#[test]
fn the_books_count_from_the_counter_as_it_stands_at_start() {
    let mut b = StepBook::default();
    b.start(500);
    assert_eq!(b.read(500), 0);
    assert_eq!(b.read(502), 2);
    assert_eq!(b.emitted(), 2);
}

#[test]
fn after_a_hold_the_next_step_falls_at_its_half_step_crossing_from_there() {
    let t = timing();
    let timing = Timing::FIRMWARE;
    assert_eq!(t.tick_len, timing.step_timer_hz / timing.tick_hz, "a tick's timer cycles");
    let mut b = StepBook::default();
    // out to 10.4 steps: 10 steps made
    assert_eq!(b.plan(681_574, &t).count, 10);
    assert_eq!(b.read(10), 10);
    // held on the 10 steps made; then one step a tick from there: the
    // crossing of 10½ is half way through the tick
    b.hold(10 << 16);
    let p = b.plan(11 << 16, &t);
    assert_eq!((p.count, p.at(0)), (1, t.tick_len / 2));
}
