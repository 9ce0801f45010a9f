//! Settings while running or faulted: what `install_config` allows, and
//! what it keeps.

use super::rig::{per_tick, Rig};
use super::*;
use crate::cam::Cam;
use crate::config::Config;

fn install(r: &mut Rig, name: &str, value: &str) -> Result<(), Refusal> {
    let c = r.c.config().with(name, value).unwrap();
    r.c.install_config(&PreparedConfig::prepare(c, r.c.config(), Timing::FIRMWARE))
}

#[test]
fn after_a_ramped_fault_has_stopped_the_settings_change_and_not_while_it_ramps() {
    let mut r = Rig::new(Config::default());
    r.run(per_tick(0.5), 3_000); // the lathe turning steadily first
    r.c.engage().unwrap();
    r.until(per_tick(0.5), 20_000, |c| c.state() == State::Synced);
    r.run(per_tick(0.5), 1_000);
    r.c.trip(Fault::FollowingError);
    assert!(r.c.follower().velocity > 0);
    assert_eq!(install(&mut r, "max-accel", "300000"), Err(Refusal::NotIdle), "ramping down");
    r.until(0, 50_000, |c| c.follower().velocity == 0);
    assert_eq!(install(&mut r, "max-accel", "300000"), Ok(()), "stopped");
}

#[test]
fn an_x_axis_stays_fitted_unless_cpr_changes() {
    let table: &'static [i32] = std::vec::Vec::leak(std::vec![0, 10]);
    let mut r = Rig::new(Config::default());
    r.c.set_x_axis(Some(XAxis::new(Cam::new(table, 2_400).unwrap(), super::rig::x_limits(1_000_000)))).unwrap();
    install(&mut r, "steps", "1600").unwrap();
    assert!(r.c.x_axis().is_some(), "a motor setting keeps the cam");
    install(&mut r, "cpr", "4000").unwrap();
    assert!(r.c.x_axis().is_none(), "the cam's period is in counts of the old encoder");
}

#[test]
fn a_cam_fitted_for_a_cutter_keeps_its_cutter_until_cam_off() {
    let table: &'static [i32] = std::vec::Vec::leak(std::vec![0, 10]);
    let fit = |r: &mut Rig| {
        r.c.set_x_axis(Some(XAxis::new(Cam::new(table, 400).unwrap(), super::rig::x_limits(1_000_000)))).unwrap()
    };
    let mut r = Rig::new(Config::default());
    fit(&mut r);
    // a compensating table's period is one pass of this cutter: another
    // ratio, edge count or drive would run it out of step
    let other_sense = if Config::default().sense == crate::Sense::Same { "opposite" } else { "same" };
    for (name, value) in [("ratio", "1"), ("edges", "2"), ("dir", other_sense), ("drive", "none"), ("drive", "bldc")] {
        assert_eq!(install(&mut r, name, value), Err(Refusal::CamFitted), "{name} {value}");
    }
    assert!(r.c.x_axis().is_some() && r.c.config().ratio == Config::default().ratio);
    install(&mut r, "max-accel", "300000").unwrap();
    // with the cam off, the cutter may change
    r.c.set_x_axis(None).unwrap();
    install(&mut r, "ratio", "1").unwrap();
    // no cutter before or after: a single-point tool's table takes any ratio
    install(&mut r, "drive", "none").unwrap();
    fit(&mut r);
    install(&mut r, "ratio", "1/2").unwrap();
    install(&mut r, "edges", "4").unwrap();
    assert_eq!(install(&mut r, "drive", "stepper"), Err(Refusal::CamFitted), "a cutter added under the cam");
}

#[test]
fn setting_the_same_phase_while_synced_stays_synced() {
    let mut r = Rig::new(Config::default().with("phase", "10").unwrap());
    r.run(per_tick(0.5), 3_000);
    r.c.engage().unwrap();
    r.until(per_tick(0.5), 20_000, |c| c.state() == State::Synced);
    install(&mut r, "phase", "10").unwrap();
    assert_eq!(r.c.state(), State::Synced, "nothing to move to");
    install(&mut r, "phase", "12").unwrap();
    assert_eq!(r.c.state(), State::Engaging, "a nudge is a move, not lag");
}
