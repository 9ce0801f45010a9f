//! Engaging drops the whole cutter turns the gear is ahead of the cutter
//! (they cut the same section: one cutter turn turns it by 2π/GR, and
//! N/GR is whole), so the cutter catches up at most half a turn, the
//! nearest way, and the offset is exactly whole turns of M steps.

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;
use crate::gear::Scale;

/// 3200 steps a turn and 8/3 steps a count (the defaults): half a cutter
/// turn is 600 lathe counts exactly.
const M: i64 = 3_200;

/// Turns the lathe `counts` while idle, lets it come to rest, engages and
/// waits for synchronism: the turns dropped (steps) and the steps the
/// cutter made to get there.
fn engage_after(counts: i64) -> (i64, i64) {
    let mut r = Rig::new(Config::default());
    let speed = if counts >= 0 { per_tick(1.0) } else { -per_tick(1.0) };
    r.run(speed, counts.unsigned_abs() as usize);
    r.run(0, 1_000);
    assert_eq!(r.c.status().target_steps, Scale::round(r.c.derived().scale, counts));
    r.c.engage().unwrap();
    r.until(0, 50_000, |c| c.state() == State::Synced);
    r.run(0, 100);
    (r.c.turn_offset_steps(), r.cutter_net)
}

#[test]
fn engaging_half_a_turn_behind_or_less_drops_nothing() {
    // 599 counts: 1597.3 steps, 1597 (under half a turn)
    assert_eq!(engage_after(599), (0, 1_597));
    assert_eq!(engage_after(-599), (0, -1_597));
}

#[test]
fn engaging_exactly_half_a_turn_behind_drops_a_turn_away_from_zero() {
    // 600 counts: 1600 steps, half a turn: rounds away from zero, so the
    // cutter goes half a turn back instead of forward
    assert_eq!(engage_after(600), (-M, 1_600 - M));
    assert_eq!(engage_after(-600), (M, M - 1_600));
}

#[test]
fn engaging_many_turns_behind_catches_up_only_the_nearest_fraction() {
    // 10 000 counts: 26 666.7 steps, 26 667: 8.33 turns, 8 dropped
    assert_eq!(engage_after(10_000), (-8 * M, 26_667 - 8 * M));
    // 11 000 counts: 29 333.3, 29 333 steps: 9.17 turns, 9 dropped
    assert_eq!(engage_after(-11_000), (9 * M, 9 * M - 29_333));
}

#[test]
fn engaging_again_counts_the_turns_from_where_the_cutter_stands() {
    // engaged 10 000 counts on (8 turns dropped, the cutter at 26 667 −
    // 25 600 = 1067), stopped; the lathe turns 5 000 counts more: the gear
    // says 40 000 steps, 14 400 after the turns dropped, 13 333 ahead of
    // the cutter: 4.17 turns, 4 more dropped, 533 steps to go
    let mut r = Rig::new(Config::default());
    r.run(per_tick(1.0), 10_000);
    r.run(0, 1_000);
    r.c.engage().unwrap();
    r.until(0, 50_000, |c| c.state() == State::Synced);
    r.c.disengage();
    r.until(0, 50_000, |c| c.state() == State::Idle);
    r.run(0, 100);
    let before = r.cutter_net;
    assert_eq!(before, 26_667 - 8 * M);
    r.run(per_tick(1.0), 5_000);
    r.run(0, 1_000);
    r.c.engage().unwrap();
    // at once, before a tick: the phase error shown is what is left to go
    assert_eq!(r.c.status().phase_error_q16 >> 16, 40_000 - 12 * M - before);
    r.until(0, 50_000, |c| c.state() == State::Synced);
    r.run(0, 100);
    assert_eq!(r.c.turn_offset_steps(), -12 * M);
    assert_eq!(r.cutter_net, 40_000 - 12 * M);
}
