//! Decode speed on the real DAVIS240C recording (issue 5 targets, single-threaded): USB words and
//! AEDAT 2.0 at ≥ 200 M events/s, AEDAT 4.0 with LZ4 at ≥ 50 M events/s. Each file is loaded
//! into memory once and decoded repeatedly; criterion reports events/s (`elem/s`).
//!
//! Two groups measure the same code: `davis240_decode` in wall-clock time (criterion's default)
//! and `davis240_decode_cpu` in the benchmark thread's CPU time (`clock_gettime` with
//! `CLOCK_THREAD_CPUTIME_ID`), which other processes sharing the cores cannot inflate by
//! time-slicing.
//!
//! `cargo bench --bench davis240_decode`

mod common;

use criterion::measurement::Measurement;
use criterion::{Criterion, Throughput};
use neurotac::core::EventBuffer;
use neurotac::sensor::davis::UsbDecoder;
use neurotac::sensor::format::{Aedat2Reader, Aedat4Reader, EventReader};
use std::hint::black_box;

fn load(name: &str) -> Option<Vec<u8>> {
    let path = common::shared_recording(name)?;
    std::fs::read(&path)
        .map_err(|e| eprintln!("skipping {name}: {e}"))
        .ok()
}

/// Reads every event of `reader` into `out` (cleared first); returns the count.
fn drain(mut reader: impl EventReader, out: &mut EventBuffer) -> usize {
    out.clear();
    reader.read_to_end(out).unwrap() as usize
}

fn decode<M: Measurement>(c: &mut Criterion<M>, group_name: &str) {
    let mut group = c.benchmark_group(group_name);
    let mut out = EventBuffer::with_capacity(1 << 17);
    if let Some(bytes) = load("pick_usb_words.bin") {
        let mut decoder = UsbDecoder::davis240();
        decoder.decode(&bytes, &mut out);
        group.throughput(Throughput::Elements(out.len() as u64));
        // The stream starts with a timestamp reset, so decoding it again gives the same events.
        group.bench_function("usb_words_real_recording", |b| {
            b.iter(|| {
                out.clear();
                decoder.decode(black_box(&bytes), &mut out);
                out.len()
            })
        });
    }
    if let Some(bytes) = load("pick.aedat") {
        let n = drain(Aedat2Reader::new(&bytes[..]).unwrap(), &mut out);
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function("aedat2_real_recording", |b| {
            b.iter(|| drain(Aedat2Reader::new(black_box(&bytes[..])).unwrap(), &mut out))
        });
    }
    for (name, file) in [
        ("aedat4_lz4_real_recording", "pick_lz4.aedat4"),
        ("aedat4_zstd_real_recording", "pick_zstd.aedat4"),
        ("aedat4_none_real_recording", "pick_none.aedat4"),
    ] {
        if let Some(bytes) = load(file) {
            let n = drain(Aedat4Reader::new(&bytes[..]).unwrap(), &mut out);
            group.throughput(Throughput::Elements(n as u64));
            group.bench_function(name, |b| {
                b.iter(|| drain(Aedat4Reader::new(black_box(&bytes[..])).unwrap(), &mut out))
            });
        }
    }
    group.finish();
}

wall_and_cpu_main!(decode, "davis240_decode");
