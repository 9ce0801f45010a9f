//! Lost ticks, seen from the service task. The core counts the tick's
//! instants itself (`stamps_per_tick` a tick: `polyturn_sync::edges`), so
//! a tick whose interrupt never ran (held off past the next update: UIF
//! stays set until the tick clears it, RM0383 §14.5.3, and an interrupt
//! already pending stays one pending interrupt, PM0214 §4.3's hardware and
//! software control of interrupts) would leave every later instant a tick
//! early: the lathe placed a tick's travel off (up to a count at speed),
//! for good.
//! The save's erase loses ticks knowingly and measures the clock again
//! (`Controller::end_stall`, `app::tick::restart_edges`); this watch
//! catches any other loss, from the µs clock (TIM5, embassy's time driver)
//! and the ticks that ran.
//!
//! Read under the tick's lock (it cannot run, so the count of ticks that
//! ran stands still), µs first, then TIM11's UIF: an instant that comes
//! between the two reads is counted as run (pending), never as lost. The
//! watch counts only instants a whole µs behind the clock read, so an
//! update within the µs the clock shows is not yet counted either.

use super::STAMPS_PER_TICK;

/// Where the count of ticks stands against the µs clock: an instant and
/// the tick count its tick leaves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Watch {
    /// the instant, on embassy's 64-bit µs clock
    instant_us: u64,
    /// `app::tick`'s tick count once that instant's tick has run
    ticks_after: u32,
}

impl Watch {
    /// From the edge clock's measurement: `first_instant` the stamp (the
    /// µs clock's low 16 bits, `edgetime::start`) of the next tick's
    /// instant, or of one whose tick is pending; `now_us` the µs clock
    /// read with it, within half the stamp's wrap (32 ms); `ticks` the
    /// ticks run so far (that instant's tick makes one more).
    pub fn anchor(first_instant: u16, now_us: u64, ticks: u32) -> Watch {
        // the instant's distance from now, signed: ahead, or just behind
        let from_now = first_instant.wrapping_sub(now_us as u16) as i16 as i64;
        Watch { instant_us: now_us.wrapping_add(from_now as u64), ticks_after: ticks.wrapping_add(1) }
    }

    /// Ticks lost by `now_us`: instants a whole µs behind it for which no
    /// tick ran, with `ticks` the ticks run and `pending` TIM11's UIF (an
    /// instant whose tick is still to run), read in that order under the
    /// tick's lock. 0 while every instant has had its tick.
    pub fn lost(&self, now_us: u64, ticks: u32, pending: bool) -> u32 {
        let Some(since) = now_us.checked_sub(1).and_then(|t| t.checked_sub(self.instant_us)) else { return 0 };
        // the anchor's instant and every one since, a tick apart
        let instants = since / STAMPS_PER_TICK as u64 + 1;
        let run = ticks.wrapping_sub(self.ticks_after).wrapping_add(1) as u64 + pending as u64;
        instants.saturating_sub(run).min(u32::MAX as u64) as u32
    }
}

#[cfg(test)]
#[path = "watch_tests.rs"]
mod tests;
