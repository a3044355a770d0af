//! Event-driven populations: work follows activity, spikes stay those of the clock-driven
//! network.

use neurotac_core::{
    Connectivity, ExpSynapse, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig, NeuronModel,
    ReadoutId, SpikeArrayInput, SpikeBuffer, SpikeRecorder,
};
use neurotac_neurons::{
    InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Real,
};
use rand::SeedableRng;

mod common;
use common::push_poisson;

const DT: f64 = 1e-4;

/// `n` taxel channels of which `active` (evenly spaced) fire as Poisson trains at `rate_hz` over
/// `duration_s` (seeded); the others are silent.
fn taxels(n: usize, active: usize, rate_hz: f64, duration_s: f64, seed: u64) -> MultiSpikeTrain {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let stride = n / active;
    let channels = (0..n).map(|c| {
        let mut train = Vec::new();
        if c % stride == 0 && c / stride < active {
            push_poisson(&mut train, &mut rng, rate_hz, 0.0, duration_s);
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
    net.run(1.0, &neurotac_core::OneProcess).unwrap();
    let out = net.readout(spikes).unwrap().spikes().to_vec();
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

/// The afferent pipeline with Izhikevich RS afferents starting at rest (`tolerance` in mV),
/// run for 1 s: the network, its spikes and the afferents' final `(v, u)`.
fn izhikevich_afferents(
    input: &MultiSpikeTrain,
    tolerance: f64,
    event_driven: bool,
) -> (Network, Vec<(u32, f64)>) {
    let params = IzhikevichParams {
        rest_tolerance: tolerance,
        ..IzhikevichParams::rs()
    };
    let rest = params.resting_potential().unwrap();
    let model = Izhikevich::<f64>::new(input.n_channels(), params)
        .with_initial_potential(InitialPotential::Constant(rest));
    let (mut net, spikes) = pipeline(input, model, event_driven, false);
    net.run(1.0, &neurotac_core::OneProcess).unwrap();
    let out = net.readout(spikes).unwrap().spikes().to_vec();
    (net, out)
}

#[test]
fn event_driven_izhikevich_holds_neurons_at_rest_and_spikes_as_clock_driven() {
    let input = taxels(1000, 10, 40.0, 0.9, 2);
    let tolerance = IzhikevichParams::rs().rest_tolerance;
    let (clock, clock_spikes) = izhikevich_afferents(&input, tolerance, false);
    let (event, event_spikes) = izhikevich_afferents(&input, tolerance, true);
    assert!(clock.event_driven_populations().is_empty());
    assert_eq!(event.event_driven_populations(), ["pop"]);
    assert!(clock_spikes.len() > 20, "{}", clock_spikes.len());
    assert_eq!(event_spikes, clock_spikes);
    // The 10 driven neurons are stepped while they have input and while they settle back to
    // rest; the 990 silent ones are never touched.
    assert!(
        event.neuron_updates() <= 10 * 10_000,
        "{}",
        event.neuron_updates()
    );
    assert!(
        event.neuron_updates() > 10 * 1_000,
        "{}",
        event.neuron_updates()
    );
}

/// One RS neuron from rest, driven at 20 for 5 ms from 50 ms (it spikes), then left without
/// input for the rest of `steps` steps of 0.1 ms, clock- and event-driven with `integrator`:
/// the two neurons after `settle`, their spike counts and the event-driven updates.
fn izhikevich_pulse<F: Real>(
    params: IzhikevichParams,
    integrator: Integrator,
    steps: usize,
) -> [((f64, f64), usize, u64); 2] {
    let rest = params.resting_potential().unwrap();
    let mut clock = Izhikevich::<F>::new(1, params)
        .with_integrator(integrator)
        .with_initial_potential(InitialPotential::Constant(rest));
    let mut event = clock.clone();
    clock.prepare(DT).unwrap();
    event.prepare(DT).unwrap();
    assert!(event.event_driven());
    let mut spikes = SpikeBuffer::default();
    let (mut clock_spikes, mut event_spikes, mut updates) = (0, 0, 0);
    for k in 0..steps {
        let input = if (500..550).contains(&k) { 20.0 } else { 0.0 };
        spikes.clear();
        clock.step(&[input], &mut spikes);
        clock_spikes += spikes.len();
        spikes.clear();
        updates += if input != 0.0 {
            event.step_active(&[0], &[input], &mut spikes)
        } else {
            event.step_active(&[], &[], &mut spikes)
        };
        event_spikes += spikes.len();
    }
    event.settle();
    [
        (clock.state_of(0), clock_spikes, steps as u64),
        (event.state_of(0), event_spikes, updates),
    ]
}

#[test]
fn izhikevich_held_by_default_only_where_the_clock_driven_step_stays() {
    // The default holds a neuron once a step at input 0 no longer moves it, so after any
    // quiet stretch its state is the clock-driven one bit for bit, at any length of the run.
    let integrators = [
        Integrator::Izhikevich2003,
        Integrator::Euler,
        Integrator::ExponentialEuler,
        Integrator::Rk2,
        Integrator::Rk4,
    ];
    for integrator in integrators {
        for steps in [3_000, 10_000, 20_000, 40_000] {
            let runs = [
                (
                    "f64",
                    izhikevich_pulse::<f64>(IzhikevichParams::rs(), integrator, steps),
                ),
                (
                    "f32",
                    izhikevich_pulse::<f32>(IzhikevichParams::rs(), integrator, steps),
                ),
            ];
            for (precision, [(clock, clock_spikes, _), (event, event_spikes, updates)]) in runs {
                let at = format!("{integrator:?} {precision} after {steps} steps");
                assert!(clock_spikes > 0, "{at}");
                assert_eq!(event_spikes, clock_spikes, "{at}");
                assert_eq!(event.0.to_bits(), clock.0.to_bits(), "v, {at}");
                assert_eq!(event.1.to_bits(), clock.1.to_bits(), "u, {at}");
                if steps >= 20_000 {
                    // Held from some point on: not stepped for the whole run.
                    assert!(updates < steps as u64 - 2_000, "{at}: {updates}");
                }
            }
        }
    }
}

#[test]
fn izhikevich_state_held_at_rest_stays_within_the_tolerance() {
    // With a positive tolerance a neuron is held once back within it of rest: its state after
    // `settle` is within the tolerance of the clock-driven one (which keeps converging to the
    // resting point), after fewer updates than the exact default.
    let (v_rest, u_rest) = (-70.0, -14.0);
    assert!((IzhikevichParams::rs().resting_potential().unwrap() - v_rest).abs() < 1e-12);
    let [_, (_, _, exact_updates)] =
        izhikevich_pulse::<f64>(IzhikevichParams::rs(), Integrator::Izhikevich2003, 10_000);
    for tolerance in [1e-1, 1e-3] {
        let params = IzhikevichParams {
            rest_tolerance: tolerance,
            ..IzhikevichParams::rs()
        };
        let [
            ((v_c, u_c), clock_spikes, _),
            ((v_e, u_e), event_spikes, updates),
        ] = izhikevich_pulse::<f64>(params, Integrator::Izhikevich2003, 10_000);
        assert!(clock_spikes > 0);
        assert_eq!(event_spikes, clock_spikes);
        assert!((v_e - v_rest).abs() <= tolerance && (u_e - u_rest).abs() <= tolerance);
        assert!((v_e - v_c).abs() <= 2.0 * tolerance, "{v_e} vs {v_c}");
        assert!((u_e - u_c).abs() <= 2.0 * tolerance, "{u_e} vs {u_c}");
        // Stepped from the input until back within the tolerance, not for the whole second.
        assert!(updates > 100 && updates < 9_000, "{tolerance}: {updates}");
        assert!(
            updates < exact_updates,
            "{tolerance}: {updates} vs {exact_updates}"
        );
    }
}

#[test]
fn izhikevich_updates_scale_with_the_input_events() {
    let updates = |k: usize| {
        let channels: Vec<Vec<f64>> = (0..100)
            .map(|c| if c < k { vec![0.1] } else { Vec::new() })
            .collect();
        let input = MultiSpikeTrain::from_channels(channels).unwrap();
        izhikevich_afferents(&input, 1e-3, true).0.neuron_updates()
    };
    let (u0, u1, u2, u8) = (updates(0), updates(1), updates(2), updates(8));
    assert_eq!(u0, 0);
    assert!(u1 > 0 && u1 < 10_000, "{u1}");
    assert_eq!((u2, u8), (2 * u1, 8 * u1));
}

#[test]
fn izhikevich_away_from_rest_is_stepped_until_it_settles() {
    // From the default −65 mV every neuron is stepped, without input, until it reaches the
    // step's fixed point at rest (≈ 1.1 s in f64 at 0.1 ms), then held.
    let input = MultiSpikeTrain::from_channels(vec![Vec::new(); 10]).unwrap();
    let model = Izhikevich::<f64>::new(10, IzhikevichParams::rs());
    let (mut clock, _) = pipeline(&input, model.clone(), false, false);
    let (mut event, _) = pipeline(&input, model, true, false);
    clock.run(2.0, &neurotac_core::OneProcess).unwrap();
    event.run(2.0, &neurotac_core::OneProcess).unwrap();
    let updates = event.neuron_updates();
    assert!(
        updates > 10 * 1_000 && updates < clock.neuron_updates(),
        "{updates}"
    );
    assert_eq!(updates % 10, 0);
}

#[test]
fn populations_that_cannot_skip_stay_clock_driven() {
    let izhikevich = |tolerance: f64, interpolate: bool| {
        let params = IzhikevichParams {
            rest_tolerance: tolerance,
            ..IzhikevichParams::rs()
        };
        Izhikevich::<f64>::new(2, params).with_interpolation(interpolate)
    };
    let lif = |interpolate: bool| {
        Lif::<f64>::new(2, LifParams::default()).with_interpolation(interpolate)
    };
    fn event_driven(model: impl NeuronModel + 'static, with_state: bool) -> bool {
        let input = MultiSpikeTrain::from_channels(vec![vec![0.01], vec![]]).unwrap();
        !pipeline(&input, model, true, with_state)
            .0
            .event_driven_populations()
            .is_empty()
    }
    assert!(event_driven(lif(false), false));
    assert!(event_driven(izhikevich(1e-3, false), false));
    assert!(event_driven(izhikevich(0.0, false), false));
    // A state readout, interpolated spike times, Izhikevich without decay (a = 0: no stable
    // resting point): clock-driven.
    assert!(!event_driven(lif(false), true));
    assert!(!event_driven(lif(true), false));
    assert!(!event_driven(izhikevich(1e-3, true), false));
    assert!(!event_driven(izhikevich(0.0, true), false));
    let no_decay = IzhikevichParams {
        a: 0.0,
        ..IzhikevichParams::rs()
    };
    assert!(!event_driven(Izhikevich::<f64>::new(2, no_decay), false));
}
