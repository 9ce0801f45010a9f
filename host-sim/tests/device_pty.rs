//! `polyturn device` against a fake serial port (a pseudo-terminal): the
//! real sync-core console behind the firmware's framing, and boards that
//! misbehave (each test names the way).
#![cfg(unix)]

use polyturn_sync::console::{self, tag, Action};
use polyturn_sync::{Config, Controller, TickInput, Timing};
use serialport::{SerialPort, TTYPort};
use std::io::{Read, Write};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How the fake board behaves.
#[derive(Clone, Copy)]
enum Board {
    /// the real console, tags and `watch` as the firmware's usb.rs does
    Real,
    Silent,
    BlankLines,
    NoNewline,
    Chatty,
    /// a port that echoes every byte back (a terminal in echo mode, some
    /// USB-serial adapters, a loopback plug), with the real console behind
    /// it or nothing
    Echo {
        board: bool,
    },
    /// answers every command with this after its tag
    Odd(&'static str),
    /// answers every command with a line of `n` bytes (its tag, `ok` and
    /// x's; CR LF after)
    Long(usize),
    /// closes the port when a command arrives, unanswered
    Hangup,
    /// the real console on a board whose time passes: it has been on
    /// 0.2 s, and this many ms of control ticks pass before each line, the
    /// lathe at rest
    Ticking(usize),
}

struct Fake {
    path: String,
    heard: Arc<Mutex<Vec<String>>>,
    stop: Arc<AtomicBool>,
    _slave: TTYPort,
}

impl Drop for Fake {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
    }
}

/// Held while a pty is made and while a child starts: `TTYPort::pair`'s
/// master is inherited by any child started meanwhile (no close-on-exec),
/// and a master held open by a `polyturn` process keeps its port from
/// ever seeing the board hang up.
static SPAWN: Mutex<()> = Mutex::new(());

fn spawning() -> std::sync::MutexGuard<'static, ()> {
    SPAWN.lock().unwrap_or_else(|e| e.into_inner())
}

fn fake(board: Board) -> Fake {
    let (mut master, slave) = {
        let _g = spawning();
        let (master, slave) = TTYPort::pair().expect("a pty");
        (master.try_clone_native().expect("a close-on-exec master"), slave)
    };
    master.set_timeout(Duration::from_millis(20)).unwrap();
    let path = slave.name().expect("pty name");
    let heard = Arc::new(Mutex::new(Vec::new()));
    let stop = Arc::new(AtomicBool::new(false));
    let (h, st) = (heard.clone(), stop.clone());
    std::thread::spawn(move || serve(&mut master, board, &h, &st));
    Fake { path, heard, stop, _slave: slave }
}

fn serve(port: &mut TTYPort, board: Board, heard: &Mutex<Vec<String>>, stop: &AtomicBool) {
    let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
    let pass = |ctl: &mut Controller, ms: usize| {
        for _ in 0..ms * Timing::FIRMWARE.tick_hz as usize / 1_000 {
            ctl.tick(&TickInput::default());
        }
    };
    if let Board::Ticking(_) = board {
        pass(&mut ctl, 200);
    }
    let (mut line, mut watching, mut buf) = (Vec::new(), false, [0u8; 64]);
    while !stop.load(Ordering::SeqCst) {
        let n = port.read(&mut buf).unwrap_or(0);
        if let Board::Echo { .. } = board {
            let _ = port.write_all(&buf[..n]);
        }
        match board {
            Board::BlankLines => drop(port.write_all(b"\r\n\r\n\r\n")),
            Board::NoNewline => drop(port.write_all(&[b'x'; 64])),
            _ => {}
        }
        if watching && n == 0 {
            let (r, _) = console::handle(b"status", &mut ctl);
            let _ = port.write_all(format!("{r}\r\n").as_bytes());
            std::thread::sleep(Duration::from_millis(30));
        }
        for &b in &buf[..n] {
            if b != b'\r' && b != b'\n' {
                line.push(b);
                continue;
            }
            if line.is_empty() {
                continue;
            }
            watching = false;
            let text = String::from_utf8_lossy(&std::mem::take(&mut line)).into_owned();
            heard.lock().unwrap().push(text.clone());
            let tag = text.split_once(' ').map_or("", |(t, _)| t);
            if let Board::Ticking(ms) = board {
                pass(&mut ctl, ms);
            }
            let reply = match board {
                Board::Hangup => {
                    // the command is in: the board goes (unplugged, a reset)
                    std::thread::sleep(Duration::from_millis(100));
                    return;
                }
                Board::Odd(body) => format!("{tag} {body}\r\n"),
                Board::Long(n) => format!("{tag} ok {}\r\n", "x".repeat(n - tag.len() - 4)),
                Board::Real | Board::Echo { board: true } | Board::Ticking(_) => match tag::split(text.as_bytes()) {
                    Ok((t, body)) => {
                        let (r, a) = console::handle(body, &mut ctl);
                        watching = a == Action::Watch;
                        let t = t.map(|t| format!("#{} ", String::from_utf8_lossy(t))).unwrap_or_default();
                        format!("{t}{r}\r\n")
                    }
                    Err(e) => format!("error: {e}\r\n"),
                },
                Board::Chatty => "AT OK\r\n".into(),
                _ => String::new(),
            };
            let _ = port.write_all(reply.as_bytes());
        }
    }
}

fn polyturn(port: &str, args: &str) -> (i32, String, String, Duration) {
    polyturn_raw(port, &format!("--timeout 0.5 {args}"))
}

/// `polyturn device --port PORT ARGS`, no `--timeout` of ours.
fn polyturn_raw(port: &str, args: &str) -> (i32, String, String, Duration) {
    let t = Instant::now();
    let child = {
        let _g = spawning();
        Command::new(env!("CARGO_BIN_EXE_polyturn"))
            .args(["device", "--port", port])
            .args(args.split(' '))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let out = child.wait_with_output().unwrap();
    let s = |b: Vec<u8>| String::from_utf8_lossy(&b).into_owned();
    (out.status.code().unwrap_or(-1), s(out.stdout), s(out.stderr), t.elapsed())
}

#[test]
fn the_binary_talks_to_the_real_console_with_tagged_lines() {
    let f = fake(Board::Real);
    let (code, out, err, _) = polyturn(&f.path, "set edges 4");
    assert_eq!((code, out.trim()), (0, "ok edges=4"), "{err}");
    let (code, _, err, _) = polyturn(&f.path, "set ratio 0");
    assert_eq!(code, 2);
    assert!(err.starts_with("error: device: error: ratio"), "{err}");
    let (code, out, _, _) = polyturn(&f.path, "set phase -12.5");
    assert_eq!((code, out.trim()), (0, "ok phase=-12.500"));
    assert!(f.heard.lock().unwrap().iter().all(|l| l.starts_with('#')), "every command is tagged");
}

/// `polyturn device set cpr 1000 && polyturn device save`, a millisecond
/// of the board's time apart, the lathe at rest: the save goes.
#[test]
fn set_then_save_with_the_lathe_at_rest_is_saved() {
    let f = fake(Board::Ticking(1));
    let (code, out, err, _) = polyturn(&f.path, "set cpr 1000");
    assert_eq!((code, out.trim()), (0, "ok cpr=1000"), "{err}");
    let (code, out, err, _) = polyturn(&f.path, "save");
    assert_eq!((code, out.trim(), err.as_str()), (0, "ok saving", ""));
}

#[test]
fn a_watch_ended_with_ctrl_c_leaves_the_board_answering_the_next_command() {
    let f = fake(Board::Real);
    let mut child = {
        let _g = spawning();
        Command::new(env!("CARGO_BIN_EXE_polyturn"))
            .args(["device", "--port", &f.path, "watch"])
            .stdout(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let mut first = [0u8; 64];
    let n = child.stdout.as_mut().unwrap().read(&mut first).unwrap();
    assert!(String::from_utf8_lossy(&first[..n]).starts_with("ok state=idle"));
    std::thread::sleep(Duration::from_millis(200));
    let pid = child.id().to_string();
    let killed = {
        let _g = spawning();
        Command::new("kill").args(["-INT", &pid]).status().unwrap()
    };
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}");
    // the board was sent a tagged command after the watch, which ended it
    let heard = f.heard.lock().unwrap().clone();
    assert!(heard.len() >= 2 && heard[heard.len() - 1].ends_with(" status"), "{heard:?}");
    let (code, out, err, _) = polyturn(&f.path, "set edges 5");
    assert_eq!((code, out.trim()), (0, "ok edges=5"), "{err}");
}

#[test]
fn a_misbehaving_port_gets_a_timeout_naming_it_and_nothing_hangs() {
    for (board, says) in [
        (Board::Silent, "no reply to 'status' within 0.5 s"),
        (Board::BlankLines, "no reply to 'status' within 0.5 s"),
        (Board::NoNewline, "longer than 512 bytes"),
        (Board::Chatty, "it sent 'AT OK': is this a polyturn board?"),
    ] {
        let f = fake(board);
        let (code, out, err, took) = polyturn(&f.path, "status");
        assert_eq!(code, 2, "{says}: {out}{err}");
        assert!(out.is_empty(), "{says}: printed {out}");
        assert!(err.starts_with(&format!("error: --port {}: ", f.path)) && err.contains(says), "{err}");
        assert!(took < Duration::from_secs(5), "{says}: took {took:?}");
    }
}

#[test]
fn a_command_with_a_hidden_second_line_is_never_sent() {
    let f = fake(Board::Real);
    let out = {
        let _g = spawning();
        Command::new(env!("CARGO_BIN_EXE_polyturn"))
            .args(["device", "--port", &f.path, "set", "phase", "1\r\nset cpr 4000"])
            .output()
            .unwrap()
    };
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("control character"));
    std::thread::sleep(Duration::from_millis(100));
    assert!(f.heard.lock().unwrap().is_empty(), "nothing reached the board");
}

/// `polyturn device ARGS` against `board`: its exit status and what it
/// printed, with what the board heard.
fn run_against(board: Board, args: &str) -> (i32, String, String, Vec<String>) {
    let f = fake(board);
    let (code, out, err, took) =
        if args.contains("--timeout") { polyturn_raw(&f.path, args) } else { polyturn(&f.path, args) };
    // `save` waits 10 s for its reply (a flash erase): at most that
    assert!(took < Duration::from_secs(12), "{args}: took {took:?}");
    std::thread::sleep(Duration::from_millis(50));
    let heard = f.heard.lock().unwrap().clone();
    (code, out, err, heard)
}

#[test]
fn an_echoing_port_is_never_taken_for_the_board() {
    for args in ["set cpr 1000", "engage", "save", "dfu", "status"] {
        let (code, out, err, _) = run_against(Board::Echo { board: false }, args);
        assert_eq!(code, 2, "{args}: {out}{err}");
        assert!(out.is_empty(), "{args}: printed {out}");
        assert!(err.contains("echoed the command back"), "{args}: {err}");
    }
}

#[test]
fn behind_an_echoing_port_the_boards_own_reply_is_taken_ok_or_error() {
    let (code, out, err, _) = run_against(Board::Echo { board: true }, "set cpr 0");
    assert_eq!(code, 2, "{out}");
    assert!(err.starts_with("error: device: error: cpr"), "{err}");
    let (code, out, err, _) = run_against(Board::Echo { board: true }, "set cpr 4000");
    assert_eq!((code, out.trim()), (0, "ok cpr=4000"), "{err}");
}

#[test]
fn a_tagged_reply_that_is_neither_ok_nor_error_is_an_error_quoting_it() {
    for odd in [" error: cpr 4..=1000000", "ERROR: cpr", "", "okay", "garbage", "error:no space", "Ok cpr=1"] {
        let (code, out, err, _) = run_against(Board::Odd(odd), "set cpr 1000");
        assert_eq!(code, 2, "{odd:?}: {out}");
        assert!(out.is_empty(), "{odd:?}: printed {out}");
        assert!(err.contains("--port /dev/pts/") && err.contains("neither ok nor error"), "{odd:?}: {err}");
        assert!(err.contains(&format!(" {odd}'")), "{odd:?}: the reply is quoted: {err}");
    }
}

#[test]
fn control_bytes_from_the_board_never_reach_the_terminal_raw() {
    let (code, out, err, _) = run_against(Board::Odd("ok \x1b[2J\x00\x07cleared"), "status");
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.trim_end(), "ok \\u{1b}[2J\\u{0}\\u{7}cleared");
    assert!(!out.bytes().any(|b| b.is_ascii_control() && b != b'\n'), "{out:?}");
    let (code, _, err, _) = run_against(Board::Odd("error: \x1b[2Jgone"), "status");
    assert_eq!(code, 2);
    assert!(err.contains("\\u{1b}[2Jgone") && !err.contains('\x1b'), "{err:?}");
}

#[test]
fn a_reply_line_is_bounded_at_exactly_512_bytes() {
    let (code, out, err, _) = run_against(Board::Long(512), "status");
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("ok xxx") && out.trim_end().ends_with("xxx"), "{out}");
    for n in [513, 600, 766] {
        let (code, out, err, _) = run_against(Board::Long(n), "status");
        assert_eq!(code, 2, "{n}: {out}");
        assert!(err.contains("longer than 512 bytes"), "{n}: {err}");
    }
}

#[test]
fn a_board_that_closes_the_port_mid_command_is_reported_as_a_disconnect() {
    let (code, out, err, _) = run_against(Board::Hangup, "status");
    assert_eq!(code, 2, "{out}");
    assert!(err.contains("closed the port") && !err.contains("no reply"), "{err}");
}

#[test]
fn a_jog_the_console_would_refuse_is_refused_before_anything_is_sent() {
    for deg in ["1e308", "inf", "-inf", "nan", "NaN", "3600.001", "-3600.5", "+90", "90.0001", "0x10"] {
        let (code, out, err, heard) = run_against(Board::Odd("ok jogging"), &format!("jog {deg}"));
        assert_eq!(code, 2, "{deg}: {out}");
        assert!(err.contains("-3600..=3600"), "{deg}: {err}");
        assert!(heard.is_empty(), "{deg}: sent {heard:?}");
    }
}

#[test]
fn a_number_of_divisions_the_console_would_refuse_is_refused_before_anything_is_sent() {
    for n in ["0", "1e9", "six", "-6", "3601", "6.5"] {
        let (code, out, err, heard) = run_against(Board::Odd("ok divide=6"), &format!("divide {n}"));
        assert_eq!(code, 2, "{n}: {out}");
        assert!(err.contains("1..=3600 divisions of a turn, at most cpr/4"), "{n}: {err}");
        assert!(heard.is_empty(), "{n}: sent {heard:?}");
    }
}

/// `polyturn device divide 6` on the real console: the readout, a line
/// each status line (stdout is a pipe here), until Ctrl-C, which ends the
/// watch and the dividing on the board.
#[test]
fn divide_shows_the_readout_until_ctrl_c_then_stops_dividing_on_the_board() {
    let f = fake(Board::Real);
    let mut child = {
        let _g = spawning();
        Command::new(env!("CARGO_BIN_EXE_polyturn"))
            .args(["device", "--port", &f.path, "divide", "6"])
            .stdout(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let mut first = [0u8; 256];
    let n = child.stdout.as_mut().unwrap().read(&mut first).unwrap();
    let shown = String::from_utf8_lossy(&first[..n]).into_owned();
    assert!(
        shown.starts_with("division 0 of 6 (0.0°): turn 0.0° (0.00 counts): WITHIN ±1 count | spindle 0.0°"),
        "{shown}"
    );
    std::thread::sleep(Duration::from_millis(200));
    let pid = child.id().to_string();
    let killed = {
        let _g = spawning();
        Command::new("kill").args(["-INT", &pid]).status().unwrap()
    };
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).trim_end().ends_with("ok divide ended"), "{out:?}");
    let heard = f.heard.lock().unwrap().clone();
    let last: Vec<&str> = heard.iter().rev().take(2).map(|l| l.split_once(' ').map_or("", |(_, c)| c)).collect();
    assert_eq!(last, ["divide stop", "status"], "{heard:?}");
    assert!(heard[0].ends_with(" divide 6"), "{heard:?}");
}

#[test]
fn negative_numbers_on_nested_commands_are_refused_naming_their_flag_and_range() {
    for (args, says) in [
        ("selftest --rpm -1", "--rpm"),
        ("check-encoder --turns -1", "--turns"),
        ("check-encoder --seconds -0", "--seconds"),
        ("--timeout -inf status", "--timeout"),
        ("--timeout -1 status", "--timeout"),
    ] {
        let (code, out, err, heard) = run_against(Board::Real, args);
        assert_eq!(code, 2, "{args}: {out}");
        assert!(err.starts_with(&format!("error: {says} must be")) && err.contains("(got '-"), "{args}: {err}");
        assert!(heard.is_empty(), "{args}: sent {heard:?}");
    }
}

/// The machinist's terminal: a pseudo-terminal whose master the test
/// types into and reads (non-blocking), and whose slave becomes the
/// child's stdin, stdout, stderr and controlling terminal.
struct Term {
    master: std::fs::File,
    slave: std::os::fd::OwnedFd,
    seen: Vec<u8>,
}

impl Term {
    fn new() -> Term {
        use std::os::fd::FromRawFd;
        let _g = spawning();
        let (mut m, mut s) = (0, 0);
        // SAFETY: openpty writes two new descriptors, owned from here on
        let r = unsafe { libc::openpty(&mut m, &mut s, std::ptr::null_mut(), std::ptr::null(), std::ptr::null()) };
        assert_eq!(r, 0, "openpty");
        // SAFETY: m and s are open descriptors owned by no one else
        unsafe {
            libc::fcntl(m, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(s, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(m, libc::F_SETFL, libc::O_NONBLOCK);
            Term { master: std::fs::File::from_raw_fd(m), slave: std::os::fd::OwnedFd::from_raw_fd(s), seen: vec![] }
        }
    }

    /// `polyturn device --port PORT ARGS` on this terminal.
    fn spawn(&self, port: &str, args: &[&str]) -> std::process::Child {
        use std::os::unix::process::CommandExt;
        let _g = spawning();
        let io = || Stdio::from(self.slave.try_clone().unwrap());
        let mut c = Command::new(env!("CARGO_BIN_EXE_polyturn"));
        c.args(["device", "--port", port]).args(args).stdin(io()).stdout(io()).stderr(io());
        // SAFETY: only async-signal-safe calls between fork and exec
        unsafe {
            c.pre_exec(|| {
                libc::setsid();
                libc::ioctl(0, libc::TIOCSCTTY as _, 0);
                Ok(())
            });
        }
        c.spawn().unwrap()
    }

    /// Reads until `text` has been shown (at most 20 s).
    fn until(&mut self, text: &str) {
        let deadline = Instant::now() + Duration::from_secs(20);
        while !String::from_utf8_lossy(&self.seen).contains(text) {
            assert!(Instant::now() < deadline, "'{text}' never shown: {:?}", String::from_utf8_lossy(&self.seen));
            self.read();
        }
    }

    /// Reads until the cursor was last hidden, not shown (at most 20 s).
    fn until_hidden(&mut self, hide: &str, show: &str) {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            let shown = String::from_utf8_lossy(&self.seen).into_owned();
            if shown.rfind(hide).is_some_and(|h| shown.rfind(show).is_none_or(|s| s < h)) {
                return;
            }
            assert!(Instant::now() < deadline, "the cursor never hidden: {shown:?}");
            self.read();
        }
    }

    fn read(&mut self) {
        let mut buf = [0u8; 4096];
        match self.master.read(&mut buf) {
            Ok(n) if n > 0 => self.seen.extend_from_slice(&buf[..n]),
            _ => std::thread::sleep(Duration::from_millis(10)),
        }
    }

    fn type_keys(&mut self, keys: &[u8]) {
        self.master.write_all(keys).unwrap();
    }

    /// Waits (at most 20 s) for the child to end, reading what it shows.
    fn end(&mut self, child: &mut std::process::Child) -> std::process::ExitStatus {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            self.read();
            if let Some(status) = child.try_wait().unwrap() {
                for _ in 0..20 {
                    self.read();
                }
                return status;
            }
            assert!(Instant::now() < deadline, "still running: {:?}", String::from_utf8_lossy(&self.seen));
        }
    }
}

#[test]
fn ctrl_c_at_a_yes_no_or_a_list_prompt_gives_the_terminal_its_cursor_back() {
    const HIDE: &str = "\x1b[?25l";
    const SHOW: &str = "\x1b[?25h";
    // (keys before Ctrl-C, what is on screen then): the index question
    // (yes/no); the cutter question (a list), after the encoder check
    for (keys, prompt) in [(&[][..], "index (Z) pulse"), (&[&b"y"[..], b"\r", b"600\r"][..], "What turns the cutter?")]
    {
        let f = fake(Board::Real);
        let mut t = Term::new();
        let mut child = t.spawn(&f.path, &["setup"]);
        t.until("index (Z) pulse");
        for (i, k) in keys.iter().enumerate() {
            t.type_keys(k);
            t.until(["Turn the chuck", "Encoder lines", prompt][i]);
        }
        t.until_hidden(HIDE, SHOW);
        t.type_keys(b"\x03");
        let status = t.end(&mut child);
        let shown = String::from_utf8_lossy(&t.seen).into_owned();
        assert!(!status.success(), "{prompt}: cancelled is not a success: {shown:?}");
        let (hidden, back) = (shown.rfind(HIDE).unwrap(), shown.rfind(SHOW));
        assert!(back.is_some_and(|b| b > hidden), "{prompt}: the cursor is left hidden: {shown:?}");
    }
}

/// A cam table file whose steps per mm no `polyturn cam` makes, or whose
/// points no X axis follows, is refused before anything is sent.
#[test]
fn a_cam_table_the_board_would_refuse_is_refused_before_anything_is_sent() {
    let dir = std::env::temp_dir().join(format!("polyturn-pty-cam-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let table = |spm: &str, jump: i32| {
        let points: Vec<String> = (0..1024).map(|i| if i == 500 { jump.to_string() } else { "0".into() }).collect();
        let rate = polyturn_sync::cam_upload::X_MAX_RATE_HZ;
        format!(
            r#"{{"format":"polyturn-cam-1","counts_per_rev":2400,"period_counts":2400,"steps_per_mm":{spm},"max_rate_hz":{rate},"max_accel":1000000,"points":[{}]}}"#,
            points.join(",")
        )
    };
    for (name, text, says) in [
        ("zero.json", table("0", 0), "steps_per_mm must be a finite number >= 1 and <= 100000 (got 0.0)"),
        ("neg.json", table("-800", 0), "(got -800.0)"),
        ("huge.json", table("1e308", 0), "(got 1e308)"),
        ("jump.json", table("800", 100_000), "neighbouring points 100000 steps apart need 1706650 X steps/s"),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let (code, out, err, heard) = run_against(Board::Real, &format!("upload-cam {}", path.display()));
        assert_eq!(code, 2, "{name}: {out}");
        assert!(err.contains("is refused: ") && err.contains(says), "{name}: {err}");
        assert!(heard.is_empty(), "{name}: sent {heard:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
