//! CUBA's populations are fed by two projections and nothing else, so the network hands their
//! synaptic currents to the LIF loop (`NeuronModel::step_synaptic`), which sums and decays
//! them in its own pass and leaves out the floor and flush it proves to be no-ops. The spikes
//! must be those of the unfused step, which a zero injected current forces.

use neurotac_core::{
    Connectivity, CurrentInput, ExpSynapse, Network, NetworkBuilder, NetworkConfig, ReadoutId,
    SpikeRecorder,
};
use neurotac_neurons::{InitialPotential, Integrator, Lif, LifParams, Real};

/// A CUBA network (`neurotac bench cuba`'s, denser, so that a short run is busy) of `n`
/// neurons in precision `F`, optionally with a zero current injected into both populations.
fn cuba_like<F: Real>(n: usize, zero_current: bool) -> (Network, [ReadoutId<SpikeRecorder>; 2]) {
    let params = LifParams {
        tau_m_s: 0.02,
        v_rest: -49.0,
        v_th: -50.0,
        v_reset: -60.0,
        t_ref_s: 5e-3,
        v_min: f64::NEG_INFINITY,
    };
    let population = |n: usize, seed: u64| {
        Lif::<F>::new(n, params)
            .with_integrator(Integrator::Exact)
            .with_initial_potential(InitialPotential::Uniform {
                low: -60.0,
                high: -50.0,
                seed,
            })
    };
    let mut b = NetworkBuilder::new();
    let n_exc = n * 4 / 5;
    let exc = b
        .add_population("excitatory", population(n_exc, 1))
        .unwrap();
    let inh = b
        .add_population("inhibitory", population(n - n_exc, 2))
        .unwrap();
    for (k, (pre, post, weight, tau)) in [
        (exc, exc, 1.62, 5e-3),
        (exc, inh, 1.62, 5e-3),
        (inh, exc, -9.0, 10e-3),
        (inh, inh, -9.0, 10e-3),
    ]
    .into_iter()
    .enumerate()
    {
        let random = Connectivity::Random {
            probability: 0.05,
            weight,
            seed: 10 + k as u64,
        };
        b.connect(pre, post, random, ExpSynapse::new(tau)).unwrap();
    }
    if zero_current {
        let zero = b
            .add_current_input("zero", CurrentInput::constant(0.0))
            .unwrap();
        b.inject(zero, exc).unwrap();
        b.inject(zero, inh).unwrap();
    }
    let recorders = [b.record_spikes(exc).unwrap(), b.record_spikes(inh).unwrap()];
    let net = b.build(NetworkConfig { dt_s: 1e-4 }).unwrap();
    (net, recorders)
}

fn spikes<F: Real>(zero_current: bool) -> Vec<Vec<(u32, f64)>> {
    let (mut net, recorders) = cuba_like::<F>(1000, zero_current);
    net.run(0.2).unwrap();
    recorders
        .iter()
        .map(|&r| net.readout(r).spikes().to_vec())
        .collect()
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
