//! `divide N` through the controller: its range and refusals, the cutter
//! off with the chuck turned by hand either way, and the angle from the
//! index kept across a reset.

use super::activity::Asked;
use super::selftest::SelfTestRefusal;
use super::*;
use crate::angle::{Angle, Division};
use crate::config::Config;
use std::string::ToString;

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

#[test]
fn divisions_out_of_range_are_refused_and_change_nothing() {
    let mut c = ctl();
    // cpr 2400: at most 600, four counts apart
    for n in [0, 601, 3600, 3601, u32::MAX] {
        assert_eq!(c.start_divide(n), Err(Refusal::DivideRange), "{n}");
        assert_eq!(c.dividing(), None, "{n}");
    }
    assert_eq!(
        Refusal::DivideRange.describe(),
        "divide 1..=3600 divisions of a turn, at most cpr/4 (4 counts or more apart)"
    );
    for n in [1, 6, 600] {
        assert_eq!(c.start_divide(n), Ok(()));
        assert_eq!(c.dividing(), Some(n), "a new number while dividing");
    }
    assert_eq!(c.start_divide(601), Err(Refusal::DivideRange));
    assert_eq!(c.dividing(), Some(600), "a refused number keeps the last");
    let mut fine = Controller::new(Config { encoder_counts_per_rev: 14_400, ..Config::default() }, Timing::FIRMWARE);
    assert_eq!(fine.start_divide(3600), Ok(()), "the table's top needs 14 400 counts");
}

#[test]
fn while_dividing_nothing_moves_the_cutter_but_a_jog_which_returns_to_dividing() {
    let mut c = ctl();
    c.start_divide(6).unwrap();
    assert_eq!(c.engage(), Err(Refusal::Dividing));
    assert_eq!(c.start_encoder_check(), Err(Refusal::Dividing));
    assert_eq!(c.start_selftest(None).err(), Some(SelfTestRefusal::Dividing));
    assert_eq!(c.admit(Asked::Dfu), Err(Refusal::Dividing));
    assert_eq!(c.state(), State::Idle);
    let mut r = rig::Rig::new(Config::default());
    r.c.start_divide(6).unwrap();
    r.c.jog(90_000).unwrap();
    assert_eq!((r.c.state(), r.c.dividing()), (State::Jogging, Some(6)), "still dividing under the jog");
    assert_eq!(r.c.start_divide(8), Err(Refusal::Moving));
    r.until(0, 100_000, |c| c.state() == State::Idle);
    assert_eq!(r.cutter_net, 800, "the jog's quarter turn");
    let mut c = r.c;
    assert_eq!(c.dividing(), Some(6), "dividing again after the jog");
    assert_eq!(c.stop_divide(), Some(6));
    assert_eq!(c.stop_divide(), None);
    assert_eq!(c.engage(), Ok(()), "after divide stop");
}

#[test]
fn divide_stop_under_a_jog_leaves_a_plain_jog() {
    let mut c = ctl();
    c.start_divide(6).unwrap();
    c.jog(90_000).unwrap();
    assert_eq!(c.stop_divide(), Some(6));
    assert_eq!((c.state(), c.dividing()), (State::Jogging, None));
    assert_eq!(c.admit(Asked::Divide), Err(Refusal::Moving), "the jog runs on, as a jog");
    c.disengage();
    assert_eq!(c.dividing(), None);
    assert_eq!(c.admit(Asked::Divide), Err(Refusal::CutterOn), "ramping down");
    // the jog, its dividing stopped, ends as a jog does: at its target, idle
    let mut r = rig::Rig::new(Config::default());
    r.c.start_divide(6).unwrap();
    r.c.jog(90_000).unwrap();
    assert_eq!(r.c.stop_divide(), Some(6));
    r.until(0, 100_000, |c| c.state() == State::Idle);
    assert_eq!((r.cutter_net, r.c.dividing()), (800, None), "the jog's quarter turn, and no dividing after it");
}

#[test]
fn dividing_starts_only_with_nothing_else_running_and_the_cutter_idle() {
    let mut c = ctl();
    c.jog(90_000).unwrap();
    assert_eq!(c.start_divide(6), Err(Refusal::Moving));
    let mut c = ctl();
    c.start_encoder_check().unwrap();
    assert_eq!(c.start_divide(6), Err(Refusal::Checking));
    let mut c = ctl();
    c.start_selftest(None).unwrap();
    assert_eq!(c.start_divide(6), Err(Refusal::SelfTesting));
    let mut c = ctl();
    c.engage().unwrap();
    assert_eq!(c.start_divide(6), Err(Refusal::CutterOn));
    let mut c = ctl();
    c.trip(crate::state::Fault::EStop);
    assert_eq!(c.start_divide(6), Err(Refusal::Faulted));
    assert_eq!(c.dividing(), None);
}

/// A spindle turned by hand: its place in counts from a fixed mark, its
/// index at `INDEX` counts past the mark, and the board's counter, which
/// starts wherever the spindle stands when the board does.
struct Hand {
    at: i64,
    board_from: i64,
}

const CPR: i64 = 2400;
const INDEX: i64 = 5;

impl Hand {
    /// A board starting with the spindle `at` counts from the mark.
    fn board(at: i64) -> (Hand, Controller) {
        (Hand { at, board_from: at }, ctl())
    }

    /// Turns the spindle to `to`, a count every ten ticks (a hand's pace:
    /// a turn in a second), the index latched as it passes, at its count
    /// either way (an index one count wide).
    fn turn_to(&mut self, c: &mut Controller, to: i64) {
        while self.at != to {
            let next = self.at + (to - self.at).signum();
            // the count between the two places, which the index marks
            let crossed = next.max(self.at);
            let index = ((crossed - INDEX).rem_euclid(CPR) == 0).then_some((crossed - self.board_from) as u16);
            self.at = next;
            let raw = (self.at - self.board_from) as u16;
            c.tick(&TickInput { lathe: raw, index, ..TickInput::default() });
            let out = c.tick(&TickInput { lathe: raw, ..TickInput::default() });
            assert!(!out.enable && out.plan.count == 0, "the cutter stays off");
            for _ in 0..8 {
                c.tick(&TickInput { lathe: raw, ..TickInput::default() });
            }
            assert_eq!(c.fault(), None);
        }
    }
}

fn angle(c: &Controller) -> Angle {
    let s = c.status();
    Angle::of(s.lathe_counts, s.index_counts, c.config().encoder_counts_per_rev)
}

#[test]
fn the_angle_is_from_the_index_once_seen_and_the_same_after_a_reset() {
    let (mut hand, mut c) = Hand::board(1000);
    c.start_divide(6).unwrap();
    hand.turn_to(&mut c, 1300);
    assert_eq!(angle(&c), Angle { counts: 300, cpr: 2400, from_index: false }, "from the start");
    hand.turn_to(&mut c, 2400 + 405);
    assert_eq!(angle(&c), Angle { counts: 400, cpr: 2400, from_index: true }, "from the index");
    let d = Division::of(&angle(&c), 6);
    assert_eq!((d.number, d.within()), (1, true), "on division 1");
    // a reset: the spindle stays where it is, the board's count starts at 0
    let (mut hand, mut c) = Hand::board(hand.at);
    c.start_divide(6).unwrap();
    assert_eq!(angle(&c), Angle { counts: 0, cpr: 2400, from_index: false }, "no index yet");
    // back past the index, then forward to the same place
    hand.turn_to(&mut c, 2000);
    assert_eq!(angle(&c), Angle { counts: 2400 - 5 - 400, cpr: 2400, from_index: true });
    hand.turn_to(&mut c, 2400 + 405);
    assert_eq!(angle(&c), Angle { counts: 400, cpr: 2400, from_index: true }, "the same origin as before the reset");
}

#[test]
fn turned_by_hand_either_way_every_division_is_found() {
    let (mut hand, mut c) = Hand::board(0);
    c.start_divide(6).unwrap();
    hand.turn_to(&mut c, INDEX + 1); // past the index
    for (k, way) in [(1, 1), (2, 1), (5, -1), (4, -1), (0, 1), (3, -1)] {
        // to a division's count, from the way given
        let target = INDEX + 400 * k + CPR;
        hand.turn_to(&mut c, target - 30 * way);
        let d = Division::of(&angle(&c), 6);
        assert!(!d.within(), "division {k}: 30 counts short");
        hand.turn_to(&mut c, target);
        let d = Division::of(&angle(&c), 6);
        assert_eq!((d.number, d.within(), d.to_counts().to_string()), (k as u32, true, "0.00".into()), "{k} {way}");
    }
    assert_eq!(c.dividing(), Some(6));
}
