//! The settings added after the first record layout (`codec::VERSION` 1),
//! in a block of their own: magic `PX`, version, a reserved 0, the fields
//! little-endian, CRC-32. The store writes it beside the first record,
//! before the commit marker; a slot saved by a firmware without it holds
//! erased flash there (all 0xFF), which loads as the new fields' defaults.
//! As for the first record, decoding is one-to-one: a block decodes only
//! if `encode` writes exactly its bytes, or, saved by the previous
//! firmware, the version-1 block (no `start-rate`) followed by erased flash.

use super::{crc32, DecodeError};
use crate::config::Config;

pub const MAGIC: [u8; 2] = *b"PX";
/// 2: `start-rate` added (version 1 held cutter-cpr and lost-steps).
pub const VERSION: u8 = 2;
/// magic 2, version 1, reserved 1, cutter-cpr 4, lost-steps 4, start-rate
/// 4, crc 4: a multiple of the flash's 4-byte writes.
pub const LEN: usize = 20;
/// Version 1's length: its CRC where start-rate now is, erased flash after.
const LEN_V1: usize = 16;

pub fn encode(c: &Config) -> [u8; LEN] {
    let mut out = [0u8; LEN];
    out[..2].copy_from_slice(&MAGIC);
    out[2] = VERSION;
    out[4..8].copy_from_slice(&c.cutter_encoder_cpr.to_le_bytes());
    out[8..12].copy_from_slice(&c.lost_step_limit_steps.to_le_bytes());
    out[12..16].copy_from_slice(&c.start_rate_hz.to_le_bytes());
    let crc = crc32(&out[..LEN - 4]);
    out[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
    out
}

/// `base` (from the first record) with the block's fields: erased flash
/// (every byte 0xFF) gives the defaults of the new fields.
pub fn decode(base: Config, bytes: &[u8]) -> Result<Config, DecodeError> {
    if bytes.len() != LEN {
        return Err(DecodeError::Length);
    }
    let defaults = Config::default();
    if bytes.iter().all(|&b| b == 0xFF) {
        return Ok(Config {
            cutter_encoder_cpr: defaults.cutter_encoder_cpr,
            lost_step_limit_steps: defaults.lost_step_limit_steps,
            start_rate_hz: defaults.start_rate_hz,
            ..base
        });
    }
    if bytes[..2] != MAGIC {
        return Err(DecodeError::Magic);
    }
    let word = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    let (len, start_rate_hz) = match bytes[2] {
        VERSION => (LEN, word(12)),
        // (erased flash after it: `encode_version` checks that too)
        1 => (LEN_V1, defaults.start_rate_hz),
        v => return Err(DecodeError::Version(v)),
    };
    if crc32(&bytes[..len - 4]) != word(len - 4) {
        return Err(DecodeError::Checksum);
    }
    let c = Config { cutter_encoder_cpr: word(4), lost_step_limit_steps: word(8), start_rate_hz, ..base };
    c.validate().map_err(|e| DecodeError::Invalid(e.field))?;
    if encode_version(&c, bytes[2]) != *bytes {
        return Err(DecodeError::NonCanonical("extension"));
    }
    Ok(c)
}

/// The block `c` would have been saved as in `version` (1: the previous
/// firmware's, erased flash after it).
fn encode_version(c: &Config, version: u8) -> [u8; LEN] {
    if version == VERSION {
        return encode(c);
    }
    let mut out = [0xFFu8; LEN];
    out[..LEN_V1 - 4].copy_from_slice(&encode(c)[..LEN_V1 - 4]);
    out[2] = version;
    let crc = crc32(&out[..LEN_V1 - 4]);
    out[12..LEN_V1].copy_from_slice(&crc.to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_encoder() -> Config {
        Config::default().with("cutter-cpr", "4000").unwrap().with("lost-steps", "48").unwrap()
    }

    #[test]
    fn the_start_rate_round_trips() {
        let c = with_encoder().with("start-rate", "1600").unwrap();
        assert_eq!(decode(Config::default(), &encode(&c)), Ok(c));
        assert_eq!(&encode(&c)[12..16], &1600u32.to_le_bytes());
    }

    #[test]
    fn round_trips_and_detects_every_single_bit_flip() {
        let c = with_encoder();
        let bytes = encode(&c);
        assert_eq!(decode(Config::default(), &bytes), Ok(c));
        for bit in 0..LEN * 8 {
            let mut b = bytes;
            b[bit / 8] ^= 1 << (bit % 8);
            assert!(decode(Config::default(), &b).is_err(), "bit {bit} flipped still decodes");
        }
    }

    #[test]
    fn erased_flash_is_a_record_from_before_the_block_with_the_defaults() {
        // (a base holding other values for them: the block's absence means
        // the defaults, whatever the base)
        let base = with_encoder().with("ratio", "5/2").unwrap().with("start-rate", "1600").unwrap();
        let c = decode(base, &[0xFF; LEN]).unwrap();
        assert_eq!(c, Config { cutter_encoder_cpr: 0, lost_step_limit_steps: 32, start_rate_hz: 0, ..base });
    }

    /// A block saved by the previous firmware (version 1: no start-rate,
    /// erased flash after its CRC) loads with start-rate's default; one
    /// with anything but erased flash there is refused, and so is a flip.
    #[test]
    fn a_version_1_block_loads_with_the_start_rates_default() {
        let base = Config::default().with("start-rate", "1600").unwrap();
        let mut v1 = [0xFFu8; LEN];
        v1[..4].copy_from_slice(&[b'P', b'X', 1, 0]);
        v1[4..8].copy_from_slice(&4000u32.to_le_bytes());
        v1[8..12].copy_from_slice(&48u32.to_le_bytes());
        let crc = crc32(&v1[..12]);
        v1[12..16].copy_from_slice(&crc.to_le_bytes());
        let c = decode(base, &v1).unwrap();
        assert_eq!(c, Config { start_rate_hz: 0, ..with_encoder() });
        let mut tail = v1;
        tail[17] = 0;
        assert!(decode(base, &tail).is_err());
        for bit in 0..16 * 8 {
            let mut b = v1;
            b[bit / 8] ^= 1 << (bit % 8);
            assert!(decode(base, &b).is_err(), "bit {bit} flipped still decodes");
        }
    }

    #[test]
    fn an_out_of_range_or_non_canonical_block_is_refused() {
        let mut b = encode(&with_encoder());
        b[4..8].copy_from_slice(&2u32.to_le_bytes()); // cutter-cpr 2: below 4
        let crc = crc32(&b[..LEN - 4]);
        b[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(decode(Config::default(), &b), Err(DecodeError::Invalid("cutter-cpr")));
        let mut b = encode(&with_encoder());
        b[3] = 1; // the reserved byte
        let crc = crc32(&b[..LEN - 4]);
        b[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(decode(Config::default(), &b), Err(DecodeError::NonCanonical("extension")));
    }
}
