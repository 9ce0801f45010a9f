//! A fake board for tests and the web page's device panel: the real sync
//! core's console and controller behind the firmware's framing (`usb.rs`:
//! tags split off and put back, CR LF after each reply, `watch` streaming
//! until the next line), with a machine (`machine.rs`) that lets time pass
//! between commands.

mod machine;

pub use machine::Machine;
use polyturn_sync::cam_upload::{CamUpload, Progress};
use polyturn_sync::console::{self, tag, Action};
use polyturn_sync::{Config, Controller, Timing};
use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};

/// Control ticks (25 kHz) between two `watch` lines: the firmware's 10 Hz.
const WATCH_TICKS: usize = 2_500;

/// The real console behind the firmware's framing: tags split off and put
/// back, `watch` streaming until the next line.
pub struct FakeDevice {
    pub ctl: Controller,
    pending: Vec<u8>,
    out: VecDeque<u8>,
    watching: bool,
    /// time passing between commands, if the test wants it
    pub machine: Option<Machine>,
    /// every command line received, in order
    pub received: Vec<String>,
    /// the cam upload's staging buffer (the console task's, on the board)
    upload: Box<CamUpload>,
}

impl Default for FakeDevice {
    fn default() -> FakeDevice {
        FakeDevice::new()
    }
}

impl FakeDevice {
    /// A board that has just started, with the default settings.
    pub fn new() -> FakeDevice {
        let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        ctl.start(0, 0, 0);
        FakeDevice {
            ctl,
            pending: vec![],
            out: VecDeque::new(),
            watching: false,
            machine: None,
            received: vec![],
            upload: Box::default(),
        }
    }

    /// The replies waiting to be read (what the board has sent).
    pub fn take_replies(&mut self) -> Vec<u8> {
        self.out.drain(..).collect()
    }

    /// While `watch` runs, its next line: a tenth of a second passes on the
    /// machine, then the real `status` reply. Nothing otherwise.
    pub fn watch_line(&mut self) -> Vec<u8> {
        if !self.watching {
            return Vec::new();
        }
        if let Some(m) = &mut self.machine {
            m.pass(&mut self.ctl, WATCH_TICKS);
        }
        let (reply, _) = console::handle(b"status", &mut self.ctl);
        let mut line = reply.as_bytes().to_vec();
        line.extend(b"\r\n");
        line
    }

    /// One line of a cam upload, staged and checked as the firmware's
    /// console task does (`firmware/src/app/usb.rs` `cam_line`); this board
    /// has no flash, so a complete table is checked but not saved or fitted,
    /// and its reply says so.
    fn cam_line(&mut self, args: &[u8]) -> String {
        let args = std::str::from_utf8(args).unwrap_or("?");
        let was_uploading = self.upload.in_progress();
        match self.upload.line(args) {
            Err(e) if was_uploading => format!("error: {e}; the upload is abandoned (start again with cam begin)"),
            Err(e) => format!("error: {e}"),
            Ok(Progress::Begun) => "ok cam begin".into(),
            Ok(Progress::Received(n)) => format!("ok cam {n}"),
            Ok(Progress::Complete(h)) => match self.ctl.check_cam(&h) {
                Ok(()) => {
                    format!("ok cam {} points checked (a simulated board: no flash, not saved or fitted)", h.points)
                }
                Err(e) => format!("error: {e}"),
            },
        }
    }

    fn line(&mut self) {
        self.watching = false;
        let text = String::from_utf8_lossy(&self.pending).to_string();
        if let Some(m) = &mut self.machine {
            m.run(&mut self.ctl, &text);
        }
        self.received.push(text);
        let line = std::mem::take(&mut self.pending);
        let (t, reply, action) = match tag::split(&line) {
            Ok((t, body)) if body.starts_with(b"cam ") && !body.ends_with(b" off") => {
                (t.map(|t| t.to_vec()), self.cam_line(&body[4..]), Action::None)
            }
            Ok((t, body)) => {
                let (r, a) = console::handle(body, &mut self.ctl);
                (t.map(|t| t.to_vec()), r.to_string(), a)
            }
            Err(e) => (None, format!("error: {e}"), Action::None),
        };
        if let Some(t) = t {
            self.out.extend(b"#");
            self.out.extend(t);
            self.out.extend(b" ");
        }
        self.out.extend(reply.as_bytes());
        self.out.extend(b"\r\n");
        self.watching = action == Action::Watch;
    }
}

impl Read for FakeDevice {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.out.is_empty() {
            let line = self.watch_line();
            self.out.extend(line);
        }
        if self.out.is_empty() {
            return Err(ErrorKind::TimedOut.into());
        }
        let n = buf.len().min(self.out.len());
        for (b, o) in buf.iter_mut().zip(self.out.drain(..n)) {
            *b = o;
        }
        Ok(n)
    }
}

impl Write for FakeDevice {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        for &b in data {
            match b {
                b'\n' | b'\r' if self.pending.is_empty() => {}
                b'\n' | b'\r' => self.line(),
                _ => self.pending.push(b),
            }
        }
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
