//! The `polyturn` command-line contracts, run through the real binary.

use std::process::Command;

fn polyturn(args: &str) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn")).args(args.split_whitespace()).output().expect("runs");
    let text = |b: Vec<u8>| String::from_utf8(b).expect("utf-8");
    (out.status.code().unwrap_or(-1), text(out.stdout), text(out.stderr))
}

const HEX: &str = "--cutter-radius 50 --stock-radius 10 --depth 1.5 --ratio 2 --edges 3 --direction same";

#[test]
fn help_and_version_work() {
    let (code, out, _) = polyturn("--help");
    assert_eq!(code, 0);
    for command in ["demo", "geometry", "setups", "simulate", "device", "sequence", "compensate", "cam", "completions"]
    {
        assert!(out.contains(&format!("\n  {command} ")), "{command} missing from --help:\n{out}");
    }
    let (code, out, _) = polyturn("--version");
    assert_eq!((code, out.trim()), (0, format!("polyturn {}", env!("CARGO_PKG_VERSION")).as_str()));
}

#[test]
fn geometry_json_carries_the_contract_fields() {
    let (code, out, err) = polyturn(&format!("geometry {HEX} --json"));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["sides"], 6);
    assert_eq!(v["revolutions"], 1);
    assert!((v["inscribed_radius"].as_f64().unwrap() - 8.5).abs() < 1e-6);
    assert!((v["across_flats"].as_f64().unwrap() - 17.0).abs() < 1e-6);
    assert!(v["circumscribed_radius"].as_f64().unwrap() > 8.5);
    assert!(v["flat_deviation"].as_f64().unwrap() > 0.0);
    assert_eq!(v["corners_sharp"], true);
    let (_, out, _) = polyturn(
        "geometry --cutter-radius 50 --stock-radius 10 --depth 1 --ratio 5/2 --edges 2 --direction same --json",
    );
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!((v["sides"].as_u64(), v["across_flats"].is_null()), (Some(5), true));
}

#[test]
fn every_bad_value_exits_2_with_one_line_naming_the_flag() {
    let base = "geometry --cutter-radius 50 --stock-radius 10 --depth 1.5 --ratio 2 --edges 3 --direction same";
    for (bad, flag) in [
        ("--ratio 0", "--ratio"),
        ("--ratio -2", "--ratio"),
        ("--ratio 1/0", "--ratio"),
        ("--ratio abc", "--ratio"),
        ("--ratio 1001", "--ratio"),
        ("--edges 0", "--edges"),
        ("--edges 13", "--edges"),
        ("--depth 0", "--depth"),
        ("--depth 10", "--depth"),
        ("--depth NaN", "--depth"),
        ("--cutter-radius -1", "--cutter-radius"),
        ("--cutter-radius inf", "--cutter-radius"),
        ("--direction clockwise", "--direction"),
    ] {
        let (code, out, err) = polyturn(&format!("{base} {bad}"));
        assert_eq!(code, 2, "{bad}: {out}{err}");
        assert_eq!(err.lines().count(), 1, "{bad}: {err}");
        assert!(err.starts_with(&format!("error: {flag} ")), "{bad}: {err}");
    }
}

#[test]
fn simulate_json_carries_the_contract_fields() {
    let (code, out, err) = polyturn(&format!("simulate {HEX} --rpm 600 --revolutions 3 --json"));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in [
        "final_error_steps",
        "max_error_steps",
        "max_error_deg",
        "max_profile_deviation",
        "faults",
        "ticks",
        "steps_emitted",
        "encoder_counts",
    ] {
        assert!(!v[k].is_null(), "missing {k}");
    }
    assert_eq!(v["final_error_steps"], 0);
    assert_eq!(v["cut"]["sides"], 6);
    assert_eq!(v["faults"].as_array().map(Vec::len), Some(0));
}

#[test]
fn simulate_refuses_a_run_that_would_overspeed_the_motor() {
    let (code, _, err) = polyturn(&format!("simulate {HEX} --rpm 5000 --revolutions 3"));
    assert_eq!(code, 2);
    assert!(err.starts_with("error: --rpm must be at most 1442 rpm for ratio 2 at 3200 steps a turn"), "{err}");
    assert!(err.trim_end().ends_with("(got 5000)"), "{err}");
}

#[test]
fn demo_writes_the_hexagon_picture() {
    let dir = std::env::temp_dir().join(format!("polyturn-demo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("hexagon.svg");
    let (code, out, err) = polyturn(&format!("demo --svg {}", svg.display()));
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("6 sides") && out.contains("final error at rest: 0 steps"), "{out}");
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    // the README's quick start shows what the demo prints, line for line
    // (its last line names the file written, here another path)
    let readme = include_str!("../../README.md");
    let block = readme.split("```\npolyturn demo:").nth(1).expect("the README quotes the demo").split("```").next();
    let quoted: Vec<&str> = block.unwrap().lines().collect();
    let printed: Vec<&str> = out.lines().collect();
    let n = printed.len() - 1;
    assert_eq!(format!("polyturn demo:{}", quoted[0]), printed[0]);
    assert_eq!(&quoted[1..n], &printed[1..n], "README.md's demo output differs from the demo's: copy it in");
}

#[test]
fn a_closed_pipe_ends_quietly_not_with_a_panic() {
    use std::process::Stdio;
    let svg = std::env::temp_dir().join(format!("polyturn-pipe-{}.svg", std::process::id()));
    let mut child = Command::new(env!("CARGO_BIN_EXE_polyturn"))
        .args(["demo", "--svg", svg.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before the demo writes
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.status.success());
}

/// A drawing sent to stdout (`--svg -`) whose reader closed the pipe ends
/// as the report does, exit 0; a stdout that refuses it (a full disk) is
/// named `stdout`, not `-`.
#[test]
fn a_drawing_to_stdout_ends_quietly_at_a_closed_pipe_and_names_stdout_when_refused() {
    use std::process::Stdio;
    let args = ["geometry", "--cutter-radius", "50", "--stock-diameter", "20", "--depth", "1.5", "--ratio", "2"];
    let args = [&args[..], &["--edges", "3", "--direction", "same", "--svg", "-"]].concat();
    let mut child = Command::new(env!("CARGO_BIN_EXE_polyturn"))
        .args(&args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // `| head` gone before the drawing is written
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !err.contains("error"), "{err}");
    #[cfg(target_os = "linux")]
    {
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").expect("/dev/full");
        let out = Command::new(env!("CARGO_BIN_EXE_polyturn")).args(&args).stdout(full).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.starts_with("error: --svg could not write to stdout: No space left on device"), "{err}");
    }
}

const OCTAGON: &str = "cam --sides 8 --inscribed-radius 20 --x-max-speed 12 --x-max-accel 2000";

#[test]
fn cam_plans_sharp_corners_writes_the_table_and_rounds_when_too_fast() {
    let dir = std::env::temp_dir().join(format!("polyturn-cam-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let table = dir.join("octagon.json");
    let (code, out, err) = polyturn(&format!("{OCTAGON} --rpm 12 --json --table {}", table.display()));
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["corners"], "sharp");
    assert_eq!(j["order"], serde_json::json!([0, 3, 6, 1, 4, 7, 2, 5]));
    assert_eq!(j["within_1um"], true, "{out}");
    assert!(j["velocity_jump_mm_s"].as_f64().unwrap() < 1e-3);
    let file: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&table).unwrap()).unwrap();
    assert_eq!(file["format"], "polyturn-cam-1");
    assert_eq!(file["points"].as_array().unwrap().len(), 900);
    // faster than the axis allows for sharp corners: a fillet, and why
    let (code, out, _) = polyturn(&format!("{OCTAGON} --rpm 30 --json"));
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!((code, j["corners"].as_str()), (0, Some("rounded")));
    assert!(j["corner_rounding_um"].as_f64().unwrap() > 1.0 && j["sharp_max_rpm"].as_f64().unwrap() < 30.0);
}

#[test]
fn every_drawings_text_fits_within_its_width() {
    // the cam's title ran off its right edge from 10 sides on
    let drawings = [
        "cam --sides 360 --m 127 --inscribed-radius 20 --x-max-speed 12 --x-max-accel 2000 --rpm 1 --svg -",
        "cam --sides 12 --m 11 --inscribed-radius 20 --x-max-speed 12 --x-max-accel 2000 --rpm 1 --svg -",
        &format!("geometry {HEX} --svg -"),
        &format!("simulate {HEX} --rpm 600 --revolutions 2 --svg -"),
    ];
    for args in drawings {
        let (code, out, err) = polyturn(args);
        assert_eq!(code, 0, "{args}: {err}");
        let svg = &out[out.find("<svg").unwrap_or(0)..];
        assert!(svg.contains("<text"), "{args}: {out}");
        assert_eq!(polyturn_host::geometry::svg::text_overflow(svg), Vec::<String>::new(), "{args}");
    }
}

#[test]
fn cam_refuses_bad_input_naming_the_flag() {
    for (bad, flag) in
        [("--rpm 12 --m 2", "--m"), ("--rpm 0", "--rpm"), ("--rpm 12 --steps-per-mm 5000", "--x-max-speed")]
    {
        let (code, out, err) = polyturn(&format!("{OCTAGON} {bad}"));
        assert_eq!(code, 2, "{bad}: {out}");
        assert!(err.starts_with(&format!("error: {flag} ")), "{bad}: {err}");
    }
}

/// A fresh directory for one test's files.
fn scratch(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("polyturn-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[cfg(unix)]
#[test]
fn an_output_through_a_symlink_writes_the_file_it_names_and_keeps_the_link() {
    use std::os::unix::fs::symlink;
    let dir = scratch("symlink");
    std::fs::write(dir.join("real.svg"), "old").unwrap();
    symlink("real.svg", dir.join("l.svg")).unwrap();
    // a link to a file not made yet: that file is made
    symlink(dir.join("new.svg"), dir.join("d.svg")).unwrap();
    for (link, real) in [("l.svg", "real.svg"), ("d.svg", "new.svg")] {
        let (code, _, err) = polyturn(&format!("geometry {HEX} --svg {}", dir.join(link).display()));
        assert_eq!(code, 0, "{err}");
        assert!(std::fs::symlink_metadata(dir.join(link)).unwrap().file_type().is_symlink(), "{link} replaced");
        assert!(std::fs::read_to_string(dir.join(real)).unwrap().starts_with("<svg"), "{real} not written");
    }
    // two flags naming one file, through a link: still refused
    let (code, _, err) = polyturn(&format!(
        "{OCTAGON} --rpm 12 --table {} --svg {}",
        dir.join("real.svg").display(),
        dir.join("l.svg").display()
    ));
    assert_eq!(code, 2);
    assert!(err.starts_with("error: --svg names the same file as --table"), "{err}");
}

#[cfg(unix)]
#[test]
fn an_output_fifo_is_written_into_not_replaced() {
    use std::os::unix::fs::FileTypeExt;
    let dir = scratch("fifo");
    let fifo = dir.join("pipe.svg");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let (code, out, err) = polyturn(&format!("demo --svg {}", fifo.display()));
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(), "the FIFO was replaced: {out}");
    assert!(reader.join().unwrap().starts_with("<svg"));
}

#[cfg(unix)]
#[test]
fn a_read_only_output_is_refused_and_a_hard_linked_one_written_through() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let dir = scratch("readonly");
    let keep = dir.join("keep.svg");
    std::fs::write(&keep, "old").unwrap();
    std::fs::set_permissions(&keep, std::fs::Permissions::from_mode(0o444)).unwrap();
    let (code, out, err) = polyturn(&format!("demo --svg {}", keep.display()));
    assert_eq!(code, 2, "{out}");
    assert_eq!(
        err.trim_end(),
        format!("error: --svg must name a file it may write (got '{}': read-only, mode 0444; chmod u+w it, or name another)", keep.display())
    );
    assert_eq!(
        (std::fs::read_to_string(&keep).unwrap().as_str(), std::fs::metadata(&keep).unwrap().mode() & 0o777),
        ("old", 0o444)
    );
    // two names of one file: both see the new picture
    std::fs::write(dir.join("a.svg"), "old").unwrap();
    std::fs::hard_link(dir.join("a.svg"), dir.join("b.svg")).unwrap();
    let (code, _, err) = polyturn(&format!("demo --svg {}", dir.join("a.svg").display()));
    assert_eq!(code, 0, "{err}");
    for name in ["a.svg", "b.svg"] {
        assert!(std::fs::read_to_string(dir.join(name)).unwrap().starts_with("<svg"), "{name}");
    }
    assert_eq!(std::fs::metadata(dir.join("b.svg")).unwrap().nlink(), 2);
}

/// Ctrl-C (SIGINT), SIGTERM or SIGHUP (a closed terminal) while an output
/// FIFO waits for its reader: the command dies of the signal, and the table
/// it had staged is gone. (SIGQUIT is handled alike; not sent here, whose
/// default action may leave a core file.)
#[cfg(unix)]
#[test]
fn an_interrupted_write_leaves_no_temporary_behind() {
    use std::os::unix::process::ExitStatusExt;
    for (sig, name) in [(libc::SIGINT, "int"), (libc::SIGTERM, "term"), (libc::SIGHUP, "hup")] {
        let dir = scratch(&format!("interrupted-{name}"));
        let fifo = dir.join("pipe.svg");
        assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let line = format!("{OCTAGON} --rpm 12 --table {} --svg {}", dir.join("t.json").display(), fifo.display());
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_polyturn"));
        cmd.args(line.split_whitespace()).stdout(std::process::Stdio::null()).stderr(std::process::Stdio::null());
        // the signal at its default action in the child, as at a terminal:
        // a test run under nohup (or a CI runner) inherits SIGHUP ignored
        use std::os::unix::process::CommandExt;
        // SAFETY: signal(2) is async-signal-safe, as pre_exec requires
        unsafe {
            cmd.pre_exec(move || {
                libc::signal(sig, libc::SIG_DFL);
                Ok(())
            });
        }
        let mut child = cmd.spawn().unwrap();
        let tmp = dir.join(format!(".t.json.polyturn-{}.tmp", child.id()));
        // the table is staged before the FIFO is opened; the FIFO then waits
        // (10 s) for a reader that never comes
        for _ in 0..1000 {
            if tmp.exists() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        assert!(tmp.exists(), "{name}: the table was never staged");
        // SAFETY: a signal to our own child
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
        let status = child.wait().unwrap();
        assert_eq!(status.signal(), Some(sig), "{name}: {status:?}");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left, vec![std::ffi::OsString::from("pipe.svg")], "{name}");
    }
}

/// `device upload-cam` on a FIFO no one writes, a device, a directory:
/// refused at once, naming FILE, before any port is opened (a FIFO would
/// wait for a writer for ever). Bounded here: a hang fails, it does not
/// hold the test run.
#[cfg(unix)]
#[test]
fn upload_cam_refuses_a_file_that_is_not_regular_at_once() {
    let dir = scratch("upload-fifo");
    let fifo = dir.join("table.json");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    for file in [fifo.display().to_string(), "/dev/zero".into(), dir.display().to_string()] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_polyturn"))
            .args(["device", "upload-cam", &file, "--port", "/nonexistent/tty"])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut status = None;
        for _ in 0..2000 {
            status = child.try_wait().unwrap();
            if status.is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let Some(status) = status else {
            let _ = child.kill();
            panic!("upload-cam {file}: still waiting after 20 s");
        };
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(status.code(), Some(2), "{file}: {err}");
        assert_eq!(
            err.trim_end(),
            format!("error: FILE must be a regular file, the table `polyturn cam --table` writes (got '{file}': not a regular file)"),
        );
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_device_is_an_error_naming_the_flag_and_stays_a_device() {
    use std::os::unix::fs::FileTypeExt;
    // /dev/full takes an open and refuses every write (ENOSPC)
    for line in ["demo --svg /dev/full".to_string(), format!("{OCTAGON} --rpm 12 --table /dev/full")] {
        let (code, out, err) = polyturn(&line);
        assert_eq!(code, 2, "{line}: {out}");
        assert!(err.starts_with("error: --") && err.contains("could not write '/dev/full'"), "{line}: {err}");
        assert_eq!(err.lines().count(), 1);
        assert!(std::fs::metadata("/dev/full").unwrap().file_type().is_char_device(), "{line} replaced /dev/full");
    }
}

#[test]
fn a_dash_writes_the_file_to_stdout_and_the_report_to_stderr() {
    let (code, out, err) = polyturn("demo --svg -");
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("<svg") && out.trim_end().ends_with("</svg>"), "{out}");
    assert!(err.contains("6 sides"), "{err}");
    assert!(!std::path::Path::new("-").exists(), "a file named '-' was made");
    let (code, out, err) = polyturn(&format!("{OCTAGON} --rpm 12 --table - --json"));
    assert_eq!(code, 0, "{err}");
    let table: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(table["format"], "polyturn-cam-1");
    // stdout by its name is stdout too (written through, the link kept)
    #[cfg(target_os = "linux")]
    {
        let (code, out, err) = polyturn(&format!("{OCTAGON} --rpm 12 --table /dev/stdout"));
        assert_eq!(code, 0, "{err}");
        assert!(out.starts_with("{\"format\":\"polyturn-cam-1\"") && err.contains("8 sides"), "{out}");
        assert!(std::fs::symlink_metadata("/dev/stdout").unwrap().file_type().is_symlink());
    }
    let (code, _, err) = polyturn(&format!("{OCTAGON} --rpm 12 --table - --svg -"));
    assert_eq!(code, 2);
    assert!(err.starts_with("error: --svg names the same file as --table"), "{err}");
}

#[cfg(unix)]
#[test]
fn a_long_simulation_on_a_terminal_shows_it_is_alive_and_away_from_one_stays_quiet() {
    use serialport::{SerialPort, TTYPort};
    use std::io::Read;
    // some seconds of work: 240 s of lathe time, 6 million ticks (60 s
    // of it ran in about 1 s once the simulator grew faster: the line
    // comes only after a second)
    let long = "simulate --cutter-radius 50 --stock-radius 10 --depth 1.5 --ratio 1000/999 --edges 12 --direction same --rpm 600 --revolutions 2400 --motor-steps 100";
    let (mut master, slave) = {
        let (master, slave) = TTYPort::pair().expect("a pty");
        (master.try_clone_native().expect("a close-on-exec master"), slave)
    };
    master.set_timeout(std::time::Duration::from_millis(200)).unwrap();
    let tty = std::fs::OpenOptions::new().write(true).open(slave.name().unwrap()).unwrap();
    // read while it runs: a pty's unread output may be lost at hang-up
    let reader = std::thread::spawn(move || {
        let (mut seen, mut buf) = (Vec::new(), [0u8; 256]);
        loop {
            match master.read(&mut buf) {
                Ok(n) if n > 0 => seen.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                _ => return seen,
            }
        }
    });
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn")).args(long.split_whitespace()).stderr(tty).output().unwrap();
    drop(slave);
    assert!(out.status.success());
    let seen = reader.join().unwrap();
    let seen = String::from_utf8_lossy(&seen);
    assert!(seen.contains("\rsimulating 2400 lathe turns at 600 rpm (240 s of cutting"), "{seen:?}");
    assert!(seen.ends_with("\r\x1b[K"), "the line is left behind: {seen:?}");
    let (code, _, err) = polyturn(long);
    assert_eq!((code, err.as_str()), (0, ""));
}

#[test]
fn cam_refuses_an_m_past_its_useful_range_at_once_saying_the_range() {
    let axis = "--inscribed-radius 20 --rpm 12 --x-max-speed 12 --x-max-accel 2000";
    let (code, _, err) = polyturn(&format!("cam --sides 7 {axis} --m 999"));
    assert_eq!(code, 2);
    assert!(
        err.starts_with("error: --m must be in 2..=6 for 7 sides: m and m - 7 cut the sides in the same order"),
        "{err}"
    );
    assert!(err.trim_end().ends_with("(got '999')"), "{err}");
    let (code, _, err) = polyturn(&format!("cam --sides 360 {axis} --m 131"));
    assert_eq!(code, 2);
    assert!(err.starts_with("error: --m must be in 2..=128 for 360 sides: the table's 1024 points"), "{err}");
}

#[test]
fn setups_warns_of_what_no_lathe_can_do_and_still_exits_0_with_its_table() {
    let (code, out, err) = polyturn("setups --sides 6 --stock-diameter 40 --depth 3 --rpm 3000");
    assert_eq!((code, err.as_str()), (0, ""), "{out}");
    let warnings: Vec<&str> = out.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(warnings.len(), 4, "tip speed, cutter speed, swing and the refused simulate line:\n{out}");
    assert!(out.contains("\n2      3     same      1 "), "the table is still there:\n{out}");
    let (code, out, _) = polyturn("setups --sides 6 --stock-radius 10 --depth 1.5 --cutter-radius 50 --rpm 300");
    assert_eq!(code, 0);
    assert!(!out.contains("warning:"), "{out}");
}
