//! The CRC calculation unit (RM0383 §4), which the firmware's boot check of
//! its own image uses (`polyturn_firmware::seal`) and whose result
//! `polyturn image` writes into the image's seal. At 0x4002_3000 (§2.3
//! Table 1, AHB1), clocked by RCC_AHB1ENR.CRCEN (§6.3.9, bit 12; the model,
//! like the emulator's others, does not check the enable).
//!
//! * §4.2: the CRC-32 (Ethernet) polynomial 0x04C11DB7, fixed; one 32-bit
//!   data register; a general-purpose 8-bit register (IDR).
//! * §4.3: a write to DR combines the previous CRC with the new word, "done
//!   on the whole 32-bit data word, and not byte per byte"; a read of DR
//!   gives the result so far. CR.RESET sets DR to 0xFFFF_FFFF and leaves
//!   IDR alone.
//! * §4.4: DR resets to 0xFFFF_FFFF, IDR and CR to 0; CR.RESET reads 0 (it
//!   is cleared by hardware).
//!
//! The manual draws no shift register, so the bit order is a reading: the
//! word's bit 31 enters first, with no reflection and no final XOR, which
//! is the CRC-32/MPEG-2 of the word's bytes taken most significant first
//! (ST's community reports the F401's unit matching CRC-32/MPEG-2). The
//! test vector below (0x12345678 → 0xDF8A8A2B) is that reading's.

/// Register offsets (§4.4.4 register map).
pub use polyturn_regs::addr::crc_off::{CR, DR, IDR};
/// CR bit 0 (§4.4.3).
pub const CR_RESET: u32 = polyturn_regs::bits::crc_cr::RESET.mask();
/// §4.2.
pub const POLY: u32 = 0x04C1_1DB7;
/// DR after reset or CR.RESET (§4.3, §4.4.1).
pub const INIT: u32 = 0xFFFF_FFFF;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Crc {
    dr: u32,
    idr: u8,
}

impl Default for Crc {
    fn default() -> Crc {
        Crc { dr: INIT, idr: 0 }
    }
}

/// The unit's combination of the CRC so far with one data word (§4.3).
pub fn step(crc: u32, word: u32) -> u32 {
    let mut c = crc ^ word;
    for _ in 0..32 {
        c = if c & 0x8000_0000 != 0 { (c << 1) ^ POLY } else { c << 1 };
    }
    c
}

/// What DR reads after CR.RESET and one write of each word in turn.
pub fn of_words(words: impl IntoIterator<Item = u32>) -> u32 {
    words.into_iter().fold(INIT, step)
}

impl Crc {
    pub fn read(&self, off: u32) -> u32 {
        match off {
            DR => self.dr,
            IDR => self.idr as u32,
            _ => 0,
        }
    }

    /// A write of the bits in `mask` (a byte or halfword access writes only
    /// its lanes). DR takes whole words only: the manual gives no meaning to
    /// a narrower write (§4.3 computes on "the whole 32-bit data word").
    pub fn write(&mut self, off: u32, value: u32, mask: u32) {
        let v = value & mask;
        match off {
            DR if mask == u32::MAX => self.dr = step(self.dr, v),
            DR => crate::unmodelled(&format!("a {}-lane write to CRC_DR", mask.count_ones() / 8)),
            IDR => self.idr = (self.idr as u32 & !mask | v) as u8,
            CR => {
                crate::only_bits("CRC", 0x4002_3000, CR, "CR", v, CR_RESET);
                if v & CR_RESET != 0 {
                    self.dr = INIT;
                }
            }
            _ => crate::unmodelled(&format!("CRC register at offset {off:#x}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_word_after_reset_gives_the_mpeg2_crc_of_its_bytes_4_3() {
        let mut c = Crc::default();
        assert_eq!(c.read(DR), 0xFFFF_FFFF, "§4.4.1 reset value");
        c.write(DR, 0x1234_5678, u32::MAX);
        assert_eq!(c.read(DR), 0xDF8A_8A2B);
        // CRC-32/MPEG-2 of "12345678" as two big-endian words and of bytes
        // taken one at a time, most significant bit first, agree
        let bytes = b"12345678";
        let by_byte = bytes.iter().fold(INIT, |mut crc, &b| {
            crc ^= (b as u32) << 24;
            for _ in 0..8 {
                crc = if crc & 0x8000_0000 != 0 { (crc << 1) ^ POLY } else { crc << 1 };
            }
            crc
        });
        let words = bytes.chunks(4).map(|w| u32::from_be_bytes([w[0], w[1], w[2], w[3]]));
        assert_eq!(of_words(words), by_byte);
    }

    #[test]
    fn reset_restarts_the_crc_and_keeps_idr_4_3() {
        let mut c = Crc::default();
        c.write(IDR, 0xA5, 0xFF);
        c.write(DR, 7, u32::MAX);
        assert_ne!(c.read(DR), INIT);
        c.write(CR, CR_RESET, u32::MAX);
        assert_eq!((c.read(DR), c.read(IDR), c.read(CR)), (INIT, 0xA5, 0));
        c.write(DR, 0x1234_5678, u32::MAX);
        assert_eq!(c.read(DR), 0xDF8A_8A2B, "the same word, the same CRC");
    }

    #[test]
    fn each_write_folds_into_the_crc_so_far() {
        let mut c = Crc::default();
        for w in [1u32, 2, 3] {
            c.write(DR, w, u32::MAX);
        }
        assert_eq!(c.read(DR), step(step(step(INIT, 1), 2), 3));
        assert_eq!(c.read(DR), of_words([1, 2, 3]));
        assert_ne!(of_words([1, 2, 3]), of_words([1, 3, 2]), "order matters");
    }

    #[test]
    #[should_panic(expected = "not modelled")]
    fn a_byte_write_to_dr_is_not_modelled() {
        Crc::default().write(DR, 0x12, 0xFF);
    }
}
