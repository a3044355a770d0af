//! Exact multi-unit Van Rossum matrices at the spec's benchmark sizes: 1100 samples × 49 taxels,
//! 4.5 s, ~10 and ~35 spikes per taxel (synthetic, seeded). The spec's pymuvr anchors for the
//! same sizes are ≈ 391 s and ≈ 1489 s of CPU (`square_distance_matrix`, measured for the spec on
//! a 2-core machine, not here). τ = 76 ms; the cost does not depend on cos θ.

use criterion::{Criterion, criterion_group, criterion_main};
use neurotac::core::distance::VanRossum;
use neurotac::experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use std::hint::black_box;
use std::time::Duration;

fn van_rossum_matrix(c: &mut Criterion) {
    let vr = VanRossum::new(0.076).unwrap();
    let mut group = c.benchmark_group("van_rossum_matrix_1100x49");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(60))
        .warm_up_time(Duration::from_secs(1));
    for spikes in [10.0, 35.0] {
        let data = synthetic_dataset(&SyntheticConfig {
            spikes_per_unit: spikes,
            ..Default::default()
        });
        group.bench_function(format!("{spikes:.0}_spikes_per_unit"), |b| {
            b.iter(|| {
                black_box(
                    vr.matrices(black_box(data.observations()), &neurotac_core::OneProcess)
                        .unwrap(),
                )
            })
        });
    }
    group.finish();
}

fn van_rossum_pair(c: &mut Criterion) {
    let data = synthetic_dataset(&SyntheticConfig {
        samples: 2,
        spikes_per_unit: 35.0,
        ..Default::default()
    });
    let vr = VanRossum::new(0.076).unwrap();
    let prepared = vr.prepare(data.observations()).unwrap();
    c.bench_function("van_rossum_pair_49x35", |b| {
        b.iter(|| black_box(prepared.squared_parts(0, 1)))
    });
}

criterion_group!(benches, van_rossum_pair, van_rossum_matrix);
criterion_main!(benches);
