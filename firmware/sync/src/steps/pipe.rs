//! The books of the cutter's hardware-timed step output, which emits each
//! tick's plan two ticks later (the firmware's DMA-fed TIM1,
//! `polyturn_firmware::stepgen`): the plan made at tick k runs in window
//! k+2, so when tick k starts, windows k and k+1 are in flight.
//!
//! The pulse counter read at tick k holds every pulse of the windows up to
//! k−1 and some of window k. A count outside that range means the output
//! did not do what it was told: the controller stops (`Fault::StepOutput`).
//! After a halt the count is final, and the books take it as the truth:
//! the pulses of the windows cut short are given to them in order.

use super::{plan, Dir, Prev, StepPlan, StepTiming};
use crate::encoder::Extender;

/// Ticks between a plan and the start of its emission.
pub const LEAD_TICKS: i64 = 2;

/// Windows kept: the two in flight and the one before them (a halt from
/// the E-stop interrupt is seen by the next tick, one window late).
const KEPT: usize = 3;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Window {
    count: u16,
    dir: Dir,
}

impl Window {
    fn signed(self) -> i64 {
        if self.dir == Dir::Forward {
            self.count as i64
        } else {
            -(self.count as i64)
        }
    }
}

/// The books while the output is halted: what was committed before the
/// windows that the halt cut short.
#[derive(Clone, Copy, Debug)]
struct Halt {
    base_pulses: i64,
    base_position: i64,
    cut: [Window; KEPT],
}

#[derive(Clone, Copy, Debug)]
pub struct StepPipe {
    counter: Extender,
    /// pulses the hardware counted since `start`
    counted: i64,
    /// pulses of every planned window (in flight included)
    planned: i64,
    /// signed steps of every planned window: where the motor will be
    position: i64,
    /// the newest windows, oldest first
    kept: [Window; KEPT],
    prev: Prev,
    last_to: i64,
    halt: Option<Halt>,
}

impl Default for StepPipe {
    fn default() -> StepPipe {
        StepPipe {
            counter: Extender::default(),
            counted: 0,
            planned: 0,
            position: 0,
            kept: [Window::default(); KEPT],
            prev: Prev::idle(Dir::Forward),
            last_to: 0,
            halt: None,
        }
    }
}

impl StepPipe {
    pub fn start(&mut self, raw: u16) {
        self.counter = Extender::new(raw);
    }

    /// The committed position in steps: every planned step, in flight too.
    pub fn position(&self) -> i64 {
        self.position
    }

    /// Where the pulses counted so far put the motor: the windows in
    /// flight given those pulses in order (`settle`'s sum, without ending
    /// anything). The committed `position` less what is still to come.
    #[inline]
    pub fn emitted(&self) -> i64 {
        if self.halt.is_some() {
            return self.position; // settled: the count is the truth
        }
        let pulses: i64 = self.kept.iter().map(|w| w.count as i64).sum();
        let steps: i64 = self.kept.iter().map(|w| w.signed()).sum();
        let mut extra = (self.counted - (self.planned - pulses)).max(0);
        let mut at = self.position - steps;
        for w in self.kept {
            let n = extra.min(w.count as i64);
            extra -= n;
            at += if w.dir == Dir::Forward { n } else { -n };
        }
        at
    }

    fn read(&mut self, raw: u16) {
        self.counted += self.counter.update(raw) as i64;
    }

    /// Reads the pulse counter at the start of a tick; false if it does not
    /// fit the windows in flight. Ends a halt (the output re-arms now).
    #[inline]
    pub fn check(&mut self, raw: u16) -> bool {
        self.read(raw);
        // (tested before it is taken: `take` moves the whole `Halt` every
        // tick, a fifth of this check's cost on the MCU)
        if let Some(h) = self.halt {
            self.halt = None;
            self.settle(&h);
            self.kept = [Window::default(); KEPT];
            self.prev = Prev::idle(Dir::Forward);
            return true;
        }
        // planned − queued − in_progress ≤ counted ≤ planned − queued, as
        // one unsigned compare: 0 ≤ x ≤ in_progress (below 0 x wraps high)
        let (in_progress, queued) = (self.kept[1].count as u64, self.kept[2].count as i64);
        let x = self.planned - queued - self.counted;
        x as u64 <= in_progress
    }

    /// The output is halted (or about to be, at the end of this tick): the
    /// count is the truth. Called every tick while halted.
    pub fn halted(&mut self, raw: u16) {
        self.read(raw);
        let h = *self.halt.get_or_insert_with(|| {
            let kept = self.kept;
            let pulses: i64 = kept.iter().map(|w| w.count as i64).sum();
            let steps: i64 = kept.iter().map(|w| w.signed()).sum();
            Halt { base_pulses: self.planned - pulses, base_position: self.position - steps, cut: kept }
        });
        self.settle(&h);
    }

    /// Gives the pulses counted since `h`'s base to its windows, in order.
    fn settle(&mut self, h: &Halt) {
        let mut extra = (self.counted - h.base_pulses).max(0);
        self.position = h.base_position;
        for w in h.cut {
            let n = extra.min(w.count as i64);
            extra -= n;
            self.position += if w.dir == Dir::Forward { n } else { -n };
        }
        self.planned = self.counted;
    }

    fn push(&mut self, w: Window) {
        self.kept = [self.kept[1], self.kept[2], w];
        self.planned += w.count as i64;
        self.position += w.signed();
    }

    /// Plans the window two ticks ahead, from the last command to `to`
    /// (Q16 steps). Nothing while halted.
    #[inline]
    pub fn plan(&mut self, to: i64, t: &StepTiming) -> StepPlan {
        if self.halt.is_some() {
            self.last_to = to;
            return StepPlan::default();
        }
        let p = plan(self.last_to, to, self.position, &self.prev, t);
        self.prev = self.prev.after(&p, t);
        self.push(Window { count: p.count, dir: p.dir });
        self.last_to = to;
        p
    }

    /// Holds still at `position` (Q16): an empty window (DIR forward, as
    /// the controller's empty output says).
    #[inline]
    pub fn hold(&mut self, position: i64, t: &StepTiming) {
        self.last_to = position;
        if self.halt.is_none() {
            self.prev = self.prev.after(&StepPlan::default(), t);
            self.push(Window { count: 0, dir: Dir::Forward });
        }
    }
}

#[cfg(test)]
mod tests;
