//! Transduction speed on the real DAVIS240C recording (`../shared/data/davis240`): the
//! background-activity filter alone, and filter + receptive fields + pooling + re-centring.
//!
//! `cargo bench --bench transduction`; criterion's "elem/s" = pixel events per second, one core;
//! the `transduction_cpu` group measures the thread's CPU time (robust to a busy machine).
//! Same-run comparison with dv-processing's filter: `benches/peers/dv_processing_ba.py`.
//!
//! Only the processing of the recording is timed: the filter and the transducer are built (maps
//! allocated, receptive-field tables laid out) and dropped outside the measurement, once per
//! iteration, as they are built once per recording.

mod common;

use criterion::measurement::Measurement;
use criterion::{BatchSize, Criterion, Throughput};
use neurotac::core::EventBuffer;
use neurotac::sensor::filter::{BackgroundActivityFilter, MapStart};
use neurotac::sensor::stage::EventFilter;
use neurotac::sensor::taxel::{TaxelLayout, Transducer, TransductionConfig};
use std::time::Duration;

fn recording() -> Option<EventBuffer> {
    let path = common::shared_recording("pick.aedat")?;
    neurotac::sensor::format::read_file(&path)
        .map(|(events, _)| events)
        .map_err(|e| eprintln!("skipping: {e}"))
        .ok()
}

fn transduction<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let Some(events) = recording() else { return };
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(events.len() as u64))
        .measurement_time(Duration::from_secs(3));
    g.bench_function("ba_filter_real_recording", |b| {
        b.iter_batched(
            || BackgroundActivityFilter::new(240, 180, 5000, MapStart::Zero).expect("valid"),
            |mut f| {
                let kept = events
                    .iter()
                    .filter(|&e| f.retain(e).expect("in range"))
                    .count();
                (kept, f)
            },
            BatchSize::LargeInput,
        )
    });
    let layout = TaxelLayout::neurotac_default();
    g.bench_function("filter_mask_pooling_real_recording", |b| {
        b.iter_batched(
            || Transducer::new(&layout, TransductionConfig::default()).expect("valid"),
            |mut t| {
                t.push(&events).expect("ordered, in range");
                t.finish();
                t
            },
            BatchSize::LargeInput,
        )
    });
    g.finish();
}

wall_and_cpu_main!(transduction, "transduction");
