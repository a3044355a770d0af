//! Neuron updates per second (N × steps / s) on one core: every model of the menu
//! (`NeuronKind::ALL`: LIF, Izhikevich), f32 and f64, every integrator its reports compare,
//! N = 10³ … 10⁶ at dt = 0.1 ms; plus 10⁷ neurons (memory-bound) and all cores at 10⁶. The cases
//! are the models' benchmarks, Brian2's: LIF I = 1.04, Izhikevich RS I = 10.
//!
//! `afferent_activity`: the afferent pipeline (10⁴ taxels → exponential synapses → each model's
//! afferents: LIF exact, Izhikevich RS from rest; f64, one core) with 0.1 … 100 % of the taxels
//! firing at 20 Hz, clock-driven, event-driven and automatic;
//! "elem/s" there is the *effective* throughput, N × steps per second, whatever was updated.
//!
//! `cargo bench --bench neuron_throughput`; criterion reports "elem/s" = neuron updates/s.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use neurotac::experiments::menu::Menu;
use neurotac::experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision};
use neurotac::experiments::threads::with_threads;
use std::time::Duration;

const DT: f64 = 1e-4;

/// Times `steps` steps of `n` neurons; only stepping is timed.
fn bench_setup(
    c: &mut Criterion,
    group: &str,
    setup: &NeuronSetup,
    sizes: &[usize],
    threads: usize,
) {
    let mut g = c.benchmark_group(group);
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for &n in sizes {
        // About 10⁷ updates per iteration, at least 2 steps.
        let steps = ((1e7 / n as f64) as u64).max(2);
        g.throughput(Throughput::Elements(n as u64 * steps));
        let id = BenchmarkId::new(setup.integrator.name(), format!("{n:.0e}"));
        g.bench_function(id, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let (_, wall) = with_threads(threads, || {
                        setup
                            .run_constant(n, setup.kind.benchmark_current(), DT, steps)
                            .expect("valid set-up")
                    })
                    .expect("thread pool");
                    total += Duration::from_secs_f64(wall);
                }
                total
            })
        });
    }
    g.finish();
}

fn per_core(c: &mut Criterion) {
    for &kind in NeuronKind::ALL {
        for precision in [Precision::F32, Precision::F64] {
            for &integrator in kind.integrators() {
                let setup = NeuronSetup {
                    integrator,
                    ..NeuronSetup::benchmark(kind, precision)
                };
                let group = format!("{}_{}", kind.name(), precision.name());
                bench_setup(c, &group, &setup, &[1_000, 10_000, 100_000, 1_000_000], 1);
            }
        }
    }
}

fn memory_bound_and_all_cores(c: &mut Criterion) {
    for &kind in NeuronKind::ALL {
        let setup = NeuronSetup::benchmark(kind, Precision::F32);
        bench_setup(
            c,
            &format!("{}_f32_1e7_one_core", kind.name()),
            &setup,
            &[10_000_000],
            1,
        );
        bench_setup(
            c,
            &format!("{}_f32_all_cores", kind.name()),
            &setup,
            &[1_000_000, 10_000_000],
            0,
        );
    }
}

fn afferent_activity(c: &mut Criterion) {
    use neurotac::experiments::afferents::AfferentConfig;
    use neurotac_cli::bench::{activity_taxels, afferent_network};
    use neurotac_core::Stepping;
    let (n, duration_s) = (10_000, 0.2);
    let mut g = c.benchmark_group("afferent_activity");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    g.throughput(Throughput::Elements(n as u64 * (duration_s / DT) as u64));
    let models: Vec<_> = NeuronKind::ALL
        .iter()
        .map(|&kind| (kind.name(), AfferentConfig::of(kind)))
        .collect();
    for active in [0.001, 0.01, 0.1, 1.0] {
        let taxels = activity_taxels(n, active, 20.0, duration_s, 1);
        for ((model, config), (mode, stepping)) in models.iter().copied().flat_map(|m| {
            [
                (m, ("clock", Stepping::Clock)),
                (m, ("event", Stepping::Event)),
                (m, ("auto", Stepping::auto())),
            ]
        }) {
            let (mut net, _) =
                afferent_network(&taxels, config, DT, stepping, &neurotac_core::OneProcess)
                    .expect("valid network");
            g.bench_function(BenchmarkId::new(format!("{model}_{mode}"), active), |b| {
                b.iter(|| {
                    net.reset();
                    with_threads(1, || {
                        net.run(duration_s, &neurotac_core::OneProcess)
                            .expect("runs")
                    })
                    .expect("thread pool")
                })
            });
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    per_core,
    memory_bound_and_all_cores,
    afferent_activity
);
criterion_main!(benches);
