//! Step/dir books closed on the pulses really emitted, for an output
//! stepped from the tick (the X axis).

use super::{plan, Dir, Prev, StepPlan, StepTiming};
use crate::encoder::Extender;

/// Step/dir for an output that runs each plan in the tick it was planned
/// (the X axis, stepped from the tick): what was emitted (from its pulse
/// count) and what was last commanded. Steps planned but not emitted are
/// planned again. The cutter's hardware-timed output runs its plans two
/// ticks later and keeps its books in `steps::pipe`.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepBook {
    pulses: Extender,
    emitted: i64,
    dir: Dir,
    last_to: i64,
}

impl StepBook {
    pub fn start(&mut self, raw: u16) {
        self.pulses = Extender::new(raw);
    }

    /// Reads the pulse counter; every pulse since the last read went the
    /// way of the last plan (a plan always finishes inside its tick).
    #[inline]
    pub fn read(&mut self, raw: u16) -> i64 {
        let n = self.pulses.update(raw).max(0) as i64;
        self.emitted += if self.dir == Dir::Forward { n } else { -n };
        self.emitted
    }

    #[inline]
    pub fn plan(&mut self, to: i64, timing: &StepTiming) -> StepPlan {
        let p = plan(self.last_to, to, self.emitted, &Prev::idle(self.dir), timing);
        if p.count > 0 {
            self.dir = p.dir;
        }
        self.last_to = to;
        p
    }

    /// Holds still at `position` (Q16): the next plan starts from there.
    pub fn hold(&mut self, position: i64) {
        self.last_to = position;
    }

    pub fn emitted(&self) -> i64 {
        self.emitted
    }
}

#[cfg(test)]
mod tests;
