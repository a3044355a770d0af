//! CUBA's populations are fed by two projections and nothing else, so the network hands their
//! synaptic currents to the LIF loop (`NeuronModel::step_synaptic`), which sums and decays
//! them in its own pass and leaves out the floor and flush it proves to be no-ops. The spikes
//! must be those of the unfused step, which a zero injected current forces.

use neurotac_cli::bench::{CubaConfig, cuba_builder};
use neurotac_core::{CurrentInput, NetworkConfig};
use neurotac_neurons::Real;

/// The spikes of `neurotac bench cuba`'s network (denser, so that a short run is busy) in
/// precision `F`, optionally with a zero current injected into both populations.
fn spikes<F: Real>(zero_current: bool) -> [Vec<(u32, f64)>; 2] {
    let config = CubaConfig {
        n_exc: 800,
        n_inh: 200,
        probability: 0.05,
        ..CubaConfig::default()
    };
    let (mut b, populations, recorders) = cuba_builder::<F>(&config).unwrap();
    if zero_current {
        let zero = b
            .add_current_input("zero", CurrentInput::constant(0.0))
            .unwrap();
        for population in populations {
            b.inject(zero, population).unwrap();
        }
    }
    let mut net = b.build(NetworkConfig { dt_s: config.dt_s }).unwrap();
    net.run(0.2, &neurotac_core::OneProcess).unwrap();
    recorders.map(|r| net.readout(r).unwrap().spikes().to_vec())
}

#[test]
fn cuba_spikes_through_the_fused_step_equal_the_unfused_step() {
    for (fused, unfused) in [
        (spikes::<f64>(false), spikes::<f64>(true)),
        (spikes::<f32>(false), spikes::<f32>(true)),
    ] {
        assert!(fused[0].len() > 500 && fused[1].len() > 100, "must be busy");
        assert!(
            fused == unfused,
            "{} vs {}",
            fused[0].len(),
            unfused[0].len()
        );
    }
}
