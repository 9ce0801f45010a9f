//! What the tick counts for the log, the watchdog and the emulator: ticks
//! run, ticks lost, late step windows, and the NDTR lead the boot learnt.

use core::sync::atomic::{AtomicU32, Ordering};

pub(super) static TICKS: AtomicU32 = AtomicU32::new(0);
static LAST_SEEN: AtomicU32 = AtomicU32::new(0);
/// Plans whose segments the DMA reached before they were written, or
/// found still being written with the next plan waiting behind it
/// (`plan::late`), and arms that could not complete.
pub(super) static STEPS_LATE: AtomicU32 = AtomicU32::new(0);
/// `Generator::ndtr_lead`, learnt at boot, for the bench's log.
pub(super) static NDTR_LEAD: AtomicU32 = AtomicU32::new(0);
/// Ticks whose interrupt never ran (`check_ticks`), since boot.
pub(super) static TICKS_LOST: AtomicU32 = AtomicU32::new(0);

/// True if the tick ran since the last call (feeds the watchdog).
pub fn alive() -> bool {
    let now = TICKS.load(Ordering::Relaxed);
    now != LAST_SEEN.swap(now, Ordering::Relaxed)
}

/// Ticks whose step segments were written too late (each one halted the
/// output), since boot.
pub fn steps_late() -> u32 {
    STEPS_LATE.load(Ordering::Relaxed)
}

/// 1 if DMA2's NDTR counted the preloaded word at the boot's probe, else 0.
pub fn ndtr_lead() -> u32 {
    NDTR_LEAD.load(Ordering::Relaxed)
}

/// Ticks run since boot.
pub fn ticks() -> u32 {
    TICKS.load(Ordering::Relaxed)
}
