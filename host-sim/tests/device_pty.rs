//! `polyturn device` against a fake serial port (a pseudo-terminal): the
//! real sync-core console behind the firmware's framing, and boards that
//! misbehave in each way the hostile-input review found.
#![cfg(unix)]

use polyturn_sync::console::{self, tag, Action};
use polyturn_sync::{Config, Controller, Timing};
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

fn fake(board: Board) -> Fake {
    let (mut master, slave) = TTYPort::pair().expect("a pty");
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
    let (mut line, mut watching, mut buf) = (Vec::new(), false, [0u8; 64]);
    while !stop.load(Ordering::SeqCst) {
        let n = port.read(&mut buf).unwrap_or(0);
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
            let reply = match board {
                Board::Real => match tag::split(text.as_bytes()) {
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
    let t = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn"))
        .args(["device", "--port", port, "--timeout", "0.5"])
        .args(args.split(' '))
        .output()
        .unwrap();
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

#[test]
fn a_watch_ended_with_ctrl_c_leaves_the_board_answering_the_next_command() {
    let f = fake(Board::Real);
    let mut child = Command::new(env!("CARGO_BIN_EXE_polyturn"))
        .args(["device", "--port", &f.path, "watch"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 64];
    let n = child.stdout.as_mut().unwrap().read(&mut first).unwrap();
    assert!(String::from_utf8_lossy(&first[..n]).starts_with("ok state=idle"));
    std::thread::sleep(Duration::from_millis(200));
    let pid = child.id().to_string();
    assert!(Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
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
    let out = Command::new(env!("CARGO_BIN_EXE_polyturn"))
        .args(["device", "--port", &f.path, "set", "phase", "1\r\nset cpr 4000"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("control character"));
    std::thread::sleep(Duration::from_millis(100));
    assert!(f.heard.lock().unwrap().is_empty(), "nothing reached the board");
}
