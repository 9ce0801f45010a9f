//! The release image's seal, and the firmware's check of its own image at
//! boot: an image cut short, grown or altered on its way to the flash is
//! refused by `polyturn flash` and the page's flasher, and if it reached
//! the flash anyway (a probe, a torn write) the board does not run it.
//!
//! `polyturn image` (and `polyturn flash` of an ELF) appends to the bytes
//! from 0x0800_0000, padded with 0xFF to a whole word, three words:
//! [`MAGIC`], the length sealed (the seal's own offset) and the CRC of
//! the sealed words as the F411's CRC unit computes it (RM0383 §4:
//! CRC-32 polynomial 0x04C11DB7, from 0xFFFF_FFFF, one whole word per
//! write; `polyturn_stm32_model::chip::crc` is the reading). The image's
//! end is known to the firmware from its link (`app/seal.rs`): the seal is
//! there or the image is not whole.
//!
//! At boot, before anything else is set up, [`verify`] runs the unit over
//! the image (a word per write, so about 29 000 writes: a few ms at the
//! 16 MHz HSI, §6.2.2) and compares. A damaged image leaves every output as
//! reset left it (inputs, §8.4.1) and shows [`crate::led::damaged`] on the
//! LEDs ([`led_on`]) until the board is flashed again.

use crate::regs::Bus;
use polyturn_regs::bits::{crc_cr, rcc_ahb1enr};

/// "PTIM" as the word the flash holds (little-endian).
pub const MAGIC: u32 = u32::from_le_bytes(*b"PTIM");
/// The seal: magic, length, CRC.
pub const SEAL_BYTES: u32 = 12;
/// Flash: the image starts here (RM0383 §2.3 Table 1; memory.x ORIGIN)
/// and may not reach the settings' sectors 6-7 (memory.x LENGTH 256K).
pub use polyturn_regs::addr::FLASH_BASE;
pub const APP_END: u32 = FLASH_BASE + 256 * 1024;

/// The CRC unit (§2.3 Table 1: 0x4002_3000) and its registers (§4.4).
pub use polyturn_regs::addr::{CRC as CRC_BASE, CRC_CR, CRC_DR};
/// CRC_CR.RESET (§4.4.3): DR back to 0xFFFF_FFFF.
pub const CR_RESET: u32 = crc_cr::RESET.mask();

/// RCC_AHB1ENR (§6.3.9, RCC at 0x4002_3800 + 0x30): GPIOAEN bit 0,
/// GPIOCEN bit 2, CRCEN bit 12.
pub use polyturn_regs::addr::RCC_AHB1ENR;
pub const GPIOAEN: u32 = rcc_ahb1enr::GPIOAEN.mask();
pub const GPIOCEN: u32 = rcc_ahb1enr::GPIOCEN.mask();
pub const CRCEN: u32 = rcc_ahb1enr::CRCEN.mask();

/// The CRC a sealed image carries, computed in software as the host writes
/// it: the CRC unit's algorithm (RM0383 §4.3: polynomial 0x04C11DB7, MSB
/// first, from 0xFFFF_FFFF after CR.RESET, one whole word per write, no
/// final XOR). The board computes it in the unit ([`verify`]); host tests
/// check this against `polyturn_stm32_model::chip::crc`, the reading of §4.
pub fn crc_of_words(words: impl IntoIterator<Item = u32>) -> u32 {
    const POLY: u32 = 0x04C1_1DB7;
    words.into_iter().fold(u32::MAX, |crc, word| {
        (0..32).fold(crc ^ word, |c, _| if c & 0x8000_0000 != 0 { (c << 1) ^ POLY } else { c << 1 })
    })
}

/// The clock the check runs at: the HSI, which the MCU runs from after a
/// reset (RM0383 §6.2.2), before embassy's init switches to the PLL.
pub const HSI_HZ: u32 = 16_000_000;

/// Why an image is not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Damage {
    /// the link's end is outside sectors 0-5 or not a word boundary
    /// (damaged code computed it)
    End(u32),
    /// erased flash where the seal belongs: never sealed (an ELF a probe
    /// wrote), or cut short
    Unsealed,
    /// something else where the seal belongs: cut short, or grown
    NoSeal,
    /// a seal whose length is not where it lies
    Length { sealed: u32 },
    /// the CRC over the image is not the one sealed
    Crc { sealed: u32, computed: u32 },
}

/// Checks the image from [`FLASH_BASE`] to `end` (where the link put its
/// last byte) against the seal at `end`, with the CRC unit. The unit's
/// clock is on only while it works (AHB1ENR as it was before, after).
pub fn verify(bus: &mut impl Bus, end: u32) -> Result<(), Damage> {
    if !end.is_multiple_of(4) || end <= FLASH_BASE || end > APP_END - SEAL_BYTES {
        return Err(Damage::End(end));
    }
    let (magic, length, sealed) = (bus.read(end), bus.read(end + 4), bus.read(end + 8));
    if magic == ERASED {
        return Err(Damage::Unsealed);
    }
    if magic != MAGIC {
        return Err(Damage::NoSeal);
    }
    if length != end - FLASH_BASE {
        return Err(Damage::Length { sealed: length });
    }
    let enabled = bus.read(RCC_AHB1ENR);
    bus.write(RCC_AHB1ENR, enabled | CRCEN);
    bus.write(CRC_CR, CR_RESET);
    let mut at = FLASH_BASE;
    while at < end {
        let word = bus.read(at);
        bus.write(CRC_DR, word);
        at += 4;
    }
    let computed = bus.read(CRC_DR);
    bus.write(RCC_AHB1ENR, enabled);
    if computed != sealed {
        return Err(Damage::Crc { sealed, computed });
    }
    Ok(())
}

/// An erased flash word (RM0383 §3.5.3: erasing sets every bit).
const ERASED: u32 = 0xFFFF_FFFF;

/// DHCSR (ARMv7-M ARM C1.6.2) and its C_DEBUGEN bit (0), set by a debugger
/// that has enabled halting debug, as probe-rs does while attached.
pub const DHCSR: u32 = 0xE000_EDF0;
pub const C_DEBUGEN: u32 = 1;

/// Whether an image refused for `damage` runs all the same: only an
/// unsealed one (`cargo fw-run`: probe-rs writes the ELF, which has no
/// seal, and erases around it) with the debugger that wrote it attached.
/// On a board in use no debugger is attached, and nothing unsealed runs.
pub fn probes_own(bus: &mut impl Bus, damage: Damage) -> bool {
    damage == Damage::Unsealed && bus.read(DHCSR) & C_DEBUGEN != 0
}

/// The status LEDs' ports: PC13 (active low) and PA10 (active high),
/// `board.rs`; GPIOx_MODER (§8.4.1, offset 0) and GPIOx_BSRR (§8.4.7,
/// offset 0x18).
pub use polyturn_regs::addr::gpio_off::{BSRR, MODER};
pub use polyturn_regs::addr::{GPIOA, GPIOC};

/// The cycle counter, which times the damaged light whatever the loop
/// around it costs: DCB_DEMCR.TRCENA (ARMv7-M ARM C1.6.5, bit 24) lets
/// the DWT run, DWT_CTRL.CYCCNTENA (C1.8.7, bit 0) starts DWT_CYCCNT
/// (C1.8.8), which counts CPU cycles.
pub const DEMCR: u32 = 0xE000_EDFC;
pub const TRCENA: u32 = 1 << 24;
pub const DWT_CTRL: u32 = 0xE000_1000;
pub const CYCCNTENA: u32 = 1;
pub const DWT_CYCCNT: u32 = 0xE000_1004;

/// Both LEDs made outputs (MODER 01, §8.4.1), unlit; every other pin as
/// reset left it; the cycle counter running. Returns its count.
pub fn led_setup(bus: &mut impl Bus) -> u32 {
    let enabled = bus.read(RCC_AHB1ENR);
    bus.write(RCC_AHB1ENR, enabled | GPIOAEN | GPIOCEN);
    led_on(bus, false);
    for (port, pin) in [(GPIOC, 13), (GPIOA, 10)] {
        let moder = bus.read(port + MODER) & !(0b11 << (2 * pin));
        bus.write(port + MODER, moder | 0b01 << (2 * pin));
    }
    for (reg, bit) in [(DEMCR, TRCENA), (DWT_CTRL, CYCCNTENA)] {
        let v = bus.read(reg);
        bus.write(reg, v | bit);
    }
    bus.read(DWT_CYCCNT)
}

/// Waits until `cycles` (below 2^31) have passed since the count `from`;
/// returns `from + cycles`, the next step's start. Bounded: each read
/// takes at least a cycle, so at most `cycles` reads.
pub fn wait(bus: &mut impl Bus, from: u32, cycles: u32) -> u32 {
    for _ in 0..cycles {
        if bus.read(DWT_CYCCNT).wrapping_sub(from) >= cycles {
            break;
        }
    }
    from.wrapping_add(cycles)
}

/// Lights or darkens both LEDs (BSRR: bits 0-15 set, 16-31 reset, §8.4.7).
pub fn led_on(bus: &mut impl Bus, lit: bool) {
    let (pc13, pa10) = if lit { (1 << (13 + 16), 1 << 10) } else { (1 << 13, 1 << (10 + 16)) };
    bus.write(GPIOC + BSRR, pc13);
    bus.write(GPIOA + BSRR, pa10);
}

#[cfg(test)]
mod tests;
