//! The record byte for byte: the layout `LEN`'s comment gives (magic,
//! version, the fields little-endian in `encode`'s order, CRC-32/ISO-HDLC
//! of the 45 bytes before it). The expected records were written out by
//! hand from that layout and their CRCs computed with Python's
//! `zlib.crc32` (the same CRC), not taken from this code.

use super::*;

/// The default settings' record.
const DEFAULT: [u8; LEN] = [
    b'P', b'T', 1, // magic, version
    0x60, 0x09, 0, 0, // cpr 2400
    0x80, 0x0C, 0, 0, // steps 3200
    2, 0, 1, 0, // ratio 2/1
    0, // dir same
    3, // edges
    0x40, 0x0D, 0x03, 0, // max-rate 200 000
    0x80, 0x1A, 0x06, 0, // max-accel 400 000
    64, 0, 0, 0, // ferror
    0, 0, 0, 0, // phase 0
    0, // drive stepper
    0, // enable low
    0x88, 0x13, 0, 0, // dir-setup 5000
    0xD0, 0x07, 0, 0, // pulse 2000
    0xDC, 0x05, // max-rpm 1500
    0xEA, 0x45, 0xA8, 0x36, // CRC 0x36A845EA
];

#[test]
fn the_default_settings_make_the_documented_record() {
    assert_eq!(encode(&Config::default()), DEFAULT);
    assert_eq!(decode(&DEFAULT), Ok(Config::default()));
}

#[test]
fn bldc_opposite_active_high_and_a_negative_phase_round_trip() {
    let c = Config::default()
        .with("drive", "bldc")
        .unwrap()
        .with("dir", "opposite")
        .unwrap()
        .with("enable", "high")
        .unwrap()
        .with("phase", "-7.25")
        .unwrap();
    let b = encode(&c);
    let mut want = DEFAULT;
    want[15] = 1; // dir opposite
    want[29..33].copy_from_slice(&[0xAE, 0xE3, 0xFF, 0xFF]); // −7250 mdeg
    want[33] = 1; // drive bldc
    want[34] = 1; // enable high
    want[45..].copy_from_slice(&[0xB9, 0xEE, 0x01, 0x24]); // CRC 0x2401EEB9
    assert_eq!(b, want);
    assert_eq!(decode(&b), Ok(c));
}

#[test]
fn each_flag_decodes_to_its_own_setting() {
    // one flag at a time, so a decoder that swapped or ignored one fails
    for (name, value) in [("dir", "opposite"), ("drive", "bldc"), ("drive", "none"), ("enable", "high")] {
        let c = Config::default().with(name, value).unwrap();
        assert_eq!(decode(&encode(&c)), Ok(c), "{name} {value}");
        assert_ne!(encode(&c), DEFAULT, "{name} {value} changes the record");
    }
}

#[test]
fn a_record_of_the_wrong_length_magic_or_version_says_which() {
    assert_eq!(decode(&DEFAULT[..LEN - 1]), Err(DecodeError::Length));
    let mut b = DEFAULT;
    b[1] = b'X';
    assert_eq!(decode(&b), Err(DecodeError::Magic));
    let mut b = DEFAULT;
    b[2] = 2;
    assert_eq!(decode(&b), Err(DecodeError::Version(2)));
    let mut b = DEFAULT;
    b[48] ^= 0x80;
    assert_eq!(decode(&b), Err(DecodeError::Checksum));
}

#[test]
fn the_crc_register_runs_across_chunks() {
    // CRC-32/ISO-HDLC: init !0, reflected 0xEDB88320, final !
    assert_eq!(!crc32_update(crc32_update(!0, b"1234"), b"56789"), 0xCBF4_3926);
    assert_eq!(crc32(b""), 0);
    assert_eq!(crc32(b"a"), 0xE8B7_BE43);
}
