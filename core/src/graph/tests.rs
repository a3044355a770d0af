use super::*;
use crate::error::GraphError;
use crate::model::{NeuronModel, SpikeBuffer};
use crate::{ModelError, MultiSpikeTrain};
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Spikes whenever its input exceeds `threshold`; its one variable `x` is the last input.
/// Counts `prepare` and `step` calls so tests can see what the network instantiates.
struct Probe {
    n: usize,
    threshold: f64,
    x: Vec<f64>,
    prepared: Arc<AtomicUsize>,
    stepped: Arc<AtomicUsize>,
}

impl Probe {
    fn new(n: usize) -> (Self, Arc<AtomicUsize>, Arc<AtomicUsize>) {
        let (p, s) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
        (
            Self {
                n,
                threshold: 0.5,
                x: Vec::new(),
                prepared: p.clone(),
                stepped: s.clone(),
            },
            p,
            s,
        )
    }
}

impl NeuronModel for Probe {
    fn model_name(&self) -> &'static str {
        "probe"
    }
    fn len(&self) -> usize {
        self.n
    }
    fn variables(&self) -> &'static [&'static str] {
        &["x"]
    }
    fn prepare(&mut self, _dt_s: f64) -> Result<(), ModelError> {
        if !self.threshold.is_finite() {
            return Err(ModelError::InvalidParameter {
                model: "probe",
                field: "threshold",
                value: self.threshold,
                expected: "finite",
            });
        }
        self.prepared.fetch_add(1, Ordering::Relaxed);
        self.x = vec![0.0; self.n];
        Ok(())
    }
    fn reset(&mut self) {
        self.x.iter_mut().for_each(|x| *x = 0.0);
    }
    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer) {
        self.stepped.fetch_add(1, Ordering::Relaxed);
        for (i, (&c, x)) in current.iter().zip(&mut self.x).enumerate() {
            *x = c;
            if c > self.threshold {
                spikes.push(i as u32);
            }
        }
    }
    fn read_variable(&self, _var: usize, neurons: &[u32], out: &mut Vec<f64>) {
        out.extend(neurons.iter().map(|&i| self.x[i as usize]));
    }
}

fn trains(channels: Vec<Vec<f64>>) -> SpikeArrayInput {
    SpikeArrayInput::new(MultiSpikeTrain::from_channels(channels).unwrap())
}

#[test]
fn unreferenced_population_is_never_prepared_or_stepped() {
    let mut b = NetworkBuilder::new();
    let input = b
        .add_spike_input("taxels", trains(vec![vec![0.001]; 3]))
        .unwrap();
    let (used, used_prepared, used_stepped) = Probe::new(3);
    let (unused, unused_prepared, unused_stepped) = Probe::new(1_000_000);
    let used = b.add_population("used", used).unwrap();
    let unused = b.add_population("unused", unused).unwrap();
    let syn = ExpSynapse::new(1e-3).with_delay(0);
    b.connect(input, used, Connectivity::OneToOne { weight: 1.0 }, syn)
        .unwrap();
    // The unused population is even fed by the used one and by a current: still never needed.
    b.connect(
        used,
        unused,
        Connectivity::AllToAll { weight: 1.0 },
        ExpSynapse::new(1e-3),
    )
    .unwrap();
    let drive = b
        .add_current_input("drive", CurrentInput::constant(2.0))
        .unwrap();
    b.inject(drive, unused).unwrap();
    let rec = b.record_spikes(used).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    net.run(0.01, &crate::OneProcess).unwrap();
    assert_eq!(used_prepared.load(Ordering::Relaxed), 1);
    assert_eq!(used_stepped.load(Ordering::Relaxed), 10);
    assert_eq!(
        unused_prepared.load(Ordering::Relaxed),
        0,
        "pruned population was prepared"
    );
    assert_eq!(
        unused_stepped.load(Ordering::Relaxed),
        0,
        "pruned population was stepped"
    );
    assert!(net.is_active(used).unwrap() && !net.is_active(unused).unwrap());
    assert_eq!(
        net.pruned_nodes(),
        &["unused".to_string(), "drive".to_string()]
    );
    assert_eq!(
        net.n_synapses(),
        3,
        "the pruned all-to-all projection is not compiled"
    );
    assert_eq!(net.readout(rec).unwrap().counts(), vec![1, 1, 1]);
}

#[test]
fn a_network_without_readouts_models_nothing() {
    let mut b = NetworkBuilder::new();
    let (p, prepared, _) = Probe::new(10);
    b.add_population("p", p).unwrap();
    let mut net = b.build(NetworkConfig::default()).unwrap();
    net.run(1.0, &crate::OneProcess).unwrap();
    assert_eq!(prepared.load(Ordering::Relaxed), 0);
}

#[test]
fn builder_rejects_wrong_shapes_roles_and_parameters() {
    let mut b = NetworkBuilder::new();
    let input = b.add_spike_input("in", trains(vec![vec![]; 49])).unwrap();
    let pop = b.add_population("pop", Probe::new(48).0).unwrap();
    let cur = b
        .add_current_input(
            "cur",
            CurrentInput::Constant {
                amplitude: vec![1.0; 3],
            },
        )
        .unwrap();
    let syn = ExpSynapse::new(5e-3);
    let e = b
        .connect(input, pop, Connectivity::OneToOne { weight: 1.0 }, syn)
        .unwrap_err();
    assert!(
        matches!(
            e,
            GraphError::SizeMismatch {
                expected: 49,
                got: 48,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("'in' → 'pop'"), "{e}");
    // A current as a presynaptic node, or an input as a target, does not compile (typed ids;
    // see the compile_fail examples on `SpikingNode`).
    assert!(matches!(
        b.inject(cur, pop),
        Err(GraphError::SizeMismatch {
            expected: 48,
            got: 3,
            ..
        })
    ));
    assert!(matches!(
        b.connect(
            InputId {
                index: 99,
                brand: b.brand
            },
            pop,
            Connectivity::AllToAll { weight: 1.0 },
            syn
        ),
        Err(GraphError::UnknownNode(99))
    ));
    assert!(matches!(
        b.connect(
            pop,
            pop,
            Connectivity::AllToAll { weight: 1.0 },
            ExpSynapse::new(5e-3).with_delay(0)
        ),
        Err(GraphError::InvalidParameter { .. })
    ));
    for tau in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(
            b.connect(
                input,
                pop,
                Connectivity::AllToAll { weight: 1.0 },
                ExpSynapse::new(tau)
            )
            .is_err()
        );
    }
    assert!(
        b.connect(input, pop, Connectivity::AllToAll { weight: f64::NAN }, syn)
            .is_err()
    );
    let e = b
        .connect(
            input,
            pop,
            Connectivity::Sparse(vec![Synapse {
                pre: 0,
                post: 48,
                weight: 1.0,
            }]),
            syn,
        )
        .unwrap_err();
    assert!(
        matches!(
            e,
            GraphError::IndexOutOfRange {
                index: 0,
                neuron: 48,
                size: 48,
                ..
            }
        ),
        "{e}"
    );
    assert!(
        b.connect(
            input,
            pop,
            Connectivity::Random {
                probability: 1.5,
                weight: 1.0,
                seed: 0
            },
            syn
        )
        .is_err()
    );
    assert!(matches!(
        b.add_population("pop", Probe::new(1).0),
        Err(GraphError::DuplicateName(_))
    ));
    let e = b.record_state(pop, "v", None, 1).unwrap_err();
    assert_eq!(
        crate::error_chain(&e),
        "population 'pop': probe has no state variable 'v' (has: x)"
    );
    assert!(matches!(
        b.record_state(pop, "x", Some(vec![48]), 1),
        Err(GraphError::IndexOutOfRange { .. })
    ));
    assert!(matches!(
        b.record_synaptic_trace(
            ProjectionId {
                index: 7,
                brand: b.brand
            },
            None
        ),
        Err(GraphError::UnknownProjection(7))
    ));
    assert!(
        b.add_current_input("nan", CurrentInput::constant(f64::NAN))
            .is_err()
    );
    b.record_spikes(pop).unwrap();
    for dt in [0.0, -1e-3, f64::NAN] {
        let mut b = NetworkBuilder::new();
        let p = b.add_population("p", Probe::new(1).0).unwrap();
        b.record_spikes(p).unwrap();
        assert!(matches!(
            b.build(NetworkConfig { dt_s: dt }),
            Err(GraphError::InvalidParameter { .. })
        ));
    }
    // A model's own validation surfaces at build with the population's name.
    let mut b = NetworkBuilder::new();
    let (mut bad, _, _) = Probe::new(1);
    bad.threshold = f64::NAN;
    let p = b.add_population("afferents", bad).unwrap();
    b.record_spikes(p).unwrap();
    let e = b.build(NetworkConfig::default()).err().unwrap();
    assert_eq!(
        crate::error_chain(&e),
        "population 'afferents': probe: parameter threshold = NaN: finite"
    );
}

#[test]
fn spikes_arrive_after_their_delay_and_decay_exactly() {
    let dt = 1e-3;
    let mut b = NetworkBuilder::new();
    let input = b.add_spike_input("in", trains(vec![vec![0.0105]])).unwrap();
    let pop = b.add_population("pop", Probe::new(1).0).unwrap();
    let proj = b
        .connect(
            input,
            pop,
            Connectivity::OneToOne { weight: 2.0 },
            ExpSynapse::new(4e-3).with_delay(3),
        )
        .unwrap();
    let trace = b.record_synaptic_trace(proj, None).unwrap();
    let state = b.record_state(pop, "x", None, 1).unwrap();
    let input_spikes = b.record_spikes(input).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: dt }).unwrap();
    net.run(0.02, &crate::OneProcess).unwrap();
    let tr = net.readout(trace).unwrap();
    assert_eq!(tr.times().len(), 20);
    let trace = tr.trace(0);
    // Emitted in step 10 (t = 10.5 ms lies in [10, 11) ms), delivered 3 steps later; the trace
    // is sampled at the end of each step, one decay after the delivery.
    assert!(trace[..13].iter().all(|&x| x == 0.0));
    for (k, &x) in trace.iter().enumerate().skip(13) {
        let expected = 2.0 * (-((k - 12) as f64) * dt / 4e-3).exp();
        assert!((x - expected).abs() < 1e-12, "step {k}: {x} vs {expected}");
    }
    assert!((tr.times()[13] - 0.014).abs() < 1e-15);
    // The population integrates the current at the start of the step: the undecayed jump.
    let st = net.readout(state).unwrap();
    let decay = (-dt / 4e-3f64).exp();
    for (k, &x) in st.trace(0).iter().enumerate().skip(13) {
        assert!((x * decay - trace[k]).abs() < 1e-12, "step {k}");
    }
    assert_eq!(st.trace(0)[13], 2.0);
    assert!((st.times()[13] - 0.014).abs() < 1e-15);
    // A spike source's recorded spike keeps its own time.
    assert_eq!(net.readout(input_spikes).unwrap().spikes(), &[(0, 0.0105)]);
}

#[test]
fn population_to_population_delay_counts_from_the_emitting_step() {
    let mut b = NetworkBuilder::new();
    let input = b.add_spike_input("in", trains(vec![vec![0.0]])).unwrap();
    let a = b.add_population("a", Probe::new(1).0).unwrap();
    let c = b.add_population("c", Probe::new(1).0).unwrap();
    let syn0 = ExpSynapse::new(1e-6).with_delay(0);
    b.connect(input, a, Connectivity::OneToOne { weight: 1.0 }, syn0)
        .unwrap();
    b.connect(
        a,
        c,
        Connectivity::OneToOne { weight: 1.0 },
        ExpSynapse::new(1e-6).with_delay(2),
    )
    .unwrap();
    let (ra, rc) = (b.record_spikes(a).unwrap(), b.record_spikes(c).unwrap());
    let mut net = b.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    net.run(0.01, &crate::OneProcess).unwrap();
    // `a` spikes in step 0 (stamped at its end, 1 ms); `c` receives it in step 2 (spike at 3 ms).
    assert_eq!(net.readout(ra).unwrap().spikes(), &[(0, 1e-3)]);
    assert_eq!(net.readout(rc).unwrap().spikes(), &[(0, 3e-3)]);
}

#[test]
fn currents_add_to_synaptic_input() {
    let mut b = NetworkBuilder::new();
    let pop = b.add_population("p", Probe::new(2).0).unwrap();
    let c1 = b
        .add_current_input(
            "c1",
            CurrentInput::Constant {
                amplitude: vec![0.25, 1.0],
            },
        )
        .unwrap();
    let c2 = b
        .add_current_input(
            "c2",
            CurrentInput::Steps {
                size: 1,
                changes: vec![(0.005, 0.5)],
            },
        )
        .unwrap();
    b.inject(c1, pop).unwrap();
    b.inject(c2, pop).unwrap();
    let st = b.record_state(pop, "x", None, 5).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    net.run(0.01, &crate::OneProcess).unwrap();
    let st = net.readout(st).unwrap();
    assert_eq!(st.times().len(), 2);
    assert_eq!(st.values(), &[0.25, 1.0, 0.75, 1.5]);
}

struct StopAfter(usize, usize);
impl Readout for StopAfter {
    fn on_step(&mut self, view: &StepView<'_>) -> ControlFlow<()> {
        self.1 += view.spikes.len();
        if self.1 >= self.0 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

#[test]
fn a_readout_can_stop_the_run_cleanly() {
    let mut b = NetworkBuilder::new();
    let input = b
        .add_spike_input("in", trains(vec![vec![0.001, 0.002, 0.003, 0.004]]))
        .unwrap();
    let stop = b.add_readout(input, StopAfter(2, 0)).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    let summary = net.run(1.0, &crate::OneProcess).unwrap();
    assert_eq!(
        summary,
        RunSummary {
            steps: 3,
            stopped_early: true
        }
    );
    assert_eq!(net.readout(stop).unwrap().1, 2);
    assert!((net.time_s() - 0.003).abs() < 1e-15);
    assert!(net.run(f64::NAN, &crate::OneProcess).is_err());
}

#[test]
fn reset_and_replaced_inputs_reproduce_runs() {
    let build = || {
        let mut b = NetworkBuilder::new();
        let input = b
            .add_spike_input("in", PoissonInput::new(20, 100.0, 42))
            .unwrap();
        let pop = b.add_population("p", Probe::new(5).0).unwrap();
        b.connect(
            input,
            pop,
            Connectivity::Random {
                probability: 0.3,
                weight: 0.4,
                seed: 9,
            },
            ExpSynapse::new(2e-3).with_delay(1),
        )
        .unwrap();
        let rec = b.record_spikes(pop).unwrap();
        (b.build(NetworkConfig { dt_s: 1e-4 }).unwrap(), rec, input)
    };
    let (mut a, ra, input) = build();
    let (mut b, rb, _) = build();
    a.run(0.2, &crate::OneProcess).unwrap();
    b.run(0.2, &crate::OneProcess).unwrap();
    let first = a.readout(ra).unwrap().spikes().to_vec();
    assert!(!first.is_empty());
    assert_eq!(first, b.readout(rb).unwrap().spikes());
    a.reset();
    a.run(0.2, &crate::OneProcess).unwrap();
    assert_eq!(a.readout(ra).unwrap().spikes(), first.as_slice());
    // Swap the input for silence: no spikes after a reset.
    a.replace_spike_input(input, trains(vec![vec![]; 20]))
        .unwrap();
    a.reset();
    a.run(0.2, &crate::OneProcess).unwrap();
    assert!(a.readout(ra).unwrap().spikes().is_empty());
    assert!(matches!(
        a.replace_spike_input(input, trains(vec![vec![]; 3])),
        Err(GraphError::SizeMismatch { .. })
    ));
}

/// A spike input (one channel), a one-neuron population fed by it through a projection, a
/// current injected into it and a spike readout of it: the same indices in every builder.
struct Wired {
    input: InputId,
    population: PopulationId,
    current: CurrentId,
    projection: ProjectionId,
    spikes: ReadoutId<SpikeRecorder>,
}

fn wired(b: &mut NetworkBuilder) -> Wired {
    let input = b.add_spike_input("in", trains(vec![vec![0.0015]])).unwrap();
    let population = b.add_population("p", Probe::new(1).0).unwrap();
    let current = b
        .add_current_input("bias", CurrentInput::constant(0.0))
        .unwrap();
    let projection = b
        .connect(
            input,
            population,
            Connectivity::OneToOne { weight: 1.0 },
            ExpSynapse::new(1e-3).with_delay(0),
        )
        .unwrap();
    b.inject(current, population).unwrap();
    let spikes = b.record_spikes(population).unwrap();
    Wired {
        input,
        population,
        current,
        projection,
        spikes,
    }
}

#[test]
fn ids_stay_copy_and_small() {
    fn copy<T: Copy>() {}
    copy::<NodeId>();
    copy::<PopulationId>();
    copy::<ReadoutId<SpikeRecorder>>();
    assert!(std::mem::size_of::<PopulationId>() <= 16);
    assert!(std::mem::size_of::<ReadoutId<SpikeRecorder>>() <= 16);
}

#[test]
fn a_builder_refuses_the_ids_of_another_builder() {
    let (mut a, mut b) = (NetworkBuilder::new(), NetworkBuilder::new());
    assert_ne!(a.brand, b.brand);
    let theirs = wired(&mut a);
    let ours = wired(&mut b);
    let (a_brand, b_brand) = (a.brand, b.brand);
    let foreign = |kind| GraphError::ForeignId {
        kind,
        id_brand: a_brand,
        builder_brand: b_brand,
    };
    let one_to_one = || Connectivity::OneToOne { weight: 1.0 };
    let syn = ExpSynapse::new(1e-3).with_delay(0);
    assert_eq!(
        b.connect(theirs.input, ours.population, one_to_one(), syn),
        Err(foreign("spike input"))
    );
    assert_eq!(
        b.connect(ours.input, theirs.population, one_to_one(), syn),
        Err(foreign("population"))
    );
    assert_eq!(
        b.connect(
            theirs.population,
            ours.population,
            one_to_one(),
            ExpSynapse::new(1e-3)
        ),
        Err(foreign("population"))
    );
    assert_eq!(
        b.inject(theirs.current, ours.population),
        Err(foreign("current input"))
    );
    assert_eq!(
        b.inject(ours.current, theirs.population),
        Err(foreign("population"))
    );
    assert_eq!(
        b.record_spikes(theirs.input).map(|_| ()),
        Err(foreign("spike input"))
    );
    assert_eq!(
        b.record_state(theirs.population, "x", None, 1).map(|_| ()),
        Err(foreign("population"))
    );
    assert_eq!(
        b.record_synaptic_trace(theirs.projection, None).map(|_| ()),
        Err(foreign("projection"))
    );
    assert_eq!(
        b.add_readout(theirs.projection, SpikeRecorder::new())
            .map(|_| ()),
        Err(foreign("projection"))
    );
    assert_eq!(
        b.add_readout(
            ReadoutSource::Node(theirs.population.into()),
            SpikeRecorder::new()
        )
        .map(|_| ()),
        Err(foreign("node"))
    );
    let e = b.record_spikes(theirs.population).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "population id of network builder #{} used with builder #{} (or its network): an id works only with the builder that handed it out and the network built from it",
            a_brand, b_brand
        )
    );
    // Nothing was wired by the refused calls, and the builder's own ids still work.
    b.record_state(ours.population, "x", None, 1).unwrap();
    b.record_synaptic_trace(ours.projection, None).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    assert_eq!(net.n_synapses(), 1);
    net.run(0.005, &crate::OneProcess).unwrap();
    assert_eq!(net.readout(ours.spikes).unwrap().spikes(), &[(0, 2e-3)]);
    assert!(net.is_active(ours.input).unwrap());
}

#[test]
fn a_network_refuses_the_ids_of_another_builder() {
    let (mut a, mut b) = (NetworkBuilder::new(), NetworkBuilder::new());
    let theirs = wired(&mut a);
    let ours = wired(&mut b);
    let (a_brand, b_brand) = (a.brand, b.brand);
    let mut net = b.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    let other = a.build(NetworkConfig { dt_s: 1e-3 }).unwrap();
    let foreign = |kind| GraphError::ForeignId {
        kind,
        id_brand: a_brand,
        builder_brand: b_brand,
    };
    net.run(0.005, &crate::OneProcess).unwrap();
    assert_eq!(
        net.readout(theirs.spikes).map(|_| ()),
        Err(foreign("readout"))
    );
    assert_eq!(net.is_active(theirs.population), Err(foreign("node")));
    assert_eq!(
        net.replace_spike_input(theirs.input, trains(vec![vec![]])),
        Err(foreign("spike input"))
    );
    // The other way round too, and each network takes its own builder's ids.
    assert_eq!(
        other.readout(ours.spikes).map(|_| ()),
        Err(GraphError::ForeignId {
            kind: "readout",
            id_brand: b_brand,
            builder_brand: a_brand,
        })
    );
    assert_eq!(net.readout(ours.spikes).unwrap().spikes(), &[(0, 2e-3)]);
    assert!(other.readout(theirs.spikes).unwrap().spikes().is_empty());
    assert!(net.is_active(ours.population).unwrap());
    assert!(net.is_active(ours.current).unwrap());
    net.replace_spike_input(ours.input, trains(vec![vec![]]))
        .unwrap();
    net.reset();
    net.run(0.005, &crate::OneProcess).unwrap();
    assert!(net.readout(ours.spikes).unwrap().spikes().is_empty());
}
