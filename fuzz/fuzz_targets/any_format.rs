//! Format detection and whichever reader it picks, on arbitrary bytes.
#![no_main]

#[path = "common.rs"]
mod common;

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::format::reader_from_bytes;

fuzz_target!(|data: &[u8]| {
    if let Ok(reader) = reader_from_bytes(data) {
        common::drain(reader);
    }
});
