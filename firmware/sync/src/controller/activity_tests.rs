//! The activity rule (`activity.rs`): one activity at a time, each start
//! refused with the reason the rule gives, whatever asks.

use super::activity::Asked;
use super::*;
use crate::config::Config;

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

/// What each start gets, by the command itself and by the rule.
fn starts(c: &Controller) -> [(Asked, Result<(), Refusal>); 5] {
    [Asked::Engage, Asked::Jog, Asked::Check, Asked::SelfTest, Asked::Dfu].map(|a| (a, c.admit(a)))
}

#[test]
fn while_one_activity_runs_every_other_start_is_refused_with_its_reason() {
    use Refusal::*;
    let mut jogging = ctl();
    jogging.jog(90_000).unwrap();
    let mut checking = ctl();
    checking.start_encoder_check().unwrap();
    let mut testing = ctl();
    testing.start_selftest(None).unwrap();
    for (c, why, own) in
        [(&jogging, Moving, None), (&checking, Checking, Some(Asked::Check)), (&testing, SelfTesting, None)]
    {
        for (asked, got) in starts(c) {
            let want = if Some(asked) == own { Ok(()) } else { Err(why) };
            assert_eq!(got, want, "{asked:?} while {why:?}");
        }
    }
    // the commands say the same
    assert_eq!(jogging.engage(), Err(Moving));
    assert_eq!(checking.jog(90_000).err(), Some(Checking));
    assert_eq!(testing.engage(), Err(SelfTesting));
    assert_eq!(testing.jog(90_000).err(), Some(SelfTesting));
    assert_eq!(testing.start_encoder_check(), Err(SelfTesting));
    assert_eq!(checking.start_selftest(None).err(), Some(selftest::SelfTestRefusal::Checking));
}

#[test]
fn with_nothing_running_the_cutters_state_decides() {
    use Refusal::*;
    let mut c = ctl();
    assert!(starts(&c).iter().all(|(_, r)| r.is_ok()), "idle: all may start");
    c.engage().unwrap();
    let engaged = [Err(Busy), Err(Engaged), Err(CutterRunning), Err(NotIdle), Err(DfuNotIdle)];
    assert_eq!(starts(&c).map(|(_, r)| r), engaged);
    c.trip(crate::state::Fault::EStop);
    assert_eq!(starts(&c).map(|(_, r)| r), [Err(Faulted), Err(Faulted), Err(Faulted), Err(Faulted), Err(DfuNotIdle)]);
}

/// The jog's activity ends with its state: a fault during a jog leaves
/// nothing running once cleared.
#[test]
fn a_fault_during_a_jog_ends_it_and_after_clear_a_jog_starts_again() {
    let mut c = ctl();
    c.jog(90_000).unwrap();
    c.tick(&TickInput::default());
    c.tick(&TickInput { estop_open: true, ..TickInput::default() });
    assert_eq!(c.state(), State::Fault(crate::state::Fault::EStop));
    c.tick(&TickInput::default());
    c.clear();
    assert_eq!(c.state(), State::Idle);
    assert!(c.start_encoder_check().is_ok(), "no jog left running");
    c.stop_encoder_check();
    assert!(c.jog(90_000).is_ok());
}

/// The last self-test's figures stay until the next one starts, whatever
/// runs between.
#[test]
fn the_last_self_tests_figures_outlive_other_activities() {
    let mut c = ctl();
    c.start_selftest(None).unwrap();
    let stopped = c.stop_selftest().unwrap();
    for _ in 0..25_000 {
        c.tick(&TickInput::default());
    }
    assert_eq!(c.state(), State::Idle);
    c.start_encoder_check().unwrap();
    c.stop_encoder_check();
    assert_eq!(c.selftest_report(), Some(stopped));
}
