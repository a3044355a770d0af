//! One simulated slide of the artificial set (60 mm at 15 mm/s, ≈ 4.55 s of recording): the
//! flat plate (only the onset and stop bursts move the pins) and the 5 mm grid (the busiest),
//! simulation alone and simulation + transduction to taxel spikes. One thread.
//!
//! `cargo bench --bench simulate_artificial_trial`

use criterion::{Criterion, criterion_group, criterion_main};
use neurotac::sensor::sim::{Camera, SimParams, Simulator, Texture, taxel_spikes};
use std::hint::black_box;
use std::time::Duration;

fn simulate_artificial_trial(c: &mut Criterion) {
    let params = SimParams::default();
    let camera = Camera::new(&params, 1);
    let mut sim = Simulator::new(params, &camera).expect("default parameters are valid");
    let mut g = c.benchmark_group("simulate_artificial_trial");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    for d in [0.0, 5.0] {
        let texture = sim.prepare(Texture::grid(d).expect("a paper grid size"));
        let mut seed = 0;
        g.bench_function(format!("grid_{d}mm"), |b| {
            b.iter(|| {
                seed += 1;
                black_box(sim.simulate(&texture, seed))
            })
        });
        g.bench_function(format!("grid_{d}mm_with_transduction"), |b| {
            b.iter(|| {
                seed += 1;
                let trial = sim.simulate(&texture, seed);
                black_box(taxel_spikes(&trial).expect("simulated events transduce"))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, simulate_artificial_trial);
criterion_main!(benches);
