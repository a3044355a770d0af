//! Format detection and whichever reader it picks, on arbitrary bytes.
#![no_main]

#[path = "common.rs"]
mod common;

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::format::reader_from_bytes;

fuzz_target!(|data: &[u8]| {
    if let Ok(reader) = reader_from_bytes(data) {
        // Sizes up to i16::MAX: an AEDAT 4.0 description may name any sensor size.
        common::drain(reader, (u16::MAX, u16::MAX));
    }
});
