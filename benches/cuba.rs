//! The CUBA network (4000 LIF, 80/20 exc/inh, 2 % connectivity, exponential current synapses),
//! 1 s of network time at 0.1 ms: wall seconds per simulated second (building not timed).
//!
//! `cargo bench --bench cuba`

use criterion::{Criterion, criterion_group, criterion_main};
use neurotac::experiments::threads::with_threads;
use neurotac_cli::bench::{CubaConfig, cuba};
use std::time::Duration;

fn cuba_1s(c: &mut Criterion) {
    let mut g = c.benchmark_group("cuba");
    g.sample_size(10).measurement_time(Duration::from_secs(3));
    for (name, threads) in [
        ("4000_neurons_1s_one_core", 1),
        ("4000_neurons_1s_all_cores", 0),
    ] {
        g.bench_function(name, |b| {
            b.iter_custom(|iters| {
                (0..iters)
                    .map(|_| {
                        let r = with_threads(threads, || {
                            cuba(CubaConfig::default(), &neurotac_core::OneProcess)
                        })
                        .expect("pool")
                        .expect("CUBA builds");
                        Duration::from_secs_f64(r.run_s)
                    })
                    .sum()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, cuba_1s);
criterion_main!(benches);
