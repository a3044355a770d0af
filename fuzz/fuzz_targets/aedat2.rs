//! The AEDAT 2.0 reader on arbitrary bytes: a typed error or events inside the sensor.
#![no_main]

#[path = "common.rs"]
mod common;

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::format::Aedat2Reader;

fuzz_target!(|data: &[u8]| {
    if let Ok(reader) = Aedat2Reader::new(data) {
        common::drain(reader);
    }
});
