//! Automatic stepping ([`Stepping::Auto`]): a population picks clock- or event-driven stepping
//! from its measured activity, switches when the activity crosses its crossover mid-run, and
//! its spikes stay those of the clock-driven network whatever the mode.

use neurotac_core::{
    Connectivity, Crossovers, ExpSynapse, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig,
    NeuronModel, OneProcess, SpikeArrayInput, Stepping, SteppingMode,
};
use neurotac_neurons::{
    InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams,
};
use rand::SeedableRng;

mod common;
use common::push_poisson;

const DT: f64 = 1e-4;
const N: usize = 1000;
/// The crossover the tests decide with (a fixed number, so the modes do not depend on the
/// machine's measured crossover).
const CROSSOVER: f64 = 0.04;

/// `N` taxel channels; channel `c` fires as a Poisson train at 40 Hz (seeded) during those of
/// the `phases` `(from_s, to_s, active)` whose `active` fraction of channels (evenly spaced)
/// includes it.
fn taxels(phases: &[(f64, f64, f64)], seed: u64) -> MultiSpikeTrain {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let channels = (0..N).map(|c| {
        let mut train = Vec::new();
        for &(from, to, active) in phases {
            let k = ((N as f64 * active).round() as usize).max(1);
            let stride = N / k;
            if !(c % stride == 0 && c / stride < k) {
                continue;
            }
            push_poisson(&mut train, &mut rng, 40.0, from, to);
        }
        train
    });
    MultiSpikeTrain::from_channels(channels.collect::<Vec<_>>()).unwrap()
}

/// Taxels → exponential synapses (τ 5 ms) → `model` ("pop"), stepped as `stepping`, run for
/// `duration_s`: the network and the population's spikes.
fn run(
    input: &MultiSpikeTrain,
    model: impl NeuronModel + 'static,
    weight: f64,
    stepping: Stepping,
    duration_s: f64,
) -> (Network, Vec<(u32, f64)>) {
    let mut b = NetworkBuilder::new();
    b.stepping(stepping);
    let taxels = b
        .add_spike_input("taxels", SpikeArrayInput::new(input.clone()))
        .unwrap();
    let pop = b.add_population("pop", model).unwrap();
    b.connect(
        taxels,
        pop,
        Connectivity::OneToOne { weight },
        ExpSynapse::new(5e-3).with_delay(0),
    )
    .unwrap();
    let spikes = b.record_spikes(pop).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    net.run(duration_s, &OneProcess).unwrap();
    let out = net.readout(spikes).unwrap().spikes().to_vec();
    (net, out)
}

fn auto() -> Stepping {
    let mut c = Crossovers::default();
    c.set(lif().model_name(), CROSSOVER).unwrap();
    c.set(izhikevich().model_name(), CROSSOVER).unwrap();
    Stepping::Auto(c)
}

fn lif() -> Lif<f64> {
    let params = LifParams {
        t_ref_s: 2e-3,
        ..LifParams::default()
    };
    Lif::<f64>::new(N, params).with_integrator(Integrator::Exact)
}

/// Izhikevich RS afferents from rest, with the default exact hold at rest.
fn izhikevich() -> Izhikevich<f64> {
    let params = IzhikevichParams::rs();
    let rest = params.resting_potential().unwrap();
    Izhikevich::<f64>::new(N, params).with_initial_potential(InitialPotential::Constant(rest))
}

/// Runs `input` through `model()` clock-driven and automatically; asserts identical spikes and
/// returns the automatic network's `(mode, activity, switches)`.
fn compare<M: NeuronModel + 'static>(
    name: &str,
    model: impl Fn() -> M,
    input: &MultiSpikeTrain,
    duration_s: f64,
) -> (SteppingMode, f64, u64) {
    let (_, clock) = run(input, model(), 5.0, Stepping::Clock, duration_s);
    let (net, auto) = run(input, model(), 5.0, auto(), duration_s);
    assert!(!clock.is_empty(), "{name}: the test must exercise spiking");
    let first = auto.iter().zip(&clock).position(|(a, c)| a != c);
    assert!(
        auto.len() == clock.len() && first.is_none(),
        "{name}: automatic spikes differ from clock-driven ({} against {}; first at {first:?}: \
         {:?} against {:?})",
        auto.len(),
        clock.len(),
        first.map(|i| auto[i]),
        first.map(|i| clock[i]),
    );
    let [report] = &net.stepping_report()[..] else {
        panic!("one population")
    };
    assert_eq!(report.crossover, Some(CROSSOVER));
    (report.mode, report.activity.unwrap(), report.switches)
}

/// [`compare`] with LIF afferents (exact, with a refractory period) and Izhikevich RS afferents
/// from rest.
fn auto_against_clock(
    input: &MultiSpikeTrain,
    duration_s: f64,
) -> [(&'static str, (SteppingMode, f64, u64)); 2] {
    [
        ("LIF", compare("LIF", lif, input, duration_s)),
        (
            "Izhikevich",
            compare("Izhikevich", izhikevich, input, duration_s),
        ),
    ]
}

#[test]
fn automatic_stepping_spikes_as_clock_driven_at_every_activity() {
    for (active, mode) in [
        (0.001, SteppingMode::Event),
        (0.01, SteppingMode::Event),
        (0.1, SteppingMode::Clock),
        (1.0, SteppingMode::Clock),
    ] {
        let input = taxels(&[(0.0, 1.0, active)], 7);
        for (name, (got, activity, _)) in auto_against_clock(&input, 1.0) {
            assert_eq!(got, mode, "{name} at {active}: activity {activity}");
            // The measured activity follows the taxels' (a synaptic current outlives its
            // spike, so it is at least the fraction of driven neurons).
            assert!(
                activity >= 0.5 * active && activity <= (20.0 * active).min(1.0),
                "{name} at {active}: activity {activity}"
            );
        }
    }
}

#[test]
fn the_mode_follows_the_activity_across_the_crossover_mid_run() {
    // Quiet, then busy: starts event-driven, turns clock-driven.
    let input = taxels(&[(0.0, 1.0, 0.001), (1.0, 2.0, 1.0)], 8);
    for (name, (mode, _, switches)) in auto_against_clock(&input, 2.0) {
        assert_eq!(
            (mode, switches),
            (SteppingMode::Clock, 1),
            "{name}, quiet → busy"
        );
    }
    // Busy, then quiet (the currents die out ~0.35 s after the last spike): clock-driven,
    // then event-driven again.
    let input = taxels(&[(0.0, 0.5, 1.0), (0.5, 2.0, 0.001)], 9);
    for (name, (mode, _, switches)) in auto_against_clock(&input, 2.0) {
        assert_eq!(
            (mode, switches),
            (SteppingMode::Event, 2),
            "{name}, busy → quiet"
        );
    }
    // Quiet, busy, quiet, busy: three switches, every one exact.
    let input = taxels(
        &[
            (0.0, 0.3, 0.001),
            (0.3, 0.8, 1.0),
            (0.8, 1.8, 0.001),
            (1.8, 2.4, 1.0),
        ],
        10,
    );
    for (name, (mode, _, switches)) in auto_against_clock(&input, 2.6) {
        assert_eq!(
            (mode, switches),
            (SteppingMode::Clock, 3),
            "{name}, four phases"
        );
    }
}
