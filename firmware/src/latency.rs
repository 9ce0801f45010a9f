//! When a handler ends, counted from the tick's instant: TIM11's count read
//! at its end (TIM11 is the tick's timer: its update event is the tick, and
//! it counts CPU cycles from it, `board::TICK_HZ`). What the bench reads for
//! the step plan: the hold-off, the tick's entry, the tick, the tail-chain
//! and the plan, all in one figure, as the emulator's bound adds them.
//!
//! One writer (the handler), any number of readers: plain loads and stores
//! of atomics, no read-modify-write (none is needed with one writer), and
//! counters that only grow, so a reader keeps its last look and subtracts.

use core::sync::atomic::{AtomicU32, Ordering::Relaxed};

/// Bins of the histogram over one tick period.
pub const BINS: usize = 16;

pub struct Latency {
    /// ends in each sixteenth of the period, since boot
    bins: [AtomicU32; BINS],
    /// ends after the next tick's instant (TIM11's UIF set again), since boot
    late: AtomicU32,
    /// the latest end within the period, since boot, in cycles
    worst: AtomicU32,
}

/// A look at a `Latency`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub bins: [u32; BINS],
    pub late: u32,
    pub worst: u32,
}

impl Counts {
    /// What happened between `before` and this look (the worst is since boot).
    pub fn since(&self, before: &Counts) -> Counts {
        let mut bins = [0; BINS];
        for (i, b) in bins.iter_mut().enumerate() {
            *b = self.bins[i].wrapping_sub(before.bins[i]);
        }
        Counts { bins, late: self.late.wrapping_sub(before.late), worst: self.worst }
    }
}

impl Latency {
    #[allow(clippy::declare_interior_mutable_const)] // an array's initialiser
    const ZERO: AtomicU32 = AtomicU32::new(0);

    pub const fn new() -> Latency {
        Latency { bins: [Self::ZERO; BINS], late: AtomicU32::new(0), worst: AtomicU32::new(0) }
    }

    /// A handler ends with TIM11 at `count` of a period of `period` cycles;
    /// `updated`: its update flag says the next tick's instant has passed
    /// (the count started again). Only the handler calls this. (32-bit
    /// arithmetic, and a constant divisor where `period` is one.)
    #[inline(always)]
    pub fn record(&self, count: u32, period: u32, updated: bool) {
        if updated {
            self.late.store(self.late.load(Relaxed).wrapping_add(1), Relaxed);
            return;
        }
        let bin = (count / (period / BINS as u32).max(1)) as usize;
        let b = &self.bins[bin.min(BINS - 1)];
        b.store(b.load(Relaxed).wrapping_add(1), Relaxed);
        if count > self.worst.load(Relaxed) {
            self.worst.store(count, Relaxed);
        }
    }

    pub fn counts(&self) -> Counts {
        let mut bins = [0; BINS];
        for (i, b) in bins.iter_mut().enumerate() {
            *b = self.bins[i].load(Relaxed);
        }
        Counts { bins, late: self.late.load(Relaxed), worst: self.worst.load(Relaxed) }
    }
}

impl Default for Latency {
    fn default() -> Latency {
        Latency::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_end_falls_in_its_sixteenth_and_the_worst_is_kept() {
        let l = Latency::new();
        l.record(0, 4800, false);
        l.record(299, 4800, false);
        l.record(300, 4800, false);
        l.record(4799, 4800, false);
        let c = l.counts();
        assert_eq!((c.bins[0], c.bins[1], c.bins[15]), (2, 1, 1));
        assert_eq!(c.worst, 4799);
        assert_eq!(c.late, 0);
    }

    #[test]
    fn an_end_after_the_next_instant_is_late_not_binned() {
        let l = Latency::new();
        l.record(10, 4800, true);
        let c = l.counts();
        assert_eq!((c.late, c.bins.iter().sum::<u32>(), c.worst), (1, 0, 0), "the count restarted: it says nothing");
    }

    #[test]
    fn a_look_subtracts_the_last_one() {
        let l = Latency::new();
        l.record(100, 4800, false);
        let first = l.counts();
        l.record(100, 4800, false);
        l.record(5, 4800, true);
        let d = l.counts().since(&first);
        assert_eq!((d.bins[0], d.late), (1, 1));
    }
}
