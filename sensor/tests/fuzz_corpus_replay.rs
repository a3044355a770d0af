//! The committed fuzz corpus (`fuzz/corpus/<target>/`), replayed on stable (no nightly, no
//! cargo-fuzz): every file goes through every reader — each format's own reader, AEDAT 4.0 with
//! and without the input length, format detection — and what a reader delivers goes through
//! every writer and back with the reader's sensor size (read → write → read gives the same events
//! and size, or the writer refuses with a typed `Unrepresentable` or `UnsupportedSensorSize`). Nothing may panic, every reader hands out bounded chunks whose
//! events lie inside the sensor and match its counters, the events decoded are bounded by the
//! input size, and the memory a file's reading allocates stays under a budget set by its size.
//!
//! The corpus is minimised by `cargo fuzz cmin` and holds the bad-input cases the readers were
//! fixed for (cut headers and magics, NUL bytes, too many fields, timestamps AEDAT 2.0 cannot
//! hold, …); `fuzz/README.md` says how it is grown.

use neurotac_core::EventBuffer;
use neurotac_core::testing::fuzz::{PeakAllocator, corpus, peak_since, reset_peak};
use neurotac_sensor::FormatError;
use neurotac_sensor::davis::UsbDecoder;
use neurotac_sensor::format::{
    Aedat2Reader, Aedat3Reader, Aedat4Reader, CsvReader, DAVIS240_SIZE, EcdTextReader, EventReader,
    Format, ReadStats, reader_from_bytes, to_bytes,
};

/// Tracks the bytes live and their peak. This test binary holds one test, so the counts are
/// that test's.
#[global_allocator]
static GLOBAL: PeakAllocator = PeakAllocator;

/// The cargo-fuzz targets, each with a corpus folder.
const TARGETS: [&str; 6] = [
    "any_format",
    "aedat2",
    "aedat3",
    "aedat4",
    "text",
    "usb_decode",
];

/// Most events one `read_chunk` call may hand out (the trait's "a few hundred thousand").
const MAX_CHUNK_EVENTS: usize = 1 << 18;

/// Fixed part of the memory budget of one file's reading: read blocks (256 KiB), AEDAT 4.0
/// packet buffers, and the events decoded.
const BUDGET_FIXED_BYTES: usize = 8 << 20;

/// Memory budget per input byte (AEDAT 4.0 packets decompress; LZ4 expands at most ~255×).
const BUDGET_PER_INPUT_BYTE: usize = 1024;

/// The smallest encoding of one event in bytes, per reader: 8-byte AEDAT 2.0/3.1 records, 16-byte
/// AEDAT 4.0 events (uncompressed), text lines of at least `0 0 0 1` plus a line end.
fn min_bytes_per_event(reader: &str, bytes: &[u8]) -> Option<usize> {
    match reader {
        "AEDAT 2.0" | "AEDAT 3.1" => Some(8),
        "ECD text" | "CSV" => Some(7),
        // Compressed AEDAT 4.0 packets have no fixed ratio; the memory budget bounds them.
        _ if bytes.starts_with(b"#!AER-DAT4.0") => None,
        _ => Some(7),
    }
}

/// A reader, or the error that refused its input's header.
type Opened<'a> = Result<Box<dyn EventReader + 'a>, FormatError>;

/// Every reader on `bytes`, named.
fn readers(bytes: &[u8]) -> Vec<(&'static str, Opened<'_>)> {
    fn boxed<'a, R: EventReader + 'a>(r: Result<R, FormatError>) -> Opened<'a> {
        r.map(|r| Box::new(r) as Box<dyn EventReader + 'a>)
    }
    let len = Some(bytes.len() as u64);
    vec![
        ("AEDAT 2.0", boxed(Aedat2Reader::new(bytes))),
        ("AEDAT 3.1", boxed(Aedat3Reader::new(bytes))),
        (
            "AEDAT 4.0 (length known)",
            boxed(Aedat4Reader::with_name(bytes, "<corpus>".into(), len)),
        ),
        (
            "AEDAT 4.0 (stream)",
            boxed(Aedat4Reader::with_name(bytes, "<corpus>".into(), None)),
        ),
        ("ECD text", boxed(EcdTextReader::new(bytes))),
        ("CSV", boxed(CsvReader::new(bytes))),
        ("detected", reader_from_bytes(bytes)),
    ]
}

/// Reads to the end or the first error, checking every chunk; returns the events, the stats
/// and the error.
fn drain(
    what: &str,
    reader: &mut dyn EventReader,
    budget_events: Option<usize>,
) -> (EventBuffer, ReadStats, Option<FormatError>) {
    let (w, h) = reader.sensor_size().unwrap_or(DAVIS240_SIZE);
    let mut all = EventBuffer::new();
    let mut chunk = EventBuffer::new();
    let error = loop {
        chunk.clear();
        match reader.read_chunk(&mut chunk) {
            Ok(0) => break None,
            Ok(n) => {
                assert!(
                    n == chunk.len() && n <= MAX_CHUNK_EVENTS,
                    "{what}: chunk of {n}"
                );
                assert!(
                    chunk.x.iter().all(|&x| x < w) && chunk.y.iter().all(|&y| y < h),
                    "{what}: an event outside {w} × {h}"
                );
                for e in chunk.iter() {
                    all.push(e);
                }
                if let Some(max) = budget_events {
                    assert!(
                        all.len() <= max,
                        "{what}: {} events from the input",
                        all.len()
                    );
                }
            }
            Err(e) => break Some(e),
        }
    };
    // The end (or the error) is final.
    chunk.clear();
    assert!(
        matches!(reader.read_chunk(&mut chunk), Ok(0)),
        "{what}: a read after the end"
    );
    let stats = reader.stats();
    assert_eq!(stats.events, all.len() as u64, "{what}: stats.events");
    (all, stats, error)
}

/// `events` of a `size` sensor through every writer and back: the same events and size, or a
/// typed refusal.
fn round_trip(what: &str, events: &EventBuffer, size: (u16, u16)) {
    for format in Format::ALL {
        let bytes = match to_bytes(events, format, size) {
            Ok(bytes) => bytes,
            Err(
                FormatError::Unrepresentable { .. } | FormatError::UnsupportedSensorSize { .. },
            ) => {
                continue;
            }
            Err(e) => panic!("{what} → {}: {e}", format.name()),
        };
        // Read back with the format's own reader: an empty text file (no events) is not
        // detected as any format, on purpose.
        let mut reader: Box<dyn EventReader> = match format {
            Format::Aedat2 => Box::new(Aedat2Reader::new(&bytes[..]).unwrap()),
            Format::Aedat3 => Box::new(Aedat3Reader::new(&bytes[..]).unwrap()),
            Format::Aedat4(_) => Box::new(Aedat4Reader::new(&bytes[..]).unwrap()),
            Format::EcdText => Box::new(EcdTextReader::new(&bytes[..]).unwrap()),
            Format::Csv => Box::new(CsvReader::new(&bytes[..]).unwrap()),
        };
        assert_eq!(
            reader.sensor_size().unwrap_or(DAVIS240_SIZE),
            size,
            "{what} → {}: the sensor size",
            format.name()
        );
        let mut back = EventBuffer::new();
        if let Err(e) = reader.read_to_end(&mut back) {
            panic!("{what} → {}: read back: {e}", format.name());
        }
        assert_eq!(
            &back,
            events,
            "{what} → {}: read → write → read changed the events",
            format.name()
        );
    }
}

/// The USB word decoder on `bytes`, in one piece and cut after the byte the first byte names
/// (as the `usb_decode` target does): the same events and counters, events inside the sensor.
fn decode_usb(name: &str, bytes: &[u8]) -> EventBuffer {
    let mut whole = EventBuffer::new();
    let mut one = UsbDecoder::davis240();
    one.decode(bytes, &mut whole);
    let split = bytes
        .first()
        .map_or(0, |&b| usize::from(b).min(bytes.len()));
    let mut parts = EventBuffer::new();
    let mut two = UsbDecoder::davis240();
    two.decode(&bytes[..split], &mut parts);
    two.decode(&bytes[split..], &mut parts);
    assert_eq!(whole, parts, "{name} [USB]: decoding in two pieces");
    assert_eq!(one.stats(), two.stats(), "{name} [USB]: counters");
    assert!(whole.x.iter().all(|&x| x < 240) && whole.y.iter().all(|&y| y < 180));
    assert!(
        whole.len() <= bytes.len() / 2,
        "{name} [USB]: events ≤ 16-bit words"
    );
    whole
}

/// One corpus file through every reader and the round trip.
fn replay(name: &str, bytes: &[u8]) {
    let usb = decode_usb(name, bytes);
    round_trip(&format!("{name} [USB]"), &usb, DAVIS240_SIZE);
    for (reader_name, reader) in readers(bytes) {
        let what = format!("{name} [{reader_name}]");
        let Ok(mut reader) = reader else { continue };
        let budget_events = min_bytes_per_event(reader_name, bytes).map(|b| bytes.len() / b + 1);
        let (events, _, _) = drain(&what, reader.as_mut(), budget_events);
        let size = reader.sensor_size().unwrap_or(DAVIS240_SIZE);
        drop(reader);
        round_trip(&what, &events, size);
    }
}

#[test]
fn every_corpus_file_through_every_reader_and_writer() {
    let mut files = 0;
    let mut total_bytes = 0;
    let mut largest_peak = 0;
    let mut seen = std::collections::HashSet::new();
    for target in TARGETS {
        let Some(entries) = corpus(target) else {
            return;
        };
        assert!(!entries.is_empty(), "{target}: empty corpus");
        for (file, bytes) in entries {
            // A file several targets share (cmin names finds by their hash) is replayed once,
            // and git stores it once.
            if !seen.insert(bytes.clone()) {
                continue;
            }
            let name = format!("{target}/{file}");
            let start = reset_peak();
            replay(&name, &bytes);
            let used = peak_since(start);
            let budget = BUDGET_FIXED_BYTES + BUDGET_PER_INPUT_BYTE * bytes.len();
            assert!(
                used <= budget,
                "{name}: {used} bytes allocated at the peak, budget {budget}"
            );
            files += 1;
            total_bytes += bytes.len();
            largest_peak = largest_peak.max(used);
        }
    }
    // The committed corpus stays small (at most 2 MB of distinct files in all).
    assert!(total_bytes <= 2_000_000, "corpus of {total_bytes} bytes");
    eprintln!(
        "replayed {files} distinct corpus files ({total_bytes} bytes); largest allocation peak {largest_peak} bytes"
    );
}
