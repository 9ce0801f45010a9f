//! When the cutter counts as synchronised (within half a step, at the
//! target's speed give or take 4 × max-accel), the BLDC's following error
//! (the command against the cutter's encoder), and the target between
//! counts (the estimator's sub-count interpolation).

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;

#[test]
fn synced_comes_once_within_half_a_step_not_at_half_a_step() {
    // 668 steps a turn and a phase of 0.270°: 32 833 / 65536 step, half a
    // step and max-accel (65 a tick² at 20 kHz). Synced at rest, then
    // nudged: the follower starts at max-accel, so after one tick it is
    // exactly half a step short (32 768) at 65 a tick, after two 32 638
    // short at 130 a tick.
    let c = Config { motor_steps_per_rev: 668, ..Config::default() };
    let mut r = Rig::new(c);
    let a = r.c.derived().limits.max_accel;
    r.c.engage().unwrap();
    r.tick(0);
    assert_eq!(r.c.state(), State::Synced);
    r.c.set_config(c.with("phase", "0.270").unwrap()).unwrap();
    assert_eq!(r.c.derived().phase_offset_q16, 32_768 + a, "half a step and max-accel");
    assert_eq!(r.c.state(), State::Engaging);
    r.tick(0);
    assert_eq!(r.c.follower().velocity, a);
    assert_eq!(r.c.state(), State::Engaging, "exactly half a step off: not yet");
    r.tick(0);
    assert_eq!(r.c.follower().velocity, 2 * a);
    assert_eq!(
        r.c.state(),
        State::Synced,
        "closer than half a step, 2 × max-accel ≤ 4 × max-accel off the target's speed"
    );
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

/// The mean of (gear − cutter), in counts, over a second at a steady 0.8
/// lathe counts a tick, with an idealised BLDC (the fastest the settings
/// take: a 20 kHz PWM, τ 1 ms): its encoder, read at each tick's instant
/// as the lathe's is, turns by each command during the tick after it.
fn bldc_steady_mean_error() -> f64 {
    let c = Config {
        drive: DriveKind::Bldc,
        bldc_out: crate::config::BldcOut::Pwm,
        pwm_hz: 20_000,
        bldc_tau_ms: 1,
        ..Config::default()
    };
    let mut ctl = Controller::new(c, Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    ctl.engage().unwrap();
    let (mut lathe_milli, mut cutter_q16, mut sum) = (0i64, 0i64, 0i64);
    let hz = Timing::FIRMWARE.tick_hz as i64;
    for k in 0..3 * hz {
        // 1 s from rest to 0.8 counts a tick, then 2 s steady
        lathe_milli += (k * 800 / hz).min(800);
        let (lathe, cutter) = (lathe_milli / 1_000, cutter_q16 >> 16);
        let input = TickInput { lathe: lathe as u16, cutter: cutter as u16, ..TickInput::default() };
        cutter_q16 += ctl.tick(&input).speed_q16 as i64;
        if k >= 2 * hz {
            // 8/3 counts of the cutter a lathe count: in thirds of a count
            sum += 8 * lathe - 3 * cutter;
        }
        assert_eq!(ctl.fault(), None, "tick {k}");
    }
    sum as f64 / 3.0 / hz as f64
}

#[test]
fn a_bldc_cutter_is_held_on_the_gear_at_the_ticks_instant_not_a_tick_ahead() {
    // a tick ahead is 0.8 × 8/3 = 2.1 counts; the encoder's whole counts
    // cost half a count on average (it reads the count it has reached)
    let mean = bldc_steady_mean_error();
    assert!(mean.abs() < 1.0, "{mean:.2} counts");
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
