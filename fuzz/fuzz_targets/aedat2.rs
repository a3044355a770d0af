//! The AEDAT 2.0 reader on arbitrary bytes: a typed error or events inside 240 × 180.
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_core::EventBuffer;
use neurotac_sensor::format::{Aedat2Reader, EventReader};

fuzz_target!(|data: &[u8]| {
    let Ok(mut reader) = Aedat2Reader::new(data) else {
        return;
    };
    let mut out = EventBuffer::new();
    let _ = reader.read_to_end(&mut out);
    assert!(out.x.iter().all(|&x| x < 240) && out.y.iter().all(|&y| y < 180));
    assert_eq!(reader.stats().events, out.len() as u64);
});
