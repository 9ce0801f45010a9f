//! Scenarios: faults fire on their condition, stop as their policy says.

use polyturn_host::geometry::Direction;
use polyturn_host::sim::{Event, Start};
use polyturn_scenarios::*;
use polyturn_sync::{Controller, DriveKind, Fault, Refusal, TickInput, Timing};

#[test]
fn overspeed_refuses_to_engage_with_a_reason() {
    // 4:1 at 2 counts a tick (1000 rpm at 20 kHz) needs 213 kHz > 200 kHz:
    // refused while the lathe turns.
    let cfg = polyturn_sync::Config::default().with("max-rpm", "900").unwrap().with("ratio", "4").unwrap();
    let mut ctl = Controller::new(cfg, Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    let mut count = 0u16;
    for _ in 0..20_000u32 {
        count = count.wrapping_add(2);
        ctl.tick(&TickInput { lathe: count, ..TickInput::default() });
    }
    assert_eq!(ctl.engage(), Err(Refusal::Overspeed));
    assert!(Refusal::Overspeed.describe().contains("max-rate"));
    assert_eq!(ctl.state(), polyturn_sync::State::Idle);
}

#[test]
fn the_following_error_trips_when_the_motor_is_too_weak() {
    let setup = setup("2", 3, Direction::Same, 1.5);
    let mut sc = scenario(setup, 600.0, 10.0, 0.0, Start::Rest, DriveKind::Bldc);
    sc.bldc_max_torque = 0.02; // far too weak for the cutting load
    sc.bldc_cut_torque = 0.05;
    let r = simulate(&sc);
    assert!(r.faults.iter().any(|(_, f)| matches!(f, Fault::FollowingError | Fault::Stall)), "{:?}", r.faults);
}

#[test]
fn estop_stops_the_steps_at_once() {
    let mut sc = scripted(hexagon(), Start::Spinning, 1200.0, &[(600.0, 1.0), (0.0, 0.1)]);
    sc.events = vec![Event::Engage(0.1), Event::EStop(0.8)];
    let stopped = simulate(&sc);
    assert_eq!(stopped.faults.first().map(|f| f.1), Some(Fault::EStop));
    let (tick, _) = stopped.faults[0];
    assert_eq!(tick, (0.8 * TICK_HZ as f64).ceil() as u64, "latched on the tick the input opened");
    // Without the e-stop the motor would have kept stepping for 0.2 s more
    // (64 kHz): with it, no step after the fault's tick. Engaged at 0.1 s,
    // the cutter caught up (within half a turn) and ran at 64 kHz to 0.8 s.
    sc.events = vec![Event::Engage(0.1)];
    let running = simulate(&sc);
    let at_fault = 64_000.0 * (0.8 - 0.1) + 1_600.0;
    assert!((stopped.steps_emitted as f64) < at_fault + 200.0, "{} steps", stopped.steps_emitted);
    assert!(running.steps_emitted > stopped.steps_emitted + 10_000);
}

#[test]
fn an_encoder_glitch_is_flagged_as_implausible() {
    let mut sc = scenario(hexagon(), 300.0, 10.0, 0.0, Start::Spinning, DriveKind::Stepper);
    sc.events.push(Event::Glitch(TICK_HZ.into(), 400)); // a second in
    let r = simulate(&sc);
    assert_eq!(r.faults.first().map(|f| f.1), Some(Fault::EncoderImplausible), "{:?}", r.faults);
}

// (the BLDC under cutting load: tests/bldc_drives.rs, on the drive the
// firmware really feeds and on the idealised one)
