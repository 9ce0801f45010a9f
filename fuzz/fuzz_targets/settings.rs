//! Any bytes as a flash record: decodes to a valid config or an error,
//! never a panic; whatever decodes re-encodes to the same bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polyturn_sync::codec;

fuzz_target!(|data: &[u8]| {
    if let Ok(c) = codec::decode(data) {
        assert_eq!(c.validate(), Ok(()));
        assert_eq!(&codec::encode(&c)[..], data);
    }
});
