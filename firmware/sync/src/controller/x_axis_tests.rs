//! The X axis through the controller: it holds where its steps really are
//! while the cutter is off, and its following error counts only once
//! everything is synchronised.

use super::rig::{per_tick, x_limits, Rig};
use super::*;
use crate::cam::Cam;
use crate::config::Config;

/// A cam that holds X at `steps` whatever the lathe's angle.
fn fixed_cam(steps: i32) -> Cam {
    let table: &'static [i32] = std::vec::Vec::leak(std::vec![steps, steps]);
    Cam::new(table, 2_400).unwrap()
}

fn with_x(config: Config, cam: Cam) -> Rig {
    let mut r = Rig::new(config);
    // the board's top rate (0.5 a tick), 1 000 000 steps/s²
    let x = XAxis::new(cam, x_limits(1_000_000));
    r.c.set_x_axis(Some(x)).unwrap();
    r
}

#[test]
fn while_idle_the_x_command_sits_on_the_x_steps_really_made() {
    let mut r = with_x(Config::default(), fixed_cam(100));
    r.x_emitted = 7; // pulses counted (DIR forward) while off
    r.tick(0);
    assert_eq!(r.c.x_axis().unwrap().position_q16(), 7 << 16);
}

#[test]
fn an_engaged_x_axis_goes_to_its_cam_and_stays() {
    let mut r = with_x(Config::default(), fixed_cam(100));
    r.c.engage().unwrap();
    r.until(0, 5_000, |c| c.state() == State::Synced);
    r.run(0, 1_000);
    let x = r.c.x_axis().unwrap().position_q16();
    assert!((x - (100 << 16)).abs() < 1 << 15, "within half a step of 100: {x}");
    assert_eq!(r.x_emitted, 100, "100 X steps made");
}

/// A phase offset of half a cutter turn keeps the cutter catching up
/// (Engaging) for about 3200 ticks: the X axis, dead (its pulses never
/// counted), is more than `ferror` (64 steps) behind its 100 long before.
fn dead_x_behind_a_slow_cutter() -> Rig {
    let c = Config::default().with("phase", "180").unwrap();
    let mut r = with_x(c, fixed_cam(100));
    r.x_emits = false;
    r.c.engage().unwrap();
    r
}

#[test]
fn an_x_axis_behind_by_more_than_ferror_trips_only_once_synced() {
    let mut r = dead_x_behind_a_slow_cutter();
    let mut behind_while_engaging = 0;
    for _ in 0..20_000 {
        let before = r.c.state();
        r.tick(0);
        if r.c.fault().is_some() {
            assert_eq!(before, State::Engaging);
            break;
        }
        assert_eq!(r.c.state(), State::Engaging);
        if r.c.x_axis().unwrap().position_q16() > 64 << 16 {
            behind_while_engaging += 1;
        }
    }
    assert!(behind_while_engaging > 1_000, "{behind_while_engaging} ticks behind while engaging");
    // the tick the cutter arrived, the X axis's lag counted
    assert_eq!(r.c.fault(), Some(Fault::FollowingError));
}

#[test]
fn an_x_axis_behind_by_less_than_ferror_is_no_fault() {
    let c = Config::default().with("phase", "180").unwrap();
    let mut r = with_x(c, fixed_cam(40));
    r.x_emits = false;
    r.c.engage().unwrap();
    r.until(0, 20_000, |c| c.state() == State::Synced);
    r.run(0, 1_000);
    assert_eq!(r.c.state(), State::Synced);
}

#[test]
fn an_x_axis_exactly_ferror_behind_is_within_the_limit() {
    // The X axis counted 164 steps (then its driver died) and its cam
    // wants 100: commanded back 64 steps, none made. From above, a
    // follower with room to accelerate lands exactly on its target (its
    // pull, error/16, floors toward −∞): the lag is exactly ferror.
    for (cam, fault) in [(100, None), (99, Some(Fault::FollowingError))] {
        let mut r = Rig::new(Config::default());
        let x = XAxis::new(fixed_cam(cam), x_limits(50_000_000));
        r.c.set_x_axis(Some(x)).unwrap();
        (r.x_emits, r.x_emitted) = (false, 164);
        r.tick(0);
        r.c.engage().unwrap();
        for _ in 0..2_000 {
            r.tick(0);
        }
        assert_eq!(r.c.fault(), fault, "cam at {cam}");
        if fault.is_none() {
            assert_eq!((r.c.state(), r.c.x_axis().unwrap().position_q16()), (State::Synced, 100 << 16));
        }
    }
}

/// Fits a cam holding X at `steps`, engages until the X axis is on it
/// and stops. Returns where the controller believed the X axis was once
/// fitted, in steps, and the X pulses the run made.
fn run_cam_once(r: &mut Rig, steps: i32) -> (i64, u16) {
    r.c.set_x_axis(Some(XAxis::new(fixed_cam(steps), x_limits(1_000_000)))).unwrap();
    r.tick(0); // idle: the X command sits on the X steps counted
    let believed = r.c.x_axis().unwrap().position_q16() >> 16;
    let before = r.x_emitted;
    r.c.engage().unwrap();
    r.until(0, 10_000, |c| c.state() == State::Synced);
    r.run(0, 1_000);
    r.c.disengage();
    r.until(0, 10_000, |c| c.state() == State::Idle);
    (believed, r.x_emitted.wrapping_sub(before))
}

#[test]
fn a_refitted_cam_starts_from_where_the_x_axis_really_is_after_forward_moves() {
    // out to 100, then further to 150 under a second cam
    let mut r = Rig::new(Config::default());
    assert_eq!(run_cam_once(&mut r, 100), (0, 100));
    assert_eq!(run_cam_once(&mut r, 150), (100, 50));
}

#[test]
fn a_refitted_cam_starts_from_where_the_x_axis_really_is_after_moves_both_ways() {
    let mut r = Rig::new(Config::default());
    // out to 100, then back to 0 under a second cam: 200 pulses, net 0
    assert_eq!(run_cam_once(&mut r, 100), (0, 100));
    assert_eq!(run_cam_once(&mut r, 0), (100, 100));
    // the same cam fitted again: the X axis is at 0 and should stay there
    // (it is believed at 200, and steps 200 back to get to 0)
    assert_eq!(run_cam_once(&mut r, 0), (0, 0));
}

#[test]
fn on_a_moving_cam_the_synced_x_command_is_where_the_cam_will_be_at_the_tick_s_end() {
    // 0 → 360 steps over half a turn (1200 counts) and back: at one count
    // a tick, 0.3 step a tick (the X output's limit is 0.5). The X plan
    // runs during the next tick, so the command leads the cam by one
    // tick's travel, as the cutter's target leads the gear by its window;
    // and the axis counts as on its cam against that lead.
    let table: &'static [i32] = std::vec::Vec::leak(std::vec![0, 360]);
    let mut r =
        with_x(Config { drive: crate::config::DriveKind::None, ..Config::default() }, Cam::new(table, 2_400).unwrap());
    r.c.engage().unwrap();
    // (settled by count 700: synced within half a step, then closing)
    let mut worst = 0;
    for _ in 0..1_100 {
        r.tick(per_tick(1.0));
        if r.c.state() == State::Synced && r.lathe() > 700 {
            // the cam at the lathe's count one tick on, Q16 steps
            let ahead = ((r.lathe_q16 + per_tick(1.0)) * 360) / 1_200;
            worst = worst.max((r.c.x_axis().unwrap().position_q16() - ahead).abs());
        }
    }
    assert_eq!(r.c.state(), State::Synced);
    assert!(worst < 1 << 10, "within 1/64 step of the cam a tick ahead: {worst}");
}

#[test]
fn an_x_axis_too_slow_to_stay_on_its_cam_trips_once_synced_though_every_step_is_made() {
    // drive=none: only X; a cam 200 steps up over half a turn and down
    // again, followed at 1 000 steps/s² (2.5e-6 steps a tick²): from rest
    // at 1 count a tick the cam runs away at 1/6 step a tick, and the X
    // command falls behind it by more than ferror (64 steps)
    let table: &'static [i32] = std::vec::Vec::leak(std::vec![0, 200]);
    let mut r = Rig::new(Config::default().with("drive", "none").unwrap());
    r.c.set_x_axis(Some(XAxis::new(Cam::new(table, 2_400).unwrap(), x_limits(1_000)))).unwrap();
    r.c.engage().unwrap();
    r.until(0, 5_000, |c| c.state() == State::Synced);
    let ticks = r.until(per_tick(1.0), 20_000, |c| c.fault().is_some());
    assert_eq!(r.c.fault(), Some(Fault::FollowingError));
    // the command hardly moves while the cam runs 1/6 step a tick: more
    // than 64 steps behind after about 6 × 64 ticks
    assert!((380..400).contains(&ticks), "{ticks}");
    // every step commanded was made: it is the cam the axis is behind
    let x = r.c.x_axis().unwrap().position_q16() >> 16;
    assert!((x - i64::from(r.x_emitted as i16)).abs() <= 1, "{x} {}", r.x_emitted);
}
