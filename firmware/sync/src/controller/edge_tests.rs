//! The controller's use of the lathe's edge times (`edges`).

use super::*;
use crate::edges::EdgeClock;

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

const CLOCK: EdgeClock = EdgeClock { first_instant: 40, stamps_per_tick: 40, low_low_odd: false };

#[test]
fn edge_times_are_off_until_the_board_starts_them() {
    let mut c = ctl();
    assert!(!c.edge_timing());
    c.start_edges(CLOCK);
    assert!(c.edge_timing());
}

/// A save's erase stalls the CPU and ticks are lost: the instants the
/// edge timer counts are wrong from then on, so it stops until the board
/// measures them again.
#[test]
fn a_save_stall_turns_the_edge_times_off_until_the_board_measures_them_again() {
    let mut c = ctl();
    c.start_edges(CLOCK);
    c.begin_stall();
    c.tick(&TickInput::default());
    c.end_stall();
    assert!(!c.edge_timing());
    c.start_edges(CLOCK);
    assert!(c.edge_timing());
}
