//! `polyturn device ...`: the firmware's console protocol over a serial port
//! (the Black Pill's USB CDC-ACM console), one line out, one line back.

use super::args::{CliError, CliResult};
use std::io::{BufRead, BufReader, Read, Write};
use std::time::Duration;

pub const USAGE: &str = "polyturn device [--port PATH] status | watch | get [NAME] | set NAME VALUE | engage | stop | clear | save | defaults | help | upload-cam FILE";

/// A console session over any byte stream.
pub struct Session<T: Read + Write> {
    io: BufReader<T>,
}

impl<T: Read + Write> Session<T> {
    pub fn new(io: T) -> Session<T> {
        Session { io: BufReader::new(io) }
    }

    /// Sends one command; returns the device's one-line reply.
    pub fn ask(&mut self, line: &str) -> std::io::Result<String> {
        let w = self.io.get_mut();
        w.write_all(line.as_bytes())?;
        w.write_all(b"\r\n")?;
        w.flush()?;
        self.read_line()
    }

    pub fn read_line(&mut self) -> std::io::Result<String> {
        let mut s = String::new();
        while s.trim().is_empty() {
            s.clear();
            if self.io.read_line(&mut s)? == 0 {
                return Err(std::io::Error::new(std::io::ErrorKind::UnexpectedEof, "device closed the console"));
            }
        }
        Ok(s.trim_end().to_string())
    }
}

/// The first USB CDC-ACM port, as Linux and macOS name them.
fn find_port() -> Option<String> {
    let mut found: Vec<String> = std::fs::read_dir("/dev")
        .ok()?
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("ttyACM") || n.starts_with("cu.usbmodem"))
        .map(|n| format!("/dev/{n}"))
        .collect();
    found.sort();
    found.into_iter().next()
}

/// Builds the protocol line from the command words, refusing unknown ones.
pub fn command_line(words: &[String]) -> CliResult<(String, bool)> {
    let known = ["status", "watch", "get", "set", "engage", "stop", "clear", "save", "defaults", "help", "upload-cam"];
    let Some(cmd) = words.first() else { return Err(CliError(format!("usage: {USAGE}"))) };
    if !known.contains(&cmd.as_str()) {
        return Err(CliError(format!("unknown device command '{cmd}' (try: {})", known.join(", "))));
    }
    Ok((words.join(" "), cmd == "watch"))
}

pub fn run(argv: &[String]) -> CliResult<String> {
    let (port, words) = match argv {
        [flag, path, rest @ ..] if flag == "--port" => (Some(path.clone()), rest),
        rest => (None, rest),
    };
    let (line, watch) = command_line(words)?;
    let path = port.or_else(find_port).ok_or_else(|| {
        CliError::flag("port", "not given and no polyturn console found (looked for /dev/ttyACM*): connect the board by USB, or give --port PATH")
    })?;
    let serial = serialport::new(&path, 115_200)
        .timeout(Duration::from_secs(3))
        .open()
        .map_err(|e| CliError::flag("port", format!("cannot open {path}: {e}")))?;
    let mut s = Session::new(serial);
    if let Some(file) = line.strip_prefix("upload-cam ") {
        return upload(&mut s, file, &path);
    }
    let reply = s.ask(&line).map_err(|e| CliError::flag("port", format!("{path}: no reply ({e})")))?;
    if !watch {
        return if reply.starts_with("error") { Err(CliError(format!("device: {reply}"))) } else { Ok(reply) };
    }
    let mut out = std::io::stdout().lock();
    let mut line = reply;
    loop {
        if writeln!(out, "{line}").and_then(|_| out.flush()).is_err() {
            return Ok(String::new()); // the reader went away (a closed pipe)
        }
        line = s.read_line().map_err(|e| CliError::flag("port", format!("{path}: {e}")))?;
    }
}

/// Sends a `polyturn cam --table` file line by line; stops at the first
/// error (the device then discards the partial table).
fn upload<P: Read + Write>(s: &mut Session<P>, file: &str, path: &str) -> CliResult<String> {
    let text = std::fs::read_to_string(file).map_err(|e| CliError(format!("upload-cam: cannot read '{file}': {e}")))?;
    let table: crate::noncircular::table::CamFile = serde_json::from_str(&text)
        .map_err(|e| CliError(format!("upload-cam: '{file}' is not a polyturn cam table: {e}")))?;
    let mut last = String::new();
    for line in table.upload_lines() {
        last = s.ask(&line).map_err(|e| CliError::flag("port", format!("{path}: no reply ({e})")))?;
        if last.starts_with("error") {
            return Err(CliError(format!("device: {last}")));
        }
    }
    Ok(last)
}

#[cfg(test)]
mod tests {
    use super::*;
    use polyturn_sync::{console, Config, Controller, Timing};
    use std::collections::VecDeque;

    /// A fake device: answers each line with the real sync-core console.
    struct FakeDevice {
        ctl: Controller,
        pending: Vec<u8>,
        out: VecDeque<u8>,
    }

    impl Read for FakeDevice {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = buf.len().min(self.out.len());
            for b in buf.iter_mut().take(n) {
                *b = self.out.pop_front().unwrap_or(b'\n');
            }
            Ok(n)
        }
    }

    impl Write for FakeDevice {
        fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
            for &b in data {
                if b == b'\n' || b == b'\r' {
                    if !self.pending.is_empty() {
                        let (reply, _) = console::handle(&self.pending, &mut self.ctl);
                        self.out.extend(reply.as_bytes());
                        self.out.extend(b"\r\n");
                        self.pending.clear();
                    }
                } else {
                    self.pending.push(b);
                }
            }
            Ok(data.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn the_host_speaks_the_firmware_console_protocol() {
        let dev = FakeDevice {
            ctl: Controller::new(Config::default(), Timing::FIRMWARE),
            pending: vec![],
            out: VecDeque::new(),
        };
        let mut s = Session::new(dev);
        assert_eq!(s.ask("set max-rpm 600").unwrap(), "ok max-rpm=600");
        assert_eq!(s.ask("set ratio 11/3").unwrap(), "ok ratio=11/3");
        assert!(s.ask("status").unwrap().starts_with("ok state=idle"));
        assert!(s.ask("set ratio 0").unwrap().starts_with("error: ratio"));
    }

    #[test]
    fn unknown_device_commands_are_refused_before_opening_a_port() {
        let w = |s: &str| s.split_whitespace().map(String::from).collect::<Vec<_>>();
        assert!(command_line(&w("launch")).is_err());
        assert_eq!(command_line(&w("set ratio 11/3")).unwrap(), ("set ratio 11/3".into(), false));
        assert!(command_line(&w("watch")).unwrap().1);
    }
}
