//! Any bytes as a flash record: decodes to a valid config or an error,
//! never a panic; whatever decodes re-encodes to the same bytes (decoding
//! is one-to-one). Checked twice per input: on the bytes as given, and, for
//! a record's length, with its CRC made valid, so the fuzzer reaches the
//! fields behind the checksum (what a buggy or foreign tool would write).
#![no_main]
use libfuzzer_sys::fuzz_target;
use polyturn_sync::codec;

fn check(record: &[u8]) {
    if let Ok(c) = codec::decode(record) {
        assert_eq!(c.validate(), Ok(()));
        assert_eq!(&codec::encode(&c)[..], record, "decoded to {c:?}");
    }
}

fuzz_target!(|data: &[u8]| {
    check(data);
    if data.len() == codec::LEN {
        let mut sealed = [0u8; codec::LEN];
        sealed.copy_from_slice(data);
        let crc = codec::crc32(&sealed[..codec::LEN - 4]);
        sealed[codec::LEN - 4..].copy_from_slice(&crc.to_le_bytes());
        check(&sealed);
    }
});
