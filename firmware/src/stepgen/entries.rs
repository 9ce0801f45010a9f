//! A tick's step plan as TIM1 segments. A segment is what one update event
//! loads (RM0383 §12.3.3: ARR, RCR and CCRx take their preloaded values at
//! the update event, and the repetition counter makes the next update come
//! after RCR + 1 periods): `rcr + 1` identical periods of `arr + 1` cycles,
//! STEP (PWM mode 2) low for `ccr1` cycles then high to the period's end,
//! DIR (PWM mode 1) high while the count is below `ccr2`.
//!
//! Segments follow each other with no gap, so the output's timeline is
//! exact: each tick's segments end where the next tick's begin.

use polyturn_sync::steps::{Dir, Prev, StepPlan, StepTiming};

/// CCR1 above any count: STEP stays low (PWM mode 2, §12.3.10).
pub const SILENT: u32 = 0xFFFF;

/// DIR high (CCR2 above any count, PWM mode 1) for forward, low for reverse.
pub const fn dir_level(dir: Dir) -> u32 {
    match dir {
        Dir::Forward => 0xFFFF,
        Dir::Reverse => 0,
    }
}

/// The registers one DMA burst writes: PSC (always 0), then ARR, RCR, CCR1,
/// CCR2. PSC comes first because in direct mode the DMA reads a burst's
/// first word from RAM before the request, right after the previous burst
/// (RM0383 §9.3.12), possibly before the tick has written the segment:
/// a constant there is harmless (PSC is preloaded too, §12.3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    pub arr: u32,
    pub rcr: u32,
    pub ccr1: u32,
    pub ccr2: u32,
}

impl Entry {
    /// `len` cycles of STEP low (len ≤ 0xFFFF: ARR stays below SILENT).
    pub const fn silent(len: u32, dir: Dir) -> Entry {
        Entry { arr: len - 1, rcr: 0, ccr1: SILENT, ccr2: dir_level(dir) }
    }

    /// `times` pulses, each `gap` cycles low then `high` cycles high.
    pub const fn pulses(gap: u32, high: u32, times: u32, dir: Dir) -> Entry {
        Entry { arr: gap + high - 1, rcr: times - 1, ccr1: gap, ccr2: dir_level(dir) }
    }

    /// Cycles from this segment's update event to the next.
    pub fn cycles(&self) -> u32 {
        (self.arr + 1) * (self.rcr + 1)
    }

    pub fn words(&self) -> [u32; 5] {
        [0, self.arr, self.rcr, self.ccr1, self.ccr2]
    }

    /// Silence that lasts: if the tick ever stopped writing, the DMA would
    /// lap the ring through these, 256 × 65535 cycles (0.17 s) each (every
    /// entry the DMA has taken becomes one, `silence_taken`), so an old
    /// segment could come round only after the rest of the ring, at least
    /// 163 fillers (28 s), after the watchdog's longest period (15 s) has
    /// reset the MCU.
    pub const fn filler() -> Entry {
        Entry { arr: 0xFFFE, rcr: 255, ccr1: SILENT, ccr2: dir_level(Dir::Forward) }
    }
}

/// Where the segments written so far end: `Prev::end`, relative to the
/// start of the next tick, the same books the planner keeps (it puts DIR's
/// change there, at the end of the last pulse).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    prev: Prev,
}

/// Segments per tick at most: a pad, the first pulse, one per further
/// step (a run of equal gaps is one segment), and two more where the tick's
/// last segment is split at `late_boundary`. The board's tick of 4800
/// cycles holds at most 25 steps of the shortest period (2 × 96 cycles).
pub const MAX_SEGMENTS: usize = 30;
pub type Segments = heapless::Vec<Entry, MAX_SEGMENTS>;

/// How far into its tick each tick's last segment starts, at the least
/// (less one shortest segment): the DMA asks for the next tick's first
/// segment as that last one starts (`Entry`), so the plan for tick k + 2,
/// written during tick k + 1, has until then for its first segment.
/// Three quarters of the tick: more than the tick itself takes, so a plan
/// whose writing has not begun when the next tick comes still makes it
/// after that tick; the last segment is still a quarter of a tick long,
/// far longer than a burst. Past it a tick's last pulse ends at every rate
/// over four steps a tick, so the silence after it needs no split then.
pub const fn late_boundary(tick_len: u32) -> u32 {
    tick_len - tick_len / 4
}

/// Where `Layout::tick` puts the segments it makes, in order: the ring
/// (`Generator::write_plan`), or a list.
pub trait Sink {
    fn put(&mut self, e: Entry);
}

impl Sink for Segments {
    fn put(&mut self, e: Entry) {
        // capacity holds every plan of the board's timing (test)
        let _ = self.push(e);
    }
}

/// Counts what `Layout::tick` hands out.
struct Out<'a, S: Sink> {
    sink: &'a mut S,
    n: usize,
}

impl<S: Sink> Out<'_, S> {
    #[inline(always)]
    fn put(&mut self, e: Entry) {
        self.sink.put(e);
        self.n += 1;
    }

    /// Silence from `from` to `to` (cycles into the tick), in two segments
    /// split at `at` when both are long enough for the DMA.
    #[inline(always)]
    fn silence(&mut self, from: i32, to: i32, at: i32, min: i32, dir: Dir) {
        if at - from >= min && to - at >= min {
            self.put(Entry::silent((at - from) as u32, dir));
            self.put(Entry::silent((to - at) as u32, dir));
        } else {
            self.put(Entry::silent((to - from) as u32, dir));
        }
    }

    /// The tick's last run of pulses, starting at `from`, made to start its
    /// last segment no earlier than `at` less `min` (the DMA asks for the
    /// next segment as one starts, not at each period): split at the first
    /// period that starts late enough, or, when none does, its last period
    /// split in its low part at `at`, or at its rise if that comes first
    /// (silence, then the rest of the low and the pulse).
    #[inline(always)]
    fn last_run(&mut self, run: Entry, from: i32, at: i32, min: i32, dir: Dir) {
        let late = at - min;
        if from >= late {
            self.put(run);
            return;
        }
        // (max(1): no division-by-zero panic path in the plan's handler)
        let period = run.arr.wrapping_add(1).max(1);
        // the first period starting at or after `late`, counted from 0
        let j = ((late - from) as u32).div_ceil(period);
        if j <= run.rcr {
            self.put(Entry { rcr: j - 1, ..run });
            self.put(Entry { rcr: run.rcr - j, ..run });
            return;
        }
        let last = from + (run.rcr * period) as i32;
        let rise = last + run.ccr1 as i32;
        // (at the rise itself if it comes first: a long pulse)
        let cut = at.min(rise);
        if cut - last < min {
            self.put(run);
            return;
        }
        if run.rcr > 0 {
            self.put(Entry { rcr: run.rcr - 1, ..run });
        }
        self.put(Entry::silent((cut - last) as u32, dir));
        self.put(Entry::pulses((rise - cut) as u32, run.arr + 1 - run.ccr1, 1, dir));
    }
}

impl Layout {
    /// The state after arming: the ring starts on a tick boundary.
    pub const fn armed(dir: Dir) -> Layout {
        Layout { prev: Prev::idle(dir) }
    }

    /// The segments of one tick, each put into `sink` in order. `min_segment`
    /// is the shortest segment the DMA can reload in time; the planner keeps
    /// every pulse and gap at least that long (`STEP_FLOOR_NS`), and a
    /// shorter stretch before the tick's start joins the first segment. Each
    /// step rises at `plan.at(i)`; equal gaps in a row share one segment (its
    /// RCR). A silence of at least a pulse after the last pulse is the
    /// tick's own, to its end, with its DIR (`Prev::fills`: the planner lets
    /// DIR change at the boundary then). The last segment starts at
    /// `late_boundary` or later, less one shortest segment, or where a pulse
    /// that ends within a pulse of the tick's end rises, if earlier (past
    /// half the tick for the console's longest pulse): the silence or the
    /// last period is split there. Handed out one at a time, so the
    /// ring is written as they are made (no list of them kept). Returns how
    /// many.
    pub fn tick(&mut self, plan: &StepPlan, t: &StepTiming, min_segment: u32, sink: &mut impl Sink) -> usize {
        let (len, min) = (t.tick_len as i32, min_segment as i32);
        let split = late_boundary(t.tick_len) as i32;
        let mut out = Out { sink, n: 0 };
        // DIR takes the plan's direction at the first segment of the tick:
        // at the end of the last pulse, or at the boundary (`Prev::after`)
        let dir = plan.dir;
        let mut at = self.prev.end;
        if -at >= min {
            // the rest of the time before this tick: its own segment, so
            // this tick's last segment starts no earlier than the tick
            out.put(Entry::silent(-at as u32, dir));
            at = 0;
        }
        self.prev = self.prev.after(plan, t);
        if plan.count == 0 {
            out.silence(at, len, split, min, dir);
            return out.n;
        }
        // a run of equal gaps is held back until a different one ends it
        let first = plan.at(0) as i32;
        let mut run = Entry::pulses((first - at) as u32, t.pulse, 1, dir);
        let mut last = plan.at(0);
        for i in 1..plan.count as u32 {
            let gap = plan.at(i) - last;
            last += gap;
            if run.ccr1 != SILENT && run.arr + 1 == gap && run.rcr < 255 {
                run.rcr += 1;
            } else {
                out.put(run);
                at += run.cycles() as i32;
                run = Entry::pulses(gap - t.pulse, t.pulse, 1, dir);
            }
        }
        let end = at + run.cycles() as i32;
        if Prev::fills(end - len, t) {
            out.put(run);
            out.silence(end, len, split, min, dir);
        } else {
            out.last_run(run, at, split, min, dir);
        }
        out.n
    }

    /// `tick`'s segments as a list (tests, and a host that keeps them).
    pub fn segments(&mut self, plan: &StepPlan, t: &StepTiming, min_segment: u32) -> Segments {
        let mut out = Segments::new();
        self.tick(plan, t, min_segment, &mut out);
        out
    }
}
