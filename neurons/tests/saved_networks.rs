//! Networks of the built-in models saved mid-run and loaded ([`Network::save`],
//! [`NetworkBuilder::load`] with [`BuiltinModels`]) continue exactly as the uninterrupted run:
//! the same spikes, weights and states, bit for bit — clock-driven, event-driven and
//! automatic, plastic and fixed, f32 and f64.

use neurotac_core::{
    Connectivity, ExpSynapse, Network, NetworkBuilder, NetworkConfig, OneProcess, PoissonInput,
    PopulationId, ProjectionId, ReadoutId, SpikeRecorder, Stdp, Stepping,
};
use neurotac_neurons::{BuiltinModels, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams};

const DT: f64 = 1e-4;

/// The parts a test reads.
struct Parts {
    hidden: PopulationId,
    out: PopulationId,
    into_hidden: ProjectionId,
    into_out: ProjectionId,
    spikes: ReadoutId<SpikeRecorder>,
}

/// Poisson inputs → (plastic or fixed, random) → LIF → (delay 5, plastic or fixed) →
/// Izhikevich, stepped as `stepping`.
fn network(stepping: &Stepping, plastic: bool, f32_lif: bool) -> (Network, Parts) {
    let mut b = NetworkBuilder::new();
    b.stepping(stepping.clone());
    let input = b
        .add_spike_input("inputs", PoissonInput::new(60, 12.0, 3))
        .unwrap();
    let hidden = if f32_lif {
        b.add_population(
            "hidden",
            Lif::<f32>::new(20, LifParams::default()).with_integrator(Integrator::Rk2),
        )
    } else {
        b.add_population("hidden", Lif::<f64>::new(20, LifParams::default()))
    }
    .unwrap();
    let out = b
        .add_population(
            "out",
            Izhikevich::<f64>::new(7, IzhikevichParams::default()),
        )
        .unwrap();
    let random = Connectivity::Random {
        probability: 0.4,
        weight: 0.4,
        seed: 9,
    };
    let (a, c) = if plastic {
        (
            b.connect_plastic(
                input,
                hidden,
                random,
                ExpSynapse::new(5e-3).with_delay(0),
                Stdp::additive(0.02, 0.02, 0.02, 0.022, 0.8),
            )
            .unwrap(),
            b.connect_plastic(
                hidden,
                out,
                Connectivity::AllToAll { weight: 3.0 },
                ExpSynapse::new(5e-3).with_delay(5),
                Stdp::additive(0.02, 0.02, 0.1, 0.11, 6.0).multiplicative(),
            )
            .unwrap(),
        )
    } else {
        (
            b.connect(input, hidden, random, ExpSynapse::new(5e-3).with_delay(0))
                .unwrap(),
            b.connect(
                hidden,
                out,
                Connectivity::AllToAll { weight: 3.0 },
                ExpSynapse::new(5e-3).with_delay(5),
            )
            .unwrap(),
        )
    };
    let spikes = b.record_spikes(out).unwrap();
    let parts = Parts {
        hidden,
        out,
        into_hidden: a,
        into_out: c,
        spikes,
    };
    (b.build(NetworkConfig { dt_s: DT }).unwrap(), parts)
}

fn bits(v: Vec<f64>) -> Vec<u64> {
    v.into_iter().map(f64::to_bits).collect()
}

#[test]
fn saved_mid_run_and_loaded_continues_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for stepping in [Stepping::Clock, Stepping::Event, Stepping::auto()] {
        for plastic in [true, false] {
            for f32_lif in [false, true] {
                let case = format!("{stepping:?}, plastic {plastic}, f32 LIF {f32_lif}");
                let (mut whole, w) = network(&stepping, plastic, f32_lif);
                whole.run(1.5, &OneProcess).unwrap();

                let (mut first, _) = network(&stepping, plastic, f32_lif);
                first.run(0.7, &OneProcess).unwrap();
                let path = dir.path().join("net.ntnet");
                first.save(&path).unwrap();
                let mut b = NetworkBuilder::load(&path, &BuiltinModels).unwrap();
                let out = b.population("out").unwrap();
                let hidden = b.population("hidden").unwrap();
                let [into_hidden, into_out] = b.projections()[..] else {
                    panic!("{case}: two projections")
                };
                let spikes = b.record_spikes(out).unwrap();
                let dt_s = b.saved_dt_s().unwrap();
                let mut second = b.build(NetworkConfig { dt_s }).unwrap();
                second.run(0.8, &OneProcess).unwrap();

                let expected: Vec<(u32, f64)> =
                    (whole.readout(w.spikes).unwrap().spikes().iter().copied())
                        .filter(|s| s.1 > 0.7 + DT / 2.0)
                        .collect();
                assert!(
                    expected.len() > 20,
                    "{case}: the output spikes after the save ({})",
                    expected.len()
                );
                assert_eq!(
                    second.readout(spikes).unwrap().spikes(),
                    &expected[..],
                    "{case}: spikes"
                );
                for (loaded, original) in [(into_hidden, w.into_hidden), (into_out, w.into_out)] {
                    assert_eq!(
                        second.weights(loaded).unwrap(),
                        whole.weights(original).unwrap(),
                        "{case}: weights"
                    );
                }
                for var in ["v", "u"] {
                    assert_eq!(
                        bits(second.state(out, var).unwrap()),
                        bits(whole.state(w.out, var).unwrap()),
                        "{case}: out {var}"
                    );
                }
                assert_eq!(
                    bits(second.state(hidden, "v").unwrap()),
                    bits(whole.state(w.hidden, "v").unwrap()),
                    "{case}: hidden v"
                );
            }
        }
    }
}
