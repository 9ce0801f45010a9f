//! The state the tick shares with lower priorities (`IO`: the core, the
//! step output, the pins) and its lock (`locked`: BASEPRI at the tick's
//! level), and what thread mode does under it: only short copies inside.

use super::super::bldc;
use super::super::drivers::{self, OutputPins};
use super::TIMING;
use core::cell::RefCell;
use core::sync::atomic::{compiler_fence, Ordering};
use cortex_m::interrupt::{CriticalSection, Mutex};
use polyturn_firmware::bldcout::Out;
use polyturn_firmware::board;
use polyturn_firmware::edgetime::{read::Gate, watch::Watch};
use polyturn_firmware::xsteps::XSteps;
use polyturn_sync::Controller;

pub(super) struct Io {
    pub core: Controller,
    pub pins: OutputPins,
    pub x: XSteps,
    /// whether the lathe's edge registers hold an edge (`edgetime::read`)
    pub gate: Gate,
    /// the edge clock's instants against the ticks run (`check_ticks`);
    /// none while the edge times are off, and through a save's stall
    pub watch: Option<Watch>,
    /// the BLDC drive's interface, as TIM10 is set up
    pub bldc: Out,
}

/// cortex-m's Mutex: its token comes only from `locked` here, so a
/// `critical_section::with` token (`cs.rs`, which the tick outranks)
/// cannot open it.
pub(super) static IO: Mutex<RefCell<Option<Io>>> = Mutex::new(RefCell::new(None));

/// BASEPRI masks every level numerically at or above it (PM0214 §2.1.3):
/// the tick's level and below, not the E-stop above it.
const TICK_MASK: u8 = board::TICK_LEVEL << 4;

/// The lock on `IO`: BASEPRI raised to the tick's level, so the tick (the
/// only other user of `IO`) waits, and the E-stop, which never touches
/// `IO`, does not. Only short copies inside. Raised through BASEPRI_MAX,
/// which never lowers it, so taking it where more is masked unmasks
/// nothing; restored on the way out. Never inlined: each closure's copy is
/// a function of this module, in SRAM with the tick (`memory.x`), so a
/// section holding the tick off does not wait on the flash.
#[inline(never)]
pub(super) fn locked<R>(f: impl FnOnce(&CriticalSection) -> R) -> R {
    let old = cortex_m::register::basepri::read();
    cortex_m::register::basepri_max::write(TICK_MASK);
    compiler_fence(Ordering::SeqCst);
    // SAFETY: nothing that touches `IO` can run until BASEPRI is restored
    let r = f(unsafe { &CriticalSection::new() });
    compiler_fence(Ordering::SeqCst);
    // SAFETY: restores the level this section found
    unsafe { cortex_m::register::basepri::write(old) };
    r
}

/// Runs `f` on the controller (console, planning, reports).
pub fn with_core<R>(f: impl FnOnce(&mut Controller) -> R) -> Option<R> {
    locked(|cs| IO.borrow(cs).borrow_mut().as_mut().map(|io| f(&mut io.core)))
}

/// Fits a cam table: the points are checked outside the lock (a pass over
/// the whole table), only the swap is under it.
pub fn fit_cam(h: &polyturn_sync::cam_upload::CamHeader, table: &'static [i32]) -> Option<Result<(), &'static str>> {
    let x = match polyturn_sync::controller::prepare_cam(h, table, TIMING) {
        Ok(x) => x,
        Err(e) => return Some(Err(e)),
    };
    with_core(|c| c.install_cam(h, x))
}

/// Applies the settings the drivers hold themselves (ENABLE polarity, the
/// pulse width a halt waits out, the BLDC drive's interface and sense)
/// after a console change, at low priority. The BLDC's scale (a 64-bit
/// division) is worked out between two short copies under the lock: only
/// thread mode changes the settings, and nothing else runs there meanwhile.
pub fn apply_driver_settings() {
    let read = |io: &Io| (*io.core.config(), io.core.derived().limits.max_velocity, io.core.derived().steps.pulse);
    let Some((config, max_q16, pulse)) = locked(|cs| IO.borrow(cs).borrow().as_ref().map(read)) else { return };
    let out = Out::new(&config, max_q16);
    drivers::set_halt_pulse(pulse);
    locked(|cs| {
        if let Some(io) = IO.borrow(cs).borrow_mut().as_mut() {
            io.pins.set_polarity(config.enable_active_high);
            // (a new scale alone keeps the frame: no reprogram, whose
            // restart would cut a frame short)
            if !out.same_frame(&io.bldc) {
                bldc::set_up(&out);
            }
            io.bldc = out;
            bldc::set_sense(&config);
        }
    });
}
