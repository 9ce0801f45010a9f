//! Flashing a Black Pill without a probe: the firmware image (a `.bin`,
//! Intel `.hex` or the ELF `cargo fw` builds), checked before anything is
//! sent (`image.rs`, `check.rs`), and the STM32F411's ROM bootloader
//! (system memory boot, USB DFU on PA11/PA12, AN2606) driven through its
//! DfuSe protocol (AN3156): download, read back to verify, leave DFU
//! (`dfuse.rs`), over USB found with nusb (`usb.rs`).
//!
//! The one rule everything here keeps: sectors 6 and 7 hold the user's
//! saved settings and cam tables (`firmware/src/flashprog.rs`), so no image
//! reaches past the end of sector 5 and nothing erases beyond it.

pub mod check;
#[cfg(feature = "device")]
pub mod dfuse;
#[cfg(feature = "device")]
mod dfuse_io;
pub mod elf;
pub mod hex;
pub mod image;
pub mod plan;
#[cfg(feature = "device")]
pub mod usb;

#[cfg(all(test, feature = "device"))]
mod dfuse_tests;
#[cfg(any(test, feature = "fakes"))]
pub mod fake;
#[cfg(test)]
mod image_tests;
#[cfg(any(test, feature = "fakes"))]
pub mod testkit;

/// Flash starts here, and the vector table with it (RM0383 §2.3 Table 1;
/// the firmware's memory.x ORIGIN).
pub const FLASH_BASE: u32 = 0x0800_0000;
/// The F411's sectors, KiB: 4 × 16, 1 × 64, 3 × 128 = 512 KiB (RM0383
/// §3.3 Table 4).
pub const SECTOR_KIB: [u32; 8] = [16, 16, 16, 16, 64, 128, 128, 128];
/// The firmware's sectors are 0..=5 (memory.x: FLASH LENGTH 256K).
pub const APP_SECTORS: usize = 6;
/// The end of sector 5: the first byte of the settings (sector 6).
pub const APP_END: u32 = FLASH_BASE + 256 * 1024;
/// The vector table's size: 16 system vectors and 86 interrupt positions,
/// the last (SPI5) at 0x194 (RM0383 Table 37). cortex-m-rt puts the
/// reset handler right after it.
pub const VECTOR_TABLE_BYTES: u32 = 0x198;
/// SRAM, 128 KiB (RM0383 §2.3 Table 1; memory.x RAM).
pub const RAM_START: u32 = 0x2000_0000;
pub const RAM_END: u32 = RAM_START + 128 * 1024;
/// The chip a polyturn image names in its marker.
pub const CHIP: &str = "stm32f411ce";
/// The marker the firmware carries in .rodata: this, the chip, `:`, the
/// version and a NUL (`polyturn-image:stm32f411ce:0.1.0\0`).
pub const MARKER: &[u8] = b"polyturn-image:";
/// Where `cargo fw` leaves the firmware (.cargo/config.toml, [profile.fw]).
pub const BUILT_ELF: &str = "target/thumbv7em-none-eabihf/fw/polyturn-firmware";

/// The address where sector `n` starts.
pub fn sector_start(n: usize) -> u32 {
    FLASH_BASE + SECTOR_KIB[..n.min(SECTOR_KIB.len())].iter().sum::<u32>() * 1024
}

/// The sectors `len_bytes` from FLASH_BASE touch: 0..=last.
pub fn last_sector(len_bytes: u32) -> usize {
    let end = FLASH_BASE.saturating_add(len_bytes.max(1));
    (0..SECTOR_KIB.len()).find(|&n| sector_start(n + 1) >= end).unwrap_or(SECTOR_KIB.len() - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flash_sectors_agree_with_the_chip_model_and_end_where_the_settings_start() {
        // the stm32-model's layout is checked against RM0383 on its own
        for (n, kib) in SECTOR_KIB.iter().enumerate() {
            assert_eq!(*kib, polyturn_stm32_model::flash::sector_kib(n as u32), "sector {n}");
        }
        assert_eq!(sector_start(APP_SECTORS), APP_END);
        assert_eq!(sector_start(6), 0x0804_0000);
        assert_eq!(sector_start(8), 0x0808_0000);
        assert_eq!((last_sector(1), last_sector(0x4000), last_sector(0x4001)), (0, 0, 1));
        assert_eq!((last_sector(0x2_0000), last_sector(0x4_0000)), (4, 5));
    }
}
