//! One console session over any byte stream: each command goes out with a
//! tag (`#N`, see the sync core's `console::tag`) and its reply is the line
//! with the same tag that reads as a reply: `#N ok`, `#N ok ...` or
//! `#N error: ...` (no command starts so, so a port that echoes the
//! command is never taken for the board). Every wait has a deadline, every
//! line a length bound, every line from the board is escaped before it is
//! shown, and a command is refused before sending if it holds a control
//! character (which could smuggle in a second command).

use super::super::errors::{escaped, CliError, CliResult};
use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

pub use super::super::console_line::{check_command, is_reply, COMMAND_MAX, DEVICE_LINE_MAX, REPLY_MAX};
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

    /// `ask` with its own deadline, the reply as it came (`ok ...` or
    /// `error: ...`, escaped); any other line with our tag is an error.
    pub fn ask_within(&mut self, command: &str, timeout: Duration) -> CliResult<String> {
        check_command(command)?;
        if is_reply(command) {
            return Err(CliError(format!("the command '{}' reads as a reply: not sent", escaped(command))));
        }
        self.tag = self.tag % 999_999 + 1;
        let prefix = format!("#{} ", self.tag);
        let sent = format!("{prefix}{command}");
        let written = self.io.write_all(format!("{sent}\r\n").as_bytes()).and_then(|_| self.io.flush());
        written.map_err(|e| self.closed(command, &format!("could not send it: {e}")))?;
        let deadline = Instant::now() + timeout;
        let mut heard = Heard::default();
        for _ in 0..OTHER_LINES_MAX {
            let got = match self.read_line(deadline) {
                Ok(l) => l,
                Err(Timeout) => return Err(self.no_reply(command, timeout, heard)),
                Err(Closed(why)) => return Err(self.closed(command, &why)),
                Err(Failed(e)) => return Err(e),
            };
            if got == sent {
                heard.echo = true; // our own line, echoed by the port
                continue;
            }
            if let Some(reply) = got.strip_prefix(&prefix) {
                if is_reply(reply) {
                    return Ok(reply.to_string());
                }
                return Err(self.port_error(format!(
                    "answered '{}' with '{}': neither ok nor error, not a polyturn reply",
                    first_word(command),
                    clipped(&got)
                )));
            }
            if got == OLD_FIRMWARE {
                return Err(self.port_error(format!("the board's firmware does not tag its replies (older than polyturn {}): flash this version (docs/src/flashing.md)", super::super::VERSION)));
            }
            // a stale status line of a watch, or noise: not the reply
            if heard.other.is_none() && !got.trim().is_empty() && !got.starts_with('#') && !got.starts_with("ok state=")
            {
                heard.other = Some(got);
            }
        }
        Err(self.no_reply(command, timeout, heard))
    }

    /// The next line by `deadline`, its control characters escaped (a
    /// board's bytes never reach the terminal raw), at most `REPLY_MAX`
    /// bytes before its line end.
    pub fn read_line(&mut self, deadline: Instant) -> Result<String, Wait> {
        let mut chunk = [0u8; 256];
        loop {
            let end = self.pending.iter().position(|&b| b == b'\n');
            if content_len(&self.pending[..end.unwrap_or(self.pending.len())]) > REPLY_MAX {
                return Err(Failed(
                    self.port_error(format!("sent a line longer than {REPLY_MAX} bytes: not a polyturn console")),
                ));
            }
            if let Some(end) = end {
                let line: Vec<u8> = self.pending.drain(..=end).collect();
                return Ok(escaped(String::from_utf8_lossy(&line).trim_end_matches(['\r', '\n'])));
            }
            if Instant::now() >= deadline {
                return Err(Timeout);
            }
            match self.io.read(&mut chunk) {
                Ok(0) => return Err(Closed("end of file".into())),
                Ok(n) => self.pending.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted) => {
                    std::thread::sleep(Duration::from_millis(1))
                }
                // after the port opened, a failed read is the board gone:
                // unplugged, restarted, or the port closed under us
                Err(e) => return Err(Closed(e.to_string())),
            }
        }
    }

    /// An error naming the port (`--port PATH: what`).
    pub fn port_error(&self, what: impl std::fmt::Display) -> CliError {
        CliError::flag("port", format!("{}: {what}", escaped(&self.port)))
    }

    /// The board went away while we waited for `command`'s reply.
    pub fn closed(&self, command: &str, why: &str) -> CliError {
        self.port_error(format!(
            "the board closed the port before replying to '{}' ({}): unplugged or restarted? Nothing is known of what it did",
            first_word(command),
            escaped(why)
        ))
    }

    fn no_reply(&self, command: &str, timeout: Duration, heard: Heard) -> CliError {
        let seen = match (heard.other, heard.echo) {
            (Some(l), _) => format!(" (it sent '{}': is this a polyturn board?)", clipped(&l)),
            (None, true) => " (the port echoed the command back: a terminal in echo mode, a loopback plug or an adapter that echoes, not a polyturn board)".into(),
            (None, false) => String::new(),
        };
        self.port_error(format!("no reply to '{}' within {:.1} s{seen}", first_word(command), timeout.as_secs_f64()))
    }
}

/// What came back while no reply did.
#[derive(Default)]
struct Heard {
    /// the first line that was not ours
    other: Option<String>,
    /// our own command came back
    echo: bool,
}

/// A line's length without the CR that ends it (CR LF, the LF not yet in).
fn content_len(line: &[u8]) -> usize {
    line.len() - usize::from(line.ends_with(b"\r"))
}

fn first_word(command: &str) -> &str {
    command.split(' ').next().unwrap_or("")
}

/// The first 80 characters of an (escaped) line, for an error.
fn clipped(line: &str) -> String {
    escaped(&line.chars().take(80).collect::<String>())
}

/// The device's `error: ...` reply as an Err, its `ok ...` as it is, and
/// anything else as an error (a reply that is neither is no success).
pub fn ok_or_device_error(reply: String) -> CliResult<String> {
    if reply.starts_with("error: ") || !is_reply(&reply) {
        return Err(CliError(format!("device: {}", escaped(&reply))));
    }
    Ok(reply)
}

/// Why `read_line` returned no line.
pub enum Wait {
    Timeout,
    /// the port closed or failed: the board is gone (why, as the OS said)
    Closed(String),
    Failed(CliError),
}
use Wait::{Closed, Failed, Timeout};
