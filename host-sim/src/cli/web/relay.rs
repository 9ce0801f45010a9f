//! `polyturn web --board PORT`: the board's console, opened on this
//! machine, shared by the pages that connect (`socket.rs`). Every line the
//! board sends goes to every page as it comes; nothing is kept for a page
//! that comes later. One page has control and its lines go to the board,
//! checked as `relay_line` says; the others watch, and a line from one of
//! them is answered with a refusal. When the board goes away (unplugged,
//! reset into its bootloader, the emulator ended) every page is told and
//! let go, and nothing it sent is sent again; the next page that connects
//! opens the port anew.

use super::super::console_line::REPLY_MAX;
use super::relay_line;
use serde::Serialize;
use std::io::{ErrorKind, Read, Write};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

/// Pages connected at once, watchers included.
pub const MEMBERS_MAX: usize = 8;
/// Events waiting for one page; a page that falls this far behind the
/// board (10 status lines a second) is let go rather than kept waiting.
const EVENTS_MAX: usize = 1024;

/// What a page hears, sent to it as JSON (`{"t":"line","line":"..."}`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "t", rename_all = "lowercase")]
pub enum Event {
    /// The relay's greeting: the port and this polyturn's version.
    Hello { port: String, version: String },
    /// A line from the board (or the relay's refusal of this page's line).
    Line { line: String },
    /// Who has control: this page, or another, or nobody (`free`).
    Control { yours: bool, free: bool },
    /// The board went away, or could not be opened: why. The page is let go.
    Gone { why: String },
    /// Something the page should show: a refusal that is not a reply.
    Notice { why: String },
}

/// The board's two ends: lines come from `reader`, commands go to `writer`.
pub type Ends = (Box<dyn Read + Send>, Box<dyn Write + Send>);
/// Opens the board (again); Err is one sentence for the page.
pub type Opener = Box<dyn Fn() -> Result<Ends, String> + Send + Sync>;

pub struct Relay {
    pub port: String,
    open: Opener,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    /// None while the board is gone.
    writer: Option<Box<dyn Write + Send>>,
    /// Which opening of the board the reader thread serves.
    opening: u64,
    members: Vec<(u64, SyncSender<Event>)>,
    controller: Option<u64>,
    next_id: u64,
}

/// A page's place: its id, and the events meant for it.
pub struct Member {
    pub id: u64,
    pub events: Receiver<Event>,
}

impl Relay {
    /// Opens the board now, so that a port that cannot be opened is
    /// refused at start; Err is the reason.
    pub fn start(port: &str, open: Opener) -> Result<Arc<Relay>, String> {
        let relay = Arc::new(Relay { port: port.into(), open, state: Mutex::new(State::default()) });
        relay.open_board(&mut relay.lock())?;
        Ok(relay)
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // a thread that panicked holding it left nothing half-done that
        // matters more than going on: the list of pages is whole
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn open_board(self: &Arc<Self>, s: &mut State) -> Result<(), String> {
        let (reader, writer) = (self.open)()?;
        s.writer = Some(writer);
        s.opening += 1;
        let (relay, opening) = (Arc::clone(self), s.opening);
        std::thread::Builder::new()
            .name("polyturn-relay".into())
            .spawn(move || relay.read_board(reader, opening))
            .map_err(|e| format!("cannot start reading the board: {e}"))?;
        Ok(())
    }

    /// A new page: control if nobody has it. The board is opened again if
    /// it had gone; Err says why the page cannot have it.
    pub fn join(self: &Arc<Self>) -> Result<Member, String> {
        let mut s = self.lock();
        if s.members.len() >= MEMBERS_MAX {
            return Err(format!("{MEMBERS_MAX} pages already have the board: close one"));
        }
        if s.writer.is_none() {
            self.open_board(&mut s)?;
        }
        let (tx, events) = sync_channel(EVENTS_MAX);
        s.next_id += 1;
        let id = s.next_id;
        let hello = Event::Hello { port: self.port.clone(), version: super::super::VERSION.into() };
        let yours = s.controller.is_none();
        if yours {
            s.controller = Some(id);
        }
        // a fresh channel has room for these two
        let _ = tx.try_send(hello);
        let _ = tx.try_send(Event::Control { yours, free: false });
        s.members.push((id, tx));
        Ok(Member { id, events })
    }

    /// Control for page `id` if nobody has it; Err says who has it.
    pub fn take(&self, id: u64) -> Result<(), String> {
        let mut s = self.lock();
        match s.controller {
            Some(c) if c == id => Ok(()),
            Some(_) => Err(relay_line::NOT_IN_CONTROL.into()),
            None => {
                s.controller = Some(id);
                tell_control(&mut s);
                Ok(())
            }
        }
    }

    /// Page `id` has gone: its control is free for the others.
    pub fn leave(&self, id: u64) {
        let mut s = self.lock();
        s.members.retain(|(m, _)| *m != id);
        if s.controller == Some(id) {
            s.controller = None;
            tell_control(&mut s);
        }
    }

    /// Sends page `id`'s line to the board; Err is the reply the page gets
    /// instead (the line's tag, `error: relay: why`).
    pub fn send(&self, id: u64, line: &str) -> Result<(), String> {
        relay_line::check(line)?;
        let mut s = self.lock();
        let tag = relay_line::tag_of(line);
        if s.writer.is_none() {
            return Err(relay_line::refusal(tag, "the board has gone: nothing was sent"));
        }
        if s.controller != Some(id) {
            return Err(relay_line::refusal(tag, relay_line::NOT_IN_CONTROL));
        }
        let Some(writer) = s.writer.as_mut() else { return Err(relay_line::refusal(tag, "the board has gone")) };
        let sent = writer.write_all(format!("{line}\r\n").as_bytes()).and_then(|_| writer.flush());
        sent.map_err(|e| {
            relay_line::refusal(tag, &format!("could not send it to the board ({e}): nothing is known of what it did"))
        })
    }

    /// The board's lines, to every page, until the board goes away.
    fn read_board(&self, mut reader: Box<dyn Read + Send>, opening: u64) {
        let mut lines = Lines::default();
        let mut chunk = [0u8; 256];
        let why = loop {
            match reader.read(&mut chunk) {
                Ok(0) => break "the port reached its end".to_string(),
                Ok(n) => {
                    for event in lines.push(&chunk[..n]) {
                        self.broadcast(opening, event);
                    }
                }
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted) => {
                    std::thread::sleep(Duration::from_millis(1));
                }
                Err(e) => break e.to_string(),
            }
            if self.lock().opening != opening {
                return;
            }
        };
        self.gone(opening, &why);
    }

    fn broadcast(&self, opening: u64, event: Event) {
        let mut s = self.lock();
        if s.opening != opening {
            return;
        }
        // a page too far behind is let go: its channel closes
        s.members.retain(|(_, tx)| {
            !matches!(tx.try_send(event.clone()), Err(TrySendError::Full(_) | TrySendError::Disconnected(_)))
        });
        if s.controller.is_some_and(|c| !s.members.iter().any(|(m, _)| *m == c)) {
            s.controller = None;
            tell_control(&mut s);
        }
    }

    /// The board went away: every page is told and let go.
    fn gone(&self, opening: u64, why: &str) {
        let mut s = self.lock();
        if s.opening != opening {
            return;
        }
        s.writer = None;
        s.controller = None;
        let why = format!(
            "the board on {} went away ({why}): unplugged, restarted or switched off? Nothing that was waiting for a reply was sent again",
            super::super::errors::escaped(&self.port)
        );
        for (_, tx) in s.members.drain(..) {
            let _ = tx.try_send(Event::Gone { why: why.clone() });
        }
    }
}

/// Tells every page who has control now.
fn tell_control(s: &mut State) {
    let controller = s.controller;
    for (id, tx) in &s.members {
        let _ = tx.try_send(Event::Control { yours: controller == Some(*id), free: controller.is_none() });
    }
}

/// The board's bytes as lines (CR LF or LF ends one), each at most
/// `REPLY_MAX` bytes: a longer one is no polyturn line, dropped whole
/// with a notice, never cut into a different one.
#[derive(Default)]
struct Lines {
    pending: Vec<u8>,
    dropping: bool,
}

impl Lines {
    fn push(&mut self, bytes: &[u8]) -> Vec<Event> {
        let mut out = Vec::new();
        for &b in bytes {
            if b == b'\n' {
                if !std::mem::take(&mut self.dropping) {
                    let line = String::from_utf8_lossy(&self.pending).trim_end_matches('\r').to_string();
                    if !line.is_empty() {
                        out.push(Event::Line { line });
                    }
                }
                self.pending.clear();
            } else if !self.dropping {
                self.pending.push(b);
                if self.pending.len() > REPLY_MAX + 1 {
                    self.pending.clear();
                    self.dropping = true;
                    out.push(Event::Notice {
                        why: format!("the board sent a line longer than {REPLY_MAX} bytes: not a polyturn console; it was dropped"),
                    });
                }
            }
        }
        out
    }
}

/// The real board: the serial port, opened as `polyturn device` opens it.
pub fn serial(port: String) -> Opener {
    Box::new(move || {
        let shown = super::super::errors::escaped(&port);
        let p = super::super::device::port::open(&port)?;
        let reader = p.try_clone().map_err(|e| format!("cannot open {shown} twice (to read and write): {e}"))?;
        Ok((reader as Box<dyn Read + Send>, p as Box<dyn Write + Send>))
    })
}

#[cfg(test)]
#[path = "relay_tests.rs"]
mod tests;
