//! The edge clock's watch: the clock the start measured (`EDGE_CLOCK`),
//! measured again after lost ticks or a save's stall, and the service
//! task's look every ms for ticks whose interrupt never ran.

use super::shared::{locked, IO};
use super::telemetry::{TICKS, TICKS_LOST};
use crate::app::mmio::Mmio;
use core::sync::atomic::{AtomicU32, Ordering};
use defmt::warn;
use polyturn_firmware::edgetime::{self, read::Gate, watch::Watch};

/// The edge clock the start measured, for the log and the emulator's
/// replay: `first_instant`, then k0 mod 4 (the count in state (A, B) =
/// (0, 0), `edgetime::start::low_low`) at bit 16, and bit 18 set if the
/// start timed edges (a clock that could not be measured again since has
/// turned the core's off: `Controller::edge_timing`; a save tries again).
/// 0 until the start.
pub(super) static EDGE_CLOCK: AtomicU32 = AtomicU32::new(0);
pub(super) const EDGES_ON: u32 = 1 << 18;

/// When the watch last looked (embassy's ms, read outside the lock: its
/// clock is right there): looks further apart than `WATCH_GAP_MS` are not
/// judged, the clock is measured again (`check_ticks`).
static LAST_LOOK_MS: AtomicU32 = AtomicU32::new(0);
/// Looks this far apart may alias the stamps (a look judges within 32 ms,
/// `edgetime::watch`): the service task looks every ms, so only a hold of
/// the whole MCU (a debugger's halt, a runaway section at the tick's
/// level) makes such a gap, and it can hide lost ticks.
const WATCH_GAP_MS: u32 = 20;

/// After lost ticks (a save's flash erase: `Controller::end_stall` drops the
/// core's edge clock; or a tick that never ran: `check_ticks`), the clock
/// measured again and given back to the core, under the lock, so that its
/// instants are the ticks it runs from here (`edgetime::start::next_instant`),
/// and the watch on the ticks started again from the next look. If it cannot be measured the
/// core's edge times go off, and the watch with them: a clock known to be
/// off must not place the lathe. Nothing if the start timed no edges.
pub fn restart_edges() {
    let on = EDGE_CLOCK.load(Ordering::Relaxed);
    if on & EDGES_ON == 0 {
        return;
    }
    let restarted = locked(|cs| {
        let first = edgetime::start::next_instant(&mut Mmio);
        let mut io = IO.borrow(cs).borrow_mut();
        let io = io.as_mut()?;
        let Some(first) = first else {
            io.core.stop_edges();
            io.watch = None;
            return Some(false);
        };
        let clock = edgetime::start::restarted(first, (on >> 16 & 3) as u16);
        EDGE_CLOCK.store(clock.first_instant as u32 | (on & !0xFFFF), Ordering::Relaxed);
        io.core.start_edges(clock);
        // (the service task's next look starts the watch again)
        io.watch = None;
        Some(true)
    });
    if restarted == Some(false) {
        warn!("edge times off: the tick's instant could not be measured again after lost ticks (a save's, or a tick that never ran)");
    }
}

/// A save is about to stall the CPU (its erase): the core is told
/// (`Controller::begin_stall`), and the watch on the ticks stops until
/// `restart_edges` measures the clock again.
pub fn begin_stall() {
    locked(|cs| {
        if let Some(io) = IO.borrow(cs).borrow_mut().as_mut() {
            io.core.begin_stall();
            io.watch = None;
        }
    });
}

/// Every ms from the service task: ticks whose interrupt never ran
/// (`edgetime::watch`), from the next tick's instant as `next_instant`
/// measures it and the ticks run, under the lock. Any lost puts the edge
/// times' instants a tick early for good: the clock is measured again
/// (`restart_edges`), as after a save.
pub fn check_ticks() {
    let now_ms = embassy_time::Instant::now().as_millis() as u32;
    let gap = now_ms.wrapping_sub(LAST_LOOK_MS.swap(now_ms, Ordering::Relaxed));
    let lost = locked(|cs| {
        let mut io = IO.borrow(cs).borrow_mut();
        let io = io.as_mut().filter(|io| io.core.edge_timing())?;
        // (a measurement no try could make: looked at again next ms)
        let next = edgetime::start::next_instant(&mut Mmio)?;
        let ticks = TICKS.load(Ordering::Relaxed);
        let Some(watch) = io.watch.as_mut() else {
            // the first look since the clock was measured: judged from here
            io.watch = Some(Watch::new(next, ticks));
            return None;
        };
        // a look too far from the last cannot tell: `None`, as the watch
        // says itself of looks 32 ms apart
        Some(watch.look(next, ticks).filter(|_| gap <= WATCH_GAP_MS))
    });
    match lost {
        Some(Some(0)) | None => {}
        Some(Some(n)) => {
            let total = TICKS_LOST.fetch_add(n, Ordering::Relaxed).wrapping_add(n);
            warn!("{} tick(s) never ran ({} since boot): the edge times' clock is measured again", n, total);
            restart_edges();
        }
        Some(None) => {
            warn!("the watch on lost ticks did not look for {} ms: the edge times' clock is measured again", gap);
            restart_edges();
        }
    }
}

/// The lathe's last timed edge, read as the tick reads it, with k0 mod 4
/// (A and B low: `EDGE_CLOCK`), for the bench's log; `None` until the tick
/// has seen a capture (the read clears CC1IF, which nothing looks at from
/// then on).
pub fn last_edge() -> Option<(polyturn_sync::edges::EdgeRegs, u16)> {
    let gate = locked(|cs| IO.borrow(cs).borrow().as_ref().map(|io| io.gate));
    if gate != Some(Gate::Open) {
        return None;
    }
    let k0 = (EDGE_CLOCK.load(Ordering::Relaxed) >> 16 & 3) as u16;
    edgetime::read::lathe(Gate::Open, &mut Mmio).1.map(|e| (e, k0))
}
