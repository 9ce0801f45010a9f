use super::*;
use crate::config::Config;
use crate::gear::Scale;

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

#[test]
fn an_implausible_jump_faults_and_clearing_rebases_the_gear_on_the_counter() {
    let mut c = ctl();
    c.tick(&TickInput { lathe: 1000, ..TickInput::default() });
    assert_eq!(c.state(), State::Fault(Fault::EncoderImplausible));
    c.clear();
    assert_eq!(c.state(), State::Idle);
    let d = c.derived().scale;
    assert_eq!(c.status().target_steps, Scale::round(d, 1000), "gear follows the counter again");
}

#[test]
fn estop_and_alarm_halt_at_once_and_drop_enable() {
    for (estop, alarm, fault) in [(true, false, Fault::EStop), (false, true, Fault::DriveAlarm)] {
        let mut c = ctl();
        c.engage().unwrap();
        let out = c.tick(&TickInput { estop_open: estop, alarm, ..TickInput::default() });
        assert_eq!(c.state(), State::Fault(fault));
        assert!(out.halt && !out.enable && out.plan.count == 0);
        assert_eq!(c.engage(), Err(Refusal::Faulted));
    }
}

#[test]
fn enable_is_off_when_idle_and_on_while_engaged() {
    let mut c = ctl();
    assert!(!c.tick(&TickInput::default()).enable);
    c.engage().unwrap();
    assert!(c.tick(&TickInput::default()).enable);
}

#[test]
fn an_estop_during_a_ramped_fault_still_stops_at_once() {
    let mut c = ctl();
    c.engage().unwrap();
    c.trip(Fault::FollowingError);
    let out = c.tick(&TickInput { estop_open: true, ..TickInput::default() });
    assert_eq!(c.state(), State::Fault(Fault::EStop), "the e-stop takes over");
    assert!(out.halt && !out.enable);
    // ...but a ramped fault never replaces an immediate one.
    c.trip(Fault::Overspeed);
    assert_eq!(c.state(), State::Fault(Fault::EStop));
}
