//! `selftest` through the console: its refusals name the reason and the
//! range, and change nothing.

use crate::console::handle;
use crate::controller::Controller;
use crate::{Config, State, TickInput, Timing};

fn ctl(c: Config) -> Controller {
    let mut c = Controller::new(c, Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

fn reply(c: &mut Controller, line: &str) -> std::string::String {
    std::string::String::from(handle(line.as_bytes(), c).0.as_str())
}

#[test]
fn start_engages_and_says_what_to_wire_and_how_long() {
    let mut c = ctl(Config::default());
    let r = reply(&mut c, "selftest start 250");
    assert_eq!(
        r,
        "ok selftest started rpm=250 cpr=2400 seconds=11.2: jumpers PA2-PA6, PA3-PA7, PA4-PB0 and PB14 to GND; the cutter turns; selftest shows the figures"
    );
    assert_eq!(c.state(), State::Engaging);
    assert_eq!(c.selftest_plan().map(|(_, p)| p.rpm), Some(250));
    let r = reply(&mut c, "selftest");
    assert!(r.starts_with("ok selftest running t=0.0/11.2 leg=rest rests=0/3 rpm=250"), "{r}");
    let r = reply(&mut c, "selftest start");
    assert_eq!(r, "error: stop first (and clear any fault): the self-test engages the gearbox");
}

#[test]
fn stop_ends_it_as_stopped_and_ramps_the_cutter_down() {
    let mut c = ctl(Config::default());
    reply(&mut c, "selftest start");
    let r = reply(&mut c, "selftest stop");
    assert!(r.starts_with("ok selftest fail: stopped before the end; rpm=300"), "{r}");
    assert!(!c.selftest_running());
    assert_eq!(c.selftest_plan(), None);
    assert!(matches!(c.state(), State::Disengaging | State::Idle));
}

#[test]
fn the_rpm_is_refused_outside_what_the_generator_and_settings_allow() {
    let mut c = ctl(Config::default());
    // 12 786 counts/s at 2400 counts a turn: 319 rpm
    assert_eq!(
        reply(&mut c, "selftest start 320"),
        "error: selftest start rpm: 1..=319 (the generator, max-rpm and max-rate allow)"
    );
    assert!(reply(&mut c, "selftest start 999999").contains("1..=319"), "six digits are a number, out of range");
    assert_eq!(
        reply(&mut c, "selftest start 0"),
        "error: selftest start rpm: 1..=319 (the generator, max-rpm and max-rate allow)"
    );
    let slow = Config::default().with("max-rpm", "200").unwrap();
    let mut c = ctl(slow);
    assert!(reply(&mut c, "selftest start 201").contains("1..=200"));
    // 2 × 3200 steps a lathe turn: 7/8 of 20 000 steps/s is 164 rpm
    let weak = Config::default().with("max-rpm", "187").unwrap().with("max-rate", "20000").unwrap();
    let mut c = ctl(weak);
    assert!(reply(&mut c, "selftest start 165").contains("1..=164"));
    assert!(reply(&mut c, "selftest start").contains("rpm=164"), "the default is capped too");
    for bad in [
        "selftest start -5",
        "selftest start 1.5",
        "selftest start 9999999",
        "selftest start +5",
        "selftest start 0500",
    ] {
        let mut c = ctl(Config::default());
        assert!(reply(&mut c, bad).starts_with("error: selftest start rpm: a whole number"), "{bad}");
        assert_eq!(c.state(), State::Idle);
    }
    let mut c = ctl(Config::default());
    assert_eq!(reply(&mut c, "selftest go"), "error: usage: selftest [start [rpm]|stop]");
    assert_eq!(reply(&mut c, "selftest start 5 6"), "error: usage: selftest [start [rpm]|stop]");
    assert_eq!(reply(&mut c, "selftest"), "error: no self-test has run: send selftest start");
}

#[test]
fn it_is_refused_without_a_cutter_with_an_odd_cpr_or_a_turning_lathe() {
    let mut c = ctl(Config::default().with("drive", "none").unwrap());
    assert_eq!(reply(&mut c, "selftest start"), "error: drive=none: there is no cutter to test");
    let mut c = ctl(Config::default().with("drive", "bldc").unwrap());
    assert!(reply(&mut c, "selftest start").starts_with("error: drive=bldc: the self-test checks the step output"));
    let mut c = ctl(Config::default().with("cpr", "1001").unwrap());
    assert_eq!(reply(&mut c, "selftest start"), "error: cpr 1001: the self-test needs an even cpr, 4 or more");
    let mut c = ctl(Config::default());
    let cam = crate::cam::Cam::new(&[0, 100, 0, -100], 2400).unwrap();
    let x = crate::controller::XAxis::new(
        cam,
        crate::follower::Limits::from_rates(1000, 10_000, crate::Timing::FIRMWARE.tick_hz as u64),
    );
    c.set_x_axis(Some(x)).unwrap();
    assert!(reply(&mut c, "selftest start").starts_with("error: a cam table is fitted"));
    let mut c = ctl(Config::default());
    for t in 0..200u16 {
        c.tick(&TickInput { lathe: t, ..TickInput::default() });
    }
    assert!(reply(&mut c, "selftest start").starts_with("error: the lathe input is moving"));
    assert_eq!(c.state(), State::Idle);
    let mut c = ctl(Config::default());
    assert!(reply(&mut c, "check-encoder start").starts_with("ok "));
    assert!(reply(&mut c, "selftest start").starts_with("error: an encoder check is running: check-encoder stop first"));
    assert!(reply(&mut c, "jog 90").starts_with("error: an encoder check is running"));
    assert_eq!(c.state(), State::Idle);
}

#[test]
fn a_start_prepared_from_stale_settings_changes_nothing() {
    use crate::console::{apply_prepared, parse, prepare, render};
    let mut c = ctl(Config::default());
    let cmd = parse(b"selftest start 500");
    let pre = prepare(&cmd, *c.config(), c.config_generation(), c.timing());
    assert_eq!(reply(&mut c, "set ratio 5/2"), "ok ratio=5/2"); // lands in between
    let (r, _) = render(&apply_prepared(cmd, pre.as_ref(), &mut c));
    assert!(r.starts_with("error: the settings changed meanwhile"), "{r}");
    assert_eq!((c.state(), c.selftest_running()), (State::Idle, false));
}

#[test]
fn a_count_mismatch_names_the_likely_wiring_fault() {
    use crate::selftest::Failure;
    let say = |seen, made| {
        let mut out = crate::console::Reply::new();
        super::write_failure(Failure::Counts { rest: 2, seen, made }, &mut out).unwrap();
        std::string::String::from(out.as_str())
    };
    assert_eq!(say(0, 7_200), "rest 2: counted 0, generated 7200: no counts: jumper PA2 to PA6 and PA3 to PA7;");
    assert_eq!(say(-7_200, 7_200), "rest 2: counted -7200, generated 7200: counting backward: PA2 and PA3 swapped;");
    assert!(say(7_199, 7_200)
        .ends_with(": counts lost or doubled: shorter jumpers, and see the README's self-test timing;"));
    assert!(say(7_200, -7_199).contains("counts lost or doubled"), "not quite backward");
}

/// The judge through the controller, in one go as the host runs it
/// (`selftest_books`: the firmware's `selftest_pending`, `judge` and
/// `selftest_judged` around its lock): books that decide nothing keep the
/// run; the generator's end is judged, and ends it with its verdict.
#[test]
fn the_controller_keeps_a_run_its_books_leave_open_and_ends_one_they_decide() {
    use crate::selftest::{Books, Verdict};
    let mut c = ctl(Config::default());
    c.start_selftest(None).unwrap();
    assert!(c.selftest_running());
    let open = Books { counts: 0, indexes: 0, ms: 10, running: true, last_index: None, latency_cycles: 0 };
    c.selftest_books(&open);
    assert!(c.selftest_running(), "nothing decided 10 ms in");
    c.selftest_books(&Books { running: false, ..open });
    assert!(!c.selftest_running(), "the generator stopped: judged, and ended");
    let verdict = c.selftest_report().map(|r| r.verdict);
    assert!(matches!(verdict, Some(Verdict::Fail(_))), "no rest was seen: {verdict:?}");
}
