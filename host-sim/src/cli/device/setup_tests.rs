//! The guided setup against the real console (a fake board whose machine
//! turns and steps): the non-interactive form from flags, and the
//! interview with scripted answers.

use super::*;
use crate::cli::device::prompt::Scripted;
use crate::cli::device::tests::{session, FakeDevice};
use clap::Parser;
use polyturn_bench::fakeboard::{ticks_in_ms, Workshop};
use polyturn_sync::Config;

#[derive(Parser)]
struct Line {
    #[command(flatten)]
    a: GuidedArgs,
}

fn args(flags: &str) -> GuidedArgs {
    try_args(flags).unwrap()
}

fn try_args(flags: &str) -> Result<GuidedArgs, clap::Error> {
    Line::try_parse_from(std::iter::once("setup").chain(flags.split_whitespace())).map(|l| l.a)
}

/// The commands the board received, tags removed.
fn sent(s: &Session<FakeDevice>) -> Vec<String> {
    s.io.received.iter().map(|l| l.split_once(' ').map_or(l.clone(), |(_, c)| c.to_string())).collect()
}

#[test]
fn the_non_interactive_setup_derives_sends_and_saves_the_settings() {
    let mut s = session(FakeDevice::new());
    let a = args("--non-interactive --encoder-lines 1000 --microsteps 8 --reduction 40/20 --max-lathe-rpm 600 --pulse-us 2.5 --encoder-reversed");
    let out = run(&mut s, &a, &mut Scripted::new(&[])).unwrap();
    let c = *s.io.ctl.config();
    assert_eq!((c.encoder_counts_per_rev, c.motor_steps_per_rev, c.max_lathe_rpm), (4_000, 3_200, 600));
    assert_eq!((c.sense, c.step_pulse_ns), (polyturn_sync::Sense::Opposite, 2_500), "a reversed encoder flips dir");
    assert_eq!(sent(&s).iter().rev().take(2).collect::<Vec<_>>(), ["get", "save"], "saved, then read back");
    assert!(out.contains("at ratio 2: 8/5 motor steps per encoder count"), "{out}");
    assert!(out.contains("ratio    4:   600 rpm"), "{out}");
}

#[test]
fn a_shaft_encoder_is_set_for_the_lost_step_alarm_and_the_summary_says_what_it_does() {
    let mut s = session(FakeDevice::new());
    let a = args("--non-interactive --encoder-lines 600 --max-lathe-rpm 600 --cutter-encoder-cpr 4000 --no-save");
    let out = run(&mut s, &a, &mut Scripted::new(&[])).unwrap();
    assert_eq!(s.io.ctl.config().cutter_encoder_cpr, 4_000);
    assert!(out.contains("lost-step alarm: the shaft encoder's 4000 counts per cutter turn"), "{out}");
    // without the flag the board's setting stays; out of range is refused
    let mut s = session(FakeDevice::new());
    run(&mut s, &args("--non-interactive --encoder-lines 600 --max-lathe-rpm 600 --no-save"), &mut Scripted::new(&[]))
        .unwrap();
    assert!(!sent(&s).iter().any(|c| c.starts_with("set cutter-cpr")), "{:?}", sent(&s));
    assert!(try_args("--non-interactive --cutter-encoder-cpr 2").is_err());
}

#[test]
fn a_start_rate_is_set_and_the_summary_says_what_catches_a_start_too_fast() {
    let base = "--non-interactive --encoder-lines 600 --max-lathe-rpm 600 --no-save";
    let mut s = session(FakeDevice::new());
    let out = run(&mut s, &args(&format!("{base} --start-rate 3200")), &mut Scripted::new(&[])).unwrap();
    assert_eq!(s.io.ctl.config().start_rate_hz, 3_200);
    assert!(out.contains("start-rate 3200 steps/s") && out.contains("silently, with no shaft encoder"), "{out}");
    let mut s = session(FakeDevice::new());
    let flags = format!("{base} --start-rate 3200 --cutter-encoder-cpr 4000");
    let out = run(&mut s, &args(&flags), &mut Scripted::new(&[])).unwrap();
    assert!(out.contains("the lost-step alarm stops it"), "{out}");
    // without the flag the board's setting stays, and nothing is said
    let mut s = session(FakeDevice::new());
    let out = run(&mut s, &args(base), &mut Scripted::new(&[])).unwrap();
    assert!(!sent(&s).iter().any(|c| c.starts_with("set start-rate")) && !out.contains("start-rate"), "{out}");
    // past the console's range: refused by the flag; past max-rate: by the rule
    assert!(try_args("--start-rate 250001").is_err());
    let mut s = session(FakeDevice::new());
    s.ask("set max-rpm 600").unwrap();
    s.ask("set max-rate 100000").unwrap();
    let e = run(&mut s, &args(&format!("{base} --start-rate 150000")), &mut Scripted::new(&[])).unwrap_err();
    assert_eq!(e.0, "--start-rate must be at most 100000 steps/s, the board's max-rate (got 150000)");
    assert!(!sent(&s).iter().any(|l| l.starts_with("set start-rate")), "{:?}", sent(&s));
}

#[test]
fn settings_that_only_fit_in_one_order_are_sent_in_it() {
    // 8000 steps at the default 1500 rpm would need 400 kHz: max-rpm first
    let mut s = session(FakeDevice::new());
    let a = args("--non-interactive --encoder-lines 600 --microsteps 40 --max-lathe-rpm 600 --no-save");
    let out = run(&mut s, &a, &mut Scripted::new(&[])).unwrap();
    let order: Vec<String> = sent(&s).into_iter().filter(|l| l.starts_with("set ")).collect();
    let at = |cmd: &str| order.iter().position(|l| l.starts_with(cmd)).unwrap();
    assert!(at("set max-rpm") < at("set steps"), "{order:?}");
    assert_eq!(s.io.ctl.config().motor_steps_per_rev, 8_000);
    assert!(!sent(&s).contains(&"save".to_string()) && out.contains("not saved"));
}

#[test]
fn missing_or_impossible_facts_change_nothing_on_the_board() {
    let mut s = session(FakeDevice::new());
    let e = run(&mut s, &args("--non-interactive --encoder-lines 600"), &mut Scripted::new(&[])).unwrap_err();
    assert!(e.0.starts_with("--max-lathe-rpm is needed"), "{}", e.0);
    let e = run(
        &mut s,
        &args("--non-interactive --encoder-lines 600 --microsteps 400 --max-lathe-rpm 3000"),
        &mut Scripted::new(&[]),
    )
    .unwrap_err();
    // 3 000 rpm x ratio 2 x 80 000 steps: the speed the motor can follow is named
    assert!(e.0.starts_with("--max-lathe-rpm must be <= 75 rpm at the board's ratio 2 (steps does not fit with the others: max-rpm x ratio x steps/60 must not exceed max-rate"), "{}", e.0);
    assert!(e.0.ends_with("(got 3000)"), "{}", e.0);
    let e = run(&mut s, &args("--non-interactive --encoder-lines 600 --motor-steps 200 --microsteps 1 --reduction 37/21 --max-lathe-rpm 600"), &mut Scripted::new(&[])).unwrap_err();
    assert!(e.0.starts_with("--motor-steps x --microsteps x --reduction: 200 x 1 x 37/21"), "{}", e.0);
    assert!(sent(&s).iter().all(|l| !l.starts_with("set ")), "{:?}", sent(&s));
    assert_eq!(*s.io.ctl.config(), Config::default());
}

/// A board whose 2 000-count lathe the machinist turns for the encoder
/// check (and only then), at 2 500 counts/s.
fn hand_turned() -> Session<FakeDevice> {
    hand_turned_at(4_400)
}

/// `hand_turned`, `ms` of the board passing before each line (the
/// check's hand still takes 4.4 s).
fn hand_turned_at(ms: u64) -> Session<FakeDevice> {
    let mut dev = FakeDevice::new();
    let mut m = Workshop::new(ticks_in_ms(ms));
    m.turn_at(2_500);
    (m.cpr, m.turn_for_check, m.check_ticks) = (2_000, true, ticks_in_ms(4_400));
    dev.workshop = Some(m);
    let mut s = session(dev);
    s.timeout = std::time::Duration::from_secs(30);
    s
}

/// A machinist who answers at once: 40 ms of the board between lines, so
/// the jog comes 80 ms after the last setting is sent, and the save 40 ms
/// after `set dir`. The lathe has rested since the check: both go.
#[test]
fn the_interview_answered_at_once_jogs_and_saves() {
    let mut s = hand_turned_at(40);
    let mut ask = Scripted::new(INTERVIEW);
    let out = run(&mut s, &args(""), &mut ask).unwrap_or_else(|e| panic!("{e:?} after {:?}", sent(&s)));
    let cmds = sent(&s);
    assert!(cmds.contains(&"jog 360".to_string()), "{cmds:?}");
    assert_eq!(cmds.iter().rev().take(2).collect::<Vec<_>>(), ["get", "save"], "saved, then read back: {cmds:?}");
    assert!(out.contains("ok saving"), "{out}");
    assert_eq!(s.io.ctl.config().sense, polyturn_sync::Sense::Opposite);
}

/// The non-interactive setup, each line 1 ms of the board apart and a
/// timeout of 10 ms: the save right after the settings is saved.
#[test]
fn the_non_interactive_setup_saves_at_once_after_its_settings() {
    let mut dev = FakeDevice::new();
    dev.workshop = Some(Workshop::new(ticks_in_ms(1)));
    let mut s = session(dev);
    s.timeout = std::time::Duration::from_millis(10);
    let a = args("--non-interactive --encoder-lines 1000 --microsteps 8 --max-lathe-rpm 600");
    let out = run(&mut s, &a, &mut Scripted::new(&[])).unwrap_or_else(|e| panic!("{e:?} after {:?}", sent(&s)));
    assert_eq!(sent(&s).iter().filter(|l| *l == "save").count(), 1, "{:?}", sent(&s));
    assert!(out.ends_with("ok saving"), "{out}");
}

/// The interview's answers, in order.
const INTERVIEW: &[&str] = &[
    "y",
    "",
    "y", // index; turn the chuck; use the measured cpr
    "a stepper",
    "200",
    "16",
    "direct",
    "same",
    "1000",
    "2500",
    "5000", // motor, sense, lathe, driver
    "n",    // no shaft encoder (the fake board has none: a jog would trip lost-steps)
    "1600", // the start rate found on the bench
    "",
    "one turn",
    "n", // the jog: one turn, but the wrong way
];

/// The cutter check after the settings went to the board: a jog that did
/// not make one turn ends the setup, saying the settings are on the
/// board, unsaved.
#[test]
fn a_setup_stopped_after_its_settings_were_sent_says_so() {
    let mut s = hand_turned();
    let mut answers = INTERVIEW.to_vec();
    *answers.iter_mut().rev().nth(1).unwrap() = "two turns";
    let e = run(&mut s, &args(""), &mut Scripted::new(&answers)).unwrap_err().0;
    assert_eq!(
        e,
        "setup: the cutter did not make one turn (settings sent, not saved): `polyturn device get` shows what the board holds, a restart drops them"
    );
    assert!(!sent(&s).contains(&"save".to_string()), "{:?}", sent(&s));
    assert_eq!(s.io.ctl.config().encoder_counts_per_rev, 2_000, "sent, as the error says");
}

/// A top speed the motor cannot follow at the board's ratio is asked
/// again with its bound, not refused with every answer at the end.
#[test]
fn a_top_speed_too_fast_for_the_boards_ratio_is_asked_again_with_its_bound() {
    let mut s = hand_turned();
    let mut answers = INTERVIEW.to_vec();
    let at = answers.iter().position(|a| *a == "1000").unwrap();
    answers[at] = "5000";
    let after = answers.iter().position(|a| *a == "1600").unwrap();
    answers.insert(after + 1, "1800");
    let mut ask = Scripted::new(&answers);
    run(&mut s, &args(""), &mut ask).unwrap_or_else(|e| panic!("{e:?}: {:?}", ask.said));
    let told = ask.said.iter().find(|l| l.starts_with("5000 rpm is too fast")).expect("told");
    assert!(told.ends_with(": at most 1875 rpm"), "{told}");
    assert_eq!(s.io.ctl.config().max_lathe_rpm, 1_800);
}

#[test]
fn the_interview_measures_the_encoder_jogs_the_cutter_and_saves() {
    let mut s = hand_turned();
    let mut ask = Scripted::new(INTERVIEW);
    let out = run(&mut s, &args(""), &mut ask).unwrap_or_else(|e| panic!("{e:?} after {:?}", sent(&s)));
    let c = *s.io.ctl.config();
    assert_eq!(c.encoder_counts_per_rev, 2_000, "measured by the check, not the default 2400");
    assert_eq!((c.motor_steps_per_rev, c.max_lathe_rpm), (3_200, 1_000));
    assert_eq!(c.sense, polyturn_sync::Sense::Opposite, "the jog turned the wrong way: dir flipped");
    assert_eq!((c.cutter_encoder_cpr, c.start_rate_hz), (0, 1_600));
    assert!(sent(&s).contains(&"set cutter-cpr off".to_string()), "{:?}", sent(&s));
    assert!(out.contains("start-rate 1600 steps/s: engaged at rest"), "{out}");
    let cmds = sent(&s);
    assert!(cmds.contains(&"jog 360".to_string()) && cmds[cmds.len() - 2] == "save", "{cmds:?}");
    assert!(ask.said.iter().any(|l| l.contains("proposed: set cpr 2000")), "{:?}", ask.said);
    assert!(out.contains("ok saving") || out.contains("saving"), "{out}");
}

const BLDC: &str = "--non-interactive --drive bldc --encoder-lines 600 --max-lathe-rpm 600 --cutter-encoder-cpr 4000 --cutter-max-rpm 3000 --no-save";

#[test]
fn a_bldc_cutter_is_set_from_its_drive_its_encoder_and_its_full_speed() {
    let mut s = session(FakeDevice::new());
    let out = run(&mut s, &args(&format!("{BLDC} --bldc-out pwm --pwm-hz 2000 --bldc-tau 5")), &mut Scripted::new(&[]))
        .unwrap();
    let c = *s.io.ctl.config();
    assert_eq!(
        (c.drive, c.bldc_out, c.pwm_hz, c.bldc_tau_ms),
        (polyturn_sync::DriveKind::Bldc, polyturn_sync::config::BldcOut::Pwm, 2_000, 5)
    );
    assert_eq!((c.motor_steps_per_rev, c.max_step_rate_hz), (4_000, 200_000), "its encoder; 3 000 rpm of it");
    assert!(out.contains("bldc-out pwm at 2000 Hz") && out.contains("expect the cutter within about 0.7°"), "{out}");
    assert!(!out.contains("bldc-tau is still the default"), "{out}");
    // an RC ESC: ferror is twice what it is expected to reach, 2 x 2° of
    // 40 000 counts, and of 4 000 counts 45
    let mut s = session(FakeDevice::new());
    let fine = "--non-interactive --drive bldc --encoder-lines 600 --max-lathe-rpm 100 --cutter-encoder-cpr 40000 --cutter-max-rpm 300 --no-save";
    run(&mut s, &args(&format!("{fine} --bldc-out esc400")), &mut Scripted::new(&[])).unwrap();
    assert_eq!(s.io.ctl.config().following_error_limit_steps, 445);
    run(&mut s, &args(&format!("{BLDC} --bldc-out esc400")), &mut Scripted::new(&[])).unwrap();
    assert_eq!(s.io.ctl.config().following_error_limit_steps, 45);
    // and back to a stepper, by the same setup
    run(&mut s, &args("--non-interactive --encoder-lines 600 --max-lathe-rpm 600 --no-save"), &mut Scripted::new(&[]))
        .unwrap();
    assert_eq!(
        (s.io.ctl.config().drive, s.io.ctl.config().motor_steps_per_rev),
        (polyturn_sync::DriveKind::Stepper, 3_200)
    );
}

#[test]
fn a_bldc_setup_the_drive_cannot_hold_or_a_flag_of_the_other_drive_changes_nothing() {
    for (flags, error) in [
        (BLDC.to_string(), "--bldc-out is needed"),
        (format!("{BLDC} --bldc-out pwm --start-rate 100"), "--start-rate is for a stepper"),
        (format!("{BLDC} --bldc-out esc400 --pwm-hz 2000"), "--pwm-hz is for --bldc-out pwm"),
        ("--non-interactive --encoder-lines 600 --max-lathe-rpm 600 --bldc-out pwm".into(), "--bldc-out is for a BLDC"),
        // 50 frames a second at 1 600 lathe rpm x 2: 53 cutter turns a second
        (
            BLDC.replace("600 --cutter", "1600 --cutter").replace("3000 --no", "3600 --no") + " --bldc-out esc50",
            "--max-lathe-rpm must be <= 1500 rpm at the board's ratio 2 (max-rpm does not fit with the others: the drive must take a command at least once per cutter revolution",
        ),
        // 600 rpm x 2 x 4 000 / 60 = 80 000 counts/s; at full command it makes 1 000 rpm: 66 666
        (BLDC.replace("3000 --no", "1000 --no") + " --bldc-out pwm", "the motor must keep up"),
    ] {
        let mut s = session(FakeDevice::new());
        let e = run(&mut s, &args(&flags), &mut Scripted::new(&[])).unwrap_err();
        assert!(e.0.contains(error), "{flags}: {}", e.0);
        assert!(sent(&s).iter().all(|l| !l.starts_with("set ")), "{flags}: {:?}", sent(&s));
        assert_eq!(*s.io.ctl.config(), Config::default());
    }
    assert!(
        try_args("--drive servo").is_err() && try_args("--pwm-hz 7000").is_err() && try_args("--bldc-out esc").is_err()
    );
}

#[test]
fn the_interview_asks_a_bldcs_drive_and_jogs_it_on_its_encoder() {
    let mut s = hand_turned();
    let mut ask = Scripted::new(&[
        "y",
        "",
        "y", // index; turn the chuck; use the measured cpr
        "a BLDC through a spindle",
        "7000",
        "8000", // a PWM the timer cannot make, then one it can
        "4000",
        "100000",
        "3000",
        "12", // encoder; a full speed past max-rate, then one within; tau
        "same",
        "1000", // sense, lathe
        "",
        "one turn",
        "y", // the jog, on the idealised drive's encoder
    ]);
    let out = run(&mut s, &args(""), &mut ask).unwrap_or_else(|e| panic!("{e:?} after {:?}", sent(&s)));
    let c = *s.io.ctl.config();
    assert_eq!(
        (c.drive, c.pwm_hz, c.bldc_tau_ms, c.motor_steps_per_rev),
        (polyturn_sync::DriveKind::Bldc, 8_000, 12, 4_000)
    );
    assert_eq!((c.max_step_rate_hz, c.max_lathe_rpm), (200_000, 1_000));
    let refused: Vec<&String> = ask.said.iter().filter(|l| l.starts_with("refused: ")).collect();
    assert_eq!(refused.len(), 2, "{:?}", ask.said);
    assert!(refused[0].contains("pwm-hz 7000") && refused[1].contains("--cutter-max-rpm"), "{refused:?}");
    assert!(!ask.said.iter().any(|l| l.contains("STEP pulse")), "no stepper's question: {:?}", ask.said);
    assert!(out.contains("bldc-out pwm at 8000 Hz"), "{out}");
}

#[test]
fn the_summary_is_what_the_board_holds_after_the_last_save() {
    let mut s = hand_turned();
    let mut ask = Scripted::new(&[
        "y",
        "",
        "y",
        "a stepper",
        "200",
        "16",
        "direct",
        "same",
        "1000",
        "2500",
        "5000",
        "n",
        "0",
        "",
        "one turn",
        "n", // the jog turned the wrong way: dir flipped and saved
    ]);
    let out = run(&mut s, &args(""), &mut ask).unwrap_or_else(|e| panic!("{e:?} after {:?}", sent(&s)));
    assert_eq!(s.io.ctl.config().sense, polyturn_sync::Sense::Opposite);
    let set = out.lines().find(|l| l.starts_with("set: ")).unwrap_or_else(|| panic!("{out}"));
    assert!(set.contains("dir=opposite") && !set.contains("dir=same"), "{out}");
    let cmds = sent(&s);
    let saved = cmds.iter().rposition(|c| c == "save").unwrap();
    assert!(cmds[saved + 1..].iter().any(|c| c == "get"), "read back after the save: {cmds:?}");
}

#[test]
fn a_bldc_setup_refuses_a_steppers_flag_as_every_other_flag_of_the_other_cutter() {
    for flag in ["--motor-steps 400", "--microsteps 8", "--reduction 2", "--pulse-ns 2500", "--dir-setup-ns 5000"] {
        let mut s = session(FakeDevice::new());
        let e = run(&mut s, &args(&format!("{BLDC} --bldc-out pwm {flag}")), &mut Scripted::new(&[])).unwrap_err();
        let name = flag.split(' ').next().unwrap();
        assert_eq!(e.0, format!("{name} is for a stepper (--drive stepper)"), "{flag}");
        assert!(sent(&s).iter().all(|l| !l.starts_with("set ")), "{flag}: {:?}", sent(&s));
    }
}

#[test]
fn a_bldc_setup_clears_what_a_stepper_left_that_would_bind_it() {
    // a stepper's start rate found at 200 000 steps/s, past the BLDC's
    // full scale (1 500 rpm x 4 000 counts / 60 = 100 000 counts/s); and a
    // slow driver's 10 µs pulse, which holds max-rate to 50 000
    let bldc = BLDC.replace("3000 --no", "1500 --no") + " --bldc-out pwm";
    for (board, full_scale) in [
        (&["set start-rate 200000"][..], 100_000),
        (&["set max-rpm 300", "set max-rate 50000", "set pulse 10000"][..], 200_000),
    ] {
        let mut s = session(FakeDevice::new());
        for l in board {
            s.ask(l).unwrap();
        }
        let flags = if full_scale == 100_000 { bldc.clone() } else { format!("{BLDC} --bldc-out pwm") };
        let out = run(&mut s, &args(&flags), &mut Scripted::new(&[])).unwrap_or_else(|e| panic!("{board:?}: {}", e.0));
        let c = *s.io.ctl.config();
        assert_eq!((c.drive, c.max_step_rate_hz), (polyturn_sync::DriveKind::Bldc, full_scale), "{out}");
        assert_eq!((c.start_rate_hz, c.step_pulse_ns), (0, Config::default().step_pulse_ns), "{out}");
        assert!(out.contains("start-rate=0") && out.contains("pulse=2000"), "said: {out}");
    }
}

#[test]
fn every_prompt_takes_the_consoles_range_and_asks_again() {
    let mut s = hand_turned();
    let mut ask = Scripted::new(&[
        "y",
        "",
        "y",
        "a stepper",
        "100000",
        "512",
        "direct", // 51 200 000 steps a cutter turn: past the console's 1 000 000
        "200",
        "16",
        "belt or gears",
        "7",
        "3", // 7/3 of 3 200 steps: no whole number
        "200",
        "16",
        "direct",
        "same",
        "20000", // past max-rpm's 10 000
        "1000",
        "500000", // a pulse past the console's 100 000 ns
        "5000",   // a step of 10 µs: past the board's max-rate of 200 000
        "2500",
        "200000", // a DIR setup past 100 000 ns
        "5000",
        "n",
        "0",
        "",
        "one turn",
        "y",
    ]);
    let out = run(&mut s, &args(""), &mut ask).unwrap_or_else(|e| panic!("{e:?}: {:?}", ask.said));
    let c = *s.io.ctl.config();
    assert_eq!((c.motor_steps_per_rev, c.max_lathe_rpm, c.step_pulse_ns, c.dir_setup_ns), (3_200, 1_000, 2_500, 5_000));
    let refused: Vec<&String> = ask.said.iter().filter(|l| l.starts_with("refused: ")).collect();
    assert_eq!(refused.len(), 6, "{:?}", ask.said);
    assert!(refused[0].contains("1..=1000000 steps per cutter rev"), "{refused:?}");
    assert!(refused[1].contains("not a whole number"), "{refused:?}");
    // the pulse asked within what the board's max-rate allows: a step is
    // a pulse high and as long low
    assert!(refused[2].contains("1..=10000") && refused[3].contains("100..=2500"), "{refused:?}");
    assert!(refused[4].contains("100..=2500"), "{refused:?}");
    assert!(refused[5].contains("0..=100000"), "{refused:?}");
    assert!(out.contains("saving"), "{out}");
}

/// A stepper too fine for the board's ratio even at the slowest lathe
/// speed (1 rpm) is refused naming the flags that make its steps and
/// their bound, and nothing is sent.
#[test]
fn a_stepper_no_lathe_speed_fits_is_refused_naming_its_flags() {
    let mut s = session(FakeDevice::new());
    for set in ["set max-rpm 1", "set steps 200", "set ratio 1000"] {
        s.ask(set).unwrap();
    }
    let before = *s.io.ctl.config();
    // 200 x 512 steps a turn at ratio 1000: 1.7 MHz at 1 rpm, 200 kHz allowed
    let e = run(
        &mut s,
        &args("--non-interactive --encoder-lines 600 --microsteps 512 --max-lathe-rpm 600 --no-save"),
        &mut Scripted::new(&[]),
    )
    .unwrap_err();
    assert_eq!(
        e.0,
        "--motor-steps x --microsteps x --reduction must make at most 12000 steps per cutter turn at the board's ratio 1000: max-rpm x ratio x steps/60 must not exceed its max-rate of 200000 steps/s even at 1 rpm (got 200 x 512 x 1 = 102400)"
    );
    assert!(sent(&s).iter().filter(|l| l.starts_with("set ")).count() == 3, "{:?}", sent(&s));
    assert_eq!(*s.io.ctl.config(), before);
}

/// So is a driver whose pulse is too long for the board's step rate.
#[test]
fn a_driver_pulse_no_step_rate_fits_is_refused_naming_its_flag() {
    let mut s = session(FakeDevice::new());
    // 5 µs high and 5 low: 100 kHz, where the board's max-rate is 200 kHz
    let e = run(
        &mut s,
        &args("--non-interactive --encoder-lines 600 --motor-steps 10 --microsteps 1 --max-lathe-rpm 600 --pulse-ns 5000 --no-save"),
        &mut Scripted::new(&[]),
    )
    .unwrap_err();
    assert_eq!(
        e.0,
        "--pulse-ns must be at most 2500 ns with the board's max-rate of 200000 steps/s: a step is a pulse high and as long low (got 5000)"
    );
    assert!(sent(&s).iter().all(|l| !l.starts_with("set ")), "{:?}", sent(&s));
    assert_eq!(*s.io.ctl.config(), Config::default());
}

/// A BLDC setup on a 1 000-count encoder at 3 000 rpm: max-rate 50 000
/// counts/s and ferror 4 counts, the board's then.
const SLOW_BLDC: &str = "--non-interactive --drive bldc --bldc-out pwm --encoder-lines 600 --max-lathe-rpm 1000 --cutter-encoder-cpr 1000 --cutter-max-rpm 3000 --no-save";

/// A stepper's setup after a BLDC's puts back what the BLDC's set that
/// binds a stepper (`max-rate`, `ferror`), sends them and shows them: the
/// stepper is judged by its own rate, not the BLDC's full speed.
#[test]
fn a_stepper_setup_after_a_bldc_puts_back_the_steppers_max_rate_and_ferror() {
    let mut s = session(FakeDevice::new());
    run(&mut s, &args(SLOW_BLDC), &mut Scripted::new(&[])).unwrap();
    assert_eq!((s.io.ctl.config().max_step_rate_hz, s.io.ctl.config().following_error_limit_steps), (50_000, 4));
    let stepper = "--non-interactive --encoder-lines 600 --max-lathe-rpm 1000 --no-save";
    let out = run(&mut s, &args(stepper), &mut Scripted::new(&[])).unwrap_or_else(|e| panic!("{}", e.0));
    let (c, d) = (*s.io.ctl.config(), Config::default());
    assert_eq!(
        (c.drive, c.max_step_rate_hz, c.max_lathe_rpm),
        (polyturn_sync::DriveKind::Stepper, d.max_step_rate_hz, 1_000)
    );
    assert_eq!(c.following_error_limit_steps, d.following_error_limit_steps);
    let set = out.lines().next().unwrap();
    assert!(set.contains(&format!("max-rate={}", d.max_step_rate_hz)), "{out}");
    assert!(set.contains(&format!("ferror={}", d.following_error_limit_steps)), "{out}");
}

/// A stepper's own max-rate, set by hand, stays through its setup.
#[test]
fn a_stepper_setup_keeps_a_steppers_own_max_rate() {
    let mut s = session(FakeDevice::new());
    s.ask("set max-rpm 600").unwrap();
    s.ask("set max-rate 150000").unwrap();
    let out = run(
        &mut s,
        &args("--non-interactive --encoder-lines 600 --max-lathe-rpm 600 --no-save"),
        &mut Scripted::new(&[]),
    )
    .unwrap();
    assert_eq!(s.io.ctl.config().max_step_rate_hz, 150_000);
    assert!(!out.contains("max-rate="), "{out}");
}

/// The interview too: its lathe speed and start rate are bounded by the
/// stepper's rate, and what it saves is a stepper's.
#[test]
fn the_interview_after_a_bldc_setup_sets_up_a_stepper_not_the_bldcs_rates() {
    let mut s = hand_turned();
    run(&mut s, &args(SLOW_BLDC), &mut Scripted::new(&[])).unwrap();
    let mut answers = INTERVIEW.to_vec();
    answers[12] = "100000"; // a start rate past the BLDC's 50 000
    let out =
        run(&mut s, &args(""), &mut Scripted::new(&answers)).unwrap_or_else(|e| panic!("{e:?} after {:?}", sent(&s)));
    let (c, d) = (*s.io.ctl.config(), Config::default());
    assert_eq!(
        (c.max_step_rate_hz, c.following_error_limit_steps),
        (d.max_step_rate_hz, d.following_error_limit_steps)
    );
    assert_eq!((c.max_lathe_rpm, c.start_rate_hz), (1_000, 100_000), "{out}");
    assert!(out.contains("ferror=") && out.contains("max-rate="), "{out}");
}

/// A start rate past the board's max-rate is refused naming the flag,
/// the bound and the value; with a pulse too long as well, both flags.
#[test]
fn a_start_rate_past_max_rate_is_refused_naming_it_and_a_bad_pulse_too() {
    let base = "--non-interactive --encoder-lines 600 --max-lathe-rpm 1000 --no-save";
    let mut s = session(FakeDevice::new());
    let e = run(&mut s, &args(&format!("{base} --start-rate 250000")), &mut Scripted::new(&[])).unwrap_err();
    assert_eq!(e.0, "--start-rate must be at most 200000 steps/s, the board's max-rate (got 250000)");
    let e = run(&mut s, &args(&format!("{base} --start-rate 250000 --pulse-ns 10000")), &mut Scripted::new(&[]))
        .unwrap_err();
    assert!(e.0.starts_with("--start-rate must be at most 200000 steps/s, the board's max-rate (got 250000); --pulse-ns must be at most 2500 ns"), "{}", e.0);
    assert!(e.0.ends_with("(got 10000)"), "{}", e.0);
    assert!(sent(&s).iter().all(|l| !l.starts_with("set ")), "{:?}", sent(&s));
    assert_eq!(*s.io.ctl.config(), Config::default());
}

/// `--pulse-us` is refused in its own words and the value typed.
#[test]
fn a_pulse_in_microseconds_too_long_is_refused_naming_pulse_us() {
    let mut s = session(FakeDevice::new());
    let flags = "--non-interactive --encoder-lines 600 --max-lathe-rpm 1000 --pulse-us 2.5000001 --no-save";
    let e = run(&mut s, &args(flags), &mut Scripted::new(&[])).unwrap_err();
    assert!(
        e.0.starts_with("--pulse-us must be at most 2.5 us with the board's max-rate of 200000 steps/s"),
        "{}",
        e.0
    );
    assert!(e.0.ends_with("(got 2.5000001, 2501 ns rounded up)"), "{}", e.0);
    assert_eq!(*s.io.ctl.config(), Config::default());
}

/// The flags of `--non-interactive` are refused before any port is
/// opened: a wrong port does not hide them.
#[test]
fn a_non_interactive_setups_flags_are_refused_before_the_port_is_opened() {
    let line = |l: &str| crate::cli::dispatch(&l.split(' ').map(String::from).collect::<Vec<_>>()).unwrap_err().0;
    let e = line("device --port /nonexistent-port setup --non-interactive --drive bldc --motor-steps 200 --encoder-lines 600 --max-lathe-rpm 1000");
    assert!(e.starts_with("--motor-steps is for a stepper"), "{e}");
    let e = line("device --port /nonexistent-port setup --non-interactive --encoder-lines 600");
    assert!(e.starts_with("--max-lathe-rpm is needed"), "{e}");
}

/// A time constant given as measured is not called the default, even at
/// the default's value; and a BLDC's figures are its encoder's counts,
/// not motor steps.
#[test]
fn a_bldc_summary_takes_a_given_time_constant_and_speaks_of_encoder_counts() {
    let mut s = session(FakeDevice::new());
    let out = run(&mut s, &args(&format!("{BLDC} --bldc-out pwm --bldc-tau 20")), &mut Scripted::new(&[])).unwrap();
    assert_eq!(s.io.ctl.config().bldc_tau_ms, 20);
    assert!(!out.contains("bldc-tau is still the default"), "{out}");
    assert!(!out.contains("motor steps") && !out.contains("steps/s"), "{out}");
    assert!(
        out.contains("cutter encoder counts per lathe encoder count") && out.contains("max-rate 200000 counts/s"),
        "{out}"
    );
    // not given: the default is pointed out
    let mut s = session(FakeDevice::new());
    let out = run(&mut s, &args(&format!("{BLDC} --bldc-out pwm")), &mut Scripted::new(&[])).unwrap();
    assert!(out.contains("bldc-tau is still the default"), "{out}");
}

/// Ctrl-C at a question asked again while its answers make no setting
/// (the motor's full steps, the PWM frequency): the setup ends there, as
/// at any other question, with nothing sent to save.
#[test]
fn ctrl_c_at_a_question_asked_again_ends_the_setup_at_once() {
    let stepper = ["y", "", "y", "a stepper", "^C", "200", "16"];
    let pwm = ["y", "", "y", "a BLDC through a spindle", "^C", "8000"];
    for (answers, question) in [(&stepper[..], "Motor full steps per turn"), (&pwm[..], "The PWM frequency")] {
        let mut s = hand_turned();
        let mut ask = Scripted::new(answers);
        let e = run(&mut s, &args(""), &mut ask).unwrap_err();
        assert_eq!(e.0, "scripted: cancelled (Ctrl-C): nothing saved", "{:?}", ask.said);
        assert_eq!(ask.said.iter().filter(|l| l.contains(question)).count(), 1, "asked again: {:?}", ask.said);
        assert!(!ask.said.iter().any(|l| l.starts_with("refused: ")), "{:?}", ask.said);
        assert!(!sent(&s).contains(&"save".to_string()), "{:?}", sent(&s));
    }
}
