use super::*;
use crate::controller::TickInput;
use crate::timing::Timing;
use proptest::prelude::*;

fn ctl() -> Controller {
    Controller::new(Config::default(), Timing::FIRMWARE)
}

fn say(c: &mut Controller, line: &str) -> (std::string::String, Action) {
    let (r, a) = handle(line.as_bytes(), c);
    (std::string::String::from(r.as_str()), a)
}

#[test]
fn a_machinist_sets_the_ratio_and_direction() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "set max-rpm 600").0, "ok max-rpm=600");
    assert_eq!(say(&mut c, "set ratio 11/3").0, "ok ratio=11/3");
    assert_eq!(say(&mut c, "set dir opposite").0, "ok dir=opposite");
    assert_eq!(say(&mut c, "get ratio").0, "ok ratio=11/3");
    assert!(say(&mut c, "get").0.contains(" dir=opposite "));
    assert!(say(&mut c, "status").0.starts_with("ok state=idle fault=none"));
}

#[test]
fn errors_name_the_field_and_change_nothing() {
    let mut c = ctl();
    let before = *c.config();
    assert_eq!(say(&mut c, "set ratio 0").0, "error: ratio must be greater than 0");
    assert!(say(&mut c, "set edges 40").0.starts_with("error: edges 1..=12"));
    assert!(say(&mut c, "set ratio 100").0.contains("max-rate"));
    assert!(say(&mut c, "set").0.starts_with("error: usage"));
    assert!(say(&mut c, "launch").0.starts_with("error:"));
    assert_eq!(*c.config(), before);
}

/// A negative term is a ratio not greater than 0, whichever term it is,
/// not a syntax error.
#[test]
fn a_negative_ratio_term_is_refused_as_not_positive() {
    let mut c = ctl();
    for ratio in ["-3/2", "3/-2", "-1.5"] {
        assert_eq!(say(&mut c, &std::format!("set ratio {ratio}")).0, "error: ratio must be greater than 0", "{ratio}");
    }
    assert!(!say(&mut c, "set ratio 3/+2").0.contains("greater than 0"), "a plus sign is a syntax error");
}

#[test]
fn save_only_while_idle_and_engage_refuses_while_faulted() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "save"), ("ok saving".into(), Action::Save));
    assert_eq!(say(&mut c, "engage").0, "ok engaging");
    assert_eq!(say(&mut c, "save").1, Action::None);
    assert!(say(&mut c, "set ratio 1").0.starts_with("error: stop first"));
    assert_eq!(say(&mut c, "set phase 10").0, "ok phase=10.000");
    c.trip(crate::state::Fault::EStop);
    assert!(say(&mut c, "engage").0.starts_with("error: a fault is latched"));
    let s = say(&mut c, "status").0;
    assert!(s.contains("fault=estop") && s.contains("reason="), "{s}");
}

proptest! {
    #[test]
    fn any_bytes_get_one_answer_and_errors_change_nothing(line in proptest::collection::vec(any::<u8>(), 0..120)) {
        let mut c = ctl();
        let before = *c.config();
        let (r, _) = handle(&line, &mut c);
        prop_assert!(r.starts_with("ok") || r.starts_with("error: "));
        prop_assert!(!r.contains('\n'));
        if r.starts_with("error") { prop_assert_eq!(*c.config(), before); }
    }

    #[test]
    fn random_set_commands_never_leave_invalid_settings(name in "[a-z-]{1,10}", value in "[-0-9./a-z]{0,12}") {
        let mut c = ctl();
        let line = std::format!("set {name} {value}");
        let _ = handle(line.as_bytes(), &mut c);
        prop_assert_eq!(c.config().validate(), Ok(()));
    }
}

#[test]
fn a_set_prepared_outside_the_lock_installs_what_apply_would() {
    let (mut a, mut b) = (ctl(), ctl());
    let cmd = parse(b"set ratio 5/2");
    let pre = prepare(&cmd, *b.config(), b.config_generation(), b.timing());
    apply(cmd, &mut a);
    apply_prepared(cmd, pre.as_ref(), &mut b);
    assert_eq!(a.config(), b.config());
    assert_eq!(a.derived(), b.derived(), "the figures derived outside are the ones installed");
}

#[test]
fn a_set_prepared_from_stale_settings_changes_nothing() {
    let mut c = ctl();
    let cmd = parse(b"set phase 10");
    let pre = prepare(&cmd, *c.config(), c.config_generation(), c.timing());
    assert_eq!(say(&mut c, "set ratio 5/2").0, "ok ratio=5/2"); // another change lands in between
    let before = *c.config();
    let (reply, _) = render(&apply_prepared(cmd, pre.as_ref(), &mut c));
    assert!(reply.starts_with("error: the settings changed meanwhile"), "{reply}");
    assert_eq!(*c.config(), before);
}

#[test]
fn check_encoder_starts_reports_and_ends() {
    let mut c = ctl();
    c.start(0, 0, 0);
    assert_eq!(say(&mut c, "check-encoder").0, "error: no encoder check running: send check-encoder start");
    assert!(say(&mut c, "check-encoder start").0.starts_with("ok encoder check started: hands off"));
    for t in 1..=4u16 {
        c.tick(&TickInput { lathe: t, ..TickInput::default() });
        c.service();
    }
    assert_eq!(
        say(&mut c, "check-encoder").0,
        "ok encoder moved=0 backward=0 jumps=0 chatter=4 still=measuring indexes=0 skipped=0 gaps=0 gap=none cpr=none"
    );
    assert!(say(&mut c, "check-encoder stop").0.starts_with("ok encoder ended moved=0 "));
    assert!(say(&mut c, "check-encoder stop").0.starts_with("error: no encoder check running"));
    assert!(say(&mut c, "check-encoder now").0.starts_with("error: usage: check-encoder [start|stop]"));
}

#[test]
fn check_encoder_start_and_engage_refuse_each_other_with_the_reason() {
    let mut c = ctl();
    c.start(0, 0, 0);
    assert_eq!(say(&mut c, "engage").0, "ok engaging");
    assert_eq!(
        say(&mut c, "check-encoder start").0,
        "error: stop first: the encoder check has the chuck turned by hand, only with the cutter idle"
    );
    assert!(say(&mut c, "check-encoder").0.starts_with("error: no encoder check running"), "none started");
    let mut c = ctl();
    c.start(0, 0, 0);
    assert!(say(&mut c, "check-encoder start").0.starts_with("ok encoder check started"));
    assert_eq!(
        say(&mut c, "engage").0,
        "error: an encoder check is running (the chuck is being turned by hand): check-encoder stop first"
    );
    assert_eq!(c.state(), crate::state::State::Idle);
    let mut c = ctl();
    c.start(0, 0, 0);
    assert!(say(&mut c, "selftest start").0.starts_with("ok selftest started"));
    assert_eq!(
        say(&mut c, "check-encoder start").0,
        "error: a self-test is running: selftest stop first, then unplug its jumpers"
    );
}

#[test]
fn jog_replies_with_its_steps_and_refuses_bad_angles() {
    let mut c = ctl();
    c.start(0, 0, 0);
    assert_eq!(say(&mut c, "jog -90.5").0, "ok jogging steps=-804 deg=-90.500 rate_hz=1600");
    assert_eq!(c.state(), crate::state::State::Jogging);
    assert_eq!(say(&mut c, "status").0.split(' ').nth(1), Some("state=jogging"));
    assert!(say(&mut c, "jog 10").0.starts_with("error: a jog is running"));
    let mut c = ctl();
    for bad in ["jog", "jog 1 2", "jog 3600.001", "jog ten", "jog 1.2345"] {
        assert!(say(&mut c, bad).0.starts_with("error: usage: jog <degrees"), "{bad}");
    }
    assert!(say(&mut c, "jog 0.01").0.starts_with("error: jog -3600..=3600 degrees"));
}

#[test]
fn dfu_only_while_idle_and_the_reply_comes_first() {
    let mut c = ctl();
    c.start(0, 0, 0);
    let (reply, action) = say(&mut c, "dfu");
    assert!(reply.starts_with("ok restarting into the ROM DFU bootloader"), "{reply}");
    assert_eq!(action, Action::Dfu);
    c.engage().unwrap();
    let (reply, action) = say(&mut c, "dfu");
    assert!(reply.starts_with("error: stop first"), "{reply}");
    assert_eq!(action, Action::None);
}

/// As `engage`, `jog` and `selftest` do: the chuck is being turned by hand,
/// or the self-test's generator plays into the lathe input.
#[test]
fn dfu_is_refused_while_an_encoder_check_or_a_self_test_runs() {
    let mut c = ctl();
    c.start(0, 0, 0);
    assert!(say(&mut c, "check-encoder start").0.starts_with("ok encoder check started"));
    assert_eq!(
        say(&mut c, "dfu"),
        (
            "error: an encoder check is running (the chuck is being turned by hand): check-encoder stop first".into(),
            Action::None
        )
    );
    assert!(say(&mut c, "check-encoder stop").0.starts_with("ok encoder ended"));
    assert!(say(&mut c, "selftest start").0.starts_with("ok selftest started"));
    assert_eq!(
        say(&mut c, "dfu"),
        ("error: a self-test is running: selftest stop first, then unplug its jumpers".into(), Action::None)
    );
    assert!(say(&mut c, "selftest stop").0.starts_with("ok"));
    // a second on
    for _ in 0..crate::Timing::FIRMWARE.tick_hz {
        c.tick(&TickInput::default());
    }
    assert_eq!(say(&mut c, "dfu").1, Action::Dfu, "{}", say(&mut c, "status").0);
}

/// What `polyturn device` takes as a reply: `ok`, `ok `
/// and more, or `error: ` and more; no command starts so, so the echo of
/// one is never taken for its reply.
fn is_reply(r: &str) -> bool {
    r == "ok" || r.starts_with("ok ") || r.starts_with("error: ")
}

#[test]
fn every_reply_starts_with_ok_or_error_so_it_cannot_be_mistaken_for_a_command() {
    let lines = [
        "help",
        "?",
        "get",
        "get cpr",
        "get x",
        "set cpr 4000",
        "set cpr 0",
        "set",
        "set phase 10",
        "engage",
        "status",
        "watch",
        "stop",
        "clear",
        "engage",
        "save",
        "stop",
        "save",
        "defaults",
        "check-encoder",
        "check-encoder start",
        "check-encoder",
        "engage",
        "check-encoder stop",
        "check-encoder x",
        "jog 90",
        "jog 90",
        "stop",
        "jog 1e308",
        "selftest",
        "selftest start 900",
        "selftest start",
        "selftest",
        "check-encoder start",
        "selftest stop",
        "selftest x",
        "dfu",
        "",
        "nonsense",
        "cam begin 2",
        "\u{7f}",
    ];
    let mut c = ctl();
    c.start(0, 0, 0);
    for line in lines {
        let (r, _) = say(&mut c, line);
        assert!(is_reply(&r), "{line:?}: {r:?}");
        let mut fresh = ctl();
        fresh.start(0, 0, 0);
        let (r, _) = say(&mut fresh, line);
        assert!(is_reply(&r), "{line:?} at start: {r:?}");
    }
    assert!(is_reply(&handle(&[0xff, 0xfe], &mut c).0));
    for word in ["get", "set", "engage", "stop", "status", "watch", "save", "defaults", "clear", "cam", "jog"] {
        assert!(!is_reply(word) && !is_reply(&std::format!("{word} x")), "{word}");
    }
    assert!(is_reply(HELP) && is_reply(checks::DFU_REPLY));
}

/// A reply at its longest, with the longest tag and its framing (`#`, the
/// digits, a space), is exactly the 512-byte line `polyturn device` takes.
#[test]
fn a_full_reply_with_the_longest_tag_is_one_512_byte_line() {
    assert_eq!(1 + tag::TAG_DIGITS + 1 + REPLY_LEN, 512);
    assert_eq!(REPLY_LEN, 504);
}

/// A complete cam table is saved only idle with the lathe at rest: at rest
/// it may be (`None`), with counts arriving it waits for the lathe, and
/// engaged for idle, each with its own reason.
#[test]
fn a_cam_table_waits_for_idle_and_a_lathe_at_rest() {
    let mut c = ctl();
    for _ in 0..Timing::FIRMWARE.tick_hz / 5 {
        c.tick(&TickInput::default());
    }
    assert!(cam_wait(&mut c).is_none(), "idle, at rest");
    let mut input = TickInput::default();
    for i in 0..200u16 {
        input.lathe = i;
        c.tick(&input);
    }
    let turning = cam_wait(&mut c);
    assert!(matches!(turning, Some(CamWait::LatheTurning(_))), "{turning:?}");
    assert!(std::format!("{}", turning.unwrap()).starts_with("stop the lathe first: its encoder counted"));
    c.engage().unwrap();
    let running = cam_wait(&mut c);
    assert!(matches!(running, Some(CamWait::Running)), "{running:?}");
    assert_eq!(std::format!("{}", running.unwrap()), "stop first: the cam changes only while idle");
}

/// Engaged, a value that does not fit is told "stop first" (it could not
/// change now anyway), but the phase, which may change while running, is
/// told its range.
#[test]
fn engaged_a_bad_value_is_told_to_stop_first_and_a_bad_phase_its_range() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "engage").0, "ok engaging");
    let steps = say(&mut c, "set steps 0").0;
    assert!(steps.starts_with("error: stop first"), "{steps}");
    let phase = say(&mut c, "set phase 1e9").0;
    assert!(phase.starts_with("error: phase"), "{phase}");
    assert_eq!(say(&mut c, "set phase 5").0, "ok phase=5.000", "the name as the console spells it");
}
