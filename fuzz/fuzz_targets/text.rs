//! The ECD text and CSV readers on arbitrary bytes: a typed error or events inside 240 × 180.
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_core::EventBuffer;
use neurotac_sensor::format::{CsvReader, EcdTextReader, EventReader};

fuzz_target!(|data: &[u8]| {
    let readers: [Box<dyn EventReader + '_>; 2] =
        [Box::new(EcdTextReader::new(data)), Box::new(CsvReader::new(data))];
    for mut reader in readers {
        let mut out = EventBuffer::new();
        let _ = reader.read_to_end(&mut out);
        assert!(out.x.iter().all(|&x| x < 240) && out.y.iter().all(|&y| y < 180));
        assert_eq!(reader.stats().events, out.len() as u64);
    }
});
