//! A controller on a simulated bench, driven by lines of text: console
//! commands (`console::handle`) and bench actions, one a line:
//!
//! ```text
//! tick <n> <counts>   n ticks, the lathe turning <counts> a tick
//! estop 0|1, alarm 0|1   the E-stop loop open, the drive's alarm, held
//! index <k>           an index latched <k> counts after the last reading
//! glitch <k>          <k> spurious pulses on the cutter's step counter
//! late <k>            each reading also sees <k> pulses of the window
//!                     being emitted (at most all of them)
//! slip <k>            the BLDC's encoder jumps <k> counts
//! stall | unstall     a flash write starts / ends (begin/end_stall)
//! service             the low-priority housekeeping
//! xcam <rate> <accel> <period> <v>...   fit an X cam (this cpr), or try
//! xoff                take the X axis off
//! ```
//! The step outputs do what they are told: the cutter's each plan two
//! ticks later (`steps::pipe`, halted at once), the X axis by the
//! firmware's own pin driver (`polyturn_firmware::xsteps`), the BLDC
//! turning at its command. Properties, never a panic (overflow checks on)
//! and after every action:
//! - the settings validate; a console reply is `ok ...` or `error: ...`,
//!   not cut at the reply buffer's end; an `error` changes neither the
//!   settings nor the state; while running, only the phase changes;
//! - nothing moves when the output is off (no steps, no X step, no speed),
//!   nor while the E-stop is open or the drive in alarm; an immediate fault
//!   (E-stop, alarm, step output) halts; idle is off, engaging and synced
//!   are on; a drive gets only its own kind of command;
//! - ramping down (disengaging, a ramped fault) never speeds up;
//! - the cutter's steps fall inside their tick, each at least a period
//!   (pulse high and low) after the one before, across ticks too, and a
//!   reversal at least a pulse and DIR's setup time after it.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polyturn_firmware::xsteps::XSteps;
use polyturn_sync::cam_upload::CamHeader;
use polyturn_sync::console::{self, Action};
use polyturn_sync::steps::{Dir, StepPlan, StepTiming};
use polyturn_sync::{Config, Controller, DriveKind, State, TickInput, TickOutput, Timing};
use std::collections::VecDeque;

/// Ticks per input at most (keeps an input fast).
const TICK_BUDGET: u32 = 12_000;

struct Bench {
    ctl: Controller,
    lathe: u16,
    /// the cutter's plans in flight, with the timing they were made for
    queue: VecDeque<(StepPlan, StepTiming)>,
    /// the cutter's step pulse counter
    pulses: u16,
    late: u16,
    /// the last rising edge emitted (timer ticks since start) and its DIR
    last_rise: Option<(u64, Dir)>,
    /// BLDC rotor, Q16 encoder counts
    cutter_q16: i64,
    x: XSteps,
    estop: bool,
    alarm: bool,
    index: Option<i16>,
    ticks: u32,
    /// X cam tables the controller borrows for 'static
    tables: Vec<*mut [i32]>,
}

impl Drop for Bench {
    fn drop(&mut self) {
        // the controller (and its X axis) goes first: nothing borrows them
        self.ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        for t in self.tables.drain(..) {
            // SAFETY: made by Box::into_raw in `xcam`; no reference remains
            drop(unsafe { Box::from_raw(t) });
        }
    }
}

fn running(s: State) -> bool {
    matches!(s, State::Engaging | State::Synced | State::Disengaging)
}

impl Bench {
    fn new() -> Bench {
        let mut ctl = Controller::new(Config::default(), Timing::FIRMWARE);
        ctl.start(0, 0, 0);
        Bench {
            ctl,
            lathe: 0,
            queue: VecDeque::new(),
            pulses: 0,
            late: 0,
            last_rise: None,
            cutter_q16: 0,
            x: XSteps::default(),
            estop: false,
            alarm: false,
            index: None,
            ticks: 0,
            tables: Vec::new(),
        }
    }

    fn console(&mut self, line: &[u8]) {
        let (before, generation, state) = (*self.ctl.config(), self.ctl.config_generation(), self.ctl.state());
        let (reply, action) = console::handle(line, &mut self.ctl);
        if trace() {
            eprintln!("> {}\n< {reply}", String::from_utf8_lossy(line));
        }
        assert!(reply.starts_with("ok") || reply.starts_with("error: "), "{reply}");
        assert!(reply.len() < console::REPLY_LEN, "reply cut at the buffer's end: {reply}");
        assert_eq!(self.ctl.config().validate(), Ok(()));
        if reply.starts_with("error") {
            assert_eq!(*self.ctl.config(), before, "{reply}");
            assert_eq!(self.ctl.config_generation(), generation, "{reply}");
            assert_eq!(self.ctl.state(), state, "{reply}");
        }
        if running(state) {
            assert!(self.ctl.config().differs_only_in_phase(&before), "settings changed while {state:?}: {reply}");
        }
        if action == Action::Save {
            assert!(state == State::Idle && self.ctl.lathe_at_rest(), "saved while {state:?}");
        }
    }

    fn tick(&mut self, counts: i32) {
        self.ticks += 1;
        let (state, velocity) = (self.ctl.state(), self.ctl.follower().velocity);
        let last = self.lathe;
        self.lathe = self.lathe.wrapping_add(counts as u16);
        let partial = self.queue.front().map_or(0, |(p, _)| self.late.min(p.count));
        let io = TickInput {
            lathe: self.lathe,
            index: self.index.take().map(|k| last.wrapping_add(k as u16)),
            emitted: self.pulses.wrapping_add(partial),
            cutter: (self.cutter_q16 >> 16) as u16,
            estop_open: self.estop,
            alarm: self.alarm,
            x_emitted: self.x.emitted,
            lathe_edge: None,
        };
        let out = self.ctl.tick(&io);
        self.check(&io, &out, state, velocity);
        self.emit(&out, partial);
    }

    fn check(&self, io: &TickInput, out: &TickOutput, before: State, velocity: i64) {
        let state = self.ctl.state();
        let c = self.ctl.config();
        assert_eq!(c.validate(), Ok(()));
        if !out.enable {
            assert_eq!((out.plan.count, out.x_plan.count, out.speed_q16), (0, 0, 0), "moves while off: {out:?}");
        }
        if io.estop_open || io.alarm {
            assert!(!out.enable && out.halt, "{state:?} {out:?}");
        }
        if let State::Fault(f) = state {
            if f.immediate() {
                assert!(out.halt && !out.enable, "{f:?} {out:?}");
            }
        }
        match state {
            State::Idle => assert!(!out.enable),
            State::Engaging | State::Synced => assert!(out.enable),
            _ => {}
        }
        match c.drive {
            DriveKind::Stepper => assert_eq!(out.speed_q16, 0),
            DriveKind::Bldc => assert_eq!(out.plan.count, 0),
            DriveKind::None => assert_eq!((out.plan.count, out.speed_q16), (0, 0)),
        }
        let ramping = matches!(state, State::Disengaging | State::Fault(_));
        if state == before && ramping {
            let now = self.ctl.follower().velocity;
            assert!(now.abs() <= velocity.abs(), "sped up while {state:?}: {velocity} -> {now}");
        }
    }

    /// The hardware: the cutter's plan two ticks later (a halt stops it
    /// where it is), the X pins now, the BLDC at its command.
    fn emit(&mut self, out: &TickOutput, partial: u16) {
        self.queue.push_back((out.plan, self.ctl.derived().steps));
        if out.halt {
            self.pulses = self.pulses.wrapping_add(partial);
            self.queue.clear();
        }
        while self.queue.len() > 2 {
            let Some((p, t)) = self.queue.pop_front() else { break };
            // this window starts at the tick just run
            let start = (self.ticks - 1) as u64 * t.tick_len as u64;
            for i in 0..p.count as u32 {
                let at = p.at(i);
                assert!(at <= t.tick_len, "step {i} at {at} past the tick ({}): {p:?}", t.tick_len);
                let rise = start + at as u64;
                if let Some((last, dir)) = self.last_rise {
                    let need = if dir == p.dir { t.min_period } else { t.pulse + t.dir_setup };
                    assert!(
                        rise >= last + need as u64,
                        "step {i} {} after the last, {need} needed: {p:?} {t:?}",
                        rise as i64 - last as i64
                    );
                }
                self.last_rise = Some((rise, p.dir));
            }
            self.pulses = self.pulses.wrapping_add(p.count);
        }
        self.x.tick(&out.x_plan, out.halt);
        if self.ctl.config().drive == DriveKind::Bldc {
            self.cutter_q16 += out.speed_q16 as i64;
        }
    }

    fn xcam(&mut self, words: &[i64]) {
        let [rate, accel, period, points @ ..] = words else { return };
        let table: Vec<i32> = points.iter().map(|&v| v as i32).collect();
        let h = CamHeader {
            points: table.len() as u32,
            period_counts: *period as u32,
            counts_per_rev: self.ctl.config().encoder_counts_per_rev,
            max_rate_hz: *rate as u32,
            max_accel: *accel as u32,
        };
        let table = Box::into_raw(table.into_boxed_slice());
        self.tables.push(table);
        // SAFETY: freed only after the controller is dropped (`Drop`)
        let fitted = self.ctl.fit_cam(&h, unsafe { &*table });
        if fitted.is_ok() {
            assert!(self.ctl.x_axis().is_some());
        }
        if trace() {
            eprintln!("xcam {h:?}: {fitted:?}");
        }
    }
}

/// `FUZZ_TRACE=1 cargo fuzz run <target> <input>` shows what an input did.
fn trace() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("FUZZ_TRACE").is_some())
}

fn numbers(words: &[&str]) -> Vec<i64> {
    words.iter().map(|w| w.parse::<i64>().unwrap_or(0)).collect()
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bench::new();
    for line in data.split(|&c| c == b'\n' || c == b'\r') {
        if line.is_empty() {
            continue; // the LF of a CRLF: the firmware's line buffer drops it
        }
        let text = String::from_utf8_lossy(line);
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        let n = numbers(words.get(1..).unwrap_or(&[]));
        let arg = |i: usize| n.get(i).copied().unwrap_or(0);
        match words.first().copied().unwrap_or("") {
            "tick" => {
                for _ in 0..arg(0).clamp(0, (TICK_BUDGET - b.ticks) as i64) {
                    b.tick(arg(1) as i32);
                }
                if trace() {
                    let s = b.ctl.status();
                    eprintln!(
                        "{text}: {:?}, cutter {} target {} steps, {} pulses",
                        s.state, s.cutter_steps, s.target_steps, b.pulses
                    );
                }
            }
            "estop" => b.estop = arg(0) != 0,
            "alarm" => b.alarm = arg(0) != 0,
            "index" => b.index = Some(arg(0) as i16),
            "glitch" => b.pulses = b.pulses.wrapping_add(arg(0) as u16),
            "late" => b.late = arg(0).clamp(0, u16::MAX as i64) as u16,
            "slip" => b.cutter_q16 += (arg(0) as i32 as i64) << 16,
            "stall" => b.ctl.begin_stall(),
            "unstall" => {
                b.ctl.end_stall();
            }
            "service" => b.ctl.service(),
            "xcam" => b.xcam(&n),
            "xoff" => {
                let _ = b.ctl.set_x_axis(None);
            }
            _ => b.console(line),
        }
        assert_eq!(b.ctl.config().validate(), Ok(()));
    }
});
