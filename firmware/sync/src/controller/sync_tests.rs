//! When the cutter counts as synchronised (within half a step, at the
//! target's speed give or take 4 × max-accel), the BLDC's following error
//! (the command against the cutter's encoder), and the target between
//! counts (the estimator's sub-count interpolation).

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;

#[test]
fn synced_comes_once_within_half_a_step_not_at_half_a_step() {
    // 670 steps a turn and a phase of 0.269°: 32 809 / 65536 step (half a
    // step and 41). Synced at rest, then nudged: the follower starts at
    // max-accel (41 a tick²), so after one tick it is exactly half a step
    // short (32 768) at 41 a tick, after two 32 686 short at 82 a tick.
    let c = Config { motor_steps_per_rev: 670, ..Config::default() };
    let mut r = Rig::new(c);
    r.c.engage().unwrap();
    r.tick(0);
    assert_eq!(r.c.state(), State::Synced);
    r.c.set_config(c.with("phase", "0.269").unwrap()).unwrap();
    assert_eq!(r.c.derived().phase_offset_q16, 32_809);
    assert_eq!(r.c.state(), State::Engaging);
    r.tick(0);
    assert_eq!(r.c.follower().velocity, 41);
    assert_eq!(r.c.state(), State::Engaging, "exactly half a step off: not yet");
    r.tick(0);
    assert_eq!(r.c.follower().velocity, 82);
    assert_eq!(r.c.state(), State::Synced, "closer than half a step, 82 ≤ 4 × 41 off the target's speed");
}

/// A BLDC cutter engaged at rest on count 0 (the follower exactly on its
/// target), its encoder then reading `cutter` counts.
fn bldc_reading(cutter: i16) -> Controller {
    let mut c = Controller::new(Config { drive: DriveKind::Bldc, ..Config::default() }, Timing::FIRMWARE);
    c.start(0, 0, 0);
    c.engage().unwrap();
    c.tick(&TickInput::default());
    assert_eq!(c.state(), State::Synced);
    for _ in 0..1_000 {
        c.tick(&TickInput { cutter: cutter as u16, ..TickInput::default() });
    }
    c
}

#[test]
fn a_bldc_cutter_exactly_ferror_behind_is_within_the_limit_and_a_count_more_is_not() {
    // ferror 64: the encoder slipped 64 counts back, then 65
    assert_eq!(bldc_reading(-64).fault(), None);
    assert_eq!(bldc_reading(64).fault(), None);
    assert_eq!(bldc_reading(-65).fault(), Some(Fault::FollowingError));
    assert_eq!(bldc_reading(65).fault(), Some(Fault::FollowingError));
}

#[test]
fn a_bldc_cutter_that_follows_its_command_is_no_following_error_anywhere() {
    // a phase of −90°: 800 counts from where it engaged; the motor follows
    // the command a tick late
    let c = Config { drive: DriveKind::Bldc, ..Config::default() }.with("phase", "-90").unwrap();
    let mut ctl = Controller::new(c, Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    ctl.engage().unwrap();
    let mut cutter = 0i64;
    for _ in 0..30_000 {
        ctl.tick(&TickInput { cutter: cutter as u16, ..TickInput::default() });
        cutter = ctl.follower().whole_steps();
        assert_eq!(ctl.fault(), None);
    }
    assert_eq!((ctl.state(), cutter), (State::Synced, -800));
}

#[test]
fn between_counts_the_target_moves_with_the_interpolated_lathe_angle() {
    // idle, no step made: the phase error is the target. At half and a
    // quarter of a count a tick it moves 4/3 and 2/3 of a step every tick,
    // not 8/3 on the ticks with a count and nothing between
    for speed in [0.5, 0.25] {
        let mut r = Rig::new(Config::default());
        r.run(per_tick(speed), 5_000);
        let ideal = (speed * 8.0 / 3.0 * 65536.0) as i64;
        let mut last = r.c.status().phase_error_q16;
        for k in 0..1_000 {
            r.tick(per_tick(speed));
            let now = r.c.status().phase_error_q16;
            assert!((now - last - ideal).abs() < 1 << 14, "{speed}, tick {k}: moved {}", now - last);
            last = now;
        }
    }
}
