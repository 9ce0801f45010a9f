//! The start's measurements (`start`) against the scripted bus of `tests`.

use super::start::{self, low_low, start_tick, PARITY_TRIES, STAMP_CYCLES, TICK_CYCLES, TICK_REWIND, TICK_START};
use super::tests::{Script, CNT3, CNT5};
use super::*;
use polyturn_sync::edges::EdgeClock;

#[test]
fn the_low_low_count_is_read_with_the_count_still_and_the_pins_waited_for() {
    // count 10 in state (1, 0): k0 = 9
    let idr = 1 << A_PIN;
    let mut bus = Script::default().with(CNT3, &[10]).with(GPIOA_IDR, &[idr]);
    assert_eq!(low_low(&mut bus), Some(9));
    let waits: Vec<u32> = bus.log.iter().filter(|l| l.0 == 'd').map(|l| l.2).collect();
    assert_eq!(waits, [start::FILTER_WAIT_CYCLES; 2]);
    // the count moves during the first try: the second is taken
    let mut moving = Script::default().with(CNT3, &[10, 11, 11, 11, 11, 11]).with(GPIOA_IDR, &[idr, 3 << A_PIN]);
    assert_eq!(low_low(&mut moving), Some(9), "11 in (1, 1)");
    // pins that differ between the two reads: another try
    let mut bounce = Script::default().with(CNT3, &[4]).with(GPIOA_IDR, &[1 << B_PIN, 0, 0, 0]);
    assert_eq!(low_low(&mut bounce), Some(4));
    assert_eq!(bounce.reads_of(GPIOA_IDR), 4);
}

#[test]
fn the_places_are_table_53s_and_give_the_cores_parity() {
    let states = [(false, false), (true, false), (true, true), (false, true)];
    for count in [0u16, 1, 2, 7, 0xFFFF] {
        for (i, &(a, b)) in states.iter().enumerate() {
            assert_eq!(start::place((a, b)), i as u16);
            let k0 = count.wrapping_sub(i as u16);
            assert_eq!(start::clock(0, k0).low_low_odd, EdgeClock::low_low_odd(count, a, b), "{count} {a} {b}");
        }
    }
}

#[test]
fn a_lathe_that_never_holds_still_leaves_the_parity_unknown() {
    let counts: Vec<u32> = (0..3 * PARITY_TRIES).collect();
    let mut bus = Script::default().with(CNT3, &counts);
    assert_eq!(low_low(&mut bus), None);
    assert_eq!(bus.reads_of(CNT3), 3 * PARITY_TRIES as usize);
}

#[test]
fn the_tick_starts_right_after_tim5_steps() {
    let mut bus = Script::default().with(CNT5, &[7, 7, 7, 8, 8]);
    assert_eq!(start_tick(&mut bus), Some(8));
    assert_eq!(bus.writes(), [TICK_START]);
    let cen = bus.log.iter().position(|l| l.0 == 'w').unwrap();
    assert_eq!(bus.log[cen - 1], ('r', CNT5, 8), "CEN written right after the step is seen");
    assert_eq!(start::clock(0xFFF0, 1).first_instant, 0xFFF0u16.wrapping_add(STAMPS_PER_TICK), "S + a tick, wrapping");
    assert!(0xFFF0 + STAMPS_PER_TICK as u32 > 0xFFFF, "the sum wraps");
}

#[test]
fn a_start_that_slips_a_stamp_is_rewound_and_tried_again() {
    let mut bus = Script::default().with(CNT5, &[7, 8, 9, 9, 10, 10]);
    assert_eq!(start_tick(&mut bus), Some(10));
    let mut want = vec![TICK_START];
    want.extend(TICK_REWIND);
    want.push(TICK_START);
    assert_eq!(bus.writes(), want);
}

#[test]
fn a_stopped_tim5_still_starts_the_tick_untimed() {
    let mut bus = Script::default().with(CNT5, &[3]);
    assert_eq!(start_tick(&mut bus), None);
    assert_eq!(bus.writes(), [TICK_START]);
    assert_eq!(bus.reads_of(CNT5), 1 + start::SPIN_READS as usize, "bounded");
}

const CNT11: u32 = TIM11 + off::CNT;
const SR11: u32 = TIM11 + off::SR;

/// The stamp `cycles` of TIM11 from now falls on, after TIM5 stepped to
/// `s`: a tick's cycles are a whole number of stamps, and a count 0.4 of a
/// stamp past one (the update trails TIM5's step by a few cycles) rounds up.
fn stamp_in(s: u16, cycles: u32) -> u16 {
    s + ((cycles + STAMP_CYCLES / 2) / STAMP_CYCLES) as u16
}

#[test]
fn the_next_instant_is_the_stamp_tim11s_count_says_its_update_falls_on() {
    // TIM5 steps to 8 with TIM11 at 1 000: a tick less 1 000 cycles to go,
    // (at 4 800 a tick: 3 800 cycles, 39.6 stamps: 40, at 48)
    assert_eq!(TICK_CYCLES % STAMP_CYCLES, 0);
    let mut bus = Script::default().with(CNT5, &[7, 8]).with(CNT11, &[1_000, 1_003]).with(SR11, &[0]);
    let at = stamp_in(8, TICK_CYCLES - 1_000);
    assert_eq!(at, 8 + STAMPS_PER_TICK - 10, "1 000 cycles is 10.4 stamps");
    assert_eq!(start::next_instant(&mut bus), Some(at));
    assert!(bus.writes().is_empty(), "TIM11 runs on untouched");
    // a tick pending (UIF): its update, a tick's stamps before, comes first
    let mut pending = Script::default().with(CNT5, &[7, 8]).with(CNT11, &[1_000, 1_003]).with(SR11, &[1]);
    assert_eq!(start::next_instant(&mut pending), Some(65_534), "8 less 10");
}

#[test]
fn an_update_between_the_reads_is_measured_again() {
    let reads = [TICK_CYCLES - 10, 2, 100, 103];
    let mut bus = Script::default().with(CNT5, &[7, 8, 9, 10]).with(CNT11, &reads).with(SR11, &[1, 0]);
    // the first try saw TIM11 wrap around UIF; the second: TIM5 at 10,
    // TIM11 at 100: a tick less 100 cycles, a stamp less
    assert_eq!(start::next_instant(&mut bus), Some(stamp_in(10, TICK_CYCLES - 100)));
    assert_eq!(stamp_in(10, TICK_CYCLES - 100), 10 + STAMPS_PER_TICK - 1);
    let mut stopped = Script::default().with(CNT5, &[3]);
    assert_eq!(start::next_instant(&mut stopped), None, "TIM5 still: no clock");
}
