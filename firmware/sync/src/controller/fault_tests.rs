//! Faults while running: overspeed, the engage margin, ramped and immediate
//! stops, which fault is kept, and the ramp from Disengaging to Idle.

use super::rig::{per_tick, Rig};
use super::*;
use crate::config::Config;

/// The control tick's rate.
const TICK_HZ: u32 = crate::Timing::FIRMWARE.tick_hz;
/// The default max-rate (200 kHz) in steps a tick: 10 at 20 kHz.
const MAX_STEPS_PER_TICK: f64 = 200_000.0 / TICK_HZ as f64;

/// Default settings: 8/3 steps per count, max-rate 200 kHz =
/// `MAX_STEPS_PER_TICK`, max-accel 400 000 steps/s² = 65/65536 step a
/// tick² at 20 kHz.
fn synced_at(counts_per_tick: f64) -> Rig {
    let mut r = Rig::new(Config::default());
    r.run(per_tick(counts_per_tick), 5_000); // the speed estimate settles
    r.c.engage().unwrap();
    r.until(per_tick(counts_per_tick), 200_000, |c| c.state() == State::Synced);
    r
}

#[test]
fn a_lathe_speeding_up_past_max_rate_while_engaged_trips_overspeed() {
    // 4 counts a tick is plausible (max-rpm 1500: 6 a tick at 20 kHz), but
    // 4 × 8/3 = 10.7 steps a tick is more than the motor's 10
    let mut r = Rig::new(Config::default());
    let d = r.c.derived();
    assert!((4 * 8) << 16 > 3 * d.limits.max_velocity && d.max_counts_per_tick >= 4);
    r.c.engage().unwrap();
    let mut tripped = None;
    for k in 0..5_000 {
        r.tick(per_tick(4.0));
        if let Some(f) = r.c.fault() {
            tripped = Some((k, f));
            break;
        }
    }
    let (k, f) = tripped.expect("overspeed");
    assert_eq!(f, Fault::Overspeed);
    // the estimate passes 3.75 counts a tick (10 steps) well before it settles
    assert!(k < 2_000, "after {k} ticks");
}

#[test]
fn with_no_cutter_a_fast_lathe_is_no_overspeed() {
    // drive=none: there is no motor to outrun (an X axis on a flat cam is
    // what there is to engage)
    static FLAT: [i32; 2] = [0, 0];
    let mut r = Rig::new(Config { drive: DriveKind::None, ..Config::default() });
    let cam = crate::cam::Cam::new(&FLAT, 2_400).unwrap();
    let limits =
        crate::follower::Limits::from_rates(crate::cam_upload::X_MAX_RATE_HZ.into(), 1_000_000, TICK_HZ.into());
    r.c.set_x_axis(Some(XAxis::new(cam, limits))).unwrap();
    r.c.engage().unwrap();
    r.run(per_tick(4.0), 5_000);
    assert_eq!(r.c.state(), State::Synced);
}

/// The motor steps a turn that make one count a tick need exactly 15/16 of
/// max-rate (2400 counts, ratio 1): 22 500 at 20 kHz, 9.375 steps a count.
const MARGIN_STEPS: u32 = 2_400 * 15 * (200_000 / TICK_HZ) / 16;

/// 2400 counts, ratio 1, `steps` a turn; max-rpm is one count a tick.
fn margin_config(steps: u32) -> Config {
    let c = Config {
        ratio: crate::Ratio::new(1, 1).unwrap(),
        motor_steps_per_rev: steps,
        max_lathe_rpm: TICK_HZ * 60 / 2_400,
        ..Config::default()
    };
    assert_eq!(c.validate(), Ok(()));
    c
}

#[test]
fn engage_keeps_a_sixteenth_of_max_rate_in_hand() {
    assert_eq!(MARGIN_STEPS as f64 / 2_400.0, MAX_STEPS_PER_TICK * 15.0 / 16.0, "a whole number of steps");
    // exactly 15/16 of max-rate: allowed
    let mut r = Rig::new(margin_config(MARGIN_STEPS));
    r.run(per_tick(1.0), 5_000);
    assert_eq!(r.c.engage(), Ok(()));
    // a step per turn more: refused, though the motor could still follow it
    let mut r = Rig::new(margin_config(MARGIN_STEPS + 1));
    r.run(per_tick(1.0), 5_000);
    assert_eq!(r.c.engage(), Err(Refusal::Overspeed));
    // ...and engaged at rest, the same speed is no fault: the margin is for
    // engaging only
    let mut r = Rig::new(margin_config(MARGIN_STEPS + 1));
    r.c.engage().unwrap();
    r.run(per_tick(1.0), 5_000);
    assert!(matches!(r.c.state(), State::Engaging | State::Synced));
}

#[test]
fn a_lathe_needing_exactly_max_rate_is_no_overspeed() {
    // 2 steps a count; a max-rpm of 0.8 counts a tick (400 rpm at 20 kHz)
    // makes 3 counts the most a tick may bring (+25 % and 2 counts of
    // jitter), and a max-rate of 6 steps a tick (120 000 at 20 kHz): 3
    // counts a tick need all of it. (The speed estimate overshoots a step
    // in speed, but the target's speed is taken at most at 3 counts a tick.)
    let six_a_tick = 6 * TICK_HZ;
    for (rate, fault) in [(six_a_tick, None), (six_a_tick - 1, Some(Fault::Overspeed))] {
        let c = Config {
            ratio: crate::Ratio::new(1, 1).unwrap(),
            motor_steps_per_rev: 4_800,
            max_step_rate_hz: rate,
            max_lathe_rpm: TICK_HZ / 50,
            ..Config::default()
        };
        assert_eq!(c.validate(), Ok(()));
        let mut r = Rig::new(c);
        assert_eq!(r.c.derived().max_counts_per_tick, 3);
        r.c.engage().unwrap();
        for _ in 0..5_000 {
            r.tick(per_tick(3.0));
        }
        assert_eq!(r.c.fault(), fault, "max-rate {rate}");
    }
}

#[test]
fn engage_refuses_a_lathe_inside_the_margin_either_way() {
    // the counts a tick max-rate follows at 8/3 steps a count (3.75 at 20
    // kHz); 96 % of that is under max-rate, over 15/16 of it
    let most = MAX_STEPS_PER_TICK * 3.0 / 8.0;
    for dir in [1.0, -1.0] {
        let mut r = Rig::new(Config::default());
        r.run(per_tick(0.96 * most * dir), 5_000);
        assert_eq!(r.c.engage(), Err(Refusal::Overspeed), "{dir}");
    }
    // 88 %: inside the margin
    let mut r = Rig::new(Config::default());
    r.run(per_tick(0.88 * most), 5_000);
    assert_eq!(r.c.engage(), Ok(()));
}

#[test]
fn a_ramped_fault_keeps_enable_and_ramps_the_cutter_down_at_max_accel() {
    let mut r = synced_at(0.5);
    let accel = r.c.derived().limits.max_accel;
    assert_eq!(accel, (400_000u64 << 16) as i64 / (TICK_HZ as i64 * TICK_HZ as i64), "400 000 steps/s² a tick², Q16");
    r.c.trip(Fault::FollowingError);
    let mut v = r.c.follower().velocity;
    assert!(v > 10 * accel, "moving: {v}");
    let mut stepping = 0;
    while v != 0 {
        let out = r.tick(per_tick(0.5));
        let now = r.c.follower().velocity;
        assert_eq!(now, (v - accel).max(0), "slows by max-accel a tick");
        // the drive stays enabled while the command moves (not halted)
        assert_eq!((out.enable, out.halt), (now != 0, false));
        stepping += (out.plan.count > 0) as u32;
        v = now;
    }
    assert!(stepping > 0, "steps go out during the ramp");
    let out = r.tick(per_tick(0.5));
    assert!(!out.enable && !out.halt, "stopped: enable off");
    assert_eq!(r.c.state(), State::Fault(Fault::FollowingError));
}

#[test]
fn an_immediate_fault_halts_and_puts_the_command_on_the_cutter() {
    let mut r = synced_at(0.5);
    let out = r.tick_with(per_tick(0.5), TickInput { alarm: true, ..TickInput::default() });
    assert!(out.halt && !out.enable);
    assert_eq!(r.c.state(), State::Fault(Fault::DriveAlarm));
    // no ramp: the command is where the cutter is, at rest
    let f = *r.c.follower();
    assert_eq!((f.velocity, f.position), (0, r.c.status().cutter_steps << 16));
}

#[test]
fn the_first_fault_is_kept_among_ramped_and_among_immediate_ones() {
    let mut r = Rig::new(Config::default());
    r.c.trip(Fault::Overspeed);
    r.c.trip(Fault::FollowingError);
    r.c.trip(Fault::Stall);
    assert_eq!(r.c.fault(), Some(Fault::Overspeed));
    let mut r = Rig::new(Config::default());
    r.c.trip(Fault::EStop);
    r.c.trip(Fault::DriveAlarm);
    r.c.trip(Fault::StepOutput);
    assert_eq!(r.c.fault(), Some(Fault::EStop));
}

#[test]
fn stop_ramps_down_then_goes_idle_when_the_cutter_stands() {
    let mut r = synced_at(0.5);
    r.c.disengage();
    assert_eq!(r.c.state(), State::Disengaging);
    let accel = r.c.derived().limits.max_accel;
    let v0 = r.c.follower().velocity;
    let mut ticks = 0;
    while r.c.state() == State::Disengaging {
        assert_ne!(r.c.follower().velocity, 0, "disengaging while it moves");
        let out = r.tick(per_tick(0.5));
        // enabled until the tick that ends the ramp (then idle)
        assert_eq!(out.enable, r.c.state() == State::Disengaging);
        ticks += 1;
        assert!(ticks < 1 << 20, "never stops"); // (a bounded test)
    }
    assert_eq!(r.c.state(), State::Idle);
    assert_eq!(r.c.follower().velocity, 0);
    // one tick per max-accel of speed, the last one partial
    assert_eq!(ticks, (v0 + accel - 1) / accel);
    assert!(!r.tick(per_tick(0.5)).enable, "idle: enable off");
}
