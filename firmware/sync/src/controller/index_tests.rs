//! Index pulses through the controller: the first one (before the first
//! engagement) becomes the gear's origin, later ones are checked against
//! it, and a slipped one is an encoder fault.

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;
use crate::gear::Scale;

/// Turns the lathe at one count a tick to `to`, latching an index when it
/// passes `index` (if given). No fault comes of it.
fn turn_to(r: &mut Rig, to: i64, index: Option<i64>) {
    let fault = r.c.fault();
    while r.lathe() < to {
        let next = r.lathe() + 1;
        let latched = (Some(next) == index).then_some(next as u16);
        r.tick_with(per_tick(1.0), TickInput { index: latched, ..TickInput::default() });
        assert_eq!(r.c.fault(), fault, "at {next}");
    }
}

fn round(r: &Rig, count: i64) -> i64 {
    Scale::round(r.c.derived().scale, count)
}

#[test]
fn the_first_index_before_engaging_becomes_the_gears_origin() {
    let mut r = Rig::new(Config::default());
    assert!(!r.c.status().indexed);
    turn_to(&mut r, 150, Some(100));
    assert!(r.c.status().indexed, "the index was seen");
    // the re-base waits for the low-priority service
    assert_eq!((r.c.gear_origin(), r.c.status().target_steps), (0, round(&r, 150)));
    r.c.service();
    assert_eq!(r.c.gear_origin(), 100);
    // 50 counts past the index: 50 × 8/3 = 133.3 steps
    assert_eq!(r.c.status().target_steps, 133);
    // once only: the next turn's index keeps the origin
    turn_to(&mut r, 2_600, Some(2_500));
    r.c.service();
    assert_eq!((r.c.gear_origin(), r.c.fault()), (100, None));
    assert_eq!(r.c.status().target_steps, round(&r, 2_500));
}

#[test]
fn the_first_index_is_not_taken_while_faulted_but_once_idle_again() {
    let mut r = Rig::new(Config::default());
    r.c.trip(Fault::EStop);
    turn_to(&mut r, 150, Some(100));
    r.c.service();
    assert_eq!(r.c.gear_origin(), 0, "not while faulted");
    r.c.clear();
    r.c.service();
    assert_eq!(r.c.gear_origin(), 100);
    assert_eq!(r.c.status().target_steps, round(&r, 50));
}

#[test]
fn an_index_first_seen_after_engaging_keeps_the_phase_of_the_boot_origin() {
    // the cutter has cut with the gear measured from count 0: re-basing it
    // on a later index would move the phase of those cuts
    let mut r = Rig::new(Config::default());
    r.c.engage().unwrap();
    r.c.disengage();
    r.until(0, 10, |c| c.state() == State::Idle);
    turn_to(&mut r, 150, Some(100));
    r.c.service();
    assert!(r.c.status().indexed);
    assert_eq!(r.c.gear_origin(), 0);
    assert_eq!(r.c.status().target_steps, round(&r, 150));
}

#[test]
fn engage_takes_a_pending_index_first() {
    let mut r = Rig::new(Config::default());
    turn_to(&mut r, 150, Some(100));
    r.c.engage().unwrap();
    assert_eq!(r.c.gear_origin(), 100);
}

#[test]
fn an_index_off_by_more_than_two_counts_is_an_encoder_fault() {
    // indexes 2400 counts apart give or take 2 (the same edge seen twice at
    // a reversal, or jitter) are consistent; 3 off means counts were lost
    for (off, fault) in
        [(2, None), (-2, None), (3, Some(Fault::EncoderImplausible)), (-3, Some(Fault::EncoderImplausible))]
    {
        let mut r = Rig::new(Config::default());
        turn_to(&mut r, 150, Some(100));
        turn_to(&mut r, 2_600, None);
        // the index latched at 2500 + off, since the last tick
        let raw = (2_500 + off) as u16;
        r.tick_with(per_tick(1.0), TickInput { index: Some(raw), ..TickInput::default() });
        assert_eq!(r.c.fault(), fault, "off by {off}");
    }
}
