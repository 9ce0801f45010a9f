//! Every command word parsed, `get` for every setting, and the replies of
//! help, watch, stop, clear, defaults and save (docs/src/first-power-up.md, setup.md).

use super::*;
use crate::controller::TickInput;
use crate::state::{Fault, State};

fn ctl() -> Controller {
    let mut c = Controller::new(Config::default(), Timing::FIRMWARE);
    c.start(0, 0, 0);
    c
}

/// The ticks in `ms` milliseconds.
fn ms(ms: u32) -> u32 {
    ms * Timing::FIRMWARE.tick_hz / 1_000
}

fn say(c: &mut Controller, line: &str) -> (std::string::String, Action) {
    let (r, a) = handle(line.as_bytes(), c);
    (r.as_str().into(), a)
}

#[test]
fn each_command_word_parses_to_its_command_and_refuses_extra_words() {
    for (line, cmd) in [
        ("help", Command::Help),
        ("?", Command::Help),
        ("get", Command::GetAll),
        ("engage", Command::Engage),
        ("stop", Command::Stop),
        ("clear", Command::Clear),
        ("status", Command::Status),
        ("watch", Command::Watch),
        ("save", Command::Save),
        ("defaults", Command::Defaults),
        ("dfu", Command::Dfu),
    ] {
        assert_eq!(parse(line.as_bytes()), cmd, "{line}");
        assert_eq!(parse(std::format!("  {line}  ").as_bytes()), cmd, "{line} with spaces");
        let extra = std::format!("{line} now");
        assert!(matches!(parse(extra.as_bytes()), Command::Bad(_)), "{extra}");
    }
    assert_eq!(parse(b"get max-rpm"), Command::Get("max-rpm"));
    assert_eq!(parse(b"set phase -1.5"), Command::Set("phase", "-1.5"));
    assert_eq!(parse(b"get bogus"), Command::Bad("get: unknown name (try help)"));
    assert_eq!(parse(b""), Command::Bad("empty line (try help)"));
}

#[test]
fn help_lists_the_commands_and_every_setting_name() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "help"), (HELP.into(), Action::None));
    assert_eq!(say(&mut c, "?").0, HELP);
    for name in NAMES {
        assert!(HELP.contains(&std::format!(" {name}")), "{name}");
    }
}

#[test]
fn get_shows_every_setting_as_set() {
    let mut c = ctl();
    for (name, value, shown) in [
        ("cpr", "4000", "4000"),
        ("steps", "1600", "1600"),
        ("ratio", "5/2", "5/2"),
        ("dir", "opposite", "opposite"),
        ("edges", "5", "5"),
        ("max-rate", "150000", "150000"),
        ("max-accel", "300000", "300000"),
        ("ferror", "32", "32"),
        ("phase", "-12.5", "-12.500"),
        ("max-rpm", "900", "900"),
        ("drive", "bldc", "bldc"),
        ("dir-setup", "2500", "2500"),
        ("pulse", "1500", "1500"),
        ("enable", "high", "high"),
        ("cutter-cpr", "4000", "4000"),
        ("lost-steps", "48", "48"),
        ("start-rate", "1600", "1600"),
        ("bldc-out", "pwm", "pwm"),
        ("pwm-hz", "5000", "5000"),
        ("bldc-tau", "4", "4"),
    ] {
        let want = std::format!("ok {name}={shown}");
        assert_eq!(say(&mut c, &std::format!("set {name} {value}")).0, want);
        assert_eq!(say(&mut c, &std::format!("get {name}")).0, want);
    }
    assert_eq!(
        say(&mut c, "get").0,
        "ok cpr=4000 steps=1600 ratio=5/2 dir=opposite edges=5 max-rate=150000 max-accel=300000 ferror=32 \
         phase=-12.500 drive=bldc dir-setup=2500 pulse=1500 enable=high max-rpm=900 cutter-cpr=4000 lost-steps=48 start-rate=1600 bldc-out=pwm pwm-hz=5000 bldc-tau=4"
    );
    assert_eq!(say(&mut c, "set cutter-cpr off").0, "ok cutter-cpr=off");
    assert_eq!(
        say(&mut c, "set cutter-cpr 2").0,
        "error: cutter-cpr 4..=1000000 counts per cutter rev, or off",
        "the range named"
    );
    assert_eq!(say(&mut c, "get cutter-cpr").0, "ok cutter-cpr=off", "a refusal changes nothing");
}

#[test]
fn set_ratio_takes_the_shops_colon_and_get_shows_it_as_before() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "set max-rpm 600").0, "ok max-rpm=600");
    for (typed, shown) in [("11:3", "11/3"), ("2:1", "2"), ("5:2", "5/2"), ("2/1", "2"), ("2", "2")] {
        assert_eq!(say(&mut c, &std::format!("set ratio {typed}")).0, std::format!("ok ratio={shown}"), "{typed}");
        assert_eq!(say(&mut c, "get ratio").0, std::format!("ok ratio={shown}"), "{typed}");
    }
    let before = *c.config();
    assert_eq!(say(&mut c, "set ratio 1:0").0, "error: ratio has a zero denominator");
    assert_eq!(
        say(&mut c, "set ratio 2:1:1").0,
        "error: ratio must be an integer, p/q, p:q or a decimal like 2.5 (up to 6 decimals)"
    );
    assert_eq!(*c.config(), before);
}

#[test]
fn the_other_values_of_the_word_settings_read_back() {
    let mut c = ctl();
    for (name, value) in [("drive", "none"), ("drive", "stepper"), ("dir", "same"), ("enable", "low"), ("ratio", "2")] {
        assert_eq!(say(&mut c, &std::format!("set {name} {value}")).0, std::format!("ok {name}={value}"));
    }
    assert_eq!(say(&mut c, "get phase").0, "ok phase=0.000", "no sign on zero");
    assert_eq!(say(&mut c, "set phase -0.5").0, "ok phase=-0.500");
    assert_eq!(say(&mut c, "set phase 0.005").0, "ok phase=0.005");
}

/// A value inside the range but with more decimals than the setting keeps
/// is told the limit, not only the range it is within.
#[test]
fn too_many_decimals_are_told_the_decimals_allowed() {
    let mut c = ctl();
    let before = *c.config();
    assert_eq!(say(&mut c, "set phase 1.2345").0, "error: phase -360..=360 degrees of the cutter, up to 3 decimals");
    assert_eq!(
        say(&mut c, "set ratio 2.0000001").0,
        "error: ratio must be an integer, p/q, p:q or a decimal like 2.5 (up to 6 decimals)"
    );
    assert_eq!(*c.config(), before);
}

#[test]
fn watch_streams_the_status_line() {
    let mut c = ctl();
    let (reply, action) = say(&mut c, "watch");
    assert_eq!(action, Action::Watch);
    assert_eq!(reply, say(&mut c, "status").0);
    assert_eq!(say(&mut c, "status").1, Action::None);
}

#[test]
fn the_status_line_shows_the_measured_speeds() {
    let mut c = ctl();
    // one count a tick on 2400 counts (500 rpm at 20 kHz), the cutter at 2:1
    let lathe_rpm = Timing::FIRMWARE.tick_hz as f64 * 60.0 / 2_400.0;
    for t in 1..=5_000u32 {
        c.tick(&TickInput { lathe: t as u16, ..TickInput::default() });
    }
    let s = say(&mut c, "status").0;
    // idle: the cutter stands, whatever the lathe does
    let idle = std::format!("ok state=idle fault=none lathe_rpm={lathe_rpm:.1} cutter_rpm=0.0 phase_err_steps=");
    assert!(s.starts_with(&idle), "{s}");
    assert!(s.contains(" target=13333 cutter=0 indexed=no "), "5000 × 8/3 = 13333.3: {s}");
    c.engage().unwrap();
    // a step output that makes each plan's pulses two ticks on (`steps::pipe`)
    let (mut emitted, mut pipe) = (0u16, [0u16; 2]);
    for t in 5_001..=30_000u32 {
        let out = c.tick(&TickInput { lathe: t as u16, emitted, ..TickInput::default() });
        let slot = t as usize % 2;
        emitted = emitted.wrapping_add(pipe[slot]);
        pipe[slot] = out.plan.count;
    }
    let s = say(&mut c, "status").0;
    let rpm: f64 = s.split(" cutter_rpm=").nth(1).and_then(|r| r.split(' ').next()).unwrap().parse().unwrap();
    assert!(s.starts_with("ok state=synced ") && (rpm - 2.0 * lathe_rpm).abs() <= 0.1, "synced at 2:1: {s}");
}

#[test]
fn stop_ramps_down_and_clear_answers_with_the_state_it_leaves() {
    let mut c = ctl();
    c.engage().unwrap();
    assert_eq!(say(&mut c, "stop"), ("ok stopping".into(), Action::None));
    assert_eq!(c.state(), State::Disengaging);
    c.trip(Fault::EStop);
    assert_eq!(say(&mut c, "clear").0, "ok idle");
    assert_eq!(c.state(), State::Idle);
}

#[test]
fn defaults_loads_the_defaults_without_saving_and_only_while_idle() {
    let mut c = ctl();
    say(&mut c, "set ratio 5/2");
    assert_eq!(say(&mut c, "defaults"), ("ok defaults loaded (not saved: use save)".into(), Action::None));
    assert_eq!(*c.config(), Config::default());
    say(&mut c, "set ratio 5/2");
    c.engage().unwrap();
    assert_eq!(say(&mut c, "defaults").0, "error: stop first: settings change only while idle");
    assert_eq!(c.config().ratio.den(), 2);
}

#[test]
fn engaged_a_setting_is_told_stop_first_whether_or_not_it_fits_with_the_others() {
    let mut c = ctl();
    c.engage().unwrap();
    let stop = "error: stop first: settings change only while idle";
    // one that fits and one that would not: the same refusal, engaged
    for line in ["set steps 1600", "set steps 6400000", "set max-rate 1", "set start-rate 250000", "set pulse 100000"] {
        assert_eq!(say(&mut c, line).0, stop, "{line}");
    }
    // the phase may change while engaged: its own range is still said
    assert!(say(&mut c, "set phase 999999").0.starts_with("error: phase "), "{:?}", say(&mut c, "set phase 999999"));
    assert_eq!(say(&mut c, "set phase 10").0, "ok phase=10.000");
}

#[test]
fn save_is_refused_while_the_lathe_turns() {
    let mut c = ctl();
    for t in 1..=5_000u16 {
        c.tick(&TickInput { lathe: t, ..TickInput::default() });
    }
    assert_eq!(
        say(&mut c, "save"),
        ("error: stop the lathe first: its encoder counted 0 ms ago (at rest after 100 ms without a count): saving pauses the controller for up to 2 s".into(), Action::None)
    );
    // 40 ms later, what the board saw then
    for _ in 0..ms(40) {
        c.tick(&TickInput { lathe: 5_000, ..TickInput::default() });
    }
    assert!(say(&mut c, "save").0.starts_with("error: stop the lathe first: its encoder counted 40 ms ago (at"));
    assert_eq!(
        say(&mut c, "jog 90").0,
        "error: stop the lathe first: its encoder counted 40 ms ago (at rest after 100 ms without a count): jog only with the lathe at rest"
    );
    // 0.1 s without a count: at rest
    for _ in 0..ms(60) {
        c.tick(&TickInput { lathe: 5_000, ..TickInput::default() });
    }
    assert_eq!(say(&mut c, "save"), ("ok saving".into(), Action::Save));
}

/// A `set` with the lathe at rest leaves it at rest: `set` then `save`, at
/// once, is saved; `set` then `jog`, at once, jogs.
#[test]
fn a_set_with_the_lathe_at_rest_leaves_save_and_jog_free_to_go_at_once() {
    let mut c = ctl();
    for t in 1..=100u16 {
        c.tick(&TickInput { lathe: t, ..TickInput::default() });
    }
    for _ in 0..ms(100) {
        c.tick(&TickInput { lathe: 100, ..TickInput::default() });
    }
    assert_eq!(say(&mut c, "set cpr 1000").0, "ok cpr=1000");
    c.tick(&TickInput { lathe: 100, ..TickInput::default() });
    assert_eq!(say(&mut c, "save"), ("ok saving".into(), Action::Save));
    assert_eq!(say(&mut c, "defaults").0, "ok defaults loaded (not saved: use save)");
    assert_eq!(say(&mut c, "set dir opposite").0, "ok dir=opposite");
    assert!(say(&mut c, "jog 90").0.starts_with("ok jogging"));
}

#[test]
fn engage_with_nothing_to_drive_is_refused_with_the_reason() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "set drive none").0, "ok drive=none");
    assert_eq!(
        say(&mut c, "engage").0,
        "error: drive=none and no cam table: nothing to engage (set drive stepper or bldc, or upload a cam table)"
    );
    assert_eq!(c.state(), State::Idle);
    assert!(!c.tick(&TickInput::default()).enable);
}

#[test]
fn jog_while_engaged_says_the_cutter_runs() {
    let mut c = ctl();
    assert_eq!(say(&mut c, "engage").0, "ok engaging");
    assert_eq!(
        say(&mut c, "jog 90").0,
        "error: stop first: the cutter is engaged or ramping down (jog only while idle)"
    );
}

#[test]
fn a_negative_phase_shows_as_a_negative_phase_error_at_rest() {
    // −90° of a 3200-step cutter: the cutter, at 0, is 800 steps ahead
    let mut c = ctl();
    assert_eq!(say(&mut c, "set phase -90").0, "ok phase=-90.000");
    c.tick(&TickInput::default());
    let s = say(&mut c, "status").0;
    assert!(s.contains(" phase_err_steps=-800.000 target=0 cutter=0 "), "{s}");
}
