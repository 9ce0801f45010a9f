//! The check at its edges: a jump is more than the lathe can turn; the
//! proposed cpr is the rounded mean of gaps that agree within one count
//! (and are not zero); the hands-off window includes its last tick.

use super::*;
use std::vec::Vec;

/// Drives a check from rest through index edges latched at `at` (counts,
/// increasing), one tick a count: returns the report.
fn indexes_at(at: &[i64]) -> EncoderReport {
    let mut s = Sample::default();
    let mut check = EncoderCheck::new(s, 0, 100);
    for &edge in at {
        while s.counts < edge {
            s.counts += 1;
            s.ticks += 1;
            check.sample(s);
        }
        s.ticks += 1;
        s.indexes = s.indexes.wrapping_add(1);
        s.last_index = edge;
        check.sample(s);
    }
    check.report()
}

/// Index edges from 10, `gaps` apart.
fn gaps(gaps: &[i64]) -> EncoderReport {
    let mut at: Vec<i64> = std::vec![10];
    for g in gaps {
        at.push(at[at.len() - 1] + g);
    }
    let r = indexes_at(&at);
    assert_eq!(r.indexes as usize, gaps.len() + 1);
    r
}

#[test]
fn gaps_a_count_apart_propose_their_mean_rounded_half_up() {
    // 1000.5 → 1001; 1000.67 → 1001 (truncating would give 1000)
    assert_eq!(gaps(&[1_000, 1_001]).cpr, Some(1_001));
    assert_eq!(gaps(&[1_000, 1_001, 1_001]).cpr, Some(1_001));
    // 1000.33 → 1000; 1000.25 → 1000 (four gaps: half of n is 2)
    assert_eq!(gaps(&[1_000, 1_000, 1_001]).cpr, Some(1_000));
    assert_eq!(gaps(&[1_000, 1_000, 1_000, 1_001]).cpr, Some(1_000));
    assert_eq!(gaps(&[1_001, 1_000, 1_001, 1_001]).cpr, Some(1_001));
}

#[test]
fn gaps_two_counts_apart_propose_nothing() {
    let r = gaps(&[1_000, 1_002]);
    assert_eq!((r.gap, r.cpr), (Some((2, 1_000, 1_002)), None));
}

#[test]
fn index_edges_with_no_motion_between_propose_nothing() {
    // noise on the index line, the chuck still: gaps of zero counts
    let r = indexes_at(&[500, 500, 500]);
    assert_eq!((r.gap, r.cpr), (Some((2, 0, 0)), None));
}

#[test]
fn the_hands_off_window_includes_its_last_tick() {
    let mut s = Sample::default();
    let mut check = EncoderCheck::new(s, 100, 100);
    (s.ticks, s.counts) = (100, 3);
    check.sample(s);
    let r = check.report();
    assert_eq!((r.still_done, r.chatter, r.moved), (false, 3, 0));
    (s.ticks, s.counts) = (101, 5);
    check.sample(s);
    let r = check.report();
    assert_eq!((r.still_done, r.chatter, r.moved), (true, 3, 2));
}

#[test]
fn a_sample_moving_the_most_the_lathe_can_is_no_jump_and_a_count_more_is() {
    // at most 100 counts a tick: 200 in two ticks is a lathe, 101 in one is not
    let mut check = EncoderCheck::new(Sample::default(), 0, 100);
    check.sample(Sample { ticks: 2, counts: 200, ..Sample::default() });
    assert_eq!(check.report().jumps, 0);
    check.sample(Sample { ticks: 3, counts: 99, ..Sample::default() });
    assert_eq!(check.report().jumps, 1);
}
