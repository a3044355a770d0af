//! The temporal coding's Δt brute force (1…200 ms, leave-one-out, k = 4) on 1100 samples × 49
//! taxels, 4.5 s, ~10 spikes per taxel (synthetic, seeded). The spec's NumPy + scikit-learn
//! anchor for the same sweep is 47.8 s of CPU (measured for the spec, not here).

use criterion::{Criterion, criterion_group, criterion_main};
use neurotac::core::Knn;
use neurotac::experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use neurotac::experiments::search::dt_sweep::dt_sweep;
use std::hint::black_box;
use std::time::Duration;

fn dt_sweep_loo_1100(c: &mut Criterion) {
    let data = synthetic_dataset(&SyntheticConfig::default());
    let mut group = c.benchmark_group("dt_sweep_loo_1100");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(40))
        .warm_up_time(Duration::from_secs(1));
    group.bench_function("1_to_200_ms", |b| {
        b.iter(|| {
            black_box(
                dt_sweep(
                    data.observations(),
                    data.labels(),
                    4500,
                    200,
                    Knn::default(),
                    &neurotac_core::OneProcess,
                )
                .unwrap(),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, dt_sweep_loo_1100);
criterion_main!(benches);
