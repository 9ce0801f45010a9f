//! Restarting into the ROM's USB DFU bootloader, so a machinist
//! flashes a new image with a USB cable and no probe (`polyturn flash`).
//!
//! The console's `dfu` leaves a word in RAM that the startup code does not
//! clear (cortex-m-rt's `.uninit` section) and resets the MCU. At the next
//! boot, before anything else, `wanted` decides from that word and the
//! reset cause whether to jump to the bootloader in system memory (the
//! MCU side is `app/dfu.rs`). Only silicon can show the jump itself: the
//! README's bench procedure says what to expect.

/// The system memory holding ST's bootloader: RM0383 §2.3 (memory map,
/// "System memory" 0x1FFF 0000 - 0x1FFF 77FF) and AN2606 (the STM32F411xx
/// bootloader, USB DFU on PA11/PA12, VID 0x0483, PID 0xDF11).
pub const SYSTEM_MEMORY: u32 = 0x1FFF_0000;

/// The request: any other value in the word means "boot the application".
pub const MAGIC: u32 = 0xDF11_B007;

/// RCC_CSR.SFTRSTF, "software reset flag" (RM0383 §6.3.21, bit 28): set by
/// the reset `dfu` makes, cleared by writing RMVF (bit 24).
pub const CSR_SFTRSTF: u32 = 1 << 28;
pub const CSR_RMVF: u32 = 1 << 24;

/// SYSCFG_MEMRMP.MEM_MODE = 01: system flash mapped at 0x0000 0000
/// (RM0383 §7.2.1), as it is when BOOT0 selects the bootloader; and
/// RCC_APB2ENR.SYSCFGEN (§6.3.12, bit 14) to write it.
pub const MEMRMP_SYSTEM_FLASH: u32 = 0b01;
pub const APB2ENR_SYSCFGEN: u32 = 1 << 14;

/// Every reset flag of RCC_CSR (§6.3.21, bits 25 to 31: BOR, pin, POR,
/// software, IWDG, WWDG, low-power). Every reset sets one (an STM32 drives
/// NRST low on any reset, so at least PINRSTF); `boot_check` clears them.
pub const CSR_RESET_FLAGS: u32 = 0xFE00_0000;

/// Whether this boot goes to the bootloader: the request word is set and
/// the reset was the software reset that `dfu` made (a power-on leaves
/// RAM random; it may hold the word by chance, but never with SFTRSTF).
pub fn wanted(word: u32, rcc_csr: u32) -> bool {
    word == MAGIC && rcc_csr & CSR_SFTRSTF != 0
}

/// How this start came about, and what to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Entry {
    /// `dfu` asked: to the ROM bootloader
    Bootloader,
    /// no reset flag: a jump, the ROM's DFU "leave" after `polyturn flash`
    /// (AN2662 §Leave DFU: it "jumps to the destination given by the
    /// Address Pointer", with its own USB interrupt and SysTick possibly
    /// still live): reset first, so the application starts from a reset
    ResetFirst,
    Application,
}

pub fn entry(word: u32, rcc_csr: u32) -> Entry {
    if rcc_csr & CSR_RESET_FLAGS == 0 {
        Entry::ResetFirst
    } else if wanted(word, rcc_csr) {
        Entry::Bootloader
    } else {
        Entry::Application
    }
}

/// The words at the start of the bootloader's vector table: (initial stack
/// pointer, reset handler). Checked before the jump: an erased or
/// unreadable system memory (it never is on a real F411) is not jumped to.
pub fn plausible_vectors(sp: u32, reset: u32) -> bool {
    let in_ram = (0x2000_0000..=0x2002_0000).contains(&sp);
    let in_system = (SYSTEM_MEMORY..SYSTEM_MEMORY + 0x7800).contains(&(reset & !1));
    in_ram && in_system && reset & 1 == 1
}

/// The marker a release image carries, so `polyturn flash` refuses an image
/// for another chip or a file that is not polyturn's.
pub const IMAGE_ID: &str = concat!("polyturn-image:stm32f411ce:", env!("CARGO_PKG_VERSION"), "\0");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_software_reset_with_the_word_set_goes_to_the_bootloader() {
        assert!(wanted(MAGIC, CSR_SFTRSTF | (1 << 26)));
        // power-on (PORRSTF) or pin reset with the same word by chance
        assert!(!wanted(MAGIC, 1 << 27));
        assert!(!wanted(MAGIC, 1 << 26));
        // a software reset without the request
        assert!(!wanted(0, CSR_SFTRSTF));
        assert!(!wanted(!MAGIC, CSR_SFTRSTF));
    }

    #[test]
    fn a_start_with_no_reset_flag_is_a_jump_and_resets_first() {
        const PIN: u32 = 1 << 26;
        assert_eq!(entry(0, 0), Entry::ResetFirst, "the ROM's leave after a flash");
        assert_eq!(entry(MAGIC, 0), Entry::ResetFirst);
        assert_eq!(entry(MAGIC, CSR_SFTRSTF | PIN), Entry::Bootloader);
        assert_eq!(entry(0, CSR_SFTRSTF | PIN), Entry::Application);
        assert_eq!(entry(MAGIC, PIN), Entry::Application, "NRST pressed");
        assert_eq!(entry(MAGIC, 1 << 29), Entry::Application, "the watchdog");
    }

    #[test]
    fn the_bootloaders_vectors_are_checked_before_the_jump() {
        // the F411's ROM: its stack in SRAM, its reset handler in system memory
        assert!(plausible_vectors(0x2000_1000, 0x1FFF_0A55));
        assert!(!plausible_vectors(0xFFFF_FFFF, 0xFFFF_FFFF), "erased");
        assert!(!plausible_vectors(0x2000_1000, 0x0800_0201), "the application's");
        assert!(!plausible_vectors(0x2000_1000, 0x1FFF_0A54), "not Thumb");
    }

    #[test]
    fn the_image_marker_names_the_chip_and_version() {
        assert!(IMAGE_ID.starts_with("polyturn-image:stm32f411ce:0."));
        assert!(IMAGE_ID.ends_with('\0'));
    }
}
