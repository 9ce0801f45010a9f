//! The critical section every crate uses (embassy, defmt-rtt, ours): it
//! raises BASEPRI to mask every interrupt below the tick's level and its
//! step plan's, not PRIMASK. defmt-rtt holds it while it encodes a whole
//! log line (the emulator measured 7 657 instructions, 80 µs, two ticks),
//! and embassy for its queues; neither may delay the tick, its plan or the
//! E-stop, which touch nothing of theirs and never log (`.ci/callgraph` checks
//! their call graphs). The state the tick shares (`tick::shared::IO`) has its own
//! lock, BASEPRI at the tick's level (`tick::shared::locked`), held only for short
//! copies; the E-stop, above the tick, is masked by neither.
//!
//! BASEPRI (PM0214 §2.1.3): "when set to a nonzero value, it prevents the
//! activation of all exceptions with the same or lower priority level";
//! written through BASEPRI_MAX, which only ever raises it, so a section
//! taken inside a more urgent handler does not unmask anything.

use polyturn_firmware::board::PLAN_LEVEL;

/// Masks the levels below the step plan's in urgency (the top 4 bits,
/// PM0214 §4.3.7): not the tick, nor its plan (`tick/plan.rs`).
const MASK: u8 = (PLAN_LEVEL + 1) << 4;

struct Basepri;
critical_section::set_impl!(Basepri);

// SAFETY: single core; BASEPRI masks every interrupt that takes this
// section (all below the plan's level), and the tick, plan and E-stop
// handlers, above it, never take it (checked on their call graphs in
// .ci/callgraph).
unsafe impl critical_section::Impl for Basepri {
    unsafe fn acquire() -> critical_section::RawRestoreState {
        let old = cortex_m::register::basepri::read() as u32;
        cortex_m::register::basepri_max::write(MASK);
        core::sync::atomic::compiler_fence(core::sync::atomic::Ordering::SeqCst);
        old
    }

    unsafe fn release(old: critical_section::RawRestoreState) {
        core::sync::atomic::compiler_fence(core::sync::atomic::Ordering::SeqCst);
        // SAFETY: restores the level this section found
        unsafe { cortex_m::register::basepri::write(old as u8) };
    }
}
