//! SysTick as an instruction counter (`-icount shift=0`: one instruction,
//! one ns of virtual time), shared by the tick's measurement (`mcu.rs`)
//! and the locked sections' (`locked.rs`).

use core::arch::asm;
use cortex_m::peripheral::SYST;
use polyturn_sync::Timing;

pub(crate) const TIMING: Timing = Timing::FIRMWARE;

fn now(syst: &SYST) -> u32 {
    let _ = syst;
    SYST::get_current()
}

/// SysTick counts elapsed over `f` (it counts down, 24 bits).
pub(crate) fn measure(syst: &SYST, f: impl FnOnce()) -> u32 {
    let a = now(syst);
    f();
    let b = now(syst);
    a.wrapping_sub(b) & 0x00FF_FFFF
}

/// 100 iterations of 10 nops + subs + bne: 1 200 instructions, plus 1 mov.
pub(crate) fn calibration_loop() {
    unsafe {
        asm!(
            "movs {n}, #100",
            "2:",
            "nop", "nop", "nop", "nop", "nop", "nop", "nop", "nop", "nop", "nop",
            "subs {n}, #1",
            "bne 2b",
            n = out(reg) _,
        );
    }
}
