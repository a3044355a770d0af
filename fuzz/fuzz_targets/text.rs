//! The ECD text and CSV readers on arbitrary bytes: a typed error or events inside the sensor
//! (the one a `# sensor` line states, else 240 × 180).
#![no_main]

#[path = "common.rs"]
mod common;

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::format::{CsvReader, EcdTextReader};

fuzz_target!(|data: &[u8]| {
    if let Ok(reader) = EcdTextReader::new(data) {
        common::drain(reader);
    }
    if let Ok(reader) = CsvReader::new(data) {
        common::drain(reader);
    }
});
