//! The code that runs from SRAM: the interrupt handlers a tick's deadline
//! rests on (the control tick, its step plan, the E-stop) and what they call,
//! placed by `memory.x` in a section whose load image is in flash and whose
//! addresses are SRAM's alias at 0. At boot the app copies the image into
//! SRAM and maps SRAM at 0 (`app/ramcode.rs`).
//!
//! Why: the I-bus fetches from SRAM mapped at 0 with no wait state (RM0383
//! §2.1.1, §2.3.1; RM0402 §2.3 says of its twin: "To get the max performance
//! on SRAM execution, physical remap should be selected"), where flash waits
//! its 3 wait states on every miss of the ART accelerator's 1 KiB cache
//! (§3.4), which the handlers' code outgrows many times. The emulator's
//! bound takes every such miss at its worst; from SRAM there is none.

use crate::regs::Op;

/// SYSCFG_MEMRMP.MEM_MODE = 11: "Embedded SRAM mapped at 0x0000 0000"
/// (RM0383 §7.2.1).
pub const MEMRMP_SRAM: u32 = 0b11;

/// The SRAM's own address of its alias at 0 (RM0383 §2.3, Table 1): where
/// the code's bytes are copied for address `a` of the section to read them.
pub use polyturn_regs::addr::SRAM_BASE;

/// Bytes of SRAM the code may take (`memory.x`'s RAMCODE; the rest is RAM).
pub const RAMCODE_SIZE: u32 = 56 * 1024;

/// Where the copy of a word at section address `vma` goes.
pub const fn sram_address(vma: u32) -> u32 {
    SRAM_BASE + vma
}

/// The Cortex-M4's MPU registers (ARM DUI 0553A §4.5.2-4.5.5).
const MPU_CTRL: u32 = 0xE000_ED94;
const MPU_RBAR: u32 = 0xE000_ED9C;
const MPU_RASR: u32 = 0xE000_EDA0;
/// MPU_CTRL: ENABLE, and PRIVDEFENA (the default map for everything no
/// region covers; the firmware runs privileged) (§4.5.2).
const CTRL_ON: u32 = 1 | 1 << 2;
/// MPU_RBAR's VALID: the region number comes with the address (§4.5.4).
const VALID: u32 = 1 << 4;
/// MPU_RASR: AP = 110, read-only (Table 4-47), instructions allowed (XN
/// clear), ENABLE; SIZE is added per region (2^(SIZE+1) bytes, §4.5.5).
const READ_ONLY: u32 = 0b110 << 24 | 1;
/// MPU_RASR's TEX, C, B as the default memory map gives each region
/// (Table 4-45; the default memory map, ARM DUI 0553A §2.2): SRAM "Normal, write-back, write-allocate"
/// (TEX 001, C, B), the code region at 0 "Normal, write-through" (TEX
/// 000, C). Code is fetched from Normal memory only: the region changes
/// the access, not the memory type.
const SRAM_NORMAL: u32 = 0b001 << 19 | 1 << 17 | 1 << 16;
const CODE_NORMAL: u32 = 1 << 17;

/// RASR's SIZE field for a power-of-two region of `bytes`.
const fn size_field(bytes: u32) -> u32 {
    (bytes.trailing_zeros() - 1) << 1
}

/// The code's SRAM read-only once it is copied, so that nothing (a stray
/// pointer, a stack run past its end) can write over the handlers the
/// E-stop and the fault path rest on: its 56 KiB as 32 + 16 + 8 KiB at
/// 0x2000_0000 (a region is a power of two aligned to its size, §4.5.4),
/// and its alias at 0 as 64 KiB (what lies past 56 KiB there is `.data`'s
/// alias, which nothing writes through). Everything else keeps the default
/// map. A write there is a MemManage fault, which, not enabled, escalates
/// to HardFault: the handler stops every output.
pub const MPU_PROGRAM: [Op; 9] = [
    Op::Write(MPU_RBAR, SRAM_BASE | VALID),
    Op::Write(MPU_RASR, READ_ONLY | SRAM_NORMAL | size_field(32 * 1024)),
    Op::Write(MPU_RBAR, (SRAM_BASE + 32 * 1024) | VALID | 1),
    Op::Write(MPU_RASR, READ_ONLY | SRAM_NORMAL | size_field(16 * 1024)),
    Op::Write(MPU_RBAR, (SRAM_BASE + 48 * 1024) | VALID | 2),
    Op::Write(MPU_RASR, READ_ONLY | SRAM_NORMAL | size_field(8 * 1024)),
    Op::Write(MPU_RBAR, VALID | 3),
    Op::Write(MPU_RASR, READ_ONLY | CODE_NORMAL | size_field(64 * 1024)),
    Op::Write(MPU_CTRL, CTRL_ON),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_alias_at_zero_is_srams_first_bytes() {
        assert_eq!(sram_address(0), 0x2000_0000);
        assert_eq!(sram_address(RAMCODE_SIZE - 4), 0x2000_DFFC, "the last word the code may take");
    }
}
