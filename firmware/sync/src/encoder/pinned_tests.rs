//! Fixed cases of what the property tests sample at random: the counter's
//! wrap both ways, a latch behind or ahead of the last reading across a
//! wrap, the largest tick each way, and index checks several turns apart.

use super::*;

#[test]
fn the_counter_wraps_both_ways_without_a_jump() {
    let mut e = Extender::new(65_535);
    assert_eq!(e.update(0), 1);
    assert_eq!(e.update(2), 2);
    assert_eq!(e.update(65_534), -4);
    assert_eq!(e.position(), -1);
    // the largest change a tick can show, each way
    assert_eq!(e.update(65_534u16.wrapping_add(32_767)), 32_767);
    assert_eq!(e.update(65_534), -32_767);
    assert_eq!(e.position(), -1);
}

#[test]
fn a_latched_value_is_placed_within_half_the_range_of_the_last_reading() {
    let mut e = Extender::new(65_530);
    e.update(4); // 10 counts on, across the wrap
    assert_eq!(e.position(), 10);
    assert_eq!(e.position_of(65_533), 3, "latched 7 back, before the wrap");
    assert_eq!(e.position_of(9), 15, "5 ahead");
    assert_eq!(e.position_of(4), 10);
}

#[test]
fn indexes_whole_turns_apart_are_consistent_either_way_and_after_missed_turns() {
    let mut t = IndexTracker::default();
    assert_eq!(t.reference(), None);
    assert_eq!(t.on_index(-50, 2400, 2), IndexEvent::Referenced(-50));
    assert_eq!(t.reference(), Some(-50));
    // forward one turn, back one turn, and the same edge twice (a reversal)
    assert_eq!(t.on_index(2350, 2400, 2), IndexEvent::Consistent);
    assert_eq!(t.on_index(-50, 2400, 2), IndexEvent::Consistent);
    assert_eq!(t.on_index(-50, 2400, 2), IndexEvent::Consistent);
    // three turns back with a pulse missed, 2 counts off: within the slack
    assert_eq!(t.on_index(-50 - 3 * 2400 + 2, 2400, 2), IndexEvent::Consistent);
    // the reference stays the first index
    assert_eq!(t.reference(), Some(-50));
}

#[test]
fn an_index_off_by_up_to_half_a_turn_is_a_slip_of_that_size() {
    let mut t = IndexTracker::default();
    t.on_index(0, 2400, 2);
    assert_eq!(t.on_index(2400 + 1_199, 2400, 2), IndexEvent::Slipped(1_199));
    // measured from the last index, not the reference
    assert_eq!(t.on_index(2400 + 1_199 + 2400 - 3, 2400, 2), IndexEvent::Slipped(-3));
    // exactly half a turn either way reads +E/2: offsets are taken in (−E/2, E/2]
    let mut t = IndexTracker::default();
    t.on_index(0, 2400, 2);
    assert_eq!(t.on_index(1_200, 2400, 2), IndexEvent::Slipped(1_200));
    assert_eq!(t.on_index(0, 2400, 2), IndexEvent::Slipped(1_200));
}

#[test]
fn the_index_check_is_bounded_eight_turns_forward_and_sixteen_back() {
    // (adds and compares only, a bounded number of them: an index further
    // from the last than that is not reconciled, and counts as a slip)
    let after = |turns: i64| {
        let mut t = IndexTracker::default();
        t.on_index(0, 2400, 2);
        t.on_index(turns * 2400 + 1, 2400, 2)
    };
    assert_eq!(after(8), IndexEvent::Consistent);
    assert_eq!(after(9), IndexEvent::Slipped(2401));
    assert_eq!(after(-16), IndexEvent::Consistent);
    assert_eq!(after(-17), IndexEvent::Slipped(-2399));
}
