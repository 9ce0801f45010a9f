//! The settings added after the first record layout (`codec::VERSION` 1),
//! in a block of their own: magic `PX`, version, a reserved 0, the fields
//! little-endian, CRC-32. The store writes it beside the first record,
//! before the commit marker; a slot saved by a firmware without it holds
//! erased flash there (all 0xFF), which loads as the new fields' defaults.
//! As for the first record, decoding is one-to-one: a block decodes only
//! if `encode` writes exactly its bytes, or, saved by an earlier firmware,
//! an earlier version's block (a prefix of this one's fields and its CRC)
//! followed by erased flash.

use super::{crc32, DecodeError};
use crate::config::{BldcOut, Config};

pub const MAGIC: [u8; 2] = *b"PX";
/// 3: the BLDC drive's `bldc-out`, `pwm-hz`, `bldc-tau` added (2 added
/// `start-rate`; 1 held cutter-cpr and lost-steps).
pub const VERSION: u8 = 3;
/// magic 2, version 1, reserved 1, cutter-cpr 4, lost-steps 4, start-rate
/// 4, pwm-hz 4, bldc-tau 2, bldc-out 1, reserved 1, crc 4: a multiple of
/// the flash's 4-byte writes.
pub const LEN: usize = 28;

/// Each version's length: a version's fields are a prefix of the next's,
/// its CRC where the next's fields go, erased flash after.
const fn len_of(version: u8) -> Option<usize> {
    match version {
        1 => Some(16),
        2 => Some(20),
        VERSION => Some(LEN),
        _ => None,
    }
}

pub fn encode(c: &Config) -> [u8; LEN] {
    let mut out = [0u8; LEN];
    out[..2].copy_from_slice(&MAGIC);
    out[2] = VERSION;
    out[4..8].copy_from_slice(&c.cutter_encoder_cpr.to_le_bytes());
    out[8..12].copy_from_slice(&c.lost_step_limit_steps.to_le_bytes());
    out[12..16].copy_from_slice(&c.start_rate_hz.to_le_bytes());
    out[16..20].copy_from_slice(&c.pwm_hz.to_le_bytes());
    out[20..22].copy_from_slice(&(c.bldc_tau_ms.min(u16::MAX as u32) as u16).to_le_bytes());
    out[22] = c.bldc_out.code();
    let crc = crc32(&out[..LEN - 4]);
    out[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
    out
}

/// The fields this block adds to the first record, at their defaults.
fn with_defaults(base: Config) -> Config {
    let d = Config::default();
    Config {
        cutter_encoder_cpr: d.cutter_encoder_cpr,
        lost_step_limit_steps: d.lost_step_limit_steps,
        start_rate_hz: d.start_rate_hz,
        bldc_out: d.bldc_out,
        pwm_hz: d.pwm_hz,
        bldc_tau_ms: d.bldc_tau_ms,
        ..base
    }
}

/// `base` (from the first record) with the block's fields: erased flash
/// (every byte 0xFF) gives the defaults of the new fields, and a block of
/// an earlier version the defaults of the fields it did not have.
pub fn decode(base: Config, bytes: &[u8]) -> Result<Config, DecodeError> {
    if bytes.len() != LEN {
        return Err(DecodeError::Length);
    }
    let d = with_defaults(base);
    if bytes.iter().all(|&b| b == 0xFF) {
        return Ok(d);
    }
    if bytes[..2] != MAGIC {
        return Err(DecodeError::Magic);
    }
    let version = bytes[2];
    let len = len_of(version).ok_or(DecodeError::Version(version))?;
    let word = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    if crc32(&bytes[..len - 4]) != word(len - 4) {
        return Err(DecodeError::Checksum);
    }
    let mut c = Config { cutter_encoder_cpr: word(4), lost_step_limit_steps: word(8), ..d };
    if version >= 2 {
        c.start_rate_hz = word(12);
    }
    if version >= 3 {
        c.pwm_hz = word(16);
        c.bldc_tau_ms = u16::from_le_bytes([bytes[20], bytes[21]]) as u32;
        c.bldc_out = BldcOut::from_code(bytes[22]).ok_or(DecodeError::Invalid("bldc-out"))?;
    }
    c.validate().map_err(|e| DecodeError::Invalid(e.field))?;
    if encode_version(&c, version, len) != *bytes {
        return Err(DecodeError::NonCanonical("extension"));
    }
    Ok(c)
}

/// The block `c` would have been saved as in `version`, `len` bytes long
/// (an earlier version's: erased flash after it).
fn encode_version(c: &Config, version: u8, len: usize) -> [u8; LEN] {
    if version == VERSION {
        return encode(c);
    }
    let mut out = [0xFFu8; LEN];
    out[..len - 4].copy_from_slice(&encode(c)[..len - 4]);
    out[2] = version;
    let crc = crc32(&out[..len - 4]);
    out[len - 4..len].copy_from_slice(&crc.to_le_bytes());
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
        let bldc = base.with("bldc-out", "pwm").unwrap().with("pwm-hz", "5000").unwrap().with("bldc-tau", "4").unwrap();
        assert_eq!(decode(bldc, &[0xFF; LEN]).unwrap(), c, "the BLDC fields' defaults too");
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
        let mut b = encode(&with_encoder());
        b[22] = 4; // no such interface
        let crc = crc32(&b[..LEN - 4]);
        b[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(decode(Config::default(), &b), Err(DecodeError::Invalid("bldc-out")));
    }

    #[test]
    fn the_bldc_drives_settings_round_trip() {
        for out in BldcOut::ALL {
            let c = with_encoder().with("bldc-out", out.name()).unwrap().with("pwm-hz", "20000").unwrap();
            let c = c.with("bldc-tau", "1000").unwrap();
            assert_eq!(decode(Config::default(), &encode(&c)), Ok(c));
            assert_eq!(encode(&c)[22], out.code());
        }
        assert_eq!(&encode(&Config::default())[16..24], &[0xE8, 3, 0, 0, 20, 0, 0, 0]);
    }

    /// A block saved by the previous firmware (version 2: no BLDC fields,
    /// erased flash after its CRC) loads with their defaults.
    #[test]
    fn a_version_2_block_loads_with_the_bldc_defaults() {
        let c = with_encoder().with("start-rate", "1600").unwrap();
        let base = c.with("bldc-out", "pwm").unwrap().with("bldc-tau", "3").unwrap();
        let mut v2 = [0xFFu8; LEN];
        v2[..16].copy_from_slice(&encode(&c)[..16]);
        v2[2] = 2;
        let crc = crc32(&v2[..16]);
        v2[16..20].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(decode(base, &v2), Ok(c));
        let mut tail = v2;
        tail[25] = 0;
        assert!(decode(base, &tail).is_err(), "anything but erased flash after it");
    }
}
