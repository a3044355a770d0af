//! The ECD text and CSV readers on arbitrary bytes: a typed error or events inside 240 × 180.
#![no_main]

#[path = "common.rs"]
mod common;

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::format::{CsvReader, EcdTextReader};

fuzz_target!(|data: &[u8]| {
    common::drain(EcdTextReader::new(data), (240, 180));
    common::drain(CsvReader::new(data), (240, 180));
});
