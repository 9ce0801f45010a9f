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

/// A part's SysTick counts over the ticks measured: sum, worst, how many.
#[derive(Default)]
pub(crate) struct Costs {
    sum: u64,
    worst: u32,
    pub(crate) n: u32,
}

impl Costs {
    pub(crate) fn add(&mut self, counts: u32) {
        (self.sum, self.worst, self.n) = (self.sum + counts as u64, self.worst.max(counts), self.n + 1);
    }

    /// (average, worst) in instructions: counts × 1201 / counts per 1201.
    pub(crate) fn instructions(&self, per_1201: u32) -> (u64, u64) {
        let avg = self.sum * 1201 / self.n.max(1) as u64 / per_1201 as u64;
        (avg, self.worst as u64 * 1201 / per_1201 as u64)
    }
}
