//! A fake board for tests and the web page's device panel: the real sync
//! core's console and controller behind the firmware's framing, from the
//! firmware's own code (`polyturn_firmware::line`: lines of at most 96
//! bytes, an over-long one dropped and answered untagged, any byte but CR
//! and LF kept; tags split off and put back, `cam` lines to the upload)
//! and as its `usb.rs` runs it (64-byte packets, CR LF after each reply,
//! `watch` streaming until a packet that is not only line ends), with a
//! machine (`workshop.rs`) that lets time pass between commands.

mod workshop;

use polyturn_firmware::line::{only_line_ends, route, Line, LineBuffer, Route, PACKET_MAX, TOO_LONG};
use polyturn_sync::cam_upload::{CamUpload, Progress, TableRefusal};
use polyturn_sync::console::{self, Action};
use polyturn_sync::controller::check_table;
use polyturn_sync::{Config, Controller, Timing};
use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};
pub use workshop::{ticks_in_ms, Workshop, TICK_HZ};

/// Control ticks between two `watch` lines: the firmware's 10 Hz.
const WATCH_TICKS: usize = (Timing::FIRMWARE.tick_hz / 10) as usize;
/// Replies waiting to be read, at most: the board blocks on a full USB
/// buffer and takes no more input; this one stops taking input too.
const OUT_MAX: usize = 64 * 1024;
/// Command lines kept for the tests (`received`): the older half goes.
const RECEIVED_MAX: usize = 100_000;

/// The real console behind the firmware's framing: tags split off and put
/// back, `watch` streaming until the next packet that is not line ends.
pub struct FakeDevice {
    pub ctl: Controller,
    lines: LineBuffer,
    out: VecDeque<u8>,
    watching: bool,
    /// time passing between commands, if the test wants it
    pub workshop: Option<Workshop>,
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
            lines: LineBuffer::default(),
            out: VecDeque::new(),
            watching: false,
            workshop: None,
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
        if let Some(m) = &mut self.workshop {
            m.pass(&mut self.ctl, WATCH_TICKS);
        }
        let (reply, _) = console::handle(b"status", &mut self.ctl);
        let mut line = reply.as_bytes().to_vec();
        line.extend(b"\r\n");
        line
    }

    /// One line of a cam upload (`args`: what follows `cam`), staged and
    /// checked as the firmware's console task does (`firmware/src/app/usb.rs`
    /// `cam_line`); this board has no flash, so a complete table is checked
    /// but not saved or fitted, and its reply says so.
    fn cam_line(&mut self, args: &[u8]) -> String {
        let args = std::str::from_utf8(args).unwrap_or("?");
        if args.trim() == "off" {
            return match self.ctl.set_x_axis(None) {
                Ok(()) => "ok cam off (save to forget it)".into(),
                Err(_) => "error: stop first: the cam changes only while idle".into(),
            };
        }
        let was_uploading = self.upload.in_progress();
        match self.upload.line(args) {
            Err(e) if was_uploading => format!("error: {e}; the upload is abandoned (start again with cam begin)"),
            Err(e) => format!("error: {e}"),
            Ok(Progress::Begun) => "ok cam begin".into(),
            Ok(Progress::Received(n)) => format!("ok cam {n}"),
            Ok(Progress::Complete(h)) => match console::cam_wait(&mut self.ctl) {
                Some(why) => format!("error: {why} ({} points kept, send cam end again)", h.points),
                None => self.check_table(&h),
            },
        }
    }

    /// A complete table, idle with the lathe at rest: checked as `usb.rs`
    /// checks it before saving (this board has no flash).
    fn check_table(&mut self, h: &polyturn_sync::cam_upload::CamHeader) -> String {
        // the header under the lock, the points outside it, as `usb.rs`
        let points = self.upload.table().map_or(&[][..], |(_, p)| p);
        match self.ctl.check_cam(h).map_err(TableRefusal::from).and_then(|()| check_table(h, points)) {
            Ok(()) => format!("ok cam {} points checked (a simulated board: no flash, not saved or fitted)", h.points),
            Err(e) => format!("error: {e}"),
        }
    }

    /// One line as the console task answers it: the reply, tagged as the
    /// line was, and what to do besides.
    fn answer(&mut self, line: &[u8]) -> Action {
        let text = String::from_utf8_lossy(line).to_string();
        if let Some(m) = &mut self.workshop {
            m.run(&mut self.ctl, &text);
        }
        if self.received.len() >= RECEIVED_MAX {
            self.received.drain(..RECEIVED_MAX / 2);
        }
        self.received.push(text);
        let (t, reply, action) = match route(line) {
            Ok((t, Route::Cam(args))) => (t, self.cam_line(args), Action::None),
            Ok((t, Route::Console(body))) => {
                let (r, a) = console::handle(body, &mut self.ctl);
                (t, r.to_string(), a)
            }
            Err(e) => (None, format!("error: {e}"), Action::None),
        };
        self.send(t, &reply);
        action
    }

    /// `#tag reply` (or `reply` untagged) and CR LF.
    fn send(&mut self, tag: Option<&[u8]>, reply: &str) {
        if let Some(t) = tag {
            self.out.extend(b"#");
            self.out.extend(t);
            self.out.extend(b" ");
        }
        self.out.extend(reply.as_bytes());
        self.out.extend(b"\r\n");
    }

    /// One USB packet, as `usb.rs`'s session loop takes it: a watch ends
    /// at a packet that is not only line ends (which is then handled), and
    /// starts only if nothing but line ends follows `watch` in its packet.
    fn packet(&mut self, packet: &[u8]) {
        if self.watching && only_line_ends(packet) {
            return;
        }
        self.watching = false;
        for (i, &byte) in packet.iter().enumerate() {
            let line = match self.lines.push(byte) {
                None => continue,
                Some(Line::TooLong) => None,
                Some(Line::Text(text)) => Some(text.to_vec()),
            };
            self.lines.clear();
            let action = match line {
                Some(text) => self.answer(&text),
                None => {
                    self.send(None, TOO_LONG);
                    Action::None
                }
            };
            self.watching = action == Action::Watch && only_line_ends(&packet[i + 1..]);
        }
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
    /// Takes the bytes in 64-byte packets while fewer than `OUT_MAX`
    /// bytes of replies wait to be read; none taken is `WouldBlock`.
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        let mut taken = 0;
        for packet in data.chunks(PACKET_MAX) {
            if self.out.len() >= OUT_MAX {
                break;
            }
            self.packet(packet);
            taken += packet.len();
        }
        if taken == 0 && !data.is_empty() {
            return Err(ErrorKind::WouldBlock.into());
        }
        Ok(taken)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests;
