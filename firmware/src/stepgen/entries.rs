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

/// Segments per tick at most: a pad, the first pulse, and one per further
/// step (a run of equal gaps is one segment). The board's tick of 4800
/// cycles holds at most 25 steps of the shortest period (2 × 96 cycles).
pub const MAX_SEGMENTS: usize = 28;
pub type Segments = heapless::Vec<Entry, MAX_SEGMENTS>;

impl Layout {
    /// The state after arming: the ring starts on a tick boundary.
    pub const fn armed(dir: Dir) -> Layout {
        Layout { prev: Prev::idle(dir) }
    }

    /// The segments of one tick, each given to `emit` in order. `min_segment`
    /// is the shortest segment the DMA can reload in time; the planner keeps
    /// every pulse and gap at least that long (`STEP_FLOOR_NS`), and a
    /// shorter stretch before the tick's start joins the first segment. Each
    /// step rises at `plan.at(i)`; equal gaps in a row share one segment (its
    /// RCR). Handed out one at a time, so the ring is written as they are
    /// made (no list of them kept). Returns how many.
    pub fn tick(&mut self, plan: &StepPlan, t: &StepTiming, min_segment: u32, mut emit: impl FnMut(Entry)) -> usize {
        let len = t.tick_len as i32;
        // DIR takes the plan's direction at the first segment of the tick:
        // at the end of the last pulse, when there was one (`Prev::after`)
        let dir = plan.dir;
        let mut at = self.prev.end;
        let mut n = 0;
        if -at >= min_segment as i32 {
            // the rest of the time before this tick: its own segment, so
            // this tick's last segment starts no earlier than the tick
            emit(Entry::silent(-at as u32, dir));
            n += 1;
            at = 0;
        }
        self.prev = self.prev.after(plan, t);
        if plan.count == 0 {
            emit(Entry::silent((len - at) as u32, dir));
            return n + 1;
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
                emit(run);
                n += 1;
                run = Entry::pulses(gap - t.pulse, t.pulse, 1, dir);
            }
        }
        emit(run);
        n + 1
    }

    /// `tick`'s segments as a list (tests, and a host that keeps them).
    pub fn segments(&mut self, plan: &StepPlan, t: &StepTiming, min_segment: u32) -> Segments {
        let mut out = Segments::new();
        self.tick(plan, t, min_segment, |e| {
            // capacity holds every plan of the board's timing (test)
            let _ = out.push(e);
        });
        out
    }
}
