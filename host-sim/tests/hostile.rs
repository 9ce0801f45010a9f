//! Hostile and careless input, table-driven, through the real binary:
//! each line is an argument list, the exit status it must get, the flag
//! its one-line error must name, and (for commands that write) that no
//! file is written on error.

use std::process::Command;

fn polyturn(args: &[String]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn")).args(args).output().expect("runs");
    let text = |b: Vec<u8>| String::from_utf8_lossy(&b).into_owned();
    (out.status.code().unwrap_or(-1), text(out.stdout), text(out.stderr))
}

/// Splits on spaces; `\n` and `\r` in a word stand for those characters.
fn words(s: &str) -> Vec<String> {
    s.split(' ').filter(|w| !w.is_empty()).map(|w| w.replace("\\n", "\n").replace("\\r", "\r")).collect()
}

const HEX: &str = "--cutter-radius 50 --stock-radius 10 --depth 1.5 --ratio 2 --edges 3 --direction same";
const NO_DIR: &str = "--cutter-radius 50 --stock-radius 10 --depth 1.5 --ratio 2 --edges 3";
const OCT: &str = "--sides 8 --inscribed-radius 20 --x-max-speed 12 --x-max-accel 2000";

/// (command line, the flag the error must name: `None` for a clean exit 0)
fn cases() -> Vec<(String, Option<&'static str>)> {
    let c = |s: String, f: Option<&'static str>| (s, f);
    vec![
        // argument handling
        c(format!("geometry {HEX} --depth 2"), Some("--depth")),
        c(format!("geometry {HEX} --json=yes"), Some("--json")),
        c(format!("geometry {HEX} --bogus 1"), Some("--bogus")),
        c(format!("geometry {HEX} --ratio 2\\n--edges"), Some("--ratio")),
        c(format!("geometry {NO_DIR} --direction \\nsame"), None), // trimmed, as numbers are
        c(format!("geometry {NO_DIR} --direction sideways"), Some("--direction")),
        c(format!("geometry {HEX} --json --json"), Some("--json")),
        // geometry nonsense
        c(
            "geometry --cutter-radius 1 --stock-radius 10 --depth 1.5 --ratio 2 --edges 3 --direction same".into(),
            Some("--cutter-radius"),
        ),
        c(
            "geometry --cutter-radius 0.002 --stock-radius 10 --depth 0.001 --ratio 2 --edges 3 --direction same"
                .into(),
            Some("--cutter-radius"),
        ),
        c(format!("geometry {HEX} --ratio -2"), Some("--ratio")),
        c(format!("geometry {HEX} --ratio 2:1:1"), Some("--ratio")),
        c(format!("geometry {HEX} --ratio 1:0"), Some("--ratio")),
        // both of a pair: one sentence naming both, the first given first
        c(format!("geometry {NO_DIR} --direction same --stock-diameter 20"), Some("--stock-radius cannot be given with --stock-diameter:")),
        c(format!("geometry {NO_DIR} --direction same --across-flats 17"), Some("--depth cannot be given with --across-flats:")),
        c("geometry --cutter-radius 50 --stock-diameter 20 --across-flats 20 --ratio 2 --edges 3 --direction same".into(), Some("--across-flats")),
        // compensate and simulate speeds
        c(format!("compensate {HEX} --rpm 1e-308 --x-max-speed 50 --x-max-accel 5000"), Some("--rpm")),
        c(format!("compensate {HEX} --rpm 600 --x-max-speed 0 --x-max-accel 5000"), Some("--x-max-speed")),
        c(format!("compensate {HEX} --rpm 600 --x-max-speed 0.001 --x-max-accel 5000"), Some("--x-max-speed")),
        c("simulate --cutter-radius 0.002 --stock-radius 10 --depth 0.001 --ratio 2 --edges 3 --direction same --rpm 600 --revolutions 1".into(), Some("--cutter-radius")),
        c(format!("geometry {HEX} --svg /tmp"), Some("--svg")),
        c(format!("simulate {HEX} --rpm 1e-308 --revolutions 1"), Some("--rpm")),
        c(format!("simulate {HEX} --rpm 1 --revolutions 100"), Some("--revolutions")),
        c(format!("simulate {HEX} --rpm 5000 --revolutions 3"), Some("--rpm")),
        c(format!("simulate {HEX} --rpm 600 --revolutions 1 --start spinning --drive servo"), Some("--drive")),
        c(format!("simulate {HEX} --rpm 600 --revolutions 1 --encoder-cpr 3"), Some("--encoder-cpr")),
        // the BLDC drive's settings: a frequency the timer cannot make, a
        // drive corrected less than once per cutter turn at max-rpm
        c(format!("simulate {HEX} --rpm 600 --revolutions 1 --drive bldc --bldc-out pwm --pwm-hz 7000"), Some("--pwm-hz")),
        c(format!("simulate {HEX} --rpm 600 --revolutions 1 --drive bldc --bldc-out esc"), Some("--bldc-out")),
        c(format!("simulate {HEX} --rpm 600 --revolutions 1 --drive bldc --bldc-tau 0"), Some("--bldc-tau")),
        c(format!("simulate {HEX} --rpm 1400 --revolutions 1 --drive bldc"), Some("--rpm must be at most 1153 rpm for ratio 2 with --bldc-out esc50")),
        c(format!("simulate {HEX} --rpm -inf --revolutions 1"), Some("--rpm")),
        c(format!("simulate {HEX} --rpm 600 --revolutions 1 --ripple -inf"), Some("--ripple")),
        // setups
        // a missing flag is a sentence naming it and its alternative
        c("setups --sides 6 --stock-radius 10".into(), Some("setups needs --depth (or --across-flats)")),
        c("setups --sides 6 --depth 1".into(), Some("setups needs --stock-radius (or --stock-diameter)")),
        c("setups --sides 6 --stock-diameter 20 --stock-radius 10 --depth 1".into(), Some("--stock-diameter cannot be given with --stock-radius:")),
        c("setups --sides 6 --stock-diameter 0 --depth 1".into(), Some("--stock-diameter")),
        c("setups --sides 6 --stock-diameter 20 --across-flats 20".into(), Some("--across-flats")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --max-tip-speed 0".into(), Some("--max-tip-speed")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --max-cutter-rpm -inf".into(), Some("--max-cutter-rpm")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --max-ratio 2:0".into(), Some("--max-ratio")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --across-flats 18".into(), Some("--depth")),
        c("setups --sides 6 --stock-radius 10 --depth 11".into(), Some("--depth")),
        c("setups --sides 6 --stock-radius 10 --depth 2 --cutter-radius 1".into(), Some("--cutter-radius")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --max-edges 13".into(), Some("--max-edges")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --rpm 0".into(), Some("--rpm")),
        // sequence
        c("sequence --sides 8 --m 2".into(), Some("--m")),
        c("sequence --sides 2".into(), Some("--sides")),
        // cam: the axis and the table
        c(format!("cam {OCT} --rpm 12 --x-max-speed 1e-6"), Some("--x-max-speed")),
        c(format!("cam {OCT} --rpm 12 --x-max-accel 1e-9"), Some("--x-max-accel")),
        c(format!("cam {OCT} --rpm 12 --steps-per-mm 0.01"), Some("--steps-per-mm")),
        c(format!("cam {OCT} --rpm 12 --steps-per-mm 1e-308"), Some("--steps-per-mm")),
        // a vanishing value is refused by its own flag, not blamed on another with 300 digits
        c("geometry --cutter-radius 50 --stock-radius 1e-308 --depth 1.5 --ratio 2 --edges 3 --direction same".into(), Some("--stock-radius")),
        c("simulate --cutter-radius 50 --stock-radius 10 --depth 1e-308 --ratio 2 --edges 3 --direction same --rpm 300".into(), Some("--depth")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --cutter-radius 1e-308".into(), Some("--cutter-radius")),
        c("setups --sides 6 --stock-radius 10 --depth 1 --max-ratio 1e-308".into(), Some("--max-ratio")),
        c("compensate --cutter-radius 50 --stock-radius 10 --depth 1.5 --ratio 2 --edges 3 --direction same --rpm 100 --x-max-speed 1e-308 --x-max-accel 100".into(), Some("--x-max-speed")),
        c(format!("cam {OCT} --rpm 12 --steps-per-mm 100001"), Some("--steps-per-mm")),
        // m past N cuts in m mod N's order, only slower and coarser
        c("cam --sides 7 --inscribed-radius 20 --rpm 12 --x-max-speed 12 --x-max-accel 2000 --m 999".into(), Some("--m")),
        c(format!("cam {OCT} --rpm 12 --m 11"), Some("--m")),
        c(format!("cam {OCT} --rpm -inf"), Some("--rpm")),
        c(format!("cam {OCT} --rpm 12 --x-max-accel -nan"), Some("--x-max-accel")),
        c(format!("cam {OCT} --rpm 12 --steps-per-mm 0.5"), Some("--steps-per-mm")),
        c(format!("cam {OCT} --rpm 12 --encoder-cpr 4"), Some("--encoder-cpr")),
        // the old spelling, a hidden alias, is refused under the documented one
        c(format!("cam {OCT} --rpm 12 --encoder-counts 4"), Some("--encoder-cpr")),
        c(format!("cam {OCT} --rpm 12 --m 2"), Some("--m")),
        c(format!("cam {OCT} --rpm 0"), Some("--rpm")),
        c(format!("cam {OCT} --rpm 12 --inscribed-radius 1500"), Some("--inscribed-radius")),
        // device: refused before any port is opened
        c("device upload-cam".into(), Some("FILE")),
        c("device set phase 1\\r\\nset cpr 4000 --port /nonexistent".into(), None),
        c("device launch".into(), Some("launch")),
        c("device status --timeout 0".into(), Some("--timeout")),
        c("device status --port /nonexistent/tty".into(), Some("--port")),
        c("device --port /nonexistent/tty status".into(), Some("--port")),
        c("device upload-cam /dev/zero --port /nonexistent".into(), None),
        // flash and image: files refused before any USB request
        c("flash /dev/zero".into(), Some("FILE")),
        c("flash /dev/null --dry-run".into(), Some("FILE")),
        c("flash /nonexistent/fw.hex --dry-run".into(), Some("FILE")),
        c("flash Cargo.toml --dry-run --any-image".into(), Some("FILE")),
        c("flash src --dry-run".into(), Some("FILE")),
        c("flash Cargo.toml --wait -1".into(), Some("--wait")),
        c("flash Cargo.toml --wait 1e9".into(), Some("--wait")),
        c("flash Cargo.toml --wait nan".into(), Some("--wait")),
        c("flash Cargo.toml --wait -inf".into(), Some("--wait")),
        c("flash Cargo.toml --wait -nan".into(), Some("--wait")),
        c("flash Cargo.toml --dry-run=yes".into(), Some("--dry-run")),
        c("flash a.bin b.bin".into(), Some("b.bin")),
        c("image /dev/zero --bin /nonexistent/a.bin --hex /nonexistent/a.hex".into(), Some("ELF")),
        c("image Cargo.toml --bin /nonexistent/a.bin --hex /nonexistent/a.hex".into(), Some("ELF")),
        c("image Cargo.toml --bin \\n --hex a.hex".into(), Some("--bin")),
        c("image Cargo.toml --bin a.bin".into(), Some("image needs --hex")),
        // anything else
        c("frobnicate".into(), None),
        // an m asked for is sharp corners, not swapped for a rounded turn
        c("cam --sides 6 --inscribed-radius 10 --rpm 60 --x-max-speed 12.5 --x-max-accel 10000 --m 5".into(), Some("--rpm")),
        // no number takes a '+', as --ratio and the console do not
        c(format!("geometry {HEX} --depth +2").replace("--depth 1.5 ", ""), Some("--depth")),
        c("web --port 1e3 --no-open".into(), Some("--port")),
        c("web --listen evil --no-open".into(), Some("--listen")),
        // a cut that misses the polygon by most of its depth is no success
        c(format!("simulate {HEX} --depth 1 --rpm 600 --revolutions 10 --drive bldc --bldc-out pwm --ripple 0.2").replace("--depth 1.5 ", ""), Some("the polygon was not cut")),
        c(format!("simulate {HEX} --depth 1 --rpm 600 --revolutions 1 --motor-steps 1").replace("--depth 1.5 ", ""), Some("the polygon was not cut")),
        c("completions tcsh".into(), Some("tcsh")),
    ]
}

#[test]
fn every_hostile_input_gets_one_true_line_and_exit_2() {
    for (line, flag) in cases() {
        let (code, out, err) = polyturn(&words(&line));
        if flag.is_none() && line.contains("--direction") {
            assert_eq!(code, 0, "{line}: {err}");
            continue;
        }
        assert_eq!(code, 2, "{line:?}: exit {code}\n{out}{err}");
        assert!(out.is_empty(), "{line:?}: printed {out}");
        assert_eq!(err.lines().count(), 1, "{line:?}: not one line: {err}");
        assert!(err.starts_with("error: "), "{line:?}: {err}");
        assert!(!err.contains("panicked"), "{line:?}: {err}");
        if let Some(flag) = flag {
            assert!(err.contains(flag), "{line:?}: does not name {flag}: {err}");
            // the named flag comes first (one flag is blamed, the right one)
            if flag.starts_with("--") {
                assert!(err.starts_with(&format!("error: {flag} ")), "{line:?}: {err}");
            }
        }
    }
}

#[test]
fn a_refused_command_writes_no_file() {
    let dir = std::env::temp_dir().join(format!("polyturn-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let t = dir.join("t.json");
    let svg = dir.join("x.svg");
    let d = |p: &std::path::Path| p.display().to_string();
    for line in [
        // the second file cannot be written: neither is
        format!("cam {OCT} --rpm 12 --table {} --svg /nonexistent-dir/x.svg", d(&t)),
        // both flags name one file
        format!("cam {OCT} --rpm 12 --table {} --svg {}/./t.json", d(&t), dir.display()),
        // refused values, files named
        format!("cam {OCT} --rpm 12 --encoder-counts 4 --table {} --svg {}", d(&t), d(&svg)),
        format!("geometry {HEX} --edges 13 --svg {}", d(&svg)),
        format!("simulate {HEX} --rpm 5000 --revolutions 3 --svg {}", d(&svg)),
        "demo --svg /nonexistent-dir/hexagon.svg".to_string(),
        // a file that is no firmware image: neither release file
        format!("image Cargo.toml --bin {}/fw.bin --hex {}/fw.hex", dir.display(), dir.display()),
        format!("image src/main.rs --bin {}/fw.bin --hex {}/fw.hex --any-image", dir.display(), dir.display()),
    ] {
        let (code, _, err) = polyturn(&words(&line));
        assert_eq!(code, 2, "{line}: {err}");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert!(left.is_empty(), "{line}: wrote {left:?}");
    }
    // and a good one writes both
    let (code, _, err) = polyturn(&words(&format!("cam {OCT} --rpm 12 --table {} --svg {}", d(&t), d(&svg))));
    assert_eq!(code, 0, "{err}");
    assert!(t.exists() && svg.exists());
}

#[test]
fn every_command_documents_every_flag() {
    let commands = ["demo", "geometry", "setups", "simulate", "sequence", "compensate", "cam", "device", "device set"];
    for cmd in commands.into_iter().chain(["flash", "image"]) {
        let (code, out, _) = polyturn(&words(&format!("{cmd} --help")));
        assert_eq!(code, 0, "{cmd}");
        let lines: Vec<&str> = out.lines().collect();
        for (i, line) in lines.iter().enumerate().filter(|(_, l)| l.trim_start().starts_with("--")) {
            // beside the flag, or (clap's layout for long flags) on the next line
            let next = lines.get(i + 1).map(|l| l.trim()).filter(|l| !l.starts_with('-')).unwrap_or("");
            let help = line.trim_start().split_once("  ").map(|(_, h)| h.trim()).unwrap_or(next);
            assert!(
                !help.is_empty() || line.contains("--help") || line.contains("--version"),
                "{cmd}: undocumented {line}"
            );
        }
    }
    let (_, out, _) = polyturn(&words("setups --help"));
    assert!(out.contains("[default: 6]") && out.contains("(1..=12)"), "{out}");
}

#[test]
fn completions_are_printed_for_bash() {
    let (code, out, _) = polyturn(&words("completions bash"));
    assert_eq!(code, 0);
    assert!(out.contains("_polyturn()") && out.contains("--inscribed-radius") && out.contains("upload-cam"));
}

#[test]
fn a_hex_with_a_blank_line_is_refused_naming_the_file_and_the_line() {
    let dir = std::env::temp_dir().join(format!("polyturn-hostile-hex-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let hex = dir.join("fw.hex");
    std::fs::write(&hex, ":020000040800F2\n\n:00000001FF\n").unwrap();
    let (code, out, err) = polyturn(&words(&format!("flash {} --dry-run", hex.display())));
    assert_eq!((code, out.as_str()), (2, ""));
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: FILE must be Intel HEX")
            && err.contains(&format!("(got '{}': line 2 is blank)", hex.display())),
        "{err}"
    );
}

/// A report that cannot be written where stdout goes (a full disk) is no
/// success: exit 2 and a line that says so, where a script would
/// otherwise get an empty file and exit 0.
#[cfg(target_os = "linux")]
#[test]
fn a_report_stdout_cannot_take_is_an_error() {
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full").expect("/dev/full");
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn"))
        .args(words(&format!("geometry {HEX} --json")))
        .stdout(full)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.starts_with("error: the report could not be written to standard output: "), "{err}");
}

/// compensate says a speed the floor allows, and no negative zero: an X
/// axis too slow for even 1 rpm is blamed as such, not given "up to 0
/// rpm"; a straightened flat reads +0.0000.
#[test]
fn compensate_says_no_speed_below_the_floor_and_no_negative_zero() {
    let (code, _, err) =
        polyturn(&words(&format!("compensate {HEX} --rpm 100 --x-max-speed 0.001 --x-max-accel 0.001")));
    assert_eq!(code, 2);
    assert!(err.contains("this X axis cannot follow even at 1 rpm") && !err.contains("0 rpm"), "{err}");
    let (code, out, err) =
        polyturn(&words(&format!("compensate {HEX} --rpm 10 --x-max-speed 100 --x-max-accel 100000")));
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("flats straightened: deviation +0.0087 mm -> +0.0000 mm"), "{out}");
}

/// An encoder so coarse that the compensating X motion repeats every
/// lathe count (6 counts a turn, 6 flats a turn) leaves no room for the
/// board's table of at least 2 points: one sentence naming --encoder-cpr
/// and what it must do, exit 2, no file.
#[test]
fn an_encoder_whose_table_repeats_every_count_is_refused_in_one_sentence() {
    let dir = std::env::temp_dir().join(format!("polyturn-cpr6-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("flats.json");
    let line = format!(
        "compensate --cutter-radius 50 --stock-radius 10 --depth 2 --ratio 3 --edges 2 --direction same --rpm 25 --x-max-speed 12.5 --x-max-accel 5000 --encoder-cpr 6 --table {}",
        file.display()
    );
    let (code, out, err) = polyturn(&words(&line));
    assert_eq!((code, out.as_str()), (2, ""), "{err}");
    assert_eq!(
        err.trim_end(),
        "error: --encoder-cpr must give the X motion at least 2 lathe counts a repeat, one for each of the at least 2 points of the board's cam table: at 6 counts a turn it repeats every count; give an encoder of more counts a turn, in 4..=1000000 (got 6)"
    );
    assert!(!file.exists(), "no file is written");
    std::fs::remove_dir_all(&dir).unwrap();
}
