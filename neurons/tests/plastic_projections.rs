//! Plastic projections (STDP) in the graph, with the real neuron models: the weight change
//! of one pre/post pair is the closed-form window, traces sum every earlier spike exactly,
//! weights stay in their bounds, frozen learning changes nothing, and learning is the same
//! clock- and event-driven and at any rank count.

mod common;

use neurotac_core::ranks::ThreadRanks;
use neurotac_core::{
    Connectivity, ExpSynapse, GraphError, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig,
    OneProcess, PoissonInput, ProjectionId, Ranks, SpikeArrayInput, Stdp, Stepping, Synapse,
};
use neurotac_neurons::{Izhikevich, Lif, LifParams};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const DT: f64 = 1e-4;

/// The rule of the window tests: τ₊ = 20 ms, τ₋ = 30 ms (different, so a swap shows).
fn rule() -> Stdp {
    Stdp::additive(0.02, 0.03, 0.01, 0.012, 1.0)
}

/// One LIF neuron made to spike exactly at the `teacher` times (a huge, instantly decaying
/// current), with a plastic synapse from one input spiking at `pre` times (weight `w0`, too
/// weak to make it spike). Returns the weight after the run.
fn weight_after(pre: &[f64], teacher: &[f64], stdp: Stdp, w0: f64, delay: u32) -> f64 {
    let mut b = NetworkBuilder::new();
    let input = b
        .add_spike_input(
            "pre",
            SpikeArrayInput::new(MultiSpikeTrain::from_channels(vec![pre.to_vec()]).unwrap()),
        )
        .unwrap();
    let teach = b
        .add_spike_input(
            "teacher",
            SpikeArrayInput::new(MultiSpikeTrain::from_channels(vec![teacher.to_vec()]).unwrap()),
        )
        .unwrap();
    let neuron = b
        .add_population("post", Lif::<f64>::new(1, LifParams::default()))
        .unwrap();
    b.connect(
        teach,
        neuron,
        Connectivity::OneToOne { weight: 1e3 },
        ExpSynapse::new(1e-6).with_delay(0),
    )
    .unwrap();
    let plastic = b
        .connect_plastic(
            input,
            neuron,
            Connectivity::OneToOne { weight: w0 },
            ExpSynapse::new(1e-6).with_delay(delay),
            stdp,
        )
        .unwrap();
    let spikes = b.record_spikes(neuron).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    let end =
        pre.iter().chain(teacher).fold(0.0f64, |a, &t| a.max(t)) + 0.01 + f64::from(delay) * DT;
    net.run(end, &OneProcess).unwrap();
    // The neuron spikes at the teacher's steps and nowhere else.
    let steps: Vec<u64> = net
        .readout(spikes)
        .unwrap()
        .spikes()
        .iter()
        .map(|s| (s.1 / DT).round() as u64 - 1)
        .collect();
    let expected: Vec<u64> = teacher.iter().map(|t| (t / DT).round() as u64).collect();
    assert_eq!(
        steps, expected,
        "the teacher sets the postsynaptic spike steps"
    );
    net.weights(plastic).unwrap().weight[0]
}

/// `Δw` read as `w − w0` (w0 ≤ 1) against its closed form: to 10⁻¹² relative, or the rounding
/// of `w` itself (2 ulp of 1).
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs() + 2.0 * f64::EPSILON
}

#[test]
fn a_single_pair_changes_the_weight_by_the_closed_form_window() {
    let w0 = 0.5;
    for delay in [0u32, 3] {
        for dk in [-900i64, -300, -37, -1, 0, 1, 2, 50, 333, 1200] {
            // Presynaptic arrival at step 1000 (emission `delay` steps earlier), post at 1000 + dk.
            let arrive = 1000i64;
            let pre = [((arrive - i64::from(delay)) as f64) * DT];
            let post = [((arrive + dk) as f64) * DT];
            let got = weight_after(&pre, &post, rule(), w0, delay) - w0;
            let expected = rule().window(dk as f64 * DT);
            assert!(
                close(got, expected),
                "delay {delay}, Δk {dk}: Δw {got} vs window {expected}"
            );
        }
    }
    // Multiplicative: potentiation ∝ w_max − w, depression ∝ w − w_min.
    let m = rule().multiplicative();
    let got = weight_after(&[0.1], &[0.1 + 40.0 * DT], m, 0.25, 0) - 0.25;
    assert!(
        close(got, 0.01 * 0.75 * (-40.0 * DT / 0.02f64).exp()),
        "{got}"
    );
    let got = weight_after(&[0.1 + 40.0 * DT], &[0.1], m, 0.25, 0) - 0.25;
    assert!(
        close(got, -0.012 * 0.25 * (-40.0 * DT / 0.03f64).exp()),
        "{got}"
    );
}

#[test]
fn traces_sum_every_earlier_spike_exactly_at_any_spacing() {
    // Irregular presynaptic spikes, 1 step to 80 ms apart, then one postsynaptic spike.
    let pre_steps = [100u64, 101, 103, 110, 190, 900, 1700, 1701, 2500];
    let post_step = 2600u64;
    let pre: Vec<f64> = pre_steps.iter().map(|&k| k as f64 * DT).collect();
    let post = [post_step as f64 * DT];
    let x: f64 = pre_steps
        .iter()
        .map(|&k| (-((post_step - k) as f64) * DT / 0.02).exp())
        .sum();
    // No post spike before the pre spikes: only potentiation, by a₊·x_pre(t_post).
    let got = weight_after(&pre, &post, rule(), 0.5, 0) - 0.5;
    assert!(close(got, 0.01 * x), "all-to-all: {got} vs {}", 0.01 * x);
    let last = (-((post_step - 2500) as f64) * DT / 0.02).exp();
    let got = weight_after(&pre, &post, rule().nearest(), 0.5, 0) - 0.5;
    assert!(close(got, 0.01 * last), "nearest: {got} vs {}", 0.01 * last);
    // And the other way: post spikes at irregular spacing, then one pre arrival.
    let post_steps = [200u64, 205, 600, 2000];
    let y: f64 = post_steps
        .iter()
        .map(|&k| (-((2600 - k) as f64) * DT / 0.03).exp())
        .sum();
    let teacher: Vec<f64> = post_steps.iter().map(|&k| k as f64 * DT).collect();
    let got = weight_after(&[2600.0 * DT], &teacher, rule(), 0.5, 0) - 0.5;
    assert!(close(got, -0.012 * y), "{got} vs {}", -0.012 * y);
}

/// 200 Poisson inputs at `rate_hz` onto `n` LIF neurons through a plastic all-to-all projection.
fn poisson_network(
    rule: Stdp,
    w0: f64,
    stepping: Stepping,
) -> (
    NetworkBuilder,
    ProjectionId,
    neurotac_core::ReadoutId<neurotac_core::SpikeRecorder>,
) {
    let mut b = NetworkBuilder::new();
    b.stepping(stepping);
    let input = b
        .add_spike_input("inputs", PoissonInput::new(200, 20.0, 7))
        .unwrap();
    let out = b
        .add_population("out", Lif::<f64>::new(4, LifParams::default()))
        .unwrap();
    let p = b
        .connect_plastic(
            input,
            out,
            Connectivity::AllToAll { weight: w0 },
            ExpSynapse::new(5e-3),
            rule,
        )
        .unwrap();
    let r = b.record_spikes(out).unwrap();
    (b, p, r)
}

#[test]
fn weights_stay_within_their_bounds() {
    for rule in [
        Stdp::additive(0.02, 0.02, 0.05, 0.06, 0.3),
        Stdp::additive(0.02, 0.02, 0.2, 0.25, 0.3).multiplicative(),
    ] {
        let (b, p, _) = poisson_network(rule, 0.15, Stepping::Clock);
        let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
        net.run(2.0, &OneProcess).unwrap();
        let w = net.weights(p).unwrap().weight;
        assert!(
            w.iter().all(|&x| (0.0..=0.3).contains(&x)),
            "{:?}",
            rule.dependence
        );
        let moved = w.iter().filter(|&&x| x != 0.15).count();
        assert!(
            moved > w.len() / 2,
            "{:?}: most weights learned ({moved} of {})",
            rule.dependence,
            w.len()
        );
        if rule.dependence == neurotac_core::WeightDependence::Additive {
            assert!(
                w.contains(&0.0) && w.contains(&0.3),
                "additive weights reach both bounds"
            );
        }
    }
}

#[test]
fn frozen_learning_changes_nothing() {
    let rule = Stdp::additive(0.02, 0.02, 0.05, 0.06, 0.3);
    // Learn a while, then freeze: weights stay, and the spikes are those of a fixed network
    // with the learned weights.
    let (b, p, r) = poisson_network(rule, 0.15, Stepping::Clock);
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    net.run(0.5, &OneProcess).unwrap();
    net.set_learning(p, false).unwrap();
    assert!(!net.is_learning(p).unwrap());
    let learned = net.weights(p).unwrap();
    net.reset();
    net.run(1.0, &OneProcess).unwrap();
    assert_eq!(
        net.weights(p).unwrap(),
        learned,
        "frozen weights do not move"
    );
    let frozen_spikes = net.readout(r).unwrap().spikes().to_vec();

    let mut b = NetworkBuilder::new();
    let input = b
        .add_spike_input("inputs", PoissonInput::new(200, 20.0, 7))
        .unwrap();
    let out = b
        .add_population("out", Lif::<f64>::new(4, LifParams::default()))
        .unwrap();
    let list = (0..learned.len())
        .map(|s| Synapse {
            pre: learned.pre[s],
            post: learned.post[s],
            weight: learned.weight[s],
        })
        .collect();
    b.connect(
        input,
        out,
        Connectivity::Sparse(list),
        ExpSynapse::new(5e-3),
    )
    .unwrap();
    let fixed = b.record_spikes(out).unwrap();
    let mut fixed_net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    fixed_net.run(1.0, &OneProcess).unwrap();
    assert!(!frozen_spikes.is_empty());
    assert_eq!(frozen_spikes, fixed_net.readout(fixed).unwrap().spikes());
}

/// One rank's result of [`two_layers`]: every learned weight (all ranks', by postsynaptic then
/// presynaptic neuron) and the output spikes as (neuron, step).
type Learned = (Vec<f64>, Vec<(u32, u64)>);

/// Learned weights and spikes of a plastic Izhikevich layer fed by a plastic LIF layer.
fn two_layers(stepping: Stepping, size: usize) -> Vec<Learned> {
    ThreadRanks::run(size, |ranks| {
        let mut b = NetworkBuilder::new();
        b.stepping(stepping.clone());
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let trains: Vec<Vec<f64>> = (0..60)
            .map(|_| {
                let mut t = Vec::new();
                common::push_poisson(&mut t, &mut rng, 15.0, 0.0, 2.0);
                t
            })
            .collect();
        let input = b
            .add_spike_input(
                "in",
                SpikeArrayInput::new(MultiSpikeTrain::from_channels(trains).unwrap()),
            )
            .unwrap();
        let hidden = b
            .add_population("hidden", Lif::<f64>::new(20, LifParams::default()))
            .unwrap();
        let out = b
            .add_population("out", Izhikevich::<f64>::new(7, Default::default()))
            .unwrap();
        let rule = Stdp::additive(0.02, 0.02, 0.02, 0.022, 0.6);
        let a = b
            .connect_plastic(
                input,
                hidden,
                Connectivity::Random {
                    probability: 0.5,
                    weight: 0.3,
                    seed: 2,
                },
                ExpSynapse::new(5e-3),
                rule,
            )
            .unwrap();
        let c = b
            .connect_plastic(
                hidden,
                out,
                Connectivity::AllToAll { weight: 3.0 },
                ExpSynapse::new(5e-3).with_delay(20),
                Stdp::additive(0.02, 0.02, 0.2, 0.21, 6.0),
            )
            .unwrap();
        let r = b.record_spikes(out).unwrap();
        let mut net: Network = if size == 1 {
            b.build(NetworkConfig { dt_s: DT }).unwrap()
        } else {
            b.build_partitioned(NetworkConfig { dt_s: DT }, ranks.rank(), ranks.size())
                .unwrap()
        };
        net.run(2.0, ranks).unwrap();
        let mut w = net.weights(a).unwrap();
        let wc = net.weights(c).unwrap();
        // Gather every rank's synapses (each holds those onto its own neurons), by (pre, post).
        let mut all: Vec<(u32, u32, f64)> = Vec::new();
        for weights in [&mut w, &mut wc.clone()] {
            let mine: Vec<u8> = (0..weights.len())
                .flat_map(|s| {
                    let mut v = weights.pre[s].to_le_bytes().to_vec();
                    v.extend(weights.post[s].to_le_bytes());
                    v.extend(weights.weight[s].to_le_bytes());
                    v
                })
                .collect();
            for block in ranks.all_gather_bytes(&mine).unwrap() {
                for c in block.chunks(16) {
                    all.push((
                        u32::from_le_bytes(c[0..4].try_into().unwrap()),
                        u32::from_le_bytes(c[4..8].try_into().unwrap())
                            + if weights.n_post == 7 { 1_000_000 } else { 0 },
                        f64::from_le_bytes(c[8..16].try_into().unwrap()),
                    ));
                }
            }
        }
        all.sort_by_key(|s| (s.1, s.0));
        let spikes = net
            .readout(r)
            .unwrap()
            .spikes()
            .iter()
            .map(|s| (s.0, (s.1 / DT).round() as u64))
            .collect();
        (all.into_iter().map(|s| s.2).collect(), spikes)
    })
}

#[test]
fn learning_is_the_same_clock_and_event_driven_and_at_any_rank_count() {
    let clock = two_layers(Stepping::Clock, 1).remove(0);
    assert!(!clock.1.is_empty(), "the output layer spikes");
    assert!(
        clock.0.iter().filter(|&&w| w != 0.3 && w != 3.0).count() > clock.0.len() / 2,
        "weights learned"
    );
    let event = two_layers(Stepping::Event, 1).remove(0);
    assert_eq!(event.1, clock.1, "event-driven spikes");
    assert_eq!(event.0, clock.0, "event-driven weights, bit for bit");
    for size in [2, 3] {
        for (rank, got) in two_layers(Stepping::Clock, size).into_iter().enumerate() {
            assert_eq!(got.0, clock.0, "{size} ranks, rank {rank}: weights");
            assert_eq!(got.1, clock.1, "{size} ranks, rank {rank}: spikes");
        }
    }
}

#[test]
fn weights_read_write_and_refuse_what_does_not_fit() {
    let (b, p, _) = poisson_network(
        Stdp::additive(0.02, 0.02, 0.05, 0.06, 0.3),
        0.15,
        Stepping::Clock,
    );
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    let mut w = net.weights(p).unwrap();
    assert_eq!((w.n_pre, w.n_post, w.len()), (200, 4, 800));
    assert_eq!(w.dense().shape(), &[200, 4]);
    w.weight[5] = 0.29;
    net.set_weights(p, &w).unwrap();
    assert_eq!(net.weights(p).unwrap().dense()[(1, 1)], 0.29);
    let mut outside = w.clone();
    outside.weight[3] = 0.31;
    let e = net.set_weights(p, &outside).unwrap_err();
    assert!(
        matches!(e, GraphError::WeightOutsideBounds { .. }) && e.to_string().contains("synapse 3"),
        "{e}"
    );
    let mut short = w.clone();
    short.weight.pop();
    assert!(matches!(
        net.set_weights(p, &short),
        Err(GraphError::SizeMismatch { .. })
    ));
    assert_eq!(
        net.weights(p).unwrap().dense()[(1, 1)],
        0.29,
        "a refused write changes nothing"
    );
    // A plastic projection refuses initial weights outside its bounds.
    let mut b = NetworkBuilder::new();
    let i = b
        .add_spike_input("i", PoissonInput::new(2, 10.0, 1))
        .unwrap();
    let o = b
        .add_population("o", Lif::<f64>::new(2, LifParams::default()))
        .unwrap();
    let e = b
        .connect_plastic(
            i,
            o,
            Connectivity::OneToOne { weight: 2.0 },
            ExpSynapse::new(5e-3),
            Stdp::additive(0.02, 0.02, 0.1, 0.1, 1.0),
        )
        .unwrap_err();
    assert!(e.to_string().contains("initial weight"), "{e}");
    let fixed = b
        .connect(
            i,
            o,
            Connectivity::OneToOne { weight: 2.0 },
            ExpSynapse::new(5e-3),
        )
        .unwrap();
    b.record_spikes(o).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    assert!(matches!(
        net.set_learning(fixed, false),
        Err(GraphError::NotPlastic { .. })
    ));
    assert_eq!(net.state(o, "v").unwrap(), vec![0.0, 0.0]);
}
