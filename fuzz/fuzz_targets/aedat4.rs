//! The AEDAT 4.0 reader (flatbuffers, LZ4 and Zstd frames) on arbitrary bytes, with and
//! without the input length: a typed error or events inside the stream's size.
#![no_main]

#[path = "common.rs"]
mod common;

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::format::Aedat4Reader;

fuzz_target!(|data: &[u8]| {
    for len in [Some(data.len() as u64), None] {
        if let Ok(reader) = Aedat4Reader::with_name(data, "<fuzz>".into(), len) {
            common::drain(reader);
        }
    }
});
