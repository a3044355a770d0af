//! Networks partitioned over ranks ([`NetworkBuilder::build_partitioned`],
//! [`Network::run`]) give, on every rank, exactly the readouts of one process: the same
//! spikes, bit for bit, in the same order, whatever the number of ranks.

use neurotac_core::ranks::ThreadRanks;
use neurotac_core::{
    Connectivity, CurrentInput, ExpSynapse, GraphError, ModelError, MultiSpikeTrain, Network,
    NetworkBuilder, NetworkConfig, NeuronModel, OneProcess, PoissonInput, PopulationId, Ranks,
    RanksError, Readout, ReadoutId, SpikeArrayInput, SpikeBuffer, SpikeRecorder, StepView, Synapse,
};
use std::ops::{ControlFlow, Range};

/// A leaky integrator: `v ← v·decay + input`, a spike and reset to 0 at `v ≥ 1`, stamped at
/// the fraction `1 − (v − 1)/v` of the step when `interpolate`. Each neuron starts from a value
/// that depends on its global index, so a block restricted from the wrong place would show.
#[derive(Clone)]
struct Leaky {
    n: usize,
    first: usize,
    decay: f64,
    interpolate: bool,
    event_driven: bool,
    /// The global neuron whose rank reports a divergence after its first step.
    diverges: Option<usize>,
    v: Vec<f64>,
    steps: u64,
}

impl Leaky {
    fn new(n: usize) -> Self {
        Self {
            n,
            first: 0,
            decay: 0.9,
            interpolate: false,
            event_driven: false,
            diverges: None,
            v: Vec::new(),
            steps: 0,
        }
    }

    fn v0(global: usize) -> f64 {
        (global * 7919 % 1000) as f64 / 1000.0 * 0.95
    }
}

impl NeuronModel for Leaky {
    fn model_name(&self) -> &'static str {
        "leaky"
    }
    fn len(&self) -> usize {
        self.n
    }
    fn variables(&self) -> &'static [&'static str] {
        &["v"]
    }
    fn prepare(&mut self, _dt_s: f64) -> Result<(), ModelError> {
        self.reset();
        Ok(())
    }
    fn reset(&mut self) {
        self.v = (self.first..self.first + self.n).map(Self::v0).collect();
        self.steps = 0;
    }
    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer) {
        self.steps += 1;
        for (i, (v, &x)) in self.v.iter_mut().zip(current).enumerate() {
            *v = *v * self.decay + x;
            if *v >= 1.0 {
                if self.interpolate {
                    spikes.push_at(i as u32, 1.0 - (*v - 1.0) / *v);
                } else {
                    spikes.push(i as u32);
                }
                *v = 0.0;
            }
        }
    }
    fn check_divergence(&self) -> Result<(), ModelError> {
        match self.diverges {
            Some(g) if (self.first..self.first + self.n).contains(&g) && self.steps > 0 => {
                Err(ModelError::Diverged {
                    model: "leaky",
                    step: 0,
                    t_s: 0.0,
                    dt_s: 1e-3,
                    integrator: "none",
                    what: "asked to",
                })
            }
            _ => Ok(()),
        }
    }
    fn read_variable(&self, _var: usize, neurons: &[u32], out: &mut Vec<f64>) {
        out.extend(neurons.iter().map(|&i| self.v[i as usize]));
    }
    // The default `step_active` steps every neuron (the others at input 0): the clock-driven
    // result, through the event-driven path of the network.
    fn event_driven(&self) -> bool {
        self.event_driven
    }
    fn restrict(&self, range: Range<usize>) -> Option<Box<dyn NeuronModel>> {
        (range.end <= self.n).then(|| {
            Box::new(Leaky {
                n: range.len(),
                first: self.first + range.start,
                ..self.clone()
            }) as Box<dyn NeuronModel>
        })
    }
}

/// A model that cannot be split.
struct Whole(Leaky);

impl NeuronModel for Whole {
    fn model_name(&self) -> &'static str {
        "whole"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn variables(&self) -> &'static [&'static str] {
        self.0.variables()
    }
    fn prepare(&mut self, dt_s: f64) -> Result<(), ModelError> {
        self.0.prepare(dt_s)
    }
    fn reset(&mut self) {
        self.0.reset()
    }
    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer) {
        self.0.step(current, spikes)
    }
    fn read_variable(&self, var: usize, neurons: &[u32], out: &mut Vec<f64>) {
        self.0.read_variable(var, neurons, out)
    }
}

const DT: f64 = 1e-3;

struct Recorders {
    population_a: Option<PopulationId>,
    a: ReadoutId<SpikeRecorder>,
    b: ReadoutId<SpikeRecorder>,
    input: ReadoutId<SpikeRecorder>,
}

/// Two recurrent populations fed by a Poisson source, a replayed source and a per-neuron
/// current; population → population delays 2, 3 and 4 (epoch: 2 steps).
fn two_populations(
    (n_a, n_b): (usize, usize),
    leaky: impl Fn(usize) -> Leaky,
    event_driven: bool,
) -> (NetworkBuilder, Recorders) {
    let mut b = NetworkBuilder::new();
    b.event_driven(event_driven);
    let poisson = b
        .add_spike_input("poisson", PoissonInput::new(50, 150.0, 11))
        .unwrap();
    let replay: Vec<Vec<f64>> = (0..n_b)
        .map(|i| {
            (0..4)
                .map(|k| 0.013 * (i + 1) as f64 + 0.05 * k as f64)
                .collect()
        })
        .collect();
    let replay = b
        .add_spike_input(
            "replay",
            SpikeArrayInput::new(MultiSpikeTrain::from_channels(replay).unwrap()),
        )
        .unwrap();
    let pa = b.add_population("a", leaky(n_a)).unwrap();
    let pb = b.add_population("b", leaky(n_b)).unwrap();
    let random = |probability, weight, seed| Connectivity::Random {
        probability,
        weight,
        seed,
    };
    let syn = |delay| ExpSynapse::new(3e-3).with_delay(delay);
    b.connect(poisson, pa, random(0.3, 0.35, 1), syn(0))
        .unwrap();
    b.connect(replay, pb, Connectivity::OneToOne { weight: 0.8 }, syn(1))
        .unwrap();
    b.connect(pa, pb, random(0.25, 0.4, 2), syn(2)).unwrap();
    b.connect(pa, pa, random(0.1, 0.2, 3), syn(4)).unwrap();
    b.connect(pb, pb, Connectivity::AllToAll { weight: -0.02 }, syn(2))
        .unwrap();
    let back: Vec<Synapse> = (0..3 * n_b)
        .map(|k| Synapse {
            pre: (k % n_b) as u32,
            post: (k * 5 % n_a) as u32,
            weight: -0.3 + 0.01 * k as f64,
        })
        .collect();
    b.connect(pb, pa, Connectivity::Sparse(back), syn(3))
        .unwrap();
    let amplitude = (0..n_a).map(|i| 0.01 * (i % 5) as f64).collect();
    let bias = b
        .add_current_input("bias", CurrentInput::Constant { amplitude })
        .unwrap();
    b.inject(bias, pa).unwrap();
    let recorders = Recorders {
        population_a: Some(pa),
        a: b.record_spikes(pa).unwrap(),
        b: b.record_spikes(pb).unwrap(),
        input: b.record_spikes(poisson).unwrap(),
    };
    (b, recorders)
}

type Spikes = [Vec<(u32, f64)>; 3];

fn spikes(net: &Network, r: &Recorders) -> Spikes {
    [r.a, r.b, r.input].map(|id| net.readout(id).unwrap().spikes().to_vec())
}

/// Runs `steps` (in several calls) in one process and over 1, 2 and 3 thread ranks; every
/// rank's spikes must be the one-process ones.
fn same_spikes_on_any_rank_count(
    network: impl Fn() -> (NetworkBuilder, Recorders) + Sync,
    runs: &[u64],
) -> Spikes {
    let (b, r) = network();
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    for &steps in runs {
        net.run_steps(steps, &neurotac_core::OneProcess).unwrap();
    }
    let one = spikes(&net, &r);
    assert!(
        one[0].len() > 50 && one[1].len() > 20,
        "{} and {} spikes: the network must be active",
        one[0].len(),
        one[1].len()
    );
    for size in 1..=3 {
        let per_rank = ThreadRanks::run(size, |ranks| {
            let (b, r) = network();
            let config = NetworkConfig { dt_s: DT };
            let mut net = b.build_partitioned(config, ranks.rank(), size).unwrap();
            for &steps in runs {
                net.run_steps(steps, ranks).unwrap();
            }
            (spikes(&net, &r), net.steps_done(), net.exchanges())
        });
        for (rank, (got, steps, exchanges)) in per_rank.into_iter().enumerate() {
            assert_eq!(steps, runs.iter().sum::<u64>());
            for (which, (g, o)) in got.iter().zip(&one).enumerate() {
                assert!(
                    g == o,
                    "{size} ranks, rank {rank}, recorder {which}: {} spikes, one process {}",
                    g.len(),
                    o.len()
                );
            }
            if size == 1 {
                assert_eq!(exchanges, 0, "one rank exchanges nothing");
            } else {
                assert!(exchanges > 0);
            }
        }
    }
    one
}

#[test]
fn two_recurrent_populations_spike_as_in_one_process_on_1_2_and_3_ranks() {
    let network = || two_populations((37, 23), Leaky::new, false);
    // 157 + 60 steps: two runs, each ending inside an epoch.
    same_spikes_on_any_rank_count(network, &[157, 60]);
}

#[test]
fn interpolated_spike_times_travel_with_their_spikes() {
    let leaky = |n| Leaky {
        interpolate: true,
        ..Leaky::new(n)
    };
    let spikes = same_spikes_on_any_rank_count(|| two_populations((37, 23), leaky, false), &[200]);
    assert!(spikes[0].iter().any(|&(_, t)| (t / DT).fract() > 1e-9));
}

#[test]
fn event_driven_populations_work_partitioned() {
    let leaky = |n| Leaky {
        event_driven: true,
        ..Leaky::new(n)
    };
    let clock =
        same_spikes_on_any_rank_count(|| two_populations((37, 23), Leaky::new, false), &[150]);
    let event = same_spikes_on_any_rank_count(|| two_populations((37, 23), leaky, true), &[150]);
    assert_eq!(clock, event);
    let populations = ThreadRanks::run(2, |ranks| {
        let (b, _) = two_populations((37, 23), leaky, true);
        let net = b
            .build_partitioned(NetworkConfig { dt_s: DT }, ranks.rank(), 2)
            .unwrap();
        net.event_driven_populations()
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
    });
    // `a` takes an injected current, so only `b` is event-driven.
    assert_eq!(populations, vec![vec!["b".to_string()]; 2]);
}

#[test]
fn more_ranks_than_neurons_leaves_some_blocks_empty() {
    // 2 and 1 neurons over 3 ranks: rank 0 owns no neuron of `a`, ranks 0 and 1 none of `b`.
    let leaky = |n| Leaky {
        decay: 0.5,
        ..Leaky::new(n)
    };
    let network = || {
        let mut b = NetworkBuilder::new();
        let input = b
            .add_spike_input("poisson", PoissonInput::new(4, 300.0, 2))
            .unwrap();
        let pa = b.add_population("a", leaky(2)).unwrap();
        let pb = b.add_population("b", leaky(1)).unwrap();
        let all = |w| Connectivity::AllToAll { weight: w };
        b.connect(input, pa, all(0.6), ExpSynapse::new(1e-3).with_delay(0))
            .unwrap();
        b.connect(pa, pb, all(0.7), ExpSynapse::new(1e-3).with_delay(1))
            .unwrap();
        b.connect(pb, pa, all(-0.2), ExpSynapse::new(1e-3).with_delay(1))
            .unwrap();
        let r = Recorders {
            population_a: None,
            a: b.record_spikes(pa).unwrap(),
            b: b.record_spikes(pb).unwrap(),
            input: b.record_spikes(input).unwrap(),
        };
        (b, r)
    };
    same_spikes_on_any_rank_count(network, &[300]);
}

#[test]
fn epochs_last_the_smallest_population_delay_and_are_timed() {
    let (b, _) = two_populations((37, 23), Leaky::new, false);
    let mut one = b.build(NetworkConfig { dt_s: DT }).unwrap();
    assert_eq!((one.epoch_steps(), one.rank(), one.n_ranks()), (2, 0, 1));
    one.run(0.01, &OneProcess).unwrap();
    assert_eq!((one.exchanges(), one.exchange_s()), (0, 0.0));
    let stats = ThreadRanks::run(2, |ranks| {
        let (b, _) = two_populations((37, 23), Leaky::new, false);
        let mut net = b
            .build_partitioned(NetworkConfig { dt_s: DT }, ranks.rank(), 2)
            .unwrap();
        net.run_steps(101, ranks).unwrap();
        let stats = (net.epoch_steps(), net.exchanges(), net.exchange_s() > 0.0);
        net.reset();
        (stats, net.exchanges())
    });
    // 50 whole epochs and the last, one-step one.
    assert_eq!(stats, vec![((2, 51, true), 0); 2]);
    // Without population → population projections: DEFAULT_EPOCH_STEPS.
    let mut b = NetworkBuilder::new();
    let input = b
        .add_spike_input("poisson", PoissonInput::new(3, 100.0, 1))
        .unwrap();
    let p = b.add_population("p", Leaky::new(3)).unwrap();
    b.connect(
        input,
        p,
        Connectivity::OneToOne { weight: 1.0 },
        ExpSynapse::new(1e-3),
    )
    .unwrap();
    b.record_spikes(p).unwrap();
    let net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    assert_eq!(net.epoch_steps(), neurotac_core::graph::DEFAULT_EPOCH_STEPS);
}

/// Asks to stop once it has seen `0` spikes; counts the steps it saw.
struct StopAfter(usize, usize, u64);

impl Readout for StopAfter {
    fn on_step(&mut self, view: &StepView<'_>) -> ControlFlow<()> {
        self.1 += view.spikes.len();
        self.2 += 1;
        if self.1 >= self.0 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
    fn reads_population_state(&self) -> bool {
        false
    }
}

#[test]
fn a_stop_request_takes_effect_at_the_end_of_the_epoch() {
    let network = || {
        let (mut b, r) = two_populations((37, 23), Leaky::new, false);
        let a = r.population_a.expect("two_populations names `a`");
        let stop = b.add_readout(a, StopAfter(5, 0, 0)).unwrap();
        (b, stop)
    };
    let (b, stop) = network();
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    let one = net.run(1.0, &neurotac_core::OneProcess).unwrap();
    assert!(one.stopped_early);
    let seen = net.readout(stop).unwrap().2;
    assert_eq!(seen, one.steps);
    let per_rank = ThreadRanks::run(3, |ranks| {
        let (b, stop) = network();
        let mut net = b
            .build_partitioned(NetworkConfig { dt_s: DT }, ranks.rank(), 3)
            .unwrap();
        let summary = net.run(1.0, ranks).unwrap();
        (summary, net.readout(stop).unwrap().2)
    });
    // Epochs of 2 steps: the run ends at the end of the stop step's epoch.
    let at_epoch_end = one.steps.div_ceil(2) * 2;
    for (summary, seen) in per_rank {
        assert!(summary.stopped_early);
        assert_eq!((summary.steps, seen), (at_epoch_end, at_epoch_end));
    }
}

#[test]
fn what_cannot_run_partitioned_is_a_typed_error() {
    let config = NetworkConfig { dt_s: DT };
    // A model without `restrict`: fine in one process, refused over two ranks.
    let whole = || {
        let mut b = NetworkBuilder::new();
        let p = b.add_population("plain", Whole(Leaky::new(4))).unwrap();
        b.record_spikes(p).unwrap();
        b
    };
    assert!(whole().build_partitioned(config, 0, 1).is_ok());
    let e = whole().build_partitioned(config, 1, 2).err().unwrap();
    assert_eq!(
        e,
        GraphError::ModelNotPartitionable {
            population: "plain".into(),
            model: "whole"
        }
    );
    assert!(
        e.to_string().contains("'plain' cannot be partitioned"),
        "{e}"
    );
    // Readouts of state one rank holds.
    let mut b = NetworkBuilder::new();
    let p = b.add_population("p", Leaky::new(4)).unwrap();
    b.record_state(p, "v", None, 1).unwrap();
    let e = b.build_partitioned(config, 0, 2).err().unwrap();
    assert!(
        matches!(&e, GraphError::ReadoutNotPartitionable { node, ranks: 2, .. } if node == "population 'p'"),
        "{e}"
    );
    let mut b = NetworkBuilder::new();
    let p = b.add_population("p", Leaky::new(4)).unwrap();
    let proj = b
        .connect(
            p,
            p,
            Connectivity::AllToAll { weight: 0.1 },
            ExpSynapse::new(1e-3),
        )
        .unwrap();
    b.record_synaptic_trace(proj, None).unwrap();
    assert!(matches!(
        b.build_partitioned(config, 0, 2),
        Err(GraphError::ReadoutNotPartitionable { .. })
    ));
    // A rank outside its group.
    for (rank, size) in [(2, 2), (0, 0)] {
        let e = whole().build_partitioned(config, rank, size).err().unwrap();
        assert_eq!(e, GraphError::InvalidPartition { rank, size });
    }
    // Running on the wrong group: refused before any collective call.
    let build = |rank| {
        let mut b = NetworkBuilder::new();
        let p = b.add_population("p", Leaky::new(4)).unwrap();
        b.record_spikes(p).unwrap();
        b.build_partitioned(config, rank, 2).unwrap()
    };
    let mismatch = |rank, size| GraphError::RanksMismatch {
        built_rank: 1,
        built_size: 2,
        rank,
        size,
    };
    assert_eq!(
        build(1).run(0.01, &neurotac_core::OneProcess).unwrap_err(),
        mismatch(0, 1)
    );
    assert_eq!(build(1).run(0.01, &OneProcess).unwrap_err(), mismatch(0, 1));
    let e = ThreadRanks::run(3, |r| build(1).run(0.01, r).unwrap_err());
    assert_eq!(e[2], mismatch(2, 3));
    assert!(build(0).run(f64::NAN, &OneProcess).is_err());
}

/// Rank 1 of 2 whose "other rank" sends `garbage`.
struct Liar(Vec<u8>);

impl Ranks for Liar {
    fn rank(&self) -> usize {
        1
    }
    fn size(&self) -> usize {
        2
    }
    fn all_gather_bytes(&self, local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError> {
        Ok(vec![self.0.clone(), local.to_vec()])
    }
}

/// A group whose communication fails.
struct Broken;

impl Ranks for Broken {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        2
    }
    fn all_gather_bytes(&self, _local: &[u8]) -> Result<Vec<Vec<u8>>, RanksError> {
        Err(RanksError::Communication {
            during: "test",
            reason: "cable cut".into(),
        })
    }
}

#[test]
fn malformed_messages_and_failed_communication_are_typed_errors() {
    let config = NetworkConfig { dt_s: DT };
    let build = |rank| {
        let (b, _) = two_populations((37, 23), Leaky::new, false);
        b.build_partitioned(config, rank, 2).unwrap()
    };
    let counts = |c: u32| {
        let mut m = vec![0u8];
        for _ in 0..2 {
            // Two steps of one spike each, no fractions, neuron index `c`.
            m.extend(1u32.to_le_bytes());
            m.extend(1u32.to_le_bytes());
            m.push(0);
            m.extend(c.to_le_bytes());
            m.extend(c.to_le_bytes());
        }
        m
    };
    for (garbage, what) in [
        (vec![], "cut short"),
        (vec![7], "status"),
        (vec![0, 1, 0], "cut short"),
        (counts(1_000), "neuron 1000"),
        ([counts(0), vec![9]].concat(), "left over"),
    ] {
        let e = build(1).run_steps(2, &Liar(garbage)).unwrap_err();
        assert!(
            matches!(&e, GraphError::Exchange { step: 2, reason } if reason.contains(what)),
            "{e}"
        );
    }
    // A well-formed message from the other rank is accepted.
    assert!(build(1).run_steps(2, &Liar(counts(0))).is_ok());
    let e = build(0).run_steps(10, &Broken).unwrap_err();
    assert!(e.to_string().contains("cable cut"), "{e}");
}

#[test]
fn a_divergence_on_one_rank_stops_every_rank() {
    let leaky = |n| Leaky {
        diverges: Some(30),
        ..Leaky::new(n)
    };
    let errors = ThreadRanks::run(3, |ranks| {
        let (b, _) = two_populations((37, 23), leaky, false);
        let mut net = b
            .build_partitioned(NetworkConfig { dt_s: DT }, ranks.rank(), 3)
            .unwrap();
        net.run(0.1, ranks).unwrap_err()
    });
    // Neuron 30 of `a` (37 neurons) is rank 2's.
    assert!(matches!(&errors[2], GraphError::Model { population, .. } if population == "a"));
    for e in &errors[..2] {
        assert_eq!(e, &GraphError::PeerDiverged { rank: 2, step: 2 });
    }
}
