//! The planning and the books on their own. The timer itself is checked in
//! `tests/quadgen_tim9.rs`, against the model written from RM0383.

use super::period::{IDLE, MAX_CLOCKS};
use super::program::{self, Op};
use super::*;
use std::vec::Vec;

const SELF_TEST: [Segment; 5] = [
    Segment::Ramp { from: 0, to: 300, ms: 200 },
    Segment::Hold { rpm: 300, ms: 100 },
    Segment::Hold { rpm: -300, ms: 100 },
    Segment::Ramp { from: -300, to: 0, ms: 150 },
    Segment::Hold { rpm: 0, ms: 10 },
];

fn periods(cpr: u32, segments: &[Segment]) -> Vec<Period> {
    Profile::new(cpr, segments).unwrap().periods().collect()
}

#[test]
fn max_rpm_follows_the_index_bound() {
    assert_eq!(MAX_COUNT_RATE, 12_786);
    assert_eq!(max_rpm(2400), 319);
    assert_eq!(PSC_MAX, 3);
}

#[test]
fn cpr_must_be_even_and_speed_within_the_bound() {
    assert_eq!(Profile::new(2401, &SELF_TEST).err(), Some(Error::Cpr(2401)));
    assert_eq!(Profile::new(2, &SELF_TEST).err(), Some(Error::Cpr(2)));
    let fast = [Segment::Hold { rpm: 10, ms: 1 }, Segment::Ramp { from: 0, to: -320, ms: 1 }];
    assert_eq!(Profile::new(2400, &fast).err(), Some(Error::TooFast { segment: 1, max_rpm: 319 }));
}

#[test]
fn every_period_fits_the_timer_and_the_index_bound() {
    for cpr in [4, 100, 2400, 40_000] {
        let top = max_rpm(cpr) as i32;
        let segs = [Segment::Ramp { from: -top, to: top, ms: 300 }];
        for p in periods(cpr, &segs) {
            assert!(p.psc <= PSC_MAX && p.half >= 2 && p.arr() as u32 + 1 == 2 * p.half as u32);
            if p.motion != Motion::Idle {
                assert!((p.psc as u32 + 1) * p.half as u32 >= HALF_MIN_CLOCKS, "{p:?}");
                let [first, second] = p.edge_offsets();
                assert!(first + MARGIN <= ENTRY_MIN && second >= LATENCY_MAX + MARGIN, "{p:?}");
            } else {
                assert!(p.ccr()[0] > p.arr() && p.ccr()[1] > p.arr());
            }
        }
    }
}

#[test]
fn periods_follow_the_profile_in_time_and_speed() {
    let ps = periods(2400, &SELF_TEST);
    let total: u64 = ps.iter().map(|p| p.clocks() as u64).sum();
    let want = 560 * (TIMER_HZ as u64 / 1000);
    assert!(total >= want && total < want + MAX_CLOCKS, "{total}");
    // in the hold at 300 rpm: 12 000 counts/s, two per period
    let mut t = 0u64;
    for p in &ps {
        let ms = t / 96_000;
        if (205..295).contains(&ms) {
            assert_eq!(p.motion, Motion::Forward);
            assert_eq!(p.clocks(), 16_000, "at {ms} ms");
        }
        if (305..395).contains(&ms) {
            assert_eq!(p.motion, Motion::Reverse);
        }
        if ms >= 551 {
            assert_eq!(*p, IDLE, "at {ms} ms");
        }
        t += p.clocks() as u64;
    }
}

/// Table 53, both inputs counting (SMS = 011), restated: the count of a
/// change of one input given the other's level.
fn table_53(a_changed: bool, new: bool, other: bool) -> i64 {
    match (a_changed, new, other) {
        (true, true, false) | (true, false, true) | (false, true, true) | (false, false, false) => 1,
        _ => -1,
    }
}

/// Toggles A and B in each period's compare order, decodes them, and
/// checks the books after every period.
#[test]
fn the_books_match_a_gray_code_decoding_of_the_toggles() {
    let ps = periods(2400, &SELF_TEST);
    let (mut a, mut b, mut count) = (false, false, 0i64);
    let mut ledger = Ledger::new(2400);
    for p in &ps {
        let [c1, c2] = p.ccr();
        let order = if p.motion == Motion::Idle {
            vec![]
        } else if c1 < c2 {
            vec![true, false]
        } else {
            vec![false, true]
        };
        for is_a in order {
            if is_a {
                a = !a;
                count += table_53(true, a, b);
            } else {
                b = !b;
                count += table_53(false, b, a);
            }
        }
        ledger.book(p);
        assert_eq!(ledger.position(), count);
        assert_eq!(ledger.levels(), (a, b));
    }
    assert!(ps.iter().any(|p| p.motion == Motion::Reverse));
}

#[test]
fn the_index_marks_the_same_two_counts_both_ways() {
    let cpr = 8;
    let fwd = Period::moving(10_000, Motion::Forward);
    let rev = Period::moving(10_000, Motion::Reverse);
    let mut e = Ledger::new(cpr);
    let mut latched = Vec::new();
    for p in [fwd; 12].iter().chain(&[rev; 20]) {
        if let Some(c) = e.index_count(p) {
            assert!(e.index_in(p));
            latched.push(c);
        }
        e.book(p);
    }
    // forward over 0, 8, 16 to 24; back over 16 (the same window), 8, 0, -8
    // and -16
    assert_eq!(latched, [1, 9, 17, 17, 9, 1, -7, -15]);
    assert!(!e.index_in(&IDLE));
}

fn generator(segs: &[Segment]) -> (Generator<Periods<&[Segment]>>, [Op; 15]) {
    let profile = Profile::new(2400, segs).unwrap();
    Generator::start(&profile, profile.periods()).unwrap()
}

#[test]
fn the_interrupt_writes_the_index_first_then_the_next_period() {
    let segs = [Segment::Hold { rpm: 300, ms: 1 }];
    let (mut gen, init) = generator(&segs);
    let ps = periods(2400, &segs);
    assert_eq!(init[4..8], program::next(&ps[0]));
    let ops = gen.on_update();
    assert_eq!(ops[0], program::index(true)); // period 0 crosses [0, 2]
    assert_eq!(ops[1], program::CLEAR_FLAGS);
    assert_eq!(ops[2..], program::next(&ps[1]));
    assert_eq!(gen.on_update()[0], program::index(false));
}

#[test]
fn the_last_period_is_followed_by_a_stop_and_both_outputs_end_low() {
    // 5 periods of 2 counts: ends on 10 ≡ 2 (mod 4), A = B = 1: one more
    let segs = [Segment::Hold { rpm: 250, ms: 1 }];
    let n = periods(2400, &segs).len();
    assert_eq!(n % 2, 1);
    let (mut gen, _) = generator(&segs);
    let mut updates = 0;
    while gen.running() {
        let ops = gen.on_update();
        updates += 1;
        if ops.contains(&program::FINISH) {
            // booked: the n periods and the extra one, which runs now
            assert_eq!(gen.ledger().updates(), n as u64 + 1);
        }
        assert!(updates < 100);
    }
    assert_eq!(gen.ledger().updates(), n as u64 + 1);
    assert_eq!(gen.ledger().position(), 2 * (n as i64 + 1));
    assert_eq!(gen.ledger().levels(), (false, false));
    assert_eq!(gen.on_update()[..], [program::CLEAR_FLAGS]);
}

#[test]
fn init_loads_the_first_period_with_the_outputs_low_and_starts_last() {
    let (_, init) = generator(&SELF_TEST);
    let at = |op: Op| init.iter().position(|o| *o == op).unwrap();
    let first = periods(2400, &SELF_TEST)[0];
    let ug = at(Op::Write(program::EGR, 1));
    assert!(at(Op::Write(program::CCMR1, program::CCMR1_LOW)) < ug);
    assert!(ug < at(Op::Write(program::CNT, first.arr() as u32)));
    assert!(ug < at(Op::Write(program::CCMR1, program::CCMR1_TOGGLE)));
    assert_eq!(init[14], Op::Write(program::CR1, 0x85));
}
