//! What the real image's tick read and did, tick by tick: the counter and pin
//! reads it builds its `TickInput` from (`app/tick.rs`), and the ENABLE pin after
//! it returned. The host's sync core, fed the same inputs, must make the same
//! step stream (`job::replay`); this records them without touching the image.

use super::Chip;
/// TIM3 (lathe), TIM4 (cutter), TIM2 (steps emitted) and GPIOB_IDR (the
/// E-stop and the alarm); TIM3's CCR3 (RM0383 §13.4.15) is the lathe count
/// latched at the index.
use polyturn_stm32_model::addr::{off, GPIOB_IDR, TIM2, TIM3, TIM4};
use polyturn_sync::TickInput;

/// A port B pin's number by its signal's name in `board::PINS` (the E-stop and
/// the drive alarm are read through GPIOB_IDR).
fn port_b(signal: &str) -> u32 {
    let p = polyturn_firmware::board::PINS.iter().find(|p| p.signal == signal).expect("a pin of board::PINS");
    p.pin.strip_prefix("PB").and_then(|n| n.parse().ok()).expect("a port B pin")
}

/// One tick as the image ran it.
#[derive(Clone, Copy, Debug)]
pub struct TickSeen {
    /// the cycle the handler was entered
    pub at: u64,
    pub input: TickInput,
    /// ENABLE at its active level when the handler returned
    pub enable: bool,
    /// the cycle of its last read of the edge registers, if it read them
    pub edge_read_at: Option<u64>,
}

/// A command the lower priorities gave the image's controller (under its lock,
/// so between two ticks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    Engage,
    Disengage,
    /// `service`'s re-basing of the gear on the index while idle
    Rebase,
}

/// The controller's methods whose entry is a `Command`, by their (legacy
/// mangled) symbol's tail: each path segment is length-prefixed.
pub(crate) const COMMANDS: &[(&str, Command)] =
    &[("6engage17h", Command::Engage), ("9disengage17h", Command::Disengage), ("6rebase17h", Command::Rebase)];

/// The counters the image read before its first tick (`Controller::start`'s
/// arguments), every tick since, and each command with the number of ticks
/// before it.
#[derive(Default)]
pub struct Tape {
    pub start: (u16, u16, u16),
    pub ticks: Vec<TickSeen>,
    pub commands: Vec<(usize, Command)>,
    now: Option<Partial>,
    /// every A rise TIM3 captured and TRGO timed (`edges`)
    pub captures: Vec<crate::edge_times::Capture>,
    /// TIM5's count at TIM11's first update event: the first tick's instant
    pub first_update_stamp: Option<u16>,
    /// the edge clock the image gave its core (`Machine::edge_clock`), set at the end
    pub edge_clock: Option<polyturn_sync::edges::EdgeClock>,
    /// ticks whose edge-register reads were not the firmware's read: the first
    pub edge_read_wrong: Option<String>,
}

/// The reads of the tick running now; the first of each is the one
/// `TickInput`'s field takes (the handler reads each once, in field order).
#[derive(Default)]
struct Partial {
    at: u64,
    lathe: Option<u16>,
    index: Option<u16>,
    emitted: Option<u16>,
    cutter: Option<u16>,
    idr: Option<u32>,
    /// the edge-time reads (`edges::is_edge_read`), in order, and the cycle
    /// of the last
    edge_reads: Vec<(u32, u32)>,
    edge_at: Option<u64>,
}

impl Tape {
    /// A register read of `word` that gave `value` at cycle `now`; `entered`
    /// is when the tick's handler making it was entered, if the tick's
    /// handler made it.
    pub fn read(&mut self, word: u32, value: u32, entered: Option<u64>, now: u64) {
        let Some(at) = entered else {
            if self.ticks.is_empty() {
                self.before_first_tick(word, value);
            }
            return;
        };
        let p = self.now.get_or_insert_with(|| Partial { at, ..Partial::default() });
        let v = Some(value as u16);
        if crate::edge_times::is_edge_read(word) {
            p.edge_reads.push((word, value));
            p.edge_at = Some(now);
        }
        match word {
            w if w == TIM3 + off::CNT => p.lathe = p.lathe.or(v),
            w if w == TIM3 + off::CCR3 => p.index = p.index.or(v),
            w if w == TIM2 + off::CNT => p.emitted = p.emitted.or(v),
            w if w == TIM4 + off::CNT => p.cutter = p.cutter.or(v),
            GPIOB_IDR => p.idr = p.idr.or(Some(value)),
            _ => {}
        }
    }

    fn before_first_tick(&mut self, word: u32, value: u32) {
        let v = value as u16;
        match word {
            w if w == TIM3 + off::CNT => self.start.0 = v,
            w if w == TIM2 + off::CNT => self.start.1 = v,
            w if w == TIM4 + off::CNT => self.start.2 = v,
            _ => {}
        }
    }

    /// The tick's handler returned with ENABLE at `enable`. A tick that read
    /// nothing (the shared state was not set yet) is not a tick of the core.
    pub fn tick_done(&mut self, enable: bool) {
        let Some(p) = self.now.take() else { return };
        let Some(lathe) = p.lathe else { return };
        let idr = p.idr.unwrap_or(0);
        let lathe_edge = crate::edge_times::pair(&p.edge_reads).unwrap_or_else(|e| {
            self.edge_read_wrong.get_or_insert(format!("tick {}: {e}", self.ticks.len()));
            None
        });
        let input = TickInput {
            lathe,
            index: p.index,
            emitted: p.emitted.unwrap_or(0),
            cutter: p.cutter.unwrap_or(0),
            estop_open: idr >> port_b("ESTOP") & 1 == 1,
            alarm: idr >> port_b("DRIVE_ALARM") & 1 == 0,
            x_emitted: 0,
            lathe_edge,
        };
        let edge_read_at = p.edge_reads.iter().any(|r| r.0 != TIM3 + off::CNT).then_some(p.edge_at).flatten();
        self.ticks.push(TickSeen { at: p.at, input, enable, edge_read_at });
    }
}

impl Chip {
    /// Feeds a read to the tape, if one is running.
    pub(crate) fn tape_read(&mut self, word: u32, value: u32) {
        let entered = self.probe.tick.entered();
        let now = self.blk;
        if let Some(t) = self.tape.as_mut() {
            t.read(word, value, entered, now);
        }
    }
}
