//! Settings as bytes for flash: magic, version, fields little-endian,
//! CRC-32. Anything that is not exactly a valid, current record decodes to
//! an error (never a panic), and the caller falls back to the defaults.
//! Decoding is one-to-one: a record decodes only if `encode` would write
//! exactly its bytes for what it decodes to (so a record is never silently
//! "repaired", e.g. an unreduced ratio 4/2 read as 2/1).

use crate::config::{Config, DriveKind, Sense};
use crate::ratio::{gcd, Ratio};

pub const MAGIC: [u8; 2] = *b"PT";
pub const VERSION: u8 = 1;
/// Encoded length: magic 2, version 1, body 42, crc 4.
pub const LEN: usize = 49;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DecodeError {
    Length,
    Magic,
    /// a record from another firmware version
    Version(u8),
    Checksum,
    /// intact but out of range (written by a buggy or foreign tool)
    Invalid(&'static str),
    /// intact and in range, but not the bytes `encode` writes for the
    /// settings it holds (an unreduced ratio such as 4/2): refused, so what
    /// decodes re-encodes to the same bytes
    NonCanonical(&'static str),
}

/// CRC-32 (IEEE, reflected), bitwise: small and only used off the tick.
pub fn crc32(data: &[u8]) -> u32 {
    !crc32_update(!0, data)
}

/// The CRC-32 register after `data` (start from !0, finish with !).
pub fn crc32_update(mut crc: u32, data: &[u8]) -> u32 {
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    crc
}

pub fn encode(c: &Config) -> [u8; LEN] {
    let mut out = [0u8; LEN];
    out[..2].copy_from_slice(&MAGIC);
    out[2] = VERSION;
    let mut w = Writer { buf: &mut out, at: 3 };
    w.u32(c.encoder_counts_per_rev);
    w.u32(c.motor_steps_per_rev);
    w.u16(c.ratio.num() as u16);
    w.u16(c.ratio.den() as u16);
    w.u8(matches!(c.sense, Sense::Opposite) as u8);
    w.u8(c.edges);
    w.u32(c.max_step_rate_hz);
    w.u32(c.max_accel_steps_per_s2);
    w.u32(c.following_error_limit_steps);
    w.u32(c.phase_offset_mdeg as u32);
    w.u8(match c.drive {
        DriveKind::Stepper => 0,
        DriveKind::Bldc => 1,
        DriveKind::None => 2,
    });
    w.u8(c.enable_active_high as u8);
    w.u32(c.dir_setup_ns);
    w.u32(c.step_pulse_ns);
    w.u16(c.max_lathe_rpm.min(u16::MAX as u32) as u16);
    debug_assert_eq!(w.at, LEN - 4, "LEN must match the fields");
    let crc = crc32(&out[..LEN - 4]);
    out[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
    out
}

pub fn decode(bytes: &[u8]) -> Result<Config, DecodeError> {
    if bytes.len() != LEN {
        return Err(DecodeError::Length);
    }
    if bytes[..2] != MAGIC {
        return Err(DecodeError::Magic);
    }
    if bytes[2] != VERSION {
        return Err(DecodeError::Version(bytes[2]));
    }
    let stored = u32::from_le_bytes([bytes[LEN - 4], bytes[LEN - 3], bytes[LEN - 2], bytes[LEN - 1]]);
    if crc32(&bytes[..LEN - 4]) != stored {
        return Err(DecodeError::Checksum);
    }
    let mut r = Reader { buf: bytes, at: 3 };
    let (cpr, steps, p, q) = (r.u32(), r.u32(), r.u16(), r.u16());
    let ratio = Ratio::new(p as u64, q as u64).map_err(|_| DecodeError::Invalid("ratio"))?;
    // `Ratio::new` reduces: 4/2 would come back as 2/1, other bytes
    if gcd(p as u64, q as u64) != 1 {
        return Err(DecodeError::NonCanonical("ratio"));
    }
    let c = Config {
        encoder_counts_per_rev: cpr,
        motor_steps_per_rev: steps,
        ratio,
        sense: if r.flag("dir")? { Sense::Opposite } else { Sense::Same },
        edges: r.u8(),
        max_step_rate_hz: r.u32(),
        max_accel_steps_per_s2: r.u32(),
        following_error_limit_steps: r.u32(),
        phase_offset_mdeg: r.u32() as i32,
        // 2 (none) came after version 1's 0/1: older records still decode
        drive: match r.u8() {
            0 => DriveKind::Stepper,
            1 => DriveKind::Bldc,
            2 => DriveKind::None,
            _ => return Err(DecodeError::Invalid("drive")),
        },
        enable_active_high: r.flag("enable")?,
        dir_setup_ns: r.u32(),
        step_pulse_ns: r.u32(),
        max_lathe_rpm: r.u16() as u32,
        // later settings are in their own block (`ext`), defaults here
        ..Config::default()
    };
    c.validate().map_err(|e| DecodeError::Invalid(e.field))?;
    // Every field above is checked to be in its encoded form; this keeps the
    // promise for any field added later without such a check.
    if encode(&c) != *bytes {
        return Err(DecodeError::NonCanonical("record"));
    }
    Ok(c)
}

struct Writer<'a> {
    buf: &'a mut [u8; LEN],
    at: usize,
}
impl Writer<'_> {
    fn put(&mut self, b: &[u8]) {
        self.buf[self.at..self.at + b.len()].copy_from_slice(b);
        self.at += b.len();
    }
    fn u8(&mut self, v: u8) {
        self.put(&[v]);
    }
    fn u16(&mut self, v: u16) {
        self.put(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.put(&v.to_le_bytes());
    }
}

struct Reader<'a> {
    buf: &'a [u8],
    at: usize,
}
impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        out.copy_from_slice(&self.buf[self.at..self.at + N]);
        self.at += N;
        out
    }
    fn u8(&mut self) -> u8 {
        self.take::<1>()[0]
    }
    /// A 0/1 byte; anything else is refused, so decoding is one-to-one.
    fn flag(&mut self, field: &'static str) -> Result<bool, DecodeError> {
        match self.u8() {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(DecodeError::Invalid(field)),
        }
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.take())
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take())
    }
}

pub mod ext;
#[cfg(test)]
mod layout_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn round_trips_and_detects_every_single_bit_flip() {
        let c = Config::default()
            .with("max-rpm", "600")
            .unwrap()
            .with("ratio", "11/3")
            .unwrap()
            .with("phase", "-7.25")
            .unwrap();
        let bytes = encode(&c);
        assert_eq!(decode(&bytes), Ok(c));
        let none = c.with("drive", "none").unwrap();
        assert_eq!(decode(&encode(&none)), Ok(none));
        for bit in 0..LEN * 8 {
            let mut b = bytes;
            b[bit / 8] ^= 1 << (bit % 8);
            assert!(decode(&b).is_err(), "bit {bit}");
        }
    }

    /// `bytes` with its CRC made valid again: what a buggy or foreign
    /// tool would write.
    fn sealed(mut bytes: [u8; LEN]) -> [u8; LEN] {
        let crc = crc32(&bytes[..LEN - 4]);
        bytes[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
        bytes
    }

    /// The record of `Config::default()` (ratio 2/1) with the ratio's
    /// terms replaced by `p`/`q` as written, CRC valid.
    fn with_ratio_terms(p: u16, q: u16) -> [u8; LEN] {
        let mut b = encode(&Config::default());
        b[11..13].copy_from_slice(&p.to_le_bytes());
        b[13..15].copy_from_slice(&q.to_le_bytes());
        sealed(b)
    }

    #[test]
    fn an_unreduced_ratio_with_a_valid_crc_is_refused() {
        // the layout: the default's ratio 2/1 sits at bytes 11..15
        assert_eq!(with_ratio_terms(2, 1), encode(&Config::default()));
        assert_eq!(decode(&with_ratio_terms(2, 1)), Ok(Config::default()));
        // 4/2, 2/2 and 2000/2 (1000/1 after reduction: in range) would
        // decode to 2/1, 1/1 and 1000/1 and re-encode to other bytes
        for (p, q) in [(4, 2), (2, 2), (6, 4), (2000, 2), (1000, 1000)] {
            assert_eq!(decode(&with_ratio_terms(p, q)), Err(DecodeError::NonCanonical("ratio")), "{p}/{q}");
        }
        // reduced ones still decode (a valid 3/2, and 1/1)
        for (p, q) in [(3, 2), (1, 1), (1, 3)] {
            let c = decode(&with_ratio_terms(p, q)).unwrap();
            assert_eq!((c.ratio.num(), c.ratio.den()), (p as u32, q as u32));
        }
        // out of range stays Invalid (not merely non-canonical)
        assert_eq!(decode(&with_ratio_terms(0, 1)), Err(DecodeError::Invalid("ratio")));
        assert_eq!(decode(&with_ratio_terms(1001, 1)), Err(DecodeError::Invalid("ratio")));
    }

    #[test]
    fn crc_matches_the_standard_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    proptest! {
        #[test]
        fn any_bytes_decode_without_panicking(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
            let _ = decode(&bytes);
        }

        /// A record with a valid checksum but a flag byte other than 0/1
        /// (the drive: 0..=2) is refused: what decodes re-encodes to the
        /// same bytes.
        #[test]
        fn decoding_is_one_to_one(flag_at in prop::sample::select(std::vec![15usize, 33, 34]), v in 2u8..=255) {
            let mut b = encode(&Config::default());
            let v = if flag_at == 33 { v.max(3) } else { v };
            b[flag_at] = v;
            let crc = crc32(&b[..LEN - 4]);
            b[LEN - 4..].copy_from_slice(&crc.to_le_bytes());
            prop_assert!(matches!(decode(&b), Err(DecodeError::Invalid(_))));
        }

        /// Whatever decodes re-encodes to exactly the same bytes, for
        /// records with a valid CRC, any ratio terms as written (reduced or
        /// not) and a few bytes of the body overwritten anywhere.
        #[test]
        fn whatever_decodes_re_encodes_to_the_same_bytes(
            p in 0u16..=40,
            q in 0u16..=40,
            pokes in proptest::collection::vec((3usize..LEN - 4, any::<u8>()), 0..4),
        ) {
            let mut b = with_ratio_terms(p, q);
            for (at, v) in pokes {
                b[at] = v;
            }
            let b = sealed(b);
            if let Ok(c) = decode(&b) {
                prop_assert_eq!(encode(&c), b);
            }
        }

        /// Every valid config survives the trip through its record.
        #[test]
        fn every_valid_config_round_trips(
            p in 1u64..=1000,
            q in 1u64..=1000,
            edges in 1u8..=12,
            phase in -360_000i32..=360_000,
            drive in 0u8..3,
            flags in 0u8..4,
            rpm in 1u32..=10_000,
        ) {
            let c = Config {
                ratio: Ratio::new(p, q).unwrap_or(Ratio::TWO),
                edges,
                phase_offset_mdeg: phase,
                drive: [DriveKind::Stepper, DriveKind::Bldc, DriveKind::None][drive as usize],
                sense: if flags & 1 == 0 { Sense::Same } else { Sense::Opposite },
                enable_active_high: flags & 2 != 0,
                max_lathe_rpm: rpm,
                max_step_rate_hz: 250_000,
                step_pulse_ns: 100,
                motor_steps_per_rev: 1,
                ..Config::default()
            };
            if c.validate().is_ok() {
                prop_assert_eq!(decode(&encode(&c)), Ok(c));
            }
        }
    }
}
