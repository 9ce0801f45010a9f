//! The cutter's STEP/DIR output: TIM1 fed by DMA, one tick's plan two ticks
//! after it was made (`polyturn_sync::steps::pipe`).
//!
//! Why this shape: TIM1 only takes new ARR/CCR values at an
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
//! segments before the DMA reaches them: the first at the start of tick
//! k+1's last segment, three quarters into tick k+1 at the earliest less
//! `MIN_SEGMENT` (`entries::late_boundary`; with a pulse longer than
//! 6.75 µs, where a pulse ending within a pulse of the tick's end rises,
//! past half the tick), the second as the first starts, at the end of
//! tick k+1's last pulse or at tick k+2. (The DMA reads each burst's first
//! word early, §9.3.12: that word is a constant, see `entries::Entry`.)
//! After an arm the first window's first segment is read at TIM1's first
//! update, the next tick's instant. A late write is detected from the
//! DMA's position (NDTR, before writing, after the first segment and at
//! the end) and halts; an entry's CCR1 is written last, so a burst that
//! reads one half written plays silence.
//!
//! NDTR has two readings in the manual: it decrements after each transfer
//! (§9.3.2 "post-decrement"), or already when direct mode preloads the word
//! from memory before the request (§9.2, §9.3.12); the second runs one
//! word ahead all the time. Which one the silicon follows is learnt once
//! at boot, with TIM1 stopped and its DMA requests off so that nothing but
//! the preload can move NDTR (`prepare`), and every arm checks NDTR reads
//! what that lead predicts before TIM1's first request, or retries: a
//! request left pending from before (the DMA's handshake keeps one,
//! §9.3.3) cannot teach a wrong lead. With a lead of 0 where it is 1 every
//! arm looks late (a fault, never a step); with 1 where it is 0 a burst's
//! second word could be read before it is written, unseen.

pub mod entries;
pub mod program;

use entries::{Entry, Layout};
use polyturn_sync::steps::{Dir, StepPlan, StepTiming};
use program::{apply, Bus, Op};

/// Segments in the ring: two ticks in flight of at most `MAX_SEGMENTS`
/// each, as much again to tell a DMA that overtook the writer, and room
/// for fillers that outlast the watchdog if the writer stops (the rest of
/// the ring; a test ties the figures).
pub const RING_ENTRIES: usize = 256;
/// Ring entries a tick silences after a halt: the ring in 16 ticks (800 µs).
pub const SILENCE_PER_TICK: usize = 16;
/// Entries written ahead of the DMA at most: more means it overtook.
pub const PENDING_MAX: usize = 64;

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
    /// after a halt, the next entry to silence (`silence_some`)
    silence_next: usize,
    /// words NDTR counts ahead of the words stored: 0 or 1 (`ndtr_lead`)
    lead: u32,
    /// ticks until a halted pulse is released (`program::RELEASE`); 0: none
    /// owed
    release_in: u32,
    /// the arm's register programs, made once (`Armer`)
    armer: Armer,
    /// `program::quiet` applied since the last halt: the arm's first half,
    /// made a tick before its second (`begin`), so that no tick makes both
    quieted: bool,
}

/// `program::quiet` and `program::arm` for one tick length, made at boot
/// and kept: made in the tick that arms, their 26 operations would be
/// stored to the stack before they were applied, on the tick's worst path.
struct Armer {
    tick_len: u32,
    quiet: [Op; 16],
    arm: [Op; 10],
}

impl Armer {
    const fn new(ring: u32, tick_len: u32) -> Armer {
        Armer {
            tick_len,
            quiet: program::quiet(tick_len, entries::dir_level(Dir::Forward)),
            arm: program::arm(ring, tick_len),
        }
    }
}

/// Cycles from enabling the stream to reading NDTR at arm: the preload is
/// one AHB read by the DMA (the model's DMA latency, 6 cycles, is the
/// whole request-to-write path); 32 leave it a wide margin. At boot, where
/// time is free, the probe waits 10 µs.
pub const PRELOAD_WAIT: u32 = 32;
pub const PROBE_WAIT: u32 = 960;

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
            silence_next: 0,
            lead: 0,
            release_in: 0,
            // (remade for the real tick length by `prepare`, or by the
            // first arm)
            armer: Armer::new(ring, 2),
            quieted: false,
        }
    }

    pub fn armed(&self) -> bool {
        self.armed
    }

    /// What the boot probe learnt: 0 if NDTR counts transfers, 1 if it
    /// counts the preloaded word too (the bench reports which).
    pub fn ndtr_lead(&self) -> u32 {
        self.lead
    }

    /// At boot, before the first tick: outputs driven quietly (STEP low),
    /// the ring silent. Zeroed RAM is no silence: CCR1 = 0 holds STEP high.
    pub fn prepare(&mut self, tick_len: u32, bus: &mut impl Bus) {
        self.armer = Armer::new(self.ring, tick_len);
        self.quieted = apply(&self.armer.quiet, bus).is_ok();
        self.silence(bus);
        // (the probe leaves TIM1 as `quiet` left it, the stream off: the
        // first arm needs only its second half)
        self.lead = probe_lead(self.ring, bus);
    }

    /// Silences the whole ring (RAM only; the stream must be off).
    fn silence(&mut self, bus: &mut impl Bus) {
        for i in 0..RING_ENTRIES {
            self.put_whole(i, &Entry::filler(), bus);
        }
        (self.silence_next, self.silent) = (RING_ENTRIES, true);
    }

    /// Silences the next `SILENCE_PER_TICK` entries (the stream must be off);
    /// true once the whole ring is silent. A tick after a halt does a share,
    /// each entry as a taken one is silenced (`silence_taken`: ARR, RCR and
    /// CCR1; PSC is 0 in every entry from the ring's first fill, `silence`,
    /// and CCR2 a DIR level that moves nothing without a step): the whole
    /// ring at once would take longer than a tick.
    fn silence_some(&mut self, bus: &mut impl Bus) -> bool {
        let end = (self.silence_next + SILENCE_PER_TICK).min(RING_ENTRIES);
        for i in self.silence_next..end {
            silence_taken(self.ring, i, bus);
        }
        self.silence_next = end;
        self.silent = end == RING_ENTRIES;
        self.silent
    }

    /// Someone else (the E-stop interrupt, a late plan) applied
    /// `program::HALT`: its pulse is released in time, and the output
    /// re-arms at the next tick that has no halt.
    pub fn halted_elsewhere(&mut self, t: &StepTiming) {
        self.armed = false;
        self.quieted = false;
        self.silent = false;
        self.silence_next = 0;
        self.release_in = program::release_ticks(t.pulse, t.tick_len);
    }

    fn halt(&mut self, t: &StepTiming, bus: &mut impl Bus) {
        let _ = apply(&program::HALT_IN_RAM, bus);
        self.halted_elsewhere(t);
    }

    /// At each tick: a halted pulse released once it has had its width.
    fn release_due(&mut self, bus: &mut impl Bus) {
        if self.release_in > 0 {
            self.release_in -= 1;
            if self.release_in == 0 {
                let _ = apply(&program::RELEASE_IN_RAM, bus);
            }
        }
    }

    /// One control tick: the core's plan for tick k+2, or its halt
    /// (`begin`, then `write_plan` if it says so), as the host runs it.
    pub fn tick(&mut self, plan: &StepPlan, halt: bool, t: &StepTiming, bus: &mut impl Bus) -> Result<(), Fail> {
        if self.begin(halt, t, bus)? {
            let written = self.write_plan(plan, t, bus);
            self.silence_behind(bus);
            written
        } else {
            Ok(())
        }
    }

    /// The tick's own part, made inside the tick it is for: a halted
    /// pulse released in its time, the halt, the ring silenced a share
    /// after one, or the arm, whose register program holds only inside its
    /// tick (`program::arm`'s `Sync`). True if the output is armed and this
    /// tick's plan is to be written (`write_plan`). That may come after the
    /// tick returns, if it ends before the DMA reads the window's first
    /// segment: after an arm, at TIM1's first update, the next tick's
    /// instant; later, at the start of the window before's last segment,
    /// up to `MIN_SEGMENT` before that instant. (`write_plan` halts if the
    /// DMA got there first: a step lost and a fault, never a wrong step.)
    pub fn begin(&mut self, halt: bool, t: &StepTiming, bus: &mut impl Bus) -> Result<bool, Fail> {
        self.release_due(bus);
        if halt {
            if self.armed {
                self.halt(t, bus);
            } else if !self.silent {
                // the ticks after the halt: the stream is off, so the ring
                // is silenced a share at a time while nothing is urgent
                self.silence_some(bus);
            }
            return Ok(false);
        }
        if !self.armed {
            if !self.silent {
                // released before the ring is silent (the E-stop interrupt
                // halted it and let go within a few ticks): silence on, arm
                // once it is done (these ticks' plans are not emitted: the
                // books catch them)
                self.silence_some(bus);
                return Err(Fail::ArmLate);
            }
            if !self.quieted || self.armer.tick_len != t.tick_len {
                // the arm's first half this tick, its second the next (this
                // tick's plan is not emitted: the books catch any step in it)
                return self.quieten(t, bus).map(|()| false);
            }
            self.arm(t, bus)?;
        }
        Ok(true)
    }

    /// The plan's part: this tick's plan into the ring, RAM writes only, and
    /// a halt if the DMA got there first. Only while armed (`begin`).
    ///
    /// The DMA asks for a tick's first segment as the tick before it starts
    /// its last, three quarters into that tick at the earliest
    /// (`entries::late_boundary`), and for its second as the first starts,
    /// at the end of the tick before's last pulse or at the tick's start:
    /// so the first is written and checked before anything else (and the
    /// output halted at once if it was asked for already), and the rest
    /// checked at the end. A write that ends after the next tick has
    /// begun, in time for both, loses nothing. After an arm, the first
    /// window's first segment is asked for at the next tick's instant.
    pub fn write_plan(&mut self, plan: &StepPlan, t: &StepTiming, bus: &mut impl Bus) -> Result<(), Fail> {
        // the stream runs, and has not reached what this tick writes
        let (started, _) = self.dma_entries(bus);
        let pending = (self.write + RING_ENTRIES - started) % RING_ENTRIES;
        if pending > PENDING_MAX || bus.read(program::S5CR) & program::DMA_EN == 0 {
            self.halt(t, bus);
            return Err(Fail::Late);
        }
        let first = self.write;
        let mut sink = RingSink { ring: self.ring, write: first, first, lead: self.lead, first_in_time: true, bus };
        let written = self.layout.tick(plan, t, MIN_SEGMENT, &mut sink);
        let (write, first_in_time) = (sink.write, sink.first_in_time);
        self.write = write;
        // did the DMA start the second or a later one before it was written?
        let (now, _) = self.dma_entries(bus);
        let reached = (now + RING_ENTRIES - first) % RING_ENTRIES;
        if !first_in_time || (2..=written).contains(&reached) {
            self.halt(t, bus);
            return Err(Fail::Late);
        }
        Ok(())
    }

    /// After a plan is written: the segments the DMA has taken whole go
    /// silent (not the one whose burst is under way: its last words are
    /// still to be read, and a mix of two segments is no segment), and
    /// long: STEP held low (`Entry::SILENT`, PWM mode 2) for the filler's
    /// 0.17 s, so that a DMA that ran on past a writer that stopped plays
    /// the ticks in flight, then silence, never an old segment's step
    /// before the watchdog resets the MCU (`Entry::filler`; the test
    /// `fillers_outlast_the_watchdog` ties the figures). Behind the DMA,
    /// so nothing it waits for: the plan is let go of before it.
    pub fn silence_behind(&mut self, bus: &mut impl Bus) {
        if !self.armed {
            return;
        }
        let (_, finished) = self.dma_entries(bus);
        while self.silenced != finished {
            silence_taken(self.ring, self.silenced, bus);
            self.silenced = (self.silenced + 1) % RING_ENTRIES;
        }
    }

    /// The arm's first half (`program::quiet`: everything stopped, STEP
    /// low, a silent segment loaded), for this tick length.
    fn quieten(&mut self, t: &StepTiming, bus: &mut impl Bus) -> Result<(), Fail> {
        if self.armer.tick_len != t.tick_len {
            self.armer = Armer::new(self.ring, t.tick_len);
        }
        if apply(&self.armer.quiet, bus).is_err() {
            self.halt(t, bus);
            (self.silent, self.silence_next) = (true, RING_ENTRIES); // the stream never ran on the ring
            return Err(Fail::ArmLate);
        }
        self.quieted = true;
        Ok(())
    }

    /// The arm's second half, a tick or more after `quieten` (nothing
    /// since undid it: a halt clears `quieted`).
    fn arm(&mut self, t: &StepTiming, bus: &mut impl Bus) -> Result<(), Fail> {
        if apply(&self.armer.arm, bus).is_err() {
            self.halt(t, bus);
            (self.silent, self.silence_next) = (true, RING_ENTRIES); // the stream never ran on the ring
            return Err(Fail::ArmLate);
        }
        if !lead_holds(self.lead, bus) {
            self.halt(t, bus);
            (self.silent, self.silence_next) = (true, RING_ENTRIES); // the DMA only read the silent ring
            return Err(Fail::ArmLate);
        }
        // a fresh generator on the armed ring, its boot's lead and its
        // programs kept (`quiet` forced STEP low: nothing left to release)
        (self.write, self.silenced, self.layout) = (0, 0, Layout::armed(Dir::Forward));
        (self.armed, self.silent, self.silence_next, self.release_in) = (true, false, 0, 0);
        Ok(())
    }

    /// Segments whose DMA burst has started, and those it has finished
    /// (they differ while a burst is under way).
    fn dma_entries(&self, bus: &mut impl Bus) -> (usize, usize) {
        dma_entries(self.lead, bus)
    }

    /// The address of word `i` of ring entry `slot`.
    fn word(&self, slot: usize, i: u32) -> u32 {
        self.ring + (slot as u32 * program::BURST_WORDS + i) * 4
    }

    /// Writes a whole entry, PSC included (the ring's first fill, silences).
    fn put_whole(&self, slot: usize, e: &Entry, bus: &mut impl Bus) {
        for (i, w) in e.words().iter().enumerate() {
            bus.write(self.word(slot, i as u32), *w);
        }
    }
}

/// How far NDTR runs ahead of the words stored, at boot: the stream on
/// over the ring with TIM1 stopped and no DMA request enabled (`quiet`
/// left DIER at 0), so NDTR is the ring's length if it counts transfers or
/// one less once the preload counted; then the stream off again. Anything
/// else (nothing can move it) leaves 0, and every arm fails its check.
fn probe_lead(ring: u32, bus: &mut impl Bus) -> u32 {
    let _ = apply(&program::probe(ring), bus);
    bus.delay(PROBE_WAIT);
    let left = bus.read(program::S5NDTR);
    let _ = apply(&program::PROBE_END, bus);
    match program::RING_WORDS - left.min(program::RING_WORDS) {
        1 => 1,
        _ => 0,
    }
}

/// Right after arming, before TIM1's first update (its UIF still clear
/// after the read; URS keeps the arm's UG from setting it, §12.4.1), NDTR
/// must read what the boot's lead predicts: else a request was served (one
/// left pending, or the tick ended around the arm) and the arm is retried.
fn lead_holds(lead: u32, bus: &mut impl Bus) -> bool {
    bus.delay(PRELOAD_WAIT);
    let left = bus.read(program::S5NDTR);
    let updated = bus.read(program::TIM1 + program::SR) & program::UIF != 0;
    !updated && left == program::RING_WORDS - lead
}

/// An entry the DMA has taken becomes a filler but for its DIR (CCR2,
/// left as it was: a level with no step moves nothing): ARR, RCR and CCR1.
#[inline(always)]
fn silence_taken(ring: u32, slot: usize, bus: &mut impl Bus) {
    let base = ring + slot as u32 * program::BURST_WORDS * 4;
    let f = Entry::filler();
    bus.write(base + 4, f.arr);
    bus.write(base + 8, f.rcr);
    bus.write(base + 12, f.ccr1);
}

/// The ring from entry `write` on, as `Layout::tick` makes the segments.
struct RingSink<'a, B: Bus> {
    ring: u32,
    write: usize,
    /// the plan's first entry, and whether it was written before the DMA
    /// asked for it (not yet asked for once written: the DMA still on
    /// entries before it)
    first: usize,
    lead: u32,
    first_in_time: bool,
    bus: &'a mut B,
}

impl<B: Bus> entries::Sink for RingSink<'_, B> {
    #[inline(always)]
    fn put(&mut self, e: Entry) {
        if !self.first_in_time {
            return; // halted: nothing more to write
        }
        put(self.ring, self.write, &e, self.bus);
        if self.write == self.first {
            self.check_first();
        }
        self.write = (self.write + 1) % RING_ENTRIES;
    }
}

impl<B: Bus> RingSink<'_, B> {
    /// The plan's first entry written: asked for already (the DMA on it,
    /// or past), it halts at once, before the entry's segment can start.
    // (out of line: once a plan, and the layout puts from several places)
    #[inline(never)]
    fn check_first(&mut self) {
        // the entry in the RAM before NDTR says the DMA has not read it
        self.bus.barrier();
        self.first_in_time = (dma_entries(self.lead, self.bus).0 + RING_ENTRIES - self.first) % RING_ENTRIES != 1;
        if !self.first_in_time {
            let _ = apply(&program::HALT_IN_RAM, self.bus);
        }
    }
}

/// The ring entries the DMA has started and finished, from NDTR and the
/// boot's lead (`Generator::dma_entries`).
fn dma_entries(lead: u32, bus: &mut impl Bus) -> (usize, usize) {
    let left = (bus.read(program::S5NDTR) + lead) % program::RING_WORDS;
    let done = (program::RING_WORDS - left) % program::RING_WORDS;
    let started = done.div_ceil(program::BURST_WORDS) as usize % RING_ENTRIES;
    (started, (done / program::BURST_WORDS) as usize)
}

/// Writes a segment's ARR, RCR, CCR1 and CCR2 into entry `slot` of the ring
/// at `ring`. Its PSC word is 0 in every entry from the ring's first fill on
/// (`put_whole`; nothing writes it otherwise), so it is not written again.
#[inline(always)]
fn put(ring: u32, slot: usize, e: &Entry, bus: &mut impl Bus) {
    let base = ring + slot as u32 * program::BURST_WORDS * 4;
    bus.write(base + 16, e.ccr2);
    bus.write(base + 4, e.arr);
    bus.write(base + 8, e.rcr);
    // CCR1 last: a slot the DMA takes is silenced first (CCR1 = SILENT,
    // `silence_taken`), so a burst that reads it half written, the writer
    // pre-empted between its words, plays silence, never a pulse with the
    // last lap's DIR or length
    bus.write(base + 12, e.ccr1);
}

#[cfg(test)]
mod tests;
