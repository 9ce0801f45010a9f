//! Lost ticks, seen from the service task. The core counts the tick's
//! instants itself (`stamps_per_tick` a tick: `polyturn_sync::edges`), so
//! a tick whose interrupt never ran (held off past the next update: UIF
//! stays set until the tick clears it, RM0383 §14.5.3, and an interrupt
//! already pending stays one pending interrupt, PM0214 §4.3's hardware and
//! software control of interrupts) would leave every later instant a tick
//! early: the lathe placed a tick's travel off (up to a count at speed),
//! for good. The save's erase loses ticks knowingly and measures the clock
//! again (`Controller::end_stall`, `app::tick::restart_edges`); this watch
//! catches any other loss.
//!
//! Each look, under the tick's lock (the ticks run stand still), takes the
//! instant of the next tick the core will run as `start::next_instant`
//! measures it (TIM5's and TIM11's counts, UIF: a pending update's instant
//! is that one) and the ticks run. Between two looks every instant from
//! the first look's to the second's should have had its tick: the ticks
//! run in between tell how many did. Only the two measured instants and
//! the tick count enter: no µs clock of embassy's, no margin for where in
//! its µs an update falls, and the looks follow each other, so neither the
//! 16-bit stamps nor the 32-bit count can wrap between them.

use super::STAMPS_PER_TICK;

/// The last look: the instant of the next tick then, and the ticks run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Watch {
    next: u16,
    ticks: u32,
}

impl Watch {
    /// A first look (or a look after the clock was measured again).
    pub fn new(next: u16, ticks: u32) -> Watch {
        Watch { next, ticks }
    }

    /// Another look: the ticks lost since the last, which this look then
    /// replaces. `None` when the two are half the stamps' wrap (32 ms) or
    /// more apart, too far to tell the instants between (the service task
    /// looks every ms): the next look judges from this one.
    pub fn look(&mut self, next: u16, ticks: u32) -> Option<u32> {
        // signed: the same instant may measure a stamp earlier the second
        // time (an interrupt inside `next_instant`'s reads that no retry
        // caught), so whole ticks are rounded
        let span = next.wrapping_sub(self.next) as i16 as i32;
        let ran = ticks.wrapping_sub(self.ticks);
        *self = Watch { next, ticks };
        let per = STAMPS_PER_TICK as i32;
        if span < -per / 2 {
            return None;
        }
        let instants = ((span + per / 2) / per) as u32;
        Some(instants.saturating_sub(ran))
    }
}

#[cfg(test)]
#[path = "watch_tests.rs"]
mod tests;
