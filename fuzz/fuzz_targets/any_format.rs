//! Format detection and whichever reader it picks, on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_core::EventBuffer;
use neurotac_sensor::format::reader_from_bytes;

fuzz_target!(|data: &[u8]| {
    let Ok(mut reader) = reader_from_bytes(data) else {
        return;
    };
    let mut out = EventBuffer::new();
    let _ = reader.read_to_end(&mut out);
    assert_eq!(reader.stats().events, out.len() as u64);
});
