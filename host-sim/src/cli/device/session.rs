//! One console session over any byte stream: each command goes out with a
//! tag (`#N`, see the sync core's `console::tag`) and only the line that
//! carries the same tag is its reply. Every wait has a deadline, every
//! line a length bound, and a command is refused before sending if it
//! holds a control character (which could smuggle in a second command).

use super::super::errors::{escaped, CliError, CliResult};
use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

pub use super::super::console_line::{check_command, COMMAND_MAX, DEVICE_LINE_MAX};
/// The longest line taken from the device (its replies are at most
/// `console::REPLY_LEN` plus the tag); anything longer is not a polyturn.
pub const REPLY_MAX: usize = 512;
/// Lines that are not the reply, at most, before giving up on one.
const OTHER_LINES_MAX: usize = 10_000;
/// What an untagged firmware answers to a tagged command.
const OLD_FIRMWARE: &str = "error: unknown command or wrong arguments (try help)";

pub struct Session<T: Read + Write> {
    pub(crate) io: T,
    pending: Vec<u8>,
    tag: u32,
    /// how long to wait for one reply
    pub timeout: Duration,
    /// the port's name, for every error
    pub port: String,
}

impl<T: Read + Write> Session<T> {
    pub fn new(io: T, port: &str, timeout: Duration) -> Session<T> {
        // tags start where the clock says, so a reply to another program's
        // (or an earlier run's) command is unlikely to match ours either
        let seed = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_micros());
        Session { io, pending: Vec::new(), tag: seed % 900_000, timeout, port: port.into() }
    }

    /// Sends one command; returns the device's reply (`ok ...`), or the
    /// device's `error: ...` as an Err.
    pub fn ask(&mut self, command: &str) -> CliResult<String> {
        ok_or_device_error(self.ask_within(command, self.timeout)?)
    }

    /// `ask` with its own deadline, the reply as it came (ok or error).
    pub fn ask_within(&mut self, command: &str, timeout: Duration) -> CliResult<String> {
        check_command(command)?;
        self.tag = self.tag % 999_999 + 1;
        let prefix = format!("#{} ", self.tag);
        let line = format!("{prefix}{command}\r\n");
        let sent = self.io.write_all(line.as_bytes()).and_then(|_| self.io.flush());
        sent.map_err(|e| self.port_error(format!("could not send '{command}': {e}")))?;
        let deadline = Instant::now() + timeout;
        let mut other: Option<String> = None;
        for _ in 0..OTHER_LINES_MAX {
            let got = match self.read_line(deadline) {
                Ok(l) => l,
                Err(Timeout) => return Err(self.no_reply(command, timeout, other)),
                Err(Failed(e)) => return Err(e),
            };
            if let Some(reply) = got.strip_prefix(&prefix) {
                return Ok(reply.to_string());
            }
            if got == OLD_FIRMWARE {
                return Err(self.port_error(format!("the board's firmware does not tag its replies (older than polyturn {}): flash this version (README, \"Flashing\")", super::super::VERSION)));
            }
            // a stale status line of a watch, or noise: not the reply
            if other.is_none() && !got.trim().is_empty() && !got.starts_with('#') && !got.starts_with("ok state=") {
                other = Some(got);
            }
        }
        Err(self.no_reply(command, timeout, other))
    }

    /// The next line, by `deadline`.
    pub fn read_line(&mut self, deadline: Instant) -> Result<String, Wait> {
        let mut chunk = [0u8; 256];
        loop {
            if let Some(end) = self.pending.iter().position(|&b| b == b'\n') {
                let line: Vec<u8> = self.pending.drain(..=end).collect();
                return Ok(String::from_utf8_lossy(&line).trim_end_matches(['\r', '\n']).to_string());
            }
            if self.pending.len() > REPLY_MAX {
                return Err(Failed(
                    self.port_error(format!("sent a line longer than {REPLY_MAX} bytes: not a polyturn console")),
                ));
            }
            if Instant::now() >= deadline {
                return Err(Timeout);
            }
            match self.io.read(&mut chunk) {
                Ok(0) => return Err(Failed(self.port_error("closed the console"))),
                Ok(n) => self.pending.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted) => {
                    std::thread::sleep(Duration::from_millis(1))
                }
                Err(e) => return Err(Failed(self.port_error(format!("read failed: {e}")))),
            }
        }
    }

    /// An error naming the port (`--port PATH: what`).
    pub fn port_error(&self, what: impl std::fmt::Display) -> CliError {
        CliError::flag("port", format!("{}: {what}", escaped(&self.port)))
    }

    fn no_reply(&self, command: &str, timeout: Duration, other: Option<String>) -> CliError {
        let word = command.split(' ').next().unwrap_or("");
        let seen = match other {
            Some(l) => {
                format!(" (it sent '{}': is this a polyturn board?)", escaped(&l.chars().take(60).collect::<String>()))
            }
            None => String::new(),
        };
        self.port_error(format!("no reply to '{word}' within {:.1} s{seen}", timeout.as_secs_f64()))
    }
}

/// The device's `error: ...` reply as an Err, any other reply as it is.
pub fn ok_or_device_error(reply: String) -> CliResult<String> {
    if reply.starts_with("error") {
        return Err(CliError(format!("device: {}", escaped(&reply))));
    }
    Ok(reply)
}

/// Why `read_line` returned no line.
pub enum Wait {
    Timeout,
    Failed(CliError),
}
use Wait::{Failed, Timeout};
