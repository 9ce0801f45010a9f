//! The cutter's STEP/DIR output: TIM1 fed by DMA, one tick's plan two ticks
//! after it was made (`polyturn_sync::steps::pipe`).
//!
//! Why this shape (issue 11): TIM1 only takes new ARR/CCR values at an
//! update event, and with a repetition counter that event comes once per
//! train (RM0383 §12.3.3), so a train cannot change its period after its
//! first pulse, and software that re-arms the timer each tick starts it at
//! the interrupt's latency, not at the tick. Here TIM1 never waits for
//! software: every update event makes it fetch its next segment (PSC, ARR,
//! RCR, CCR1, CCR2) from a ring in RAM by a DMA burst (§12.3.19), so
//! segments follow each other to the cycle. The tick only writes RAM: the
//! plan for tick k+2 at tick k, while the DMA is still on tick k+1's
//! segments. DIR is TIM1's channel 2, so it changes on a segment boundary,
//! never while STEP is high. TIM2 counts STEP pulses (TIM1's OC1REF as its
//! clock), and the core checks that count against what it planned.
//!
//! The ISR's latency does not move a step: it only has to write tick k+2's
//! segments before the DMA reaches them, at the start of tick k+1's last
//! segment, which is no earlier than `MIN_SEGMENT` before tick k+2. (The
//! DMA reads each burst's first word early, §9.3.12: that word is a
//! constant, see `entries::Entry`.) So the deadline is `tick − MIN_SEGMENT`
//! cycles after the tick, whatever the steps. A late write is detected
//! from the DMA's position (NDTR, before and after writing) and halts.
//!
//! NDTR has two readings in the manual: it decrements after each transfer
//! (§9.3.2 "post-decrement"), or already when direct mode preloads the word
//! from memory before the request (§9.2, §9.3.12); the second runs one
//! word ahead all the time. Which one the silicon follows is learnt at
//! each arm, before any request (`ndtr_lead`), so the position is the
//! words stored either way. Read with the wrong lead, every arm would look
//! late and the output would never start.

pub mod entries;
pub mod program;

use entries::{Entry, Layout};
use polyturn_sync::steps::{Dir, StepPlan, StepTiming};
use program::{apply, Bus};

/// Segments in the ring: two ticks in flight of at most `MAX_SEGMENTS`
/// each, and as much again to tell a DMA that overtook the writer.
pub const RING_ENTRIES: usize = 128;
const PENDING_MAX: usize = 64;

/// Shortest segment, timer cycles: the DMA's five-word burst must land
/// before the segment ends. 1 µs at 96 MHz; `STEP_FLOOR_NS` keeps every
/// pulse at least this long.
pub const MIN_SEGMENT: u32 = 96;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fail {
    /// re-arming found the tick too far gone to sync (it retries)
    ArmLate,
    /// the DMA reached segments not yet written, or stopped: halted
    Late,
}

pub struct Generator {
    ring: u32,
    write: usize,
    silenced: usize,
    layout: Layout,
    armed: bool,
    /// every ring entry is silent (the DMA may start on it)
    silent: bool,
    /// words NDTR counts ahead of the words stored: 0 or 1 (`ndtr_lead`)
    lead: u32,
}

/// Cycles from enabling the stream to reading NDTR at arm: the preload is
/// one AHB read by the DMA (the model's DMA latency, 6 cycles, is the
/// whole request-to-write path); 32 leave it a wide margin.
pub const PRELOAD_WAIT: u32 = 32;

impl Generator {
    /// `ring`: the address of `RING_ENTRIES × 5` words of RAM for the DMA.
    pub const fn new(ring: u32) -> Generator {
        Generator {
            ring,
            write: 0,
            silenced: 0,
            layout: Layout::armed(Dir::Forward),
            armed: false,
            silent: false,
            lead: 0,
        }
    }

    pub fn armed(&self) -> bool {
        self.armed
    }

    /// What the last arm learnt: 0 if NDTR counts transfers, 1 if it counts
    /// the preloaded word too (the bench reports which, `ndtr_lead`).
    pub fn ndtr_lead(&self) -> u32 {
        self.lead
    }

    /// At boot, before the first tick: outputs driven quietly (STEP low),
    /// the ring silent. Zeroed RAM is no silence: CCR1 = 0 holds STEP high.
    pub fn prepare(&mut self, tick_len: u32, bus: &mut impl Bus) {
        let _ = apply(&program::quiet(tick_len, entries::dir_level(Dir::Forward)), bus);
        self.silence(bus);
    }

    /// Silences the whole ring (RAM only; the stream must be off).
    fn silence(&mut self, bus: &mut impl Bus) {
        for i in 0..RING_ENTRIES {
            self.put(i, &Entry::filler(), bus);
        }
        self.silent = true;
    }

    /// Someone else (the E-stop interrupt, the panic handler) applied
    /// `program::halt`: re-arm at the next tick that has no halt.
    pub fn halted_elsewhere(&mut self) {
        self.armed = false;
        self.silent = false;
    }

    fn halt(&mut self, t: &StepTiming, bus: &mut impl Bus) {
        let _ = apply(&program::halt(t.pulse), bus);
        self.armed = false;
        self.silent = false;
    }

    /// One control tick: the core's plan for tick k+2, or its halt.
    pub fn tick(&mut self, plan: &StepPlan, halt: bool, t: &StepTiming, bus: &mut impl Bus) -> Result<(), Fail> {
        if halt {
            if self.armed {
                self.halt(t, bus);
            } else if !self.silent {
                // a tick after the halt: the stream is off, so the ring
                // can be silenced while nothing is urgent
                self.silence(bus);
            }
            return Ok(());
        }
        if !self.armed {
            if !self.silent {
                // halted by the E-stop interrupt and released before this
                // tick saw it: silence now, arm at the next tick (the
                // plan of this tick is not emitted: the books catch it)
                self.silence(bus);
                return Err(Fail::ArmLate);
            }
            self.arm(t, bus)?;
        }
        // the stream runs, and has not reached what this tick writes
        let (started, finished) = self.dma_entries(bus);
        let pending = (self.write + RING_ENTRIES - started) % RING_ENTRIES;
        if pending > PENDING_MAX || bus.read(program::S5CR) & program::DMA_EN == 0 {
            self.halt(t, bus);
            return Err(Fail::Late);
        }
        // segments the DMA has taken whole go silent (not the one whose
        // burst is under way: its last words are still to be read, and a
        // mix of two segments is no segment)
        while self.silenced != finished {
            self.put(self.silenced, &Entry::filler(), bus);
            self.silenced = (self.silenced + 1) % RING_ENTRIES;
        }
        let first = self.write;
        let segments = self.layout.tick(plan, t, MIN_SEGMENT);
        for e in &segments {
            self.put(self.write, e, bus);
            self.write = (self.write + 1) % RING_ENTRIES;
        }
        // did the DMA start one of them while they were being written?
        let (now, _) = self.dma_entries(bus);
        let reached = (now + RING_ENTRIES - first) % RING_ENTRIES;
        if (1..=segments.len()).contains(&reached) {
            self.halt(t, bus);
            return Err(Fail::Late);
        }
        Ok(())
    }

    fn arm(&mut self, t: &StepTiming, bus: &mut impl Bus) -> Result<(), Fail> {
        let quiet = program::quiet(t.tick_len, entries::dir_level(Dir::Forward));
        if apply(&quiet, bus).is_err() || apply(&program::arm(self.ring, t.tick_len), bus).is_err() {
            self.halt(t, bus);
            self.silent = true; // the stream never ran on the ring
            return Err(Fail::ArmLate);
        }
        let Some(lead) = ndtr_lead(bus) else {
            self.halt(t, bus);
            self.silent = true; // the DMA only read the silent ring
            return Err(Fail::ArmLate);
        };
        let ring = self.ring;
        *self = Generator {
            ring,
            write: 0,
            silenced: 0,
            layout: Layout::armed(Dir::Forward),
            armed: true,
            silent: false,
            lead,
        };
        Ok(())
    }

    /// Segments whose DMA burst has started, and those it has finished
    /// (they differ while a burst is under way).
    fn dma_entries(&self, bus: &mut impl Bus) -> (usize, usize) {
        let left = (bus.read(program::S5NDTR) + self.lead) % program::RING_WORDS;
        let done = (program::RING_WORDS - left) % program::RING_WORDS;
        let started = done.div_ceil(program::BURST_WORDS) as usize % RING_ENTRIES;
        (started, (done / program::BURST_WORDS) as usize)
    }

    fn put(&self, slot: usize, e: &Entry, bus: &mut impl Bus) {
        let base = self.ring + (slot as u32) * program::BURST_WORDS * 4;
        for (i, w) in e.words().iter().enumerate() {
            bus.write(base + 4 * i as u32, *w);
        }
    }
}

/// How far NDTR runs ahead of the words stored, read right after arming:
/// the stream is on and TIM1 has not yet requested anything, so NDTR is
/// the ring's length (it counts transfers) or one less (it counted the
/// preload). `None` if TIM1's update came before the read (its UIF is set;
/// URS keeps the arm's UG from setting it, §12.4.1): too late to tell, so
/// the arm is retried at the next tick.
fn ndtr_lead(bus: &mut impl Bus) -> Option<u32> {
    bus.delay(PRELOAD_WAIT);
    let left = bus.read(program::S5NDTR);
    if bus.read(program::TIM1 + program::SR) & program::UIF != 0 {
        return None;
    }
    match program::RING_WORDS.checked_sub(left) {
        Some(lead @ (0 | 1)) => Some(lead),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
