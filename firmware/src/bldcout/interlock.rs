//! The order of the tick's command and the stops that may pre-empt it.
//! The tick writes the running command; the E-stop interrupt (above the
//! tick, `board::PRIORITIES`) and the panic handler write the stop at any
//! moment, the tick's own words included. A stop must win: whatever
//! instant it lands at, once the tick's command returns the stop waits in
//! the preload and nothing but 0 or the stop can come into force.

use super::{run_ops, stop_ops, Out};
use crate::regs::{apply, Bus};
use core::sync::atomic::{compiler_fence, AtomicBool, AtomicU32, Ordering::Relaxed, Ordering::SeqCst};

/// Shared by the tick and every stop (plain loads and stores, and one
/// `fetch_add` in the stop: no critical section, nothing that waits).
pub struct Interlock {
    /// CCR1 of the interface's stop (0, no pulse, until `set_up` ends)
    stop: AtomicU32,
    /// a command written since the last stop (a speed may be in force)
    live: AtomicBool,
    /// stops so far: the tick's command compares it with its entry's
    stops: AtomicU32,
}

impl Interlock {
    pub const fn new() -> Interlock {
        Interlock { stop: AtomicU32::new(0), live: AtomicBool::new(false), stops: AtomicU32::new(0) }
    }

    /// Stops so far: read at the tick's entry, given to `command`.
    pub fn stops(&self) -> u32 {
        self.stops.load(Relaxed)
    }

    /// TIM10 (re)programmed for `out` (`Out::program`). The stop is 0 (no
    /// pulse) while the words go in, so a stop among them cannot put the
    /// new interface's stop in the old frame; a stop that came after
    /// `program`'s last word and before the new stop was kept left 0
    /// waiting, so the stop is written into the preload again. (The fences
    /// keep the stores and loads on their side of the register writes:
    /// volatile writes are ordered only among themselves.)
    pub fn set_up(&self, out: &Out, bus: &mut impl Bus) {
        let since = self.stops();
        self.stop.store(0, Relaxed);
        self.live.store(false, Relaxed);
        compiler_fence(SeqCst);
        let _ = apply(&out.program(), bus);
        compiler_fence(SeqCst);
        self.stop.store(out.stop, Relaxed);
        compiler_fence(SeqCst);
        if self.stops() != since {
            let _ = apply(&run_ops(out.stop), bus);
        }
    }

    /// The stop at once, from any context (`stop_ops`).
    pub fn stop(&self, bus: &mut impl Bus) {
        self.live.store(false, Relaxed);
        let _ = apply(&stop_ops(self.stop.load(Relaxed)), bus);
        compiler_fence(SeqCst);
        self.stops.fetch_add(1, Relaxed);
    }

    /// The tick's command, `ccr` (the stop, or a speed), one word into the
    /// preload: a pulse under way keeps its width, the command is the next
    /// frame's (a speed falling to the stop while the drive runs is no
    /// fault: cutting the pulse would send an ESC a pulse below its range,
    /// frame after frame while the speed hovers at zero). `since`:
    /// `stops()` at the tick's entry. Nothing is written while the stop
    /// waits since the last stop (`live` clear) and the command is the
    /// stop, nor if a stop came since the tick began (that stop halted what
    /// this tick computed). A stop that lands after that check, before or
    /// after the word, is written again after it: the command can be in
    /// the preload for the cycles from the word to that stop's first word,
    /// and in force only if an update event falls in them, until its third
    /// (a runt of those cycles; the fences keep the loads on their side of
    /// the word).
    pub fn command(&self, ccr: u32, since: u32, bus: &mut impl Bus) {
        if ccr == self.stop.load(Relaxed) && !self.live.load(Relaxed) {
            return;
        }
        if self.stops() != since {
            return;
        }
        self.live.store(true, Relaxed);
        compiler_fence(SeqCst);
        let _ = apply(&run_ops(ccr), bus);
        compiler_fence(SeqCst);
        if self.stops() != since {
            self.stop(bus);
        }
    }

    /// The tick's halt (an immediate fault): the stop at once, unless the
    /// stop already waits since the last one (cutting a stop pulse would
    /// only make it short).
    pub fn halt(&self, bus: &mut impl Bus) {
        if self.live.load(Relaxed) {
            self.stop(bus);
        }
    }
}

impl Default for Interlock {
    fn default() -> Interlock {
        Interlock::new()
    }
}
