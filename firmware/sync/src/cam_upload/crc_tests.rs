//! The upload's checksum is CRC-32/ISO-HDLC (the settings record's, see
//! `codec::crc32`) over the five header words then the points, each
//! little-endian, as one message: the value a host computes with any
//! standard CRC-32 (here Python's `zlib.crc32`, worked out by hand below).

use super::*;

const HEADER: CamHeader =
    CamHeader { points: 4, period_counts: 900, counts_per_rev: 2400, max_rate_hz: 12_000, max_accel: 1_600_000 };
const POINTS: [i32; 4] = [0, -1, 1_000, -100_000];

#[test]
fn the_checksum_is_the_standard_crc_32_of_the_header_and_points() {
    // zlib.crc32(struct.pack("<5I4i", 4, 900, 2400, 12000, 1600000,
    //                        0, -1, 1000, -100000)) == 0x5AC3B2FE
    assert_eq!(checksum(&HEADER, &POINTS), 0x5AC3_B2FE);
    // the same as the CRC of those 36 bytes in one go
    let mut bytes = std::vec::Vec::new();
    HEADER.words().iter().for_each(|w| bytes.extend_from_slice(&w.to_le_bytes()));
    POINTS.iter().for_each(|p| bytes.extend_from_slice(&p.to_le_bytes()));
    assert_eq!(crate::codec::crc32(&bytes), 0x5AC3_B2FE);
}

#[test]
fn the_header_words_are_in_begin_order() {
    assert_eq!(HEADER.words(), [4, 900, 2400, 12_000, 1_600_000]);
}

#[test]
fn an_upload_ending_with_the_standard_crc_completes() {
    let mut u = std::boxed::Box::new(CamUpload::default());
    assert_eq!(u.line("begin 4 900 2400 12000 1600000"), Ok(Progress::Begun));
    assert_eq!(u.line("data 0 0 -1"), Ok(Progress::Received(2)));
    assert_eq!(u.line("data 2 1000 -100000"), Ok(Progress::Received(4)));
    assert_eq!(u.line("end 5ac3b2fe"), Ok(Progress::Complete(HEADER)));
    assert_eq!(u.table(), Some((HEADER, &POINTS[..])));
}

#[test]
fn an_upload_refuses_points_beyond_those_announced_and_ending_short() {
    let mut u = std::boxed::Box::new(CamUpload::default());
    u.line("begin 4 900 2400 12000 1600000").unwrap();
    assert_eq!(u.line("data 0 1 2 3 4 5"), Err("cam data: more points than announced"));
    u.line("begin 4 900 2400 12000 1600000").unwrap();
    u.line("data 0 1 2 3").unwrap();
    assert_eq!(u.line("end 0"), Err("cam end: fewer points than announced"));
    // points may not outnumber the counts of the period
    assert_eq!(u.line("begin 4 3 2400 1 1"), Err("cam begin: period-counts must be >= points"));
    assert_eq!(u.line("begin 4 4 2400 1 1"), Ok(Progress::Begun));
    assert_eq!(u.line("begin 1 4 2400 1 1"), Err("cam begin: points must be in 2..=1024"));
    assert_eq!(u.line("begin 2 4 2400 1 1"), Ok(Progress::Begun));
}
