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
    c.stop_edges();
    assert!(!c.edge_timing(), "a clock that could not be measured again");
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

/// A steady lathe, 0.17 counts a tick (106 rpm) after a ramp, through the controller engaged, its
/// A rises latched (the count after the rise, k0 = 0) when `edges`: how
/// far the commanded cutter wanders about the exact line over 2 000 ticks
/// (max − min of commanded − exact, steps).
fn wander(sense: crate::config::Sense, edges: bool) -> f64 {
    use super::rig::Rig;
    let top_q16 = (0.17 * 65536.0) as i64;
    let mut r = Rig::new(Config { sense, ..Config::default() });
    if edges {
        r.c.start_edges(CLOCK);
    }
    r.c.engage().unwrap();
    let spc = r.c.derived().steps_per_count_q16 as f64 / 65536.0;
    let sign = if sense == crate::config::Sense::Same { 1.0 } else { -1.0 };
    let (mut rise, mut lo, mut hi) = (None, f64::MAX, f64::MIN);
    for k in 0..5000i64 {
        // up to speed over the first 1 000 ticks (the cutter catches up)
        let speed_q16 = top_q16 * k.min(1000) / 1000 + 1;
        let (before, after) = (r.lathe_q16, r.lathe_q16 + speed_q16);
        // A rises as the count becomes 1 (mod 4)
        let count = (after >> 16) - ((after >> 16) + 3) % 4;
        if count << 16 > before {
            let stamp = 40 * k + 40 * ((count << 16) - before) / speed_q16;
            rise = Some(crate::edges::EdgeRegs { count: count as u16, stamp: stamp as u16 });
        }
        r.tick_with(speed_q16, TickInput { lathe_edge: rise, ..TickInput::default() });
        if k >= 3000 {
            let off = r.c.follower().position as f64 / 65536.0 - sign * spc * r.lathe_q16 as f64 / 65536.0;
            (lo, hi) = (lo.min(off), hi.max(off));
        }
    }
    assert_eq!(r.c.state(), State::Synced);
    hi - lo
}

/// With the edge times the commanded cutter follows the steady lathe to a
/// few hundredths of a step either way round; with the count alone it
/// wanders with the count's quantisation.
#[test]
fn with_edge_times_a_steady_lathe_is_followed_to_hundredths_of_a_step_both_ways() {
    for sense in [crate::config::Sense::Same, crate::config::Sense::Opposite] {
        let (with, without) = (wander(sense, true), wander(sense, false));
        assert!(with < 0.05, "{sense:?}: {with}");
        assert!(without > 2.0 * with, "{sense:?}: {without} against {with}");
    }
}
