//! The seal at the end of a release image (`polyturn_firmware::seal`, which
//! the firmware checks at boot): the bytes from 0x08000000 padded with
//! 0xFF to a whole word, then "PTIM", the length sealed and the CRC of the
//! sealed words as the F411's CRC unit computes it (RM0383 §4;
//! `polyturn_firmware::seal::crc_of_words`, checked against the model of
//! the unit in the tests). An image cut short,
//! grown, or with any byte changed no longer ends in a seal that fits it.

use super::Refusal;
use polyturn_firmware::seal::{crc_of_words, MAGIC, SEAL_BYTES};

const SEAL: usize = SEAL_BYTES as usize;

/// The rule a refusal names.
pub const RULE: &str =
    "must end with the seal `polyturn image` writes (its length and CRC-32), as the board checks it at boot";

/// What a whole image's seal says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Seal {
    /// the bytes sealed, from the image's start to the seal
    pub length: u32,
    pub crc32: u32,
}

/// The CRC unit's result over `words` (whole little-endian words, as the
/// CPU reads them from flash and writes them to CRC_DR).
pub fn crc_of(words: &[u8]) -> u32 {
    crc_of_words(words.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])))
}

/// Pads `bytes` to a whole word with erased flash (0xFF) and appends the
/// seal.
pub fn seal(bytes: &mut Vec<u8>) {
    bytes.resize(bytes.len().next_multiple_of(4), 0xFF);
    let (length, crc32) = (bytes.len() as u32, crc_of(bytes));
    for w in [MAGIC, length, crc32] {
        bytes.extend_from_slice(&w.to_le_bytes());
    }
}

/// Whether the image's last 12 bytes are a seal that fits it.
pub fn check(bytes: &[u8]) -> Result<Seal, Refusal> {
    let word = |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let Some(at) = bytes.len().checked_sub(SEAL).filter(|&at| word_at_is(bytes, at, MAGIC)) else {
        return Err(Refusal::new(RULE, no_seal(bytes)));
    };
    let (length, crc32) = (word(at + 4), word(at + 8));
    if length as usize != at || at % 4 != 0 {
        return Err(Refusal::new(RULE, format!("its seal is for {length} bytes, it has {at} before the seal")));
    }
    let computed = crc_of(&bytes[..at]);
    if computed != crc32 {
        return Err(Refusal::new(
            RULE,
            format!("CRC-32 0x{computed:08x} over its {at} bytes, its seal says 0x{crc32:08x}: a byte changed"),
        ));
    }
    Ok(Seal { length, crc32 })
}

/// Whether the image ends in a seal whose length fits it (its CRC
/// unchecked): an image `polyturn image` made, whole or altered.
pub fn ends_sealed(bytes: &[u8]) -> bool {
    bytes.len().checked_sub(SEAL).is_some_and(|at| word_at_is(bytes, at, MAGIC) && word_at_is(bytes, at + 4, at as u32))
}

fn word_at_is(bytes: &[u8], at: usize, want: u32) -> bool {
    bytes.get(at..at + 4).is_some_and(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) == want)
}

/// What an image without a seal at its end has: bytes after a seal that
/// fits the bytes before it (grown), or no seal at all (cut short, or not
/// made by `polyturn image`).
fn no_seal(bytes: &[u8]) -> String {
    let sealed_at = (0..bytes.len().saturating_sub(SEAL - 1))
        .step_by(4)
        .find(|&at| word_at_is(bytes, at, MAGIC) && word_at_is(bytes, at + 4, at as u32) && bytes.len() >= at + SEAL);
    match sealed_at {
        Some(at) => match bytes.len() - at - SEAL {
            1 => "1 byte after its seal (grown)".to_string(),
            n => format!("{n} bytes after its seal (grown)"),
        },
        None => format!("no seal at its end, {} bytes (cut short, or not made by `polyturn image`)", bytes.len()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sealed_image_checks_and_each_damage_is_named() {
        let mut b: Vec<u8> = (0..1001u32).map(|i| i as u8).collect();
        seal(&mut b);
        assert_eq!(b.len(), 1004 + 12, "padded to a word, then 12 bytes");
        assert_eq!(&b[1001..1004], &[0xFF; 3]);
        let s = check(&b).unwrap();
        assert_eq!((s.length, s.crc32), (1004, crc_of(&b[..1004])));
        let mut grown = b.clone();
        grown.extend_from_slice(&[0; 5]);
        assert_eq!(check(&grown).unwrap_err().found, "5 bytes after its seal (grown)");
        let cut = &b[..900];
        assert_eq!(
            check(cut).unwrap_err().found,
            "no seal at its end, 900 bytes (cut short, or not made by `polyturn image`)"
        );
        let mut changed = b.clone();
        changed[7] ^= 1;
        assert!(check(&changed).unwrap_err().found.ends_with("a byte changed"), "{:?}", check(&changed));
        let mut moved = b.clone();
        moved[1004 + 4] = 0;
        assert_eq!(check(&moved).unwrap_err().found, "its seal is for 768 bytes, it has 1004 before the seal");
        assert!(check(&[]).is_err() && check(&b[1004..]).is_err());
    }

    #[test]
    fn the_seal_is_the_crc_units_over_little_endian_words() {
        // the word 0x12345678 as the flash holds it
        assert_eq!(crc_of(&[0x78, 0x56, 0x34, 0x12]), 0xDF8A_8A2B);
    }
}
