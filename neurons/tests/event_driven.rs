//! Event-driven populations (issue 16 item 4): work follows activity, spikes stay those of the
//! clock-driven network.

use neurotac_core::{
    Connectivity, ExpSynapse, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig, NeuronModel,
    ReadoutId, SpikeArrayInput, SpikeRecorder,
};
use neurotac_neurons::{Integrator, Izhikevich, IzhikevichParams, Lif, LifParams};
use rand::{RngExt, SeedableRng};

const DT: f64 = 1e-4;

/// `n` taxel channels of which `active` (evenly spaced) fire as Poisson trains at `rate_hz` over
/// `duration_s` (seeded); the others are silent.
fn taxels(n: usize, active: usize, rate_hz: f64, duration_s: f64, seed: u64) -> MultiSpikeTrain {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let stride = n / active;
    let channels = (0..n).map(|c| {
        let mut train = Vec::new();
        if c % stride == 0 && c / stride < active {
            let mut t = -(1.0 - rng.random::<f64>()).ln() / rate_hz;
            while t < duration_s {
                train.push(t);
                t += -(1.0 - rng.random::<f64>()).ln() / rate_hz;
            }
        }
        train
    });
    MultiSpikeTrain::from_channels(channels.collect::<Vec<_>>()).unwrap()
}

/// Taxels → exponential synapses (τ 5 ms, weight 5) → `model` (a population named "pop"),
/// its spikes recorded (and its `v` when `with_state`), built at step `DT`.
fn pipeline(
    input: &MultiSpikeTrain,
    model: impl NeuronModel + 'static,
    event_driven: bool,
    with_state: bool,
) -> (Network, ReadoutId<SpikeRecorder>) {
    let mut b = NetworkBuilder::new();
    b.event_driven(event_driven);
    let taxels = b
        .add_spike_input("taxels", SpikeArrayInput::new(input.clone()))
        .unwrap();
    let pop = b.add_population("pop", model).unwrap();
    b.connect(
        taxels,
        pop,
        Connectivity::OneToOne { weight: 5.0 },
        ExpSynapse::new(5e-3).with_delay(0),
    )
    .unwrap();
    let spikes = b.record_spikes(pop).unwrap();
    if with_state {
        b.record_state(pop, "v", None, 1).unwrap();
    }
    (b.build(NetworkConfig { dt_s: DT }).unwrap(), spikes)
}

/// The afferent pipeline with LIF afferents (exact), run for 1 s: the network and its spikes.
fn afferents(
    input: &MultiSpikeTrain,
    lif: LifParams,
    event_driven: bool,
) -> (Network, Vec<(u32, f64)>) {
    let model = Lif::<f64>::new(input.n_channels(), lif).with_integrator(Integrator::Exact);
    let (mut net, spikes) = pipeline(input, model, event_driven, false);
    net.run(1.0).unwrap();
    let out = net.readout(spikes).spikes().to_vec();
    (net, out)
}

#[test]
fn event_driven_lif_spikes_as_the_clock_driven_one_with_far_fewer_updates() {
    let input = taxels(1000, 10, 40.0, 0.9, 1);
    for params in [
        LifParams::default(),
        LifParams {
            t_ref_s: 2e-3,
            v_rest: -0.2,
            ..LifParams::default()
        },
    ] {
        let (clock, clock_spikes) = afferents(&input, params, false);
        let (event, event_spikes) = afferents(&input, params, true);
        assert!(clock.event_driven_populations().is_empty());
        assert_eq!(event.event_driven_populations(), ["pop"]);
        assert!(!clock_spikes.is_empty());
        assert_eq!(event_spikes, clock_spikes, "{params:?}");
        assert_eq!(clock.neuron_updates(), 1000 * 10_000);
        // 1 % of the taxels drive their afferents; the others are never touched.
        assert!(
            event.neuron_updates() * 50 < clock.neuron_updates(),
            "{} vs {}",
            event.neuron_updates(),
            clock.neuron_updates()
        );
    }
}

#[test]
fn updates_scale_with_the_input_events() {
    // k taxels, each with one spike at 0.1 s: every afferent is updated while its synaptic
    // current lasts, the same number of steps for each.
    let updates = |k: usize| {
        let channels: Vec<Vec<f64>> = (0..100)
            .map(|c| if c < k { vec![0.1] } else { Vec::new() })
            .collect();
        let input = MultiSpikeTrain::from_channels(channels).unwrap();
        afferents(&input, LifParams::default(), true)
            .0
            .neuron_updates()
    };
    let (u0, u1, u2, u8) = (updates(0), updates(1), updates(2), updates(8));
    assert_eq!(u0, 0);
    assert!(u1 > 0 && u1 < 10_000, "{u1}");
    assert_eq!((u2, u8), (2 * u1, 8 * u1));
}

#[test]
fn populations_that_cannot_skip_stay_clock_driven() {
    let input = MultiSpikeTrain::from_channels(vec![vec![0.01], vec![]]).unwrap();
    let build = |with_state: bool, izhikevich: bool, interpolate: bool| {
        let network = if izhikevich {
            pipeline(
                &input,
                Izhikevich::<f64>::new(2, IzhikevichParams::rs()),
                true,
                with_state,
            )
        } else {
            let lif = Lif::<f64>::new(2, LifParams::default()).with_interpolation(interpolate);
            pipeline(&input, lif, true, with_state)
        };
        network.0
    };
    assert_eq!(
        build(false, false, false).event_driven_populations(),
        ["pop"]
    );
    // A state readout, an Izhikevich model (no closed form at rest here), interpolated spike
    // times: clock-driven.
    assert!(
        build(true, false, false)
            .event_driven_populations()
            .is_empty()
    );
    assert!(
        build(false, true, false)
            .event_driven_populations()
            .is_empty()
    );
    assert!(
        build(false, false, true)
            .event_driven_populations()
            .is_empty()
    );
}
