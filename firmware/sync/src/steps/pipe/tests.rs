use super::*;
use std::collections::VecDeque;
use std::vec::Vec;

const T: StepTiming = StepTiming { tick_len: 4000, min_period: 500, dir_setup: 500, pulse: 250 };

/// An output that runs each plan two ticks after it was made, and counts
/// pulses as they rise: at the read of tick k it has windows ≤ k−1 and
/// `early` pulses of window k.
struct Hardware {
    queue: VecDeque<StepPlan>,
    counted: u64,
    position: i64,
}

impl Hardware {
    fn new() -> Hardware {
        let mut queue = VecDeque::new();
        queue.extend([StepPlan::default(), StepPlan::default()]);
        Hardware { queue, counted: 0, position: 0 }
    }
    /// Emits `n` pulses of the front window (the one running now).
    fn emit(&mut self, n: u16) {
        let w = self.queue.front_mut().unwrap();
        let n = n.min(w.count);
        w.count -= n;
        self.counted += n as u64;
        self.position += if w.dir == Dir::Forward { n as i64 } else { -(n as i64) };
    }
    fn end_window(&mut self) {
        self.emit(u16::MAX);
        self.queue.pop_front();
    }
}

/// Drives the books with `moves` (Q16 steps per tick), `early` pulses of
/// the running window counted before each read; returns the hardware.
fn run(moves: &[i64], early: u16) -> (StepPipe, Hardware) {
    let (mut books, mut hw, mut to) = (StepPipe::default(), Hardware::new(), 0i64);
    books.start(0);
    for dv in moves {
        hw.emit(early);
        assert!(books.check(hw.counted as u16), "count {} out of range", hw.counted);
        to += dv;
        let p = books.plan(to, &T);
        hw.queue.push_back(p);
        hw.end_window();
    }
    (books, hw)
}

#[test]
fn the_count_fits_the_windows_in_flight_whatever_was_emitted_early() {
    let moves: Vec<i64> = (0..300).map(|k| ((k % 37) as i64 - 18) * 30_000).collect();
    for early in [0, 1, 3, u16::MAX] {
        let (books, mut hw) = run(&moves, early);
        // the books already count the two windows still in flight
        hw.end_window();
        hw.end_window();
        assert_eq!(books.position(), hw.position);
        assert_eq!(books.position(), (moves.iter().sum::<i64>() + (1 << 15)) >> 16);
    }
}

#[test]
fn a_missing_or_extra_pulse_is_caught() {
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    for k in 0..6 {
        assert!(books.check(hw.counted as u16));
        let p = books.plan((k + 1) * (3 << 16), &T);
        hw.queue.push_back(p);
        hw.end_window();
    }
    // the window that ended before this read lost a pulse
    assert!(!books.check(hw.counted as u16 - 1));
    let mut books2 = StepPipe::default();
    books2.start(0);
    assert!(!books2.check(1), "a pulse nobody planned");
}

#[test]
fn a_halt_gives_the_counted_pulses_to_the_windows_in_order() {
    // forward windows, then a reversal in flight
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    for to in [2 << 16, 5 << 16, 9 << 16, 6 << 16] {
        assert!(books.check(hw.counted as u16));
        hw.queue.push_back(books.plan(to, &T));
        hw.end_window();
    }
    // in flight now: +4 (running) and −3 (queued); the halt cuts the
    // running window after 3 of its 4 pulses
    hw.emit(3);
    books.halted(hw.counted as u16);
    assert_eq!(books.position(), 5 + 3);
    assert_eq!(books.position(), hw.position);
    // a tick later (a pulse rose between the read and the halt) it is 4
    hw.emit(1);
    books.halted(hw.counted as u16);
    assert_eq!(books.position(), 9);
    assert_eq!(books.position(), hw.position);
    // nothing is planned while halted; after it the books start afresh
    assert_eq!(books.plan(20 << 16, &T).count, 0);
    assert!(books.check(hw.counted as u16));
    assert_eq!(books.position(), 9);
    hw.queue.clear();
    hw.queue.extend([StepPlan::default(), StepPlan::default()]);
    books.hold(9 << 16, &T);
    for _ in 0..3 {
        assert!(books.check(hw.counted as u16));
        hw.queue.push_back(books.plan(12 << 16, &T));
        hw.end_window();
    }
    hw.end_window();
    hw.end_window();
    assert_eq!((books.position(), hw.position), (12, 12));
}

#[test]
fn a_halt_seen_a_tick_late_still_settles_exactly() {
    // the E-stop interrupt stops the output inside window k−1; the tick
    // sees it at its next read
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    for to in [3 << 16, 6 << 16, 9 << 16] {
        assert!(books.check(hw.counted as u16));
        hw.queue.push_back(books.plan(to, &T));
        hw.end_window();
    }
    // window 3 (+3) runs; halted after 1 pulse; the next read is a tick on
    hw.emit(1);
    hw.queue.clear();
    books.hold(9 << 16, &T); // the tick before the read planned nothing new
    books.halted(hw.counted as u16);
    assert_eq!(books.position(), hw.position);
    assert_eq!(hw.position, 3 + 1);
}

#[test]
fn the_books_start_from_the_counter_as_it_stands() {
    let mut books = StepPipe::default();
    books.start(40_000);
    assert!(books.check(40_000));
    let mut fresh = StepPipe::default();
    fresh.start(0);
    assert!(!fresh.check(40_000), "40000 pulses nobody planned");
}

#[test]
fn pulses_of_the_queued_window_counted_early_are_caught() {
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    for k in 0..4 {
        assert!(books.check(hw.counted as u16));
        hw.queue.push_back(books.plan((k + 1) * (3 << 16), &T));
        hw.end_window();
    }
    // the running window done, and one pulse more: of the queued one
    hw.emit(u16::MAX);
    assert!(books.check(hw.counted as u16));
    assert!(!books.check(hw.counted as u16 + 1));
}

#[test]
fn a_halt_inside_a_reverse_window_settles_backwards() {
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    for to in [6 << 16, 6 << 16, 2 << 16, 2 << 16] {
        assert!(books.check(hw.counted as u16));
        hw.queue.push_back(books.plan(to, &T));
        hw.end_window();
    }
    // the −4 window runs; cut after 3 of its pulses
    let before = hw.position;
    hw.emit(3);
    books.halted(hw.counted as u16);
    assert_eq!(hw.position, before - 3);
    assert_eq!(books.position(), hw.position);
}

#[test]
fn idle_ticks_between_plans_keep_the_windows_in_step() {
    // plan, hold, hold, plan...: every tick is one window, planned or not
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    let mut to = 0;
    for k in 0..30 {
        assert!(books.check(hw.counted as u16), "tick {k}");
        if k % 3 == 0 {
            to += 3 << 16;
            hw.queue.push_back(books.plan(to, &T));
        } else {
            books.hold(to, &T);
            hw.queue.push_back(StepPlan::default());
        }
        hw.end_window();
    }
    hw.end_window();
    hw.end_window();
    assert_eq!(books.position(), hw.position);
}

#[test]
fn emitted_is_where_the_pulses_counted_put_the_motor_both_ways_mid_window() {
    // moves that reverse every few ticks, some pulses of the running window
    // counted early: after each read the books' `emitted` is the hardware's
    // signed position, never the plans still in flight
    let moves: Vec<i64> = (0..300).map(|k| ((k % 11) as i64 - 5) * 90_000).collect();
    for early in [0, 1, 2, u16::MAX] {
        let (mut books, mut hw, mut to) = (StepPipe::default(), Hardware::new(), 0i64);
        books.start(0);
        for dv in &moves {
            hw.emit(early);
            assert!(books.check(hw.counted as u16));
            assert_eq!(books.emitted(), hw.position, "early {early}");
            to += dv;
            hw.queue.push_back(books.plan(to, &T));
            hw.end_window();
        }
        assert_ne!(books.emitted(), books.position(), "plans were in flight at the end");
    }
}

#[test]
fn emitted_after_a_halt_is_the_settled_count() {
    let mut books = StepPipe::default();
    books.start(0);
    let mut hw = Hardware::new();
    for k in 0..5 {
        assert!(books.check(hw.counted as u16));
        hw.queue.push_back(books.plan((k + 1) * 4 * 65_536, &T));
        hw.end_window();
    }
    hw.emit(1); // one pulse of the running window, then the halt
    books.halted(hw.counted as u16);
    assert_eq!(books.emitted(), hw.position);
    assert_eq!(books.emitted(), books.position());
}
