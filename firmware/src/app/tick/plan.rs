//! The tick's step plan, one level below the tick (`board::PLAN_LEVEL`).
//!
//! The plan made at tick k fills window k + 2 (`polyturn_sync::steps::pipe`):
//! it has a tick's slack the rest of the tick has not, so it runs after the
//! tick returns, as grbl plans its segments outside the step interrupt
//! (`Controller::plan_steps`, then `Generator::write_plan`'s RAM writes). The tick
//! pends this handler; nothing but the E-stop and the next tick outranks
//! it (`board::PRIORITIES`; the global critical section masks only the
//! levels below it, `cs.rs`), so it runs as the tick returns, and the tick
//! never waits for it:
//!
//! - it opens `IO` without a lock, while it holds `STATE` at `MAKING`. The
//!   tick's lock (`locked`, BASEPRI at the tick's level) masks it too, so
//!   thread mode never holds `IO` while it runs; only the tick can pre-empt
//!   it, and that tick sees `MAKING` and does not open `IO` (`making`).
//!   One store lets go of `IO` and says the plan is made.
//! - a plan not made by the next tick is a fault of its own, never a window
//!   written late (`late`, `settle`): the step output is halted at once, and
//!   the core's books, whose window went out without its steps, trip
//!   `Fault::StepOutput` as for any output that did not do what it was told
//!   (a cutter holding still, whose windows are empty, re-arms once the ring
//!   is silent, as after an E-stop's halt). A plan still being made stops the
//!   whole tick, not only its plan (`making`): the core's edge clock is then
//!   a tick off, so the tick is counted lost and the clock measured again
//!   (`check_ticks`). The cut-off is the next tick, not the window's start a
//!   tick later: with tick and plan at about half a tick together (the
//!   emulator's jobs), a plan that late means something is wrong.
//! - the register programs that must run inside the tick they were made
//!   for, an arm (`program::arm`'s `Sync` on TIM11's count and UIF), stay
//!   in the tick (`Generator::begin`): this handler only writes the ring,
//!   the first window after an arm too, and halts.

use super::{heard_of_halts, Io, IO, STEPS_LATE};
use crate::app::drivers;
use crate::app::mmio::Mmio;
use core::sync::atomic::{AtomicU32, AtomicU8, Ordering};
use cortex_m::interrupt::CriticalSection;
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::{InterruptExt, Priority};
use polyturn_firmware::board;

// the vector below is `board::PLAN_IRQ`'s (`priorities::apply` sets its level)
const _: () = assert!(matches!(board::PLAN_IRQ.as_bytes(), b"USART2"));

/// No plan left to make.
const IDLE: u8 = 0;
/// The tick left a plan, set as it pends the handler.
const OWED: u8 = 1;
/// The handler is making it: it holds `IO` until it stores `IDLE`.
const MAKING: u8 = 2;
/// The plan's state. The handler takes it from `OWED` to `MAKING` in one
/// exclusive read-and-write (`compare_exchange`: LDREX/STREX, whose
/// tag an exception removes, PM0214 §2.2.7),
/// so a tick between the two makes it read again.
static STATE: AtomicU8 = AtomicU8::new(IDLE);
/// Ticks that found their last tick's plan not made, since boot: each
/// halted the step output (`tick::halts` counts them as halts made
/// elsewhere).
static LATES: AtomicU32 = AtomicU32::new(0);

/// # Safety
/// As `InterruptExt::enable`: the handler's state (`IO`) is set.
pub(super) unsafe fn enable() {
    // (as `priorities::apply` sets it, and here again: below the tick, or
    // the handler would open `IO` inside the tick that pended it)
    interrupt::USART2.set_priority(Priority::from(board::PLAN_LEVEL << 4));
    interrupt::USART2.unpend();
    // SAFETY: as the caller says
    unsafe { interrupt::USART2.enable() };
}

/// The tick leaves this tick's plan to the handler.
pub(super) fn hand_on() {
    STATE.store(OWED, Ordering::Release);
    interrupt::USART2.pend();
    // the pend complete before the tick returns, so the plan is taken
    // before anything below it (PM0214 §2.2.4: DSB, outstanding memory
    // transactions complete before the next instruction)
    cortex_m::asm::dsb();
}

/// At the tick's entry: the handler holds `IO`, still making the last
/// tick's plan (`late`: this tick does not open `IO`).
pub(super) fn making() -> bool {
    STATE.load(Ordering::Acquire) == MAKING
}

/// A tick found its last tick's plan not made: the step output halts at
/// once (the window it was for may start before it could be written).
pub(super) fn late() {
    drivers::halt_steps();
    LATES.fetch_add(1, Ordering::Relaxed);
    STEPS_LATE.fetch_add(1, Ordering::Relaxed);
}

/// Late plans since boot (`late`).
pub(super) fn lates() -> u32 {
    LATES.load(Ordering::Relaxed)
}

/// At the tick, `IO` in hand: a plan the handler never started (it was
/// held off for a tick) is late, and made here, unwritten, so the core's
/// books hold the window it was for as it went out: without its steps.
pub(super) fn settle(io: &mut Io) {
    if STATE.load(Ordering::Relaxed) == OWED {
        late();
        let _ = io.core.plan_steps();
        STATE.store(IDLE, Ordering::Relaxed);
    }
}

/// When the plan ends, in cycles from its tick's instant (`latency`): what
/// the bench's log prints (`report`).
pub static PLAN_END: polyturn_firmware::latency::Latency = polyturn_firmware::latency::Latency::new();

#[interrupt]
fn USART2() {
    if STATE.compare_exchange(OWED, MAKING, Ordering::Acquire, Ordering::Relaxed).is_err() {
        return; // none left, or made by a tick already (`settle`)
    }
    // SAFETY: `IO` is this handler's until it stores `IDLE`: thread mode
    // opens it only under the tick's lock, which masks this handler; the
    // tick, which pre-empts it, sees `MAKING` and does not open it; the
    // E-stop never opens it. Through the pointer: the borrow's own flag
    // and `STATE` could not be let go of in one store.
    let io = unsafe { &mut *IO.borrow(&CriticalSection::new()).as_ptr() };
    if let Some(io) = io.as_mut() {
        make(io);
    }
    STATE.store(IDLE, Ordering::Release);
    super::ended(&PLAN_END);
}

/// The plan made and written. A halt since the tick (the E-stop's) leaves
/// it unwritten: a later tick re-arms once the ring is silent.
fn make(io: &mut Io) {
    let lates_before = lates();
    let plan = io.core.plan_steps();
    heard_of_halts(io);
    if !io.steps.armed() {
        return;
    }
    let timing = io.core.derived().steps;
    // (a tick that found this plan late and halted counted it: not twice)
    if io.steps.write_plan(&plan, &timing, &mut Mmio).is_err() && lates() == lates_before {
        STEPS_LATE.fetch_add(1, Ordering::Relaxed);
    }
}
