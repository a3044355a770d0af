//! The AEDAT 4.0 reader (flatbuffers, LZ4 and Zstd frames) on arbitrary bytes, with and
//! without the input length: a typed error or events inside the stream's size.
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_core::EventBuffer;
use neurotac_sensor::format::{Aedat4Reader, EventReader};

fuzz_target!(|data: &[u8]| {
    for len in [Some(data.len() as u64), None] {
        let Ok(mut reader) = Aedat4Reader::with_name(data, "<fuzz>".into(), len) else {
            return;
        };
        let (sx, sy) = reader.event_stream().map_or((240, 180), |s| s.size);
        let mut out = EventBuffer::new();
        let _ = reader.read_to_end(&mut out);
        assert!(out.x.iter().all(|&x| x < sx) && out.y.iter().all(|&y| y < sy));
        assert_eq!(reader.stats().events, out.len() as u64);
    }
});
