use super::*;
use std::vec;
use std::vec::Vec;

const CPR: i64 = 2400;
/// the board's ticks a millisecond
const MS: u64 = crate::Timing::FIRMWARE.tick_hz as u64 / 1_000;

/// A hand-turned lathe: position (counts) at each millisecond, and an
/// index latched at every multiple of `cpr` the count crosses upward (the
/// capture's rising edge), fed to a check sampled every millisecond.
fn turn(path: &[i64], cpr: i64) -> EncoderReport {
    turn_counting(path, path, cpr)
}

/// As `turn`, with the shaft at `shaft` (it makes the index) and the
/// counter at `counts` (it may miss some).
fn turn_counting(shaft: &[i64], counts: &[i64], cpr: i64) -> EncoderReport {
    let mut s = Sample::default();
    let mut check = EncoderCheck::new(s, 1_000 * MS, 100);
    let mut was = 0;
    for (ms, (&at, &count)) in shaft.iter().zip(counts).enumerate() {
        if (was + 1..=at).any(|c| c.rem_euclid(cpr) == 17) {
            s.indexes = s.indexes.wrapping_add(1);
            s.last_index = count;
        }
        was = at;
        s.counts = count;
        s.ticks = (ms as u64 + 1) * MS;
        check.sample(s);
    }
    check.report()
}

/// Still for a second, then `turns` at a steady hand speed (3 s a turn).
fn steady(turns: i64, cpr: i64) -> Vec<i64> {
    let mut p = vec![0; 1_000];
    p.extend((1..=3_000 * turns).map(|ms| ms * cpr / 3_000));
    p
}

#[test]
fn three_turns_measure_the_real_cpr_and_propose_it() {
    // a "1024-line" encoder that is really 1000 lines: 4000 counts
    let r = turn(&steady(3, 4_000), 4_000);
    assert_eq!(r.cpr, Some(4_000));
    assert_eq!(r.gap, Some((2, 4_000, 4_000)));
    assert_eq!((r.moved, r.backward, r.jumps, r.chatter, r.indexes), (12_000, 0, 0, 0, 3));
    assert!(r.still_done);
}

#[test]
fn one_turn_is_not_enough_to_propose() {
    let r = turn(&steady(1, CPR), CPR);
    assert_eq!((r.indexes, r.gap, r.cpr), (1, None, None));
    let r = turn(&steady(2, CPR), CPR);
    assert_eq!((r.gap, r.cpr), (Some((1, CPR, CPR)), None));
}

#[test]
fn turning_backwards_shows_as_negative_motion_with_the_same_cpr() {
    let path: Vec<i64> = steady(3, CPR).iter().map(|c| -c).collect();
    // (indexes latched going down: the same edge every turn)
    let mut s = Sample::default();
    let mut check = EncoderCheck::new(s, 1_000 * MS, 100);
    for (ms, &at) in path.iter().enumerate() {
        for c in (at..s.counts).rev() {
            if c.rem_euclid(CPR) == 17 {
                s.indexes += 1;
                s.last_index = c;
            }
        }
        s.counts = at;
        s.ticks = (ms as u64 + 1) * MS;
        check.sample(s);
    }
    let r = check.report();
    assert_eq!((r.moved, r.backward, r.cpr), (-3 * CPR, 0, Some(CPR as u32)));
}

#[test]
fn lost_counts_spread_the_gaps_and_nothing_is_proposed() {
    // the counter misses 5 counts in the second turn (it stands still
    // while the shaft turns on)
    let shaft = steady(3, CPR);
    let mut counts = shaft.clone();
    for i in 1_000 + 4_000..counts.len() {
        counts[i] = (counts[i] - 5).max(counts[i - 1]);
    }
    let r = turn_counting(&shaft, &counts, CPR);
    assert_eq!(r.gap, Some((2, CPR - 5, CPR)));
    assert_eq!(r.cpr, None);
}

#[test]
fn counts_at_rest_are_chatter_and_backward_motion_is_counted() {
    let mut p: Vec<i64> = (0..1_000).map(|ms| (ms / 10) % 2).collect(); // rocking on an edge
    p.extend((1..=100).map(|ms| ms * 10)); // forward 1000
    p.extend((1..=30).map(|ms| 1_000 - ms)); // back 30
    let r = turn(&p, CPR);
    assert_eq!(r.chatter, 99);
    assert_eq!((r.moved, r.backward), (1_000 - 30 - 1, 30));
}

#[test]
fn a_jump_the_lathe_cannot_make_is_counted() {
    let mut p = steady(1, CPR);
    p.push(p[p.len() - 1] + 5_000);
    let r = turn(&p, CPR);
    assert_eq!(r.jumps, 1);
}

#[test]
fn a_reversal_between_indexes_is_no_revolution() {
    // forward past two indexes, back over half a turn, forward again
    let mut p = steady(2, CPR);
    let end = *p.last().unwrap();
    p.extend((1..=600).map(|ms| end - ms * 2));
    let low = *p.last().unwrap();
    p.extend((1..=3_000).map(|ms| low + ms * 2));
    let r = turn(&p, CPR);
    assert!(r.skipped >= 1, "{r:?}");
    assert_eq!(r.gap.map(|g| (g.1, g.2)), Some((CPR, CPR)));
}
