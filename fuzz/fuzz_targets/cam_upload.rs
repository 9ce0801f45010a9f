//! Console lines as the firmware's USB session routes them: `cam ...` into
//! the upload (`CamUpload::line`), `tick <n> <counts>` runs the controller
//! with the lathe turning, anything else into `console::handle` (`set cpr`,
//! `engage`, ...). `cam end *` stands for `cam end <the right CRC>` (the
//! fuzzer cannot compute a CRC-32), worked out from the lines the upload
//! accepted. Properties, never a panic and:
//! - the upload holds exactly what was sent: a `Complete` header and table
//!   are the accepted `begin` and `data` values, and after any error there
//!   is no table;
//! - the firmware's checks before saving (`Controller::check_cam` and
//!   `check_table`, idle with the lathe at rest) accept a table exactly when
//!   the controller then fits it (`fit_cam`: `prepare_cam`, `Cam::new`,
//!   `install_cam`): no false ok, no false error;
//! - with a fitted cam, the tick runs, and plans no X step while its
//!   output is off.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polyturn_sync::cam_upload::{checksum, CamHeader, CamUpload, Progress, TableRefusal};
use polyturn_sync::controller::check_table;
use polyturn_sync::{console, Config, Controller, State, TickInput, Timing};

/// Ticks per input at most (keeps an input fast).
const TICK_BUDGET: u32 = 5_000;

/// What the upload accepted so far, as the harness saw it.
#[derive(Default)]
struct Mirror {
    header: Option<CamHeader>,
    points: Vec<i32>,
}

impl Mirror {
    fn begun(&mut self, args: &str) {
        let n: Vec<u32> = args.split_ascii_whitespace().skip(1).take(5).map(|w| w.parse().unwrap()).collect();
        let header =
            CamHeader { points: n[0], period_counts: n[1], counts_per_rev: n[2], max_rate_hz: n[3], max_accel: n[4] };
        (self.header, self.points) = (Some(header), Vec::new());
    }

    fn received(&mut self, args: &str) {
        self.points.extend(args.split_ascii_whitespace().skip(2).map(|w| w.parse::<i32>().unwrap()));
    }

    fn end_line(&self) -> String {
        let crc = self.header.map_or(0, |h| checksum(&h, &self.points));
        format!(" end {crc:08x}")
    }
}

/// `FUZZ_TRACE=1 cargo fuzz run <target> <input>` shows what an input did.
fn trace() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("FUZZ_TRACE").is_some())
}

struct Run {
    ctl: Controller,
    upload: Box<CamUpload>,
    mirror: Mirror,
    lathe: u16,
    ticks: u32,
    /// the fitted tables (the controller borrows them for 'static)
    tables: Vec<*mut [i32]>,
}

impl Run {
    fn cam(&mut self, line: &[u8]) {
        let args = core::str::from_utf8(&line[3..]).unwrap_or("?");
        if args.trim() == "off" {
            let _ = self.ctl.set_x_axis(None);
            return;
        }
        let words: Vec<&str> = args.split_ascii_whitespace().collect();
        let substituted;
        let args = if words == ["end", "*"] {
            substituted = self.mirror.end_line();
            substituted.as_str()
        } else {
            args
        };
        let progress = self.upload.line(args);
        if trace() {
            eprintln!("cam{args}: {progress:?}");
        }
        match progress {
            Err(_) => {
                assert!(self.upload.table().is_none(), "an error abandons the upload");
                self.mirror = Mirror::default();
            }
            Ok(Progress::Begun) => {
                self.mirror.begun(args);
                assert!(self.upload.table().is_none());
            }
            Ok(Progress::Received(n)) => {
                self.mirror.received(args);
                assert_eq!(n, self.mirror.points.len());
                assert!(n <= self.mirror.header.unwrap().points as usize);
                // (`cam data <all>` with no values after `cam end` keeps the
                // checked table: it is still exactly what was sent)
                if let Some((h, points)) = self.upload.table() {
                    assert_eq!((Some(h), points), (self.mirror.header, &self.mirror.points[..]));
                }
            }
            Ok(Progress::Complete(h)) => self.complete(h),
        }
    }

    fn complete(&mut self, h: CamHeader) {
        assert_eq!(Some(h), self.mirror.header);
        let (h2, points) = self.upload.table().expect("a complete upload has its table");
        assert_eq!(h2, h);
        assert_eq!(points, &self.mirror.points[..]);
        assert!((2..=1024).contains(&points.len()) && h.period_counts >= h.points);
        // the firmware saves and fits only while idle with the lathe at rest
        if self.ctl.state() != State::Idle || !self.ctl.lathe_at_rest() {
            return;
        }
        let checked = self.ctl.check_cam(&h).map_err(TableRefusal::from).and_then(|()| check_table(&h, points));
        let table = Box::into_raw(points.to_vec().into_boxed_slice());
        self.tables.push(table);
        // SAFETY: freed only after the controller is dropped (`Drop`)
        let fitted = self.ctl.fit_cam(&h, unsafe { &*table });
        if trace() {
            eprintln!("checked {checked:?}, fitted {fitted:?}");
        }
        match (checked, fitted) {
            (Ok(()), Ok(())) => {
                assert_eq!(self.ctl.x_axis().map(|x| x.cam.points()), Some(points));
            }
            (Err(_), Err(_)) => {}
            (Ok(()), Err(e)) => panic!("false ok: the checks accepted {h:?}, the fit refused it: {e}"),
            (Err(e), Ok(())) => panic!("false error: the checks refused {h:?} ({e}), the fit took it"),
        }
    }

    /// `n` ticks with the lathe turning `counts` a tick; the step outputs
    /// do what they are told (the cutter's two ticks late, `steps::pipe`).
    fn run(&mut self, n: u32, counts: i32, pipe: &mut Pipe, x: &mut polyturn_firmware::xsteps::XSteps) {
        for _ in 0..n.min(TICK_BUDGET - self.ticks) {
            self.ticks += 1;
            self.lathe = self.lathe.wrapping_add(counts as u16);
            let io =
                TickInput { lathe: self.lathe, emitted: pipe.pulses, x_emitted: x.emitted, ..TickInput::default() };
            let out = self.ctl.tick(&io);
            self.ctl.service();
            pipe.execute(out.plan.count, out.halt);
            x.tick(&out.x_plan, out.halt);
            if !out.enable {
                assert_eq!(out.x_plan.count, 0);
            }
        }
    }
}

/// The cutter's step output: each plan runs two ticks after it was made.
#[derive(Default)]
struct Pipe {
    queue: std::collections::VecDeque<u16>,
    pulses: u16,
}

impl Pipe {
    fn execute(&mut self, count: u16, halt: bool) {
        self.queue.push_back(count);
        if halt {
            self.queue.clear();
        }
        if self.queue.len() > 2 {
            let n = self.queue.pop_front().unwrap_or(0);
            self.pulses = self.pulses.wrapping_add(n);
        }
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        // the controller (and its X axis) goes first: nothing borrows them
        self.ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        for t in self.tables.drain(..) {
            // SAFETY: made by Box::into_raw above; no reference remains
            drop(unsafe { Box::from_raw(t) });
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
    ctl.start(0, 0, 0);
    let mut run =
        Run { ctl, upload: Box::default(), mirror: Mirror::default(), lathe: 0, ticks: 0, tables: Vec::new() };
    let (mut pipe, mut x) = (Pipe::default(), polyturn_firmware::xsteps::XSteps::default());
    for line in data.split(|&b| b == b'\n' || b == b'\r') {
        if line.is_empty() {
            continue; // the LF of a CRLF: the firmware's line buffer drops it
        } else if line.starts_with(b"cam") {
            run.cam(line);
        } else if let Some(rest) = line.strip_prefix(b"tick ") {
            let text = String::from_utf8_lossy(rest);
            let mut w = text.split_ascii_whitespace().map(|w| w.parse::<i32>().unwrap_or(0));
            let (n, counts) = (w.next().unwrap_or(1), w.next().unwrap_or(0));
            run.run(n.max(0) as u32, counts, &mut pipe, &mut x);
            if trace() {
                eprintln!("tick {n} {counts}: {:?}, X on: {}", run.ctl.state(), run.ctl.x_axis().is_some());
            }
        } else {
            let before = *run.ctl.config();
            let (reply, _) = console::handle(line, &mut run.ctl);
            if trace() {
                eprintln!("> {}\n< {reply}", String::from_utf8_lossy(line));
            }
            if reply.starts_with("error") {
                assert_eq!(*run.ctl.config(), before);
            }
        }
    }
});
