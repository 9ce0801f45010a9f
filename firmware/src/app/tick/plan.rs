//! The step plan's writing, one level below the tick (`board::PLAN_LEVEL`).
//!
//! The tick makes the plan for window k + 2 (`Controller::plan_steps`, a
//! few integer fields) and hands it here; this handler writes it into the
//! ring (`Generator::write_plan`: RAM writes, and a halt if the DMA got
//! there first), as grbl fills its segment buffer outside the step
//! interrupt. The DMA asks for window k + 2's first segment as window
//! k + 1's last one starts, three quarters into tick k + 1 at the earliest
//! (`entries::late_boundary`): a write that ends after tick k + 1 but
//! before that loses nothing, and is only counted (`past_next`). (After
//! an arm the first window's first segment is asked for at the next
//! tick's instant: a writing later than that halts.) Nothing but the
//! E-stop and the tick outranks this handler (`board::PRIORITIES`; the
//! global critical section masks only the levels below it, `cs.rs`), so it
//! runs as the tick returns.
//!
//! - The plans cross in `SLOTS`, two of them: the tick puts one in at each
//!   tick (`hand_on`), this handler writes them in order from there
//!   (`write_next`). `MADE` and `TAKEN` count them; the tick is the only
//!   writer of one, this handler (or the tick, settling) of the other, and
//!   the tick fills only a slot no one is reading.
//! - The generator (`WRITER`) is this handler's while it holds `STATE` at
//!   `WRITING`: the tick, which pre-empts it, sees that and leaves the
//!   generator alone (`writer`): it does not arm, and a halt it needs it
//!   makes on the registers (`halt_busy`), which the generator hears of
//!   when it is free again (`heard_of_halts`). Otherwise the tick opens it.
//! - A plan still waiting when the next tick comes (this handler held off
//!   for a tick) is written by that tick itself (`settle`), before its own.
//! - A plan the handler is still writing when the tick after next comes
//!   (another waits behind it) is late for real: its window has begun.
//!   The tick that finds it halts the step output first thing (`at_entry`,
//!   `late`), and the core's books, whose window went out without its
//!   steps, stop the cutter with `fault=step-output`. So does a write the
//!   DMA overtakes (`write_plan`'s own check).
//! - One core: the two handlers interleave only by pre-emption, and a core
//!   sees its own memory accesses in program order (ARMv7-M's model, ARM
//!   DDI 0403E §A3.7), so the flags and counts need no barrier, only the
//!   compiler kept from moving accesses across them (`compiler_fence`). An
//!   Acquire load or Release store would put a DMB into every tick.
//! - The register programs that must run inside the tick they were made
//!   for, an arm (`program::arm`'s `Sync` on TIM11's count and UIF), stay
//!   in the tick (`Generator::begin`).

use super::{halts, STEPS_LATE};
use crate::app::drivers;
use crate::app::mmio::Mmio;
use core::cell::{RefCell, UnsafeCell};
use core::sync::atomic::{compiler_fence, AtomicU32, AtomicU8, Ordering};
use cortex_m::interrupt::{CriticalSection, Mutex};
use embassy_stm32::interrupt;
use embassy_stm32::interrupt::{InterruptExt, Priority};
use polyturn_firmware::board;
use polyturn_firmware::stepgen::Generator;
use polyturn_sync::steps::{Dir, StepPlan, StepTiming};

// the vector below is `board::PLAN_IRQ`'s (`priorities::apply` sets its level)
const _: () = assert!(matches!(board::PLAN_IRQ.as_bytes(), b"USART2"));

/// The step output, what it has heard of halts made elsewhere, and the
/// timing the tick last gave it (the core's, as the plans are made).
pub(super) struct Writer {
    pub steps: Generator,
    /// `halts()` when the generator last heard of a halt made elsewhere
    pub halts_seen: u32,
    pub timing: StepTiming,
}

/// The generator, the tick's or this handler's in turn (`STATE`).
static WRITER: Mutex<RefCell<Option<Writer>>> = Mutex::new(RefCell::new(None));

/// Nobody writes: the tick may open `WRITER`.
const FREE: u8 = 0;
/// This handler holds `WRITER` until it stores `FREE`.
const WRITING: u8 = 1;
static STATE: AtomicU8 = AtomicU8::new(FREE);

/// A plan as the tick made it.
#[derive(Clone, Copy)]
struct Handed {
    plan: StepPlan,
    /// `TICKS` as the tick that made it ran (`tick::ticks`)
    made_at: u32,
}

/// Two plans in flight at most (`MADE` − `TAKEN`), each written in place
/// from its slot (no copy: the handler's time is the plan's deadline).
struct Slots([UnsafeCell<Handed>; 2]);
// SAFETY: the tick writes slot `MADE % 2` only while fewer than two plans
// wait, so never the one being written (slot `TAKEN % 2`, until `TAKEN`
// passes it); a writer reads a slot only after `MADE` says it is written.
unsafe impl Sync for Slots {}
const EMPTY: Handed =
    Handed { plan: StepPlan { count: 0, dir: Dir::Forward, first: 0, period: 0, first_frac: 0, frac: 0 }, made_at: 0 };
static SLOTS: Slots = Slots([UnsafeCell::new(EMPTY), UnsafeCell::new(EMPTY)]);
/// Plans the tick handed on, since boot (only the tick writes it).
static MADE: AtomicU32 = AtomicU32::new(0);
/// Plans written, or dropped (this handler, or the tick settling).
static TAKEN: AtomicU32 = AtomicU32::new(0);

/// Ticks that found a plan still being written two ticks on, since boot:
/// each halted the step output (`tick::halts` counts them as halts made
/// elsewhere).
static LATES: AtomicU32 = AtomicU32::new(0);
/// Halts the tick made on the registers while this handler held the
/// generator (`halt_busy`), since boot.
static BUSY_HALTS: AtomicU32 = AtomicU32::new(0);
/// Ticks that found the last tick's plan not yet written (still being
/// written, or waiting), since boot. Each cost nothing unless the DMA
/// overtook the writing (then it is in `STEPS_LATE` too, and halted).
static PAST_NEXT: AtomicU32 = AtomicU32::new(0);

/// Sets the generator up, before the tick's interrupt is enabled.
pub(super) fn install(steps: Generator, timing: StepTiming, cs: &CriticalSection) {
    WRITER.borrow(cs).replace(Some(Writer { steps, halts_seen: halts(), timing }));
}

/// # Safety
/// As `InterruptExt::enable`: the handler's state (`WRITER`) is set.
pub(super) unsafe fn enable() {
    // (as `priorities::apply` sets it, and here again: below the tick, or
    // the handler would open `WRITER` inside the tick that pended it)
    interrupt::USART2.set_priority(Priority::from(board::PLAN_LEVEL << 4));
    interrupt::USART2.unpend();
    // SAFETY: as the caller says
    unsafe { interrupt::USART2.enable() };
}

/// Plans handed on and not yet written (the one being written too).
fn waiting() -> u32 {
    MADE.load(Ordering::Relaxed).wrapping_sub(TAKEN.load(Ordering::Relaxed))
}

/// The tick, when the generator is free: the generator. None while this
/// handler writes (`at_entry` has judged that).
pub(super) fn writer<'a>(cs: &'a CriticalSection) -> Option<core::cell::RefMut<'a, Option<Writer>>> {
    if STATE.load(Ordering::Relaxed) == WRITING {
        return None;
    }
    // (try_: nothing else holds it while the tick runs and the handler
    // does not; the tick keeps no panic path)
    WRITER.borrow(cs).try_borrow_mut().ok()
}

/// First thing in the tick: a writing still going with the last tick's plan
/// waiting behind it is for a window that has begun: the step output halts
/// at once, before anything of the tick (`late`). One still going with
/// nothing behind it, or a plan waiting that the handler never started, is
/// counted: it may end in time.
pub(super) fn at_entry() {
    let (writing, waiting) = (STATE.load(Ordering::Relaxed) == WRITING, waiting());
    if writing && waiting > 1 {
        late();
    } else if waiting > 0 {
        PAST_NEXT.fetch_add(1, Ordering::Relaxed);
    }
}

/// At the tick, the generator in hand: the plans the handler never started
/// (held off for a tick) are written here, in order, as it would have.
#[inline(always)]
pub(super) fn settle(w: &mut Writer) {
    if waiting() == 0 {
        return; // the common case: the handler has written them all
    }
    while write_next(w).is_some() {}
}

/// The tick leaves this tick's plan to the handler; with two still
/// waiting (which `at_entry` has already halted for) it is dropped.
#[inline(always)]
pub(super) fn hand_on(plan: &StepPlan) {
    let made = MADE.load(Ordering::Relaxed);
    if made.wrapping_sub(TAKEN.load(Ordering::Relaxed)) >= 2 {
        return;
    }
    // SAFETY: the slot no writer is on (`Slots`); only the tick writes it
    unsafe { *SLOTS.0[made as usize % 2].get() = Handed { plan: *plan, made_at: super::ticks() } };
    compiler_fence(Ordering::SeqCst);
    MADE.store(made.wrapping_add(1), Ordering::Relaxed);
    interrupt::USART2.pend();
    // the pend complete before the tick returns, so the plan is taken
    // before anything below it (PM0214 §2.2.4: DSB, outstanding memory
    // transactions complete before the next instruction)
    cortex_m::asm::dsb();
}

/// The next plan waiting, written from its slot and then let go of; the
/// tick that made it (`made_at`), or None if none waits.
fn write_next(w: &mut Writer) -> Option<u32> {
    let taken = TAKEN.load(Ordering::Relaxed);
    if MADE.load(Ordering::Relaxed) == taken {
        return None;
    }
    compiler_fence(Ordering::SeqCst);
    // SAFETY: written before `MADE` passed it, and not written again until
    // `TAKEN` passes it (`Slots`)
    let h = unsafe { &*SLOTS.0[taken as usize % 2].get() };
    write(w, &h.plan);
    let made_at = h.made_at;
    compiler_fence(Ordering::SeqCst);
    TAKEN.store(taken.wrapping_add(1), Ordering::Relaxed);
    // (after the plan is let go of: a tick meanwhile finds it written)
    w.steps.silence_behind(&mut Mmio);
    Some(made_at)
}

/// The tick needs the step output halted while this handler holds the
/// generator: on the registers, as the E-stop does; the generator hears
/// of it when it is free (`heard_of_halts`).
pub(super) fn halt_busy() {
    drivers::halt_steps();
    BUSY_HALTS.fetch_add(1, Ordering::Relaxed);
}

/// A plan still being written two ticks after it was made: its window has
/// begun. The step output halts at once.
fn late() {
    drivers::halt_steps();
    LATES.fetch_add(1, Ordering::Relaxed);
    STEPS_LATE.fetch_add(1, Ordering::Relaxed);
}

/// Halts made outside the generator by the tick and for late plans.
pub(super) fn halts_here() -> u32 {
    LATES.load(Ordering::Relaxed).wrapping_add(BUSY_HALTS.load(Ordering::Relaxed))
}

/// Ticks that found the last tick's plan not yet written, since boot
/// (`PAST_NEXT`).
pub fn past_next() -> u32 {
    PAST_NEXT.load(Ordering::Relaxed)
}

/// When the plan's writing ends, in cycles from its tick's instant
/// (`latency`): what the bench's log prints (`report`).
pub static PLAN_END: polyturn_firmware::latency::Latency = polyturn_firmware::latency::Latency::new();

#[interrupt]
fn USART2() {
    STATE.store(WRITING, Ordering::Relaxed);
    // (nothing below moved above the store: a tick before it finds the
    // generator free and `TAKEN` as it will be read here)
    compiler_fence(Ordering::SeqCst);
    // SAFETY: `WRITER` is this handler's while it holds `WRITING`: the
    // tick, which pre-empts it, sees that and does not open it; thread mode
    // and the E-stop never open it. Through the pointer: the borrow's own
    // flag and `STATE` could not be let go of in one store.
    let w = unsafe { &mut *WRITER.borrow(&CriticalSection::new()).as_ptr() };
    let mut made_at = None;
    if let Some(w) = w.as_mut() {
        while let Some(m) = write_next(w) {
            made_at = Some(m);
        }
    }
    compiler_fence(Ordering::SeqCst);
    STATE.store(FREE, Ordering::Relaxed);
    // TIM11's count says when in a period it ended; whether that is the
    // period after its tick's or a later one, `TICKS` (the tick that made
    // it counts itself as it returns: one more is the next tick)
    if let Some(made_at) = made_at {
        super::ended_after(&PLAN_END, super::ticks().wrapping_sub(made_at) > 1);
    }
}

/// One plan into the ring. A halt since it was made (the E-stop's, the
/// tick's) leaves it unwritten: a later tick re-arms once the ring is
/// silent. A write the DMA overtook has halted, and is counted, unless a
/// halt made elsewhere meanwhile is why.
#[inline(never)] // one copy for the handler and the tick's `settle`
fn write(w: &mut Writer, plan: &StepPlan) {
    // (read first: a halt made elsewhere from here on is not this write's)
    let before = halts();
    // the timing the tick last gave: it changes only while idle, when the
    // plans are empty, so a plan made a tick before is laid out as made
    let timing = w.timing;
    super::heard_of_halts(w, &timing);
    if !w.steps.armed() {
        return;
    }
    if w.steps.write_plan(plan, &timing, &mut Mmio).is_err() && halts() == before {
        STEPS_LATE.fetch_add(1, Ordering::Relaxed);
    }
}
