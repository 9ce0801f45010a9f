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

/// SYSCFG_MEMRMP.MEM_MODE = 11: "Embedded SRAM mapped at 0x0000 0000"
/// (RM0383 §7.2.1).
pub const MEMRMP_SRAM: u32 = 0b11;

/// The SRAM's own address of its alias at 0 (RM0383 §2.3, Table 1): where
/// the code's bytes are copied for address `a` of the section to read them.
pub const SRAM_BASE: u32 = 0x2000_0000;

/// Bytes of SRAM the code may take (`memory.x`'s RAMCODE; the rest is RAM).
pub const RAMCODE_SIZE: u32 = 48 * 1024;

/// Where the copy of a word at section address `vma` goes.
pub const fn sram_address(vma: u32) -> u32 {
    SRAM_BASE + vma
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_alias_at_zero_is_srams_first_bytes() {
        assert_eq!(sram_address(0), 0x2000_0000);
        assert_eq!(sram_address(RAMCODE_SIZE - 4), 0x2000_BFFC, "the last word the code may take");
    }
}
