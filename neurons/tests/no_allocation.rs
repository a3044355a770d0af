//! A prepared population steps without allocating (the shared block scaffolding included),
//! under every integrator, with and without interpolation and divergence checks. Counted by a
//! global allocator that tallies this thread's allocations.

use neurotac_core::testing::{CountingAllocator, allocations_on_this_thread};
use neurotac_core::{NeuronModel, SpikeBuffer};
use neurotac_neurons::{Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Population};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations() -> u64 {
    allocations_on_this_thread()
}

/// Steps `pop` 2 000 times after 200 warm-up steps; returns the allocations of the measured part.
fn allocations_while_stepping(pop: &mut dyn NeuronModel, current: f64) -> u64 {
    pop.prepare(1e-4).unwrap();
    let input = vec![current; pop.len()];
    let mut spikes = SpikeBuffer::new();
    for _ in 0..200 {
        spikes.clear();
        pop.step(&input, &mut spikes);
    }
    let before = allocations();
    for _ in 0..2000 {
        spikes.clear();
        pop.step(&input, &mut spikes);
        pop.check_divergence().unwrap();
    }
    allocations() - before
}

#[test]
fn populations_step_without_allocating() {
    // 5 000 neurons: two blocks, below the parallel threshold (rayon would allocate jobs).
    let n = 5_000;
    for interpolate in [false, true] {
        for integrator in [
            Integrator::Exact,
            Integrator::Euler,
            Integrator::Rk2,
            Integrator::Rk4,
        ] {
            for t_ref_s in [0.0, 2e-3] {
                let params = LifParams {
                    t_ref_s,
                    ..LifParams::default()
                };
                let mut lif = Lif::<f32>::new(n, params)
                    .with_integrator(integrator)
                    .with_interpolation(interpolate);
                assert_eq!(
                    allocations_while_stepping(&mut lif, 1.5),
                    0,
                    "lif {integrator}"
                );
            }
        }
        for integrator in [
            Integrator::Izhikevich2003,
            Integrator::Euler,
            Integrator::ExponentialEuler,
            Integrator::Rk2,
            Integrator::Rk4,
        ] {
            let mut izh = Izhikevich::<f64>::new(n, IzhikevichParams::rs())
                .with_integrator(integrator)
                .with_interpolation(interpolate);
            assert_eq!(
                allocations_while_stepping(&mut izh, 10.0),
                0,
                "izhikevich {integrator}"
            );
        }
    }
    // The benchmark path, once prepared, allocates nothing either.
    let mut lif = Lif::<f32>::new(n, LifParams::default());
    lif.run_constant(1.04, 1e-4, 10).unwrap();
    let before = allocations();
    lif.run_constant(1.04, 1e-4, 1000).unwrap();
    assert_eq!(allocations() - before, 0);
}
