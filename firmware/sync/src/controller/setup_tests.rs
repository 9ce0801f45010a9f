//! The setup checks through the controller: `jog`, and the
//! index pulses the encoder check counts.

use super::*;
use crate::config::{Config, Sense};
use crate::controller::jog::JOG_SECONDS_PER_TURN;
use crate::steps::Dir;

fn ctl(c: Config) -> Controller {
    let mut c = Controller::new(c, Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

/// Ticks with the lathe at rest and the step output doing what it is told
/// (each plan's pulses counted two ticks later, `steps::pipe`), until the
/// controller is idle again or `limit` ticks; returns (ticks, net steps,
/// the highest step count in a tick).
fn run_jog(c: &mut Controller, limit: usize) -> (usize, i64, u16) {
    run_on(c, &mut Output::default(), limit)
}

/// The step output: pulses counted so far, and the two plans in flight.
#[derive(Default)]
struct Output {
    emitted: u16,
    pipe: [(u16, Option<Dir>); 2],
    t: usize,
}

fn run_on(c: &mut Controller, o: &mut Output, limit: usize) -> (usize, i64, u16) {
    let (mut net, mut most) = (0i64, 0u16);
    for t in 0..limit {
        let out = c.tick(&TickInput { emitted: o.emitted, ..TickInput::default() });
        let (n, dir) = o.pipe[o.t % 2];
        o.emitted = o.emitted.wrapping_add(n);
        net += if dir == Some(Dir::Forward) { n as i64 } else { -(n as i64) };
        o.pipe[o.t % 2] = (out.plan.count, Some(out.plan.dir));
        o.t += 1;
        most = most.max(out.plan.count);
        assert!(c.fault().is_none(), "{:?}", c.state());
        if c.state() == State::Idle {
            return (t, net, most);
        }
    }
    (limit, net, most)
}

#[test]
fn a_jog_of_one_turn_emits_exactly_one_turn_slowly_then_goes_idle() {
    let mut c = ctl(Config::default());
    let plan = c.jog(360_000).unwrap();
    assert_eq!(plan.steps, 3200);
    assert_eq!(plan.rate_hz, 3200 / JOG_SECONDS_PER_TURN);
    assert_eq!(c.state(), State::Jogging);
    let (ticks, net, most) = run_jog(&mut c, 200_000);
    assert_eq!(c.state(), State::Idle, "the jog ended");
    assert_eq!(net, 3200, "one commanded turn is 3200 steps");
    // at most the jog's rate: 1600 steps/s is 0.08 a tick at 20 kHz, so
    // one a tick
    assert_eq!(most, 1);
    // a turn at 1600 steps/s takes 2 s, plus the ramps
    let hz = Timing::FIRMWARE.tick_hz as usize;
    assert!((2 * hz..12 * hz / 5).contains(&ticks), "{ticks} ticks");
    assert!(!c.tick(&TickInput::default()).enable, "idle again: ENABLE off");
}

#[test]
fn a_jog_turns_the_way_the_gear_would_for_the_lathe_counting_up() {
    for (sense, deg, want) in
        [(Sense::Same, 90_000, 800), (Sense::Opposite, 90_000, -800), (Sense::Same, -45_000, -400)]
    {
        let mut c = ctl(Config { sense, ..Config::default() });
        assert_eq!(c.jog(deg).unwrap().steps, want);
        assert_eq!(run_jog(&mut c, 100_000).1, want, "{sense:?} {deg}");
    }
}

#[test]
fn jog_is_refused_while_engaged_faulted_moving_or_with_the_lathe_turning() {
    let mut c = ctl(Config::default());
    c.engage().unwrap();
    assert_eq!(c.jog(90_000), Err(Refusal::Engaged));
    let mut c = ctl(Config::default());
    c.trip(Fault::EStop);
    assert_eq!(c.jog(90_000), Err(Refusal::Faulted));
    let mut c = ctl(Config::default());
    c.jog(90_000).unwrap();
    assert_eq!(c.jog(90_000), Err(Refusal::Moving));
    assert_eq!(c.engage(), Err(Refusal::Moving));
    let mut c = ctl(Config { drive: DriveKind::None, ..Config::default() });
    assert_eq!(c.jog(90_000), Err(Refusal::NoCutter));
    let mut c = ctl(Config::default());
    assert_eq!(c.jog(10), Err(Refusal::JogRange), "0.01 degree is under a step");
    assert_eq!(c.jog(3_600_001), Err(Refusal::JogRange));
    // the lathe turning: 2 counts a tick
    let mut c = ctl(Config::default());
    for t in 1..100u16 {
        c.tick(&TickInput { lathe: t * 2, ..TickInput::default() });
    }
    assert_eq!(c.fault(), None);
    assert_eq!(c.jog(90_000), Err(Refusal::LatheTurning));
}

#[test]
fn stop_ends_a_jog_with_a_ramp_and_an_estop_at_once() {
    let mut c = ctl(Config::default());
    c.jog(360_000).unwrap();
    let mut o = Output::default();
    let (_, before, _) = run_on(&mut c, &mut o, 10_000);
    c.disengage();
    assert_eq!(c.state(), State::Disengaging);
    let (_, after, _) = run_on(&mut c, &mut o, 50_000);
    assert_eq!(c.state(), State::Idle);
    assert!(after > 0 && before + after < 3200, "{before} + {after}");
    let mut c = ctl(Config::default());
    c.jog(360_000).unwrap();
    let _ = run_jog(&mut c, 10_000);
    let out = c.tick(&TickInput { estop_open: true, ..TickInput::default() });
    assert!(out.halt && !out.enable);
}

#[test]
fn a_jog_stops_if_the_lathe_starts_turning() {
    let mut c = ctl(Config::default());
    c.jog(360_000).unwrap();
    let mut o = Output::default();
    let _ = run_on(&mut c, &mut o, 1_000);
    // the lathe moves 5 counts (more than the slack)
    c.tick(&TickInput { lathe: 5, emitted: o.emitted, ..TickInput::default() });
    assert_eq!(c.state(), State::Disengaging);
}

/// A jog is there within half a step of its target, not at half a step:
/// a follower that a tick leaves exactly half a step short goes on.
#[test]
fn a_jog_exactly_half_a_step_short_is_not_there_yet() {
    let mut c = ctl(Config::default());
    let target = crate::q16::from_steps(c.jog(360_000).unwrap().steps);
    let rate = (c.config.motor_steps_per_rev / JOG_SECONDS_PER_TURN).max(1).min(c.config.max_step_rate_hz);
    let a = Limits::from_rates(rate as u64, c.config.max_accel_steps_per_s2 as u64, c.timing.tick_hz as u64).max_accel;
    assert!(a < 1024, "the pull is wider than an acceleration step: {a}");
    // at rest, half a step and one acceleration step short: the tick's
    // track moves it by that step, to exactly half a step short
    c.follower = Follower { position: target - crate::q16::HALF - a, velocity: 0 };
    c.step_jog(target);
    assert_eq!((c.follower.position, c.follower.velocity), (target - crate::q16::HALF, a));
    assert_eq!(c.state(), State::Jogging, "half a step short is not there");
}

#[test]
fn a_jog_started_right_after_a_ramp_still_ends() {
    // the tick that ends a ramp-down leaves the follower between steps
    let mut c = ctl(Config::default());
    let mut o = Output::default();
    c.jog(360_000).unwrap();
    let _ = run_on(&mut c, &mut o, 5_000);
    c.disengage();
    for _ in 0..100_000 {
        let _ = run_on(&mut c, &mut o, 1);
        if c.state() == State::Idle {
            break;
        }
    }
    assert_eq!(c.state(), State::Idle);
    c.jog(90_000).unwrap();
    let (ticks, net, _) = run_on(&mut c, &mut o, 100_000);
    assert_eq!((c.state(), net), (State::Idle, 800));
    // ended on arrival (a quarter turn at 1600 steps/s: 0.5 s and the
    // ramps), not by the deadline's stop
    assert!(ticks < Timing::FIRMWARE.tick_hz as usize * 3 / 5, "{ticks} ticks");
}

#[test]
fn the_tick_counts_index_edges_for_the_encoder_check() {
    let mut c = ctl(Config::default());
    c.start_encoder_check().unwrap();
    // a second hands off, then three turns at 1 count a tick with an index
    // latched every 2400 counts
    for _ in 0..Timing::FIRMWARE.tick_hz {
        c.tick(&TickInput::default());
        c.service();
    }
    for t in 1..=7_300u32 {
        let index = (t % 2400 == 100).then_some(t as u16);
        c.tick(&TickInput { lathe: t as u16, index, ..TickInput::default() });
        c.service();
    }
    let r = c.stop_encoder_check().unwrap();
    assert_eq!((r.moved, r.indexes, r.gap, r.cpr), (7_300, 4, Some((3, 2400, 2400)), Some(2400)));
    assert_eq!(c.encoder_check(), None, "stopped");
}

#[test]
fn a_jog_rounds_to_the_nearest_step_and_takes_up_to_ten_turns() {
    // 68 mdeg is 0.604 step: one step, either way (rounded, not truncated)
    let mut c = ctl(Config::default());
    assert_eq!(c.jog(68).map(|p| p.steps), Ok(1));
    let mut c = ctl(Config::default());
    assert_eq!(c.jog(-68).map(|p| p.steps), Ok(-1));
    let mut c = ctl(Config::default());
    assert_eq!(c.jog(3_600_000).map(|p| p.steps), Ok(32_000), "ten turns exactly");
    let mut c = ctl(Config::default());
    assert_eq!(c.jog(-3_600_001).map(|p| p.steps), Err(Refusal::JogRange));
}

#[test]
fn a_jog_ignores_the_lathe_rocking_by_its_slack_wherever_it_stands() {
    // the lathe at rest at count 1000 (a jog measures from where it is),
    // then rocking 2 counts a tick: within 4 counts the jog goes on, at 5
    // it stops
    let mut c = ctl(Config::default());
    for k in 1..=500u16 {
        c.tick(&TickInput { lathe: 2 * k, ..TickInput::default() });
    }
    for _ in 0..3_000 {
        c.tick(&TickInput { lathe: 1_000, ..TickInput::default() });
    }
    c.jog(90_000).unwrap();
    let mut o = Output::default();
    let mut tick = |c: &mut Controller, lathe: u16| {
        let out = c.tick(&TickInput { lathe, emitted: o.emitted, ..TickInput::default() });
        let (n, _) = o.pipe[o.t % 2];
        o.emitted = o.emitted.wrapping_add(n);
        o.pipe[o.t % 2] = (out.plan.count, Some(out.plan.dir));
        o.t += 1;
    };
    for at in [1_002, 1_004, 1_002, 1_000, 998, 996, 998, 996] {
        tick(&mut c, at);
        assert_eq!(c.state(), State::Jogging, "{at}: within 4 counts");
    }
    tick(&mut c, 995);
    assert_eq!(c.state(), State::Disengaging, "5 counts: the lathe is turning");
}

#[test]
fn the_encoder_check_starts_only_while_idle_so_no_hand_meets_a_turning_cutter() {
    let refused = |c: &mut Controller, why: Refusal| {
        assert_eq!(c.start_encoder_check(), Err(why));
        assert_eq!(c.encoder_check(), None, "{why:?}: no check was started");
    };
    let mut c = ctl(Config::default());
    c.engage().unwrap();
    refused(&mut c, Refusal::CutterRunning);
    c.disengage();
    assert_eq!(c.state(), State::Disengaging);
    refused(&mut c, Refusal::CutterRunning);
    let mut c = ctl(Config::default());
    c.jog(90_000).unwrap();
    refused(&mut c, Refusal::Moving);
    let mut c = ctl(Config::default());
    c.trip(Fault::EStop);
    refused(&mut c, Refusal::Faulted);
    let mut c = ctl(Config::default());
    c.start_selftest(None).unwrap();
    refused(&mut c, Refusal::SelfTesting);
    // synced: the cutter following a lathe at rest
    let mut c = ctl(Config::default());
    c.engage().unwrap();
    for _ in 0..100 {
        c.tick(&TickInput::default());
        c.service();
    }
    assert_eq!(c.state(), State::Synced);
    refused(&mut c, Refusal::CutterRunning);
}

#[test]
fn engage_is_refused_while_an_encoder_check_runs_and_allowed_after_it() {
    let mut c = ctl(Config::default());
    c.start_encoder_check().unwrap();
    assert!(c.encoder_check_running());
    assert_eq!(c.engage(), Err(Refusal::Checking));
    assert_eq!(c.state(), State::Idle);
    c.stop_encoder_check().unwrap();
    assert!(!c.encoder_check_running());
    assert_eq!(c.engage(), Ok(()));
}

#[test]
fn nothing_moves_the_cutter_while_an_encoder_check_has_the_chuck_turned_by_hand() {
    let mut c = ctl(Config::default());
    c.start_encoder_check().unwrap();
    assert_eq!(c.jog(90_000).err(), Some(Refusal::Checking));
    assert_eq!(c.state(), State::Idle);
    let index_before = std::format!("{:?}", c.index);
    assert_eq!(c.start_selftest(None).err(), Some(super::selftest::SelfTestRefusal::Checking));
    assert_eq!(std::format!("{:?}", c.index), index_before, "a refused self-test changes nothing");
    assert!(!c.selftest_running());
    c.stop_encoder_check().unwrap();
    assert!(c.jog(90_000).is_ok(), "after the check the jog goes");
}
