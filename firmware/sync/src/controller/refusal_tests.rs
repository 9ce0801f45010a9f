//! Commands refused for what the controller really sees, and only then:
//! an engage with nothing to drive, a jog while the cutter runs, and a
//! lathe at rest that a change of the settings leaves at rest.

use super::rig::{per_tick, Rig};
use super::*;
use crate::cam::Cam;
use crate::config::Config;

fn none() -> Config {
    Config { drive: DriveKind::None, ..Config::default() }
}

#[test]
fn engage_with_no_cutter_and_no_cam_is_refused_and_enable_stays_off() {
    let mut r = Rig::new(none());
    assert_eq!(r.c.engage(), Err(Refusal::NothingToDrive));
    assert_eq!(r.c.state(), State::Idle);
    for _ in 0..100 {
        assert!(!r.tick(0).enable, "ENABLE stays off");
    }
    assert_eq!(r.c.state(), State::Idle);
    // with a cam table the X axis is something to drive
    static TABLE: [i32; 2] = [0, 0];
    let x = XAxis::new(Cam::new(&TABLE, 2_400).unwrap(), super::rig::x_limits(1_000_000));
    r.c.set_x_axis(Some(x)).unwrap();
    assert_eq!(r.c.engage(), Ok(()));
    r.until(0, 1_000, |c| c.state() == State::Synced);
}

#[test]
fn a_jog_while_the_cutter_runs_says_so_not_that_settings_wait() {
    let mut r = Rig::new(Config::default());
    r.c.engage().unwrap();
    assert_eq!(r.c.jog(90_000), Err(Refusal::Engaged));
    r.until(0, 1_000, |c| c.state() == State::Synced);
    assert_eq!(r.c.jog(90_000), Err(Refusal::Engaged));
    r.c.disengage();
    assert_eq!(r.c.jog(90_000), Err(Refusal::Engaged));
    assert_eq!(Refusal::Engaged.describe(), "stop first: the cutter is engaged or ramping down (jog only while idle)");
}

/// 0.1 s without a count is at rest: a setting changed then (the lathe
/// still) leaves it at rest, so a `save` or a `jog` right after it goes.
#[test]
fn a_setting_changed_with_the_lathe_at_rest_leaves_it_at_rest() {
    let mut r = Rig::new(Config::default());
    r.run(per_tick(1.0), 100);
    r.run(0, 2_500);
    assert!(r.c.lathe_at_rest());
    for (name, value) in [("cpr", "1000"), ("dir", "opposite"), ("steps", "1600")] {
        r.c.set_config(r.c.config().with(name, value).unwrap()).unwrap();
        assert!(r.c.lathe_at_rest(), "set {name} {value}: the lathe has not moved");
        r.tick(0);
        assert!(r.c.lathe_at_rest(), "set {name} {value}, a tick on");
    }
    assert!(r.c.jog(90_000).is_ok());
    // a lathe that turns is still seen turning after a set
    let mut r = Rig::new(Config::default());
    r.run(per_tick(1.0), 100);
    r.c.set_config(r.c.config().with("cpr", "1000").unwrap()).unwrap();
    assert!(!r.c.lathe_at_rest());
    assert_eq!(r.c.jog(90_000), Err(Refusal::LatheTurning));
}

/// A board that has just started has seen no count: at rest until one
/// comes, however soon after the start it is asked.
#[test]
fn a_board_just_started_is_at_rest_until_its_encoder_counts() {
    let mut r = Rig::new(Config::default());
    for _ in 0..100 {
        r.tick(0);
        assert!(r.c.lathe_at_rest());
    }
    r.tick(per_tick(1.0));
    assert!(!r.c.lathe_at_rest(), "a count: turning");
    assert_eq!(r.c.ticks_since_lathe_count(), 0);
}
