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
pub mod elf;
pub mod hex;
pub mod image;
pub mod plan;
pub mod seal;
#[cfg(feature = "device")]
pub mod usb;

#[cfg(all(test, feature = "device"))]
mod dfuse_tests;
#[cfg(test)]
mod image_tests;
#[cfg(test)]
mod mutants_tests;

/// Flash starts here, and the vector table with it (RM0383 §2.3 Table 1;
/// the firmware's memory.x ORIGIN): the register table's.
pub use polyturn_regs::addr::FLASH_BASE;
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

/// The image's largest size: sectors 0-5 (memory.x FLASH LENGTH).
pub const IMAGE_MAX_BYTES: u32 = APP_END - FLASH_BASE;

/// A checked image, ready to flash at `base`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    pub base: u32,
    pub bytes: Vec<u8>,
    /// From the image's marker; `None` only with `--any-image`.
    pub version: Option<String>,
    /// SHA-256 of `bytes` (the `.bin`), lower-case hex.
    pub sha256: String,
}

/// Why a file is no image to flash: the rule it breaks, and what it has.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    pub rule: String,
    pub found: String,
}

impl Refusal {
    pub fn new(rule: impl Into<String>, found: impl Into<String>) -> Refusal {
        Refusal { rule: rule.into(), found: found.into() }
    }
}

/// Sectors 0-5 as the pieces of a .hex or an ELF fill them: each byte
/// placed at most once, nothing outside FLASH_BASE..APP_END.
pub struct Canvas {
    bytes: Vec<u8>,
    placed: Vec<bool>,
    lowest: u32,
    end: u32,
}

impl Canvas {
    pub fn new() -> Canvas {
        let n = IMAGE_MAX_BYTES as usize;
        Canvas { bytes: vec![0xFF; n], placed: vec![false; n], lowest: APP_END, end: FLASH_BASE }
    }

    /// `what` names the piece in a refusal ("line 12", "segment 2").
    pub fn place(&mut self, address: u32, data: &[u8], what: &str) -> Result<(), Refusal> {
        let end = u64::from(address) + data.len() as u64;
        if address < FLASH_BASE || address >= sector_start(SECTOR_KIB.len()) {
            let rule = format!("must lie in flash, 0x{FLASH_BASE:08x}..0x{APP_END:08x} (sectors 0-5)");
            return Err(Refusal::new(rule, format!("{what} at 0x{address:08x}")));
        }
        if end > u64::from(APP_END) {
            let rule = format!(
                "must fit in sectors 0-5, 0x{FLASH_BASE:08x}..0x{APP_END:08x}, 1..={IMAGE_MAX_BYTES} bytes (sectors 6-7 keep the saved settings and cam tables)"
            );
            return Err(Refusal::new(
                rule,
                format!("{what} reaches 0x{end:08x}, {} bytes", end - u64::from(FLASH_BASE)),
            ));
        }
        let at = (address - FLASH_BASE) as usize;
        if let Some(i) = self.placed[at..at + data.len()].iter().position(|&p| p) {
            let twice = address as usize + i;
            return Err(Refusal::new("must give each byte once", format!("{what} writes 0x{twice:08x} again")));
        }
        self.bytes[at..at + data.len()].copy_from_slice(data);
        self.placed[at..at + data.len()].iter_mut().for_each(|p| *p = true);
        if !data.is_empty() {
            self.lowest = self.lowest.min(address);
            self.end = self.end.max(end as u32);
        }
        Ok(())
    }

    /// The first run of bytes no piece gave, below the last byte given:
    /// its address and length (filled 0xFF by `finish`).
    pub fn gap(&self) -> Option<(u32, usize)> {
        let span = &self.placed[..(self.end.max(FLASH_BASE) - FLASH_BASE) as usize];
        let from = span.iter().position(|&p| !p)?;
        let len = span[from..].iter().position(|&p| p).unwrap_or(span.len() - from);
        Some((FLASH_BASE + from as u32, len))
    }

    /// The image from FLASH_BASE to its last byte.
    pub fn finish(mut self) -> Result<(u32, Vec<u8>), Refusal> {
        if self.end == FLASH_BASE {
            return Err(Refusal::new(format!("must not be empty (1..={IMAGE_MAX_BYTES} bytes)"), "no data"));
        }
        if self.lowest != FLASH_BASE {
            let rule = format!("must start at 0x{FLASH_BASE:08x}, with the vector table (sector 0)");
            return Err(Refusal::new(rule, format!("starts at 0x{:08x}", self.lowest)));
        }
        self.bytes.truncate((self.end - FLASH_BASE) as usize);
        Ok((FLASH_BASE, self.bytes))
    }
}

impl Default for Canvas {
    fn default() -> Canvas {
        Canvas::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flash_sectors_end_where_the_settings_start() {
        // that they agree with the chip model: tests/flash_erase.rs
        assert_eq!(sector_start(APP_SECTORS), APP_END);
        assert_eq!(sector_start(6), 0x0804_0000);
        assert_eq!(sector_start(8), 0x0808_0000);
        assert_eq!((last_sector(1), last_sector(0x4000), last_sector(0x4001)), (0, 0, 1));
        assert_eq!((last_sector(0x2_0000), last_sector(0x4_0000)), (4, 5));
    }
}
