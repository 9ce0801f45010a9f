//! `polyturn simulate`, `cam`, `setups` and `device get` through the real
//! binary: a run that cut nothing, a flag for the other kind of cutter,
//! a derived figure out of range, and ranges taken from the console's
//! table of settings, one check for every spelling.

use std::process::Command;

fn polyturn(args: &str) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn")).args(args.split_whitespace()).output().expect("runs");
    let text = |b: Vec<u8>| String::from_utf8(b).expect("utf-8");
    (out.status.code().unwrap_or(-1), text(out.stdout), text(out.stderr))
}

/// The hexagon at 600 rpm, 20 turns of cutting.
const RUN: &str = "simulate --cutter-radius 50 --stock-diameter 20 --depth 1.5 --ratio 2 --edges 3 --direction same --rpm 600 --revolutions 20";

/// `polyturn ARGS` refused: exit 2, one line starting `error: START`.
fn refused(args: &str, start: &str) -> String {
    let (code, out, err) = polyturn(args);
    assert_eq!(code, 2, "{args}: {out}{err}");
    assert_eq!(err.lines().count(), 1, "{args}: {err}");
    assert!(out.is_empty(), "{args}: nothing on stdout: {out}");
    assert!(err.starts_with(&format!("error: {start}")), "{args}: {err}");
    err
}

#[test]
fn a_simulation_that_never_cut_says_so_and_why_and_exits_non_zero() {
    let dir = std::env::temp_dir().join(format!("polyturn-nocut-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("never.svg");
    // ±15 % once a turn at 600 rpm asks 2 x 3 200 steps of 0.15 x (20π)²
    // / 2π: 603 000 steps/s², past max-accel's 400 000
    for (flags, ripple) in [
        (format!("--start spinning --ripple 0.15 --svg {}", svg.display()), "0.15"),
        ("--start spinning --ripple 0.15 --json".to_string(), "0.15"),
        ("--ripple 0.2".to_string(), "0.2"),
        ("--drive bldc --bldc-out pwm --start spinning --ripple 0.3".to_string(), "0.3"),
    ] {
        let err = refused(&format!("{RUN} {flags}"), "simulate: nothing was cut");
        assert!(err.contains(&format!("--ripple {ripple}")) && err.contains("max-accel 400000"), "{flags}: {err}");
        assert!(err.contains("at most about 0.099"), "the ripple it holds here: {err}");
    }
    assert!(!svg.exists(), "no file written for a run that cut nothing");
    // the same run with a ripple the follower holds cuts, and exits 0
    let (code, out, err) = polyturn(&format!("{RUN} --start spinning --ripple 0.05"));
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("6 sides") && out.contains("faults: none"), "{out}");
}

/// An RC ESC cannot brake: the cut is whole, but as the lathe runs down
/// the cutter coasts behind it and the controller latches a following
/// error. The run fails (exit 2), saying which fault, when and what to do,
/// and its report (with the fault) still goes to stdout.
#[test]
fn a_run_whose_controller_latched_a_fault_after_the_cut_fails_saying_when_and_what_to_do() {
    let esc = "simulate --cutter-radius 50 --stock-radius 10 --depth 2 --ratio 2 --edges 3 --direction same --rpm 600 --revolutions 10 --drive bldc --bldc-out esc400";
    let (code, out, err) = polyturn(&format!("{esc} --json"));
    assert_eq!(code, 2, "{out}{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: simulate: the controller latched a following-error fault at "), "{err}");
    assert!(
        err.contains(" s, after the cut was whole, while the lathe ran down from 600 rpm at 1200 rpm/s: the cutter fell behind: an RC ESC (esc400) cannot brake, so the cutter coasts down slower than the lathe stops; stop the cutter (`stop` on the board) before stopping the lathe, or drive it with one that brakes (a spindle driver, --bldc-out pwm)"),
        "{err}"
    );
    let report: serde_json::Value = serde_json::from_str(&out).expect("the report, whole");
    assert_eq!(report["faults"][0]["kind"], "following-error", "{out}");
    // the human report says it too, and the run still fails
    let (code, out, err) = polyturn(esc);
    assert_eq!(code, 2, "{out}{err}");
    assert!(out.contains("following-error") && err.contains("after the cut was whole"), "{out}{err}");
}

/// A lathe encoder whose every count jumps the cutter's target past the
/// following-error limit is named as the cause, not the motor.
#[test]
fn a_run_that_never_cut_for_a_coarse_lathe_encoder_names_the_encoder() {
    let err = refused(
        "simulate --cutter-radius 50 --stock-radius 10 --depth 2 --ratio 3 --edges 2 --direction same --rpm 300 --revolutions 3 --encoder-cpr 4 --max-accel 2000000",
        "simulate: nothing was cut",
    );
    assert!(err.contains("each lathe count (--encoder-cpr 4) moves the cutter's target 2400 steps, more than the follower holds within its following-error limit of 64 steps: a finer lathe encoder, 200 counts a turn or more"), "{err}");
    assert!(!err.contains("motor too weak"), "{err}");
    // just coarser than it cuts with (2 x 3 edges cuts from 123 counts)
    let line = "simulate --cutter-radius 75 --stock-diameter 30 --depth 1 --ratio 2 --edges 3 --direction same --rpm 300 --revolutions 5";
    let err = refused(&format!("{line} --encoder-cpr 110"), "simulate: nothing was cut");
    assert!(err.contains("(--encoder-cpr 110)") && err.contains("134 counts a turn or more"), "{err}");
    let (code, _, err) = polyturn(&format!("{line} --encoder-cpr 134"));
    assert_eq!(code, 0, "the cpr it names cuts: {err}");
}

#[test]
fn a_flag_for_the_other_kind_of_cutter_is_refused_naming_it() {
    for (flags, flag, why) in [
        ("--drive stepper --bldc-out pwm", "--bldc-out", "is for a BLDC cutter (--drive bldc)"),
        ("--bldc-out esc400", "--bldc-out", "is for a BLDC cutter (--drive bldc)"),
        ("--pwm-hz 2000", "--pwm-hz", "is for a BLDC cutter (--drive bldc)"),
        ("--bldc-tau 5", "--bldc-tau", "is for a BLDC cutter (--drive bldc)"),
        ("--drive bldc --bldc-out pwm --start-rate 100", "--start-rate", "is for a stepper (--drive stepper)"),
        ("--drive bldc --start-rate 0", "--start-rate", "is for a stepper (--drive stepper)"),
        ("--drive bldc --bldc-out esc400 --pwm-hz 2000", "--pwm-hz", "is for --bldc-out pwm"),
    ] {
        let err = refused(&format!("{RUN} {flags}"), flag);
        assert!(err.contains(why), "{flags}: {err}");
    }
}

#[test]
fn a_figure_out_of_range_is_named_with_where_it_came_from_and_what_it_got() {
    // a 100-count encoder at max-rate 200 000: the RC ESC's own time
    // constant (inertia x full speed / stall torque) is 2.5 s
    let err = refused(&format!("{RUN} --drive bldc --bldc-out esc400 --motor-steps 100"), "--motor-steps");
    assert!(err.contains("(got 100)") && err.contains("2513 ms") && err.contains("bldc-tau's 1..=1000"), "{err}");
    // given, it is the flag's own range
    let err = refused(&format!("{RUN} --drive bldc --bldc-out esc400 --bldc-tau 1001"), "--bldc-tau");
    assert!(err.contains("(got '1001')"), "{err}");
}

#[test]
fn the_cam_tables_encoder_takes_the_consoles_cpr_range() {
    let cam = "cam --sides 8 --inscribed-radius 20 --rpm 12 --x-max-speed 12 --x-max-accel 2000";
    let err = refused(&format!("{cam} --encoder-cpr 1048576"), "--encoder-cpr");
    assert!(err.contains("4..=1000000 counts per lathe rev, the console's `cpr`"), "{err}");
    let (code, _, err) = polyturn(&format!("{cam} --encoder-cpr 1000000"));
    assert_eq!(code, 0, "{err}");
    let (_, help, _) = polyturn("cam --help");
    assert!(help.contains("4..=1000000 counts per lathe rev"), "{help}");
}

#[test]
fn a_ratio_bound_is_held_to_one_range_however_it_is_spelled() {
    let setups = "setups --sides 6 --stock-diameter 20 --depth 1";
    for (ratio, number) in [("1/1000", "0.001"), ("1/101", "0.0099"), ("1001:1", "1001")] {
        let by_ratio = refused(&format!("{setups} --max-ratio {ratio}"), "--max-ratio");
        let by_number = refused(&format!("{setups} --max-ratio {number}"), "--max-ratio");
        let why = |e: &str| e.split(" (got").next().unwrap().to_string();
        assert_eq!(why(&by_ratio), why(&by_number), "{ratio} and {number}");
    }
    let (code, _, err) = polyturn(&format!("{setups} --max-ratio 1/100"));
    assert_eq!(code, 0, "{err}");
}

#[test]
fn device_get_lists_every_name_of_the_consoles_table() {
    let (code, help, _) = polyturn("device get --help");
    assert_eq!(code, 0);
    for name in polyturn_sync::config::NAMES {
        assert!(help.contains(name), "{name}: {help}");
    }
    // a name the console does not have is refused before any port opens
    let err = refused("device --port /nonexistent get bogus", "NAME");
    assert!(err.contains("bldc-tau"), "{err}");
}

/// A run too short to cut every side once (7/3 with one edge cuts its 7
/// sides in 3 lathe turns; a tenth of a turn of the hexagon) is refused,
/// naming the turns it cut and those the pattern takes, and writes no file:
/// its section, whole sides uncut, is no polygon to report.
#[test]
fn a_simulation_too_short_to_cut_every_side_says_so_and_exits_non_zero() {
    let dir = std::env::temp_dir().join(format!("polyturn-short-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("short.svg");
    let seven =
        "simulate --cutter-radius 20 --stock-diameter 30 --depth 2 --edges 1 --direction same --ratio 7/3 --rpm 600";
    let err = refused(&format!("{seven} --revolutions 1 --svg {}", svg.display()), "simulate: the cut is not whole");
    assert!(err.contains("cuts its 7 sides in 3") && err.contains("got 1"), "{err}");
    assert!(!svg.exists(), "no file written for a cut that is not whole");
    let hex =
        "simulate --cutter-radius 20 --stock-diameter 30 --depth 2 --ratio 2 --edges 3 --direction same --rpm 600";
    refused(&format!("{hex} --revolutions 0.1 --json"), "simulate: the cut is not whole");
    // long enough, the same seven sides are cut and reported
    let (code, out, err) = polyturn(&format!("{seven} --revolutions 6"));
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("7 sides"), "{out}");
}

/// `--start-rate` above the simulated board's max-rate names that figure,
/// which no flag of `simulate` sets.
#[test]
fn a_start_rate_past_the_simulated_max_rate_names_it() {
    let err = refused(&format!("{RUN} --start-rate 200001"), "--start-rate");
    assert!(err.contains("max-rate, 200000 steps/s") && err.contains("got 200001"), "{err}");
}

/// `compensate` with one edge, refused for the link between passes, names
/// the ratio: fewer edges is no remedy.
#[test]
fn compensate_with_one_edge_blames_the_ratio_not_the_edges() {
    let line = "compensate --cutter-radius 20 --stock-diameter 30 --depth 2 --ratio 1/3 --edges 1 --direction same --rpm 60 --x-max-speed 10 --x-max-accel 1000";
    let err = refused(line, "--ratio");
    assert!(err.contains("another ratio") && !err.contains("fewer edges"), "{err}");
}

/// The 3:1 x 2 of the flats document: 62 µm hollow on a fixed X axis.
const FLATS: &str =
    "compensate --cutter-radius 50 --stock-radius 10 --depth 2 --ratio 3 --edges 2 --direction same --x-max-accel 5000";

#[test]
fn compensate_writes_a_table_the_board_takes_and_refuses_one_it_could_not_run() {
    let dir = std::env::temp_dir().join(format!("polyturn-compensate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let table = dir.join("flats.json");
    let (code, out, err) = polyturn(&format!("{FLATS} --rpm 25 --x-max-speed 12.5 --table {}", table.display()));
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("allows up to 28.7 rpm") && out.contains("table 400 points over 400 lathe counts"), "{out}");
    // the file is what `device upload-cam` reads, and the board's checks take it
    let text = std::fs::read_to_string(&table).unwrap();
    // the cutter it was made for, its sense included (`dir` on the board)
    assert!(text.contains(r#""cutter":{"ratio":"3","edges":2,"direction":"same"}"#), "{text}");
    let t = polyturn_host::cli::console_line::cam_table("flats.json", &text).expect("upload-cam takes it");
    assert_eq!((t.counts_per_rev, t.period_counts, t.max_rate_hz, t.max_accel), (2400, 400, 10_000, 4_000_000));
    assert!(polyturn_sync::controller::check_table(&t.header(), &t.points).is_ok());
    // a plan for a faster X axis than the board's pins: fine as a plan,
    // refused as a table, and no file written
    let (code, out, _) = polyturn(&format!("{FLATS} --rpm 25 --x-max-speed 50"));
    assert_eq!(code, 0, "{out}");
    let other = dir.join("fast.json");
    let err = refused(
        &format!("{FLATS} --rpm 25 --x-max-speed 50 --table {}", other.display()),
        "--x-max-speed must be <= 12.5 mm/s",
    );
    assert!(err.contains("10000 X steps/s (800 steps/mm)"), "{err}");
    assert!(!other.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without `--table` the plan is for any X axis: the board's flags are
/// refused there, not taken and ignored.
#[test]
fn compensate_takes_the_boards_flags_only_with_a_table() {
    for flag in ["--steps-per-mm 51200", "--encoder-cpr 7"] {
        let err = refused(&format!("{FLATS} --rpm 25 --x-max-speed 12.5 {flag}"), &flag[..flag.find(' ').unwrap()]);
        assert!(err.contains("describes the board's table: give --table FILE with it"), "{err}");
    }
}

/// A run that fails on a latched fault writes no file: an `--svg` already
/// there is kept as it was.
#[test]
fn a_run_that_latched_a_fault_writes_no_file() {
    let dir = std::env::temp_dir().join(format!("polyturn-latched-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("f.svg");
    std::fs::write(&svg, "keep").unwrap();
    let esc = "simulate --cutter-radius 50 --stock-radius 10 --depth 2 --ratio 2 --edges 3 --direction same --rpm 600 --revolutions 10 --drive bldc --bldc-out esc400";
    let (code, out, err) = polyturn(&format!("{esc} --svg {}", svg.display()));
    assert_eq!(code, 2, "{out}{err}");
    assert!(err.contains("latched a following-error fault"), "{err}");
    assert!(!out.contains("wrote"), "{out}");
    assert!(std::fs::read_to_string(&svg).unwrap() == "keep", "the file was written over");
}

/// A cut stopped by a latched fault is told by that fault and the flag
/// behind it, not as too few --revolutions.
#[test]
fn a_cut_a_fault_stopped_names_the_fault_not_the_revolutions() {
    let run = "simulate --cutter-radius 50 --stock-diameter 20 --depth 1.5 --ratio 2 --edges 3 --direction same --rpm 300 --revolutions 50";
    for (flags, cause) in
        [("--start spinning --drive bldc --bldc-out esc50", "--bldc-out esc50"), ("--ripple 0.5", "--ripple 0.5")]
    {
        let err = refused(&format!("{run} {flags}"), "simulate: the cut is not whole: the controller latched a ");
        assert!(err.contains(cause) && !err.contains("give --revolutions"), "{flags}: {err}");
    }
}

/// A start rate past what the simulated motor pulls in loses the steps
/// of the jump: named as `--start-rate`, with the motor's pull-in.
#[test]
fn a_start_rate_the_simulated_motor_cannot_pull_in_names_it() {
    let run = "simulate --cutter-radius 50 --stock-diameter 20 --depth 1.5 --ratio 2 --edges 3 --direction same --rpm 300 --revolutions 5 --start spinning";
    let err = refused(&format!("{run} --start-rate 40000"), "simulate: the polygon was not cut");
    assert!(
        err.contains("--start-rate 40000") && err.contains("pulls in at once from rest, at most 19649 steps/s"),
        "{err}"
    );
    assert!(!err.contains("--motor-steps"), "{err}");
    let (code, _, err) = polyturn(&format!("{run} --start-rate 20000"));
    assert_eq!(code, 0, "{err}");
}
