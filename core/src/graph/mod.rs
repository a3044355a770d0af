//! The network graph: defined in Rust code with a [`NetworkBuilder`], run by a [`Network`].
//!
//! Nodes are populations ([`NeuronModel`]s), spike sources ([`SpikeSource`]s: recorded arrays,
//! Poisson) and current sources ([`CurrentInput`]). Projections connect a spike-emitting node
//! to a population through exponential current synapses ([`ExpSynapse`], [`Connectivity`]).
//! Readouts ([`Readout`]) watch a node or projection.
//!
//! # Only what a readout needs is modelled
//! [`NetworkBuilder::build`] walks back from every readout: a readout needs its source; a
//! population needs every projection and current that feeds it; a projection needs its
//! presynaptic node. Everything else is dropped before it is prepared: an unreferenced
//! population is never allocated, validated against `dt` or stepped, and random connectivity
//! is drawn only for needed projections. [`Network::pruned_nodes`] lists what was dropped.
//!
//! # Phase order of one step
//! Step `k` advances time from `t_k = k·dt` to `t_k + dt`:
//! 1. **inputs**: every spike source emits the spikes that fall in `[t_k, t_k + dt)`;
//! 2. **synapses**: every projection adds the weights of the presynaptic spikes emitted `delay`
//!    steps ago (this step's, for delay 0 from an input) to its currents, giving `I(t_k)`;
//! 3. **integration**: every population sums its projections' currents `I(t_k)` and direct
//!    currents (evaluated at `t_k`) and advances one step, holding that input constant; in the
//!    same pass each projection's currents decay exactly to `I(t_k + dt) = I(t_k)·e^(−dt/τ)`;
//! 4. **threshold/reset**: inside the model's step, which pushes this step's spikes;
//! 5. **readouts**: each sees this step's spikes of its source, the population state at
//!    `t_k + dt`, or the projection currents at `t_k + dt` (decayed, before the next delivery).
//!
//! ```
//! use neurotac_core::{ExpSynapse, Connectivity, MultiSpikeTrain, NetworkBuilder, NetworkConfig, SpikeArrayInput};
//! # use neurotac_core::{NeuronModel, SpikeBuffer, ModelError};
//! # struct Relay(usize);
//! # impl NeuronModel for Relay {
//! #   fn model_name(&self) -> &'static str { "relay" }
//! #   fn len(&self) -> usize { self.0 }
//! #   fn variables(&self) -> &'static [&'static str] { &[] }
//! #   fn prepare(&mut self, _: f64) -> Result<(), ModelError> { Ok(()) }
//! #   fn reset(&mut self) {}
//! #   fn step(&mut self, i: &[f64], s: &mut SpikeBuffer) { for (k, &x) in i.iter().enumerate() { if x > 0.5 { s.push(k as u32) } } }
//! #   fn read_variable(&self, _: usize, _: &[u32], _: &mut Vec<f64>) {}
//! # }
//! let taxels = MultiSpikeTrain::from_channels(vec![vec![0.0105], vec![]])?;
//! let mut b = NetworkBuilder::new();
//! let input = b.add_spike_input("taxels", SpikeArrayInput::new(taxels))?;
//! let relay = b.add_population("relay", Relay(2))?;
//! b.connect(input, relay, Connectivity::OneToOne { weight: 1.0 }, ExpSynapse::new(5e-3).with_delay(0))?;
//! let spikes = b.record_spikes(relay)?;
//! let mut net = b.build(NetworkConfig { dt_s: 1e-3 })?;
//! net.run(0.02)?;
//! // The current is e^(−k·dt/τ) in the k-th step after the spike: above 0.5 for k = 0..=3.
//! assert_eq!(net.readout(spikes).counts(), vec![4, 0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod input;
mod readout;
mod synapse;

pub use input::{CurrentInput, PoissonInput, SpikeArrayInput, SpikeSource};
pub use readout::{
    Readout, ReadoutContext, SpikeRecorder, StateRecorder, StepView, SynapticTraceRecorder,
};
pub(crate) use synapse::decay_and_flush;
pub use synapse::{Connectivity, ExpSynapse, FLUSH_TO_ZERO, Synapse};

use crate::error::GraphError;
use crate::model::{NeuronModel, SpikeBuffer};
use std::any::Any;
use std::marker::PhantomData;
use std::ops::ControlFlow;
use synapse::RunningProjection;

/// Identifies a node of one [`NetworkBuilder`] (and of the network built from it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeId(usize);

/// Identifies a projection of one [`NetworkBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ProjectionId(usize);

/// Identifies a readout of type `T`; [`Network::readout`] returns it typed.
#[derive(Debug)]
pub struct ReadoutId<T> {
    index: usize,
    _type: PhantomData<fn() -> T>,
}

impl<T> Clone for ReadoutId<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for ReadoutId<T> {}

/// What a readout watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadoutSource {
    /// A population or spike source.
    Node(NodeId),
    /// A projection (its synaptic currents).
    Projection(ProjectionId),
}

/// Simulation settings fixed at build time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetworkConfig {
    /// Time step in seconds (> 0). Default 10⁻⁴ s (0.1 ms).
    pub dt_s: f64,
}

impl Default for NetworkConfig {
    fn default() -> Self {
        Self { dt_s: 1e-4 }
    }
}

enum NodeKind {
    Spikes(Box<dyn SpikeSource>),
    Current(CurrentInput),
    Population(Box<dyn NeuronModel>),
}

impl NodeKind {
    fn describe(&self) -> &'static str {
        match self {
            NodeKind::Spikes(_) => "spike source",
            NodeKind::Current(_) => "current source",
            NodeKind::Population(_) => "population",
        }
    }
}

struct NodeSpec {
    name: String,
    size: usize,
    kind: NodeKind,
}

struct ProjectionSpec {
    pre: usize,
    post: usize,
    connectivity: Connectivity,
    synapse: ExpSynapse,
}

/// Describes a network node by node; [`build`](Self::build) checks it and prunes it.
#[derive(Default)]
pub struct NetworkBuilder {
    nodes: Vec<NodeSpec>,
    projections: Vec<ProjectionSpec>,
    /// `(current node, population)` injections.
    injections: Vec<(usize, usize)>,
    readouts: Vec<(ReadoutSource, Box<dyn Readout>)>,
}

impl NetworkBuilder {
    /// An empty network description.
    pub fn new() -> Self {
        Self::default()
    }

    fn add(&mut self, name: &str, size: usize, kind: NodeKind) -> Result<NodeId, GraphError> {
        if self.nodes.iter().any(|n| n.name == name) {
            return Err(GraphError::DuplicateName(name.to_owned()));
        }
        self.nodes.push(NodeSpec {
            name: name.to_owned(),
            size,
            kind,
        });
        Ok(NodeId(self.nodes.len() - 1))
    }

    fn node(&self, id: NodeId) -> Result<&NodeSpec, GraphError> {
        self.nodes.get(id.0).ok_or(GraphError::UnknownNode(id.0))
    }

    fn wrong_role(node: &NodeSpec, role: &'static str) -> GraphError {
        GraphError::WrongRole {
            node: node.name.clone(),
            kind: node.kind.describe(),
            role,
        }
    }

    /// Adds a population of neurons; `model` carries its size and parameters.
    pub fn add_population(
        &mut self,
        name: &str,
        model: impl NeuronModel + 'static,
    ) -> Result<NodeId, GraphError> {
        let size = model.len();
        self.add(name, size, NodeKind::Population(Box::new(model)))
    }

    /// Adds a spike source (recorded trains, Poisson, or your own [`SpikeSource`]).
    pub fn add_spike_input(
        &mut self,
        name: &str,
        source: impl SpikeSource + 'static,
    ) -> Result<NodeId, GraphError> {
        let size = source.len();
        self.add(name, size, NodeKind::Spikes(Box::new(source)))
    }

    /// Adds a current source; attach it to populations with [`inject`](Self::inject).
    pub fn add_current_input(
        &mut self,
        name: &str,
        current: CurrentInput,
    ) -> Result<NodeId, GraphError> {
        current.validate(name)?;
        let size = current.len();
        self.add(name, size, NodeKind::Current(current))
    }

    /// Feeds a current source into a population. The source must have one value per neuron or
    /// a single broadcast value.
    pub fn inject(&mut self, current: NodeId, population: NodeId) -> Result<(), GraphError> {
        let src = self.node(current)?;
        if !matches!(src.kind, NodeKind::Current(_)) {
            return Err(Self::wrong_role(src, "injected as a current"));
        }
        let dst = self.node(population)?;
        if !matches!(dst.kind, NodeKind::Population(_)) {
            return Err(Self::wrong_role(dst, "the target of a current"));
        }
        if src.size != 1 && src.size != dst.size {
            return Err(GraphError::SizeMismatch {
                what: format!("current '{}' into population '{}'", src.name, dst.name),
                expected: dst.size,
                got: src.size,
            });
        }
        self.injections.push((current.0, population.0));
        Ok(())
    }

    /// Connects a spike-emitting node (`pre`: population or spike source) to a population
    /// (`post`) through exponential current synapses.
    pub fn connect(
        &mut self,
        pre: NodeId,
        post: NodeId,
        connectivity: Connectivity,
        synapse: ExpSynapse,
    ) -> Result<ProjectionId, GraphError> {
        let src = self.node(pre)?;
        if matches!(src.kind, NodeKind::Current(_)) {
            return Err(Self::wrong_role(src, "a presynaptic spike source"));
        }
        let dst = self.node(post)?;
        if !matches!(dst.kind, NodeKind::Population(_)) {
            return Err(Self::wrong_role(dst, "a postsynaptic target"));
        }
        let what = format!("projection '{}' → '{}'", src.name, dst.name);
        if !(synapse.tau_s.is_finite() && synapse.tau_s > 0.0) {
            return Err(GraphError::InvalidParameter {
                what: format!("{what} tau_s"),
                value: synapse.tau_s,
                expected: "finite and > 0",
            });
        }
        if matches!(src.kind, NodeKind::Population(_)) && synapse.delay_steps == 0 {
            return Err(GraphError::InvalidParameter {
                what: format!("{what} delay_steps"),
                value: 0.0,
                expected: "≥ 1 from a population (its spikes of a step exist only after integration)",
            });
        }
        connectivity.validate(&what, src.size, dst.size)?;
        self.projections.push(ProjectionSpec {
            pre: pre.0,
            post: post.0,
            connectivity,
            synapse,
        });
        Ok(ProjectionId(self.projections.len() - 1))
    }

    /// Attaches any readout. Node sources must emit spikes (population or spike source).
    pub fn add_readout<R: Readout>(
        &mut self,
        source: ReadoutSource,
        readout: R,
    ) -> Result<ReadoutId<R>, GraphError> {
        match source {
            ReadoutSource::Node(id) => {
                let n = self.node(id)?;
                if matches!(n.kind, NodeKind::Current(_)) {
                    return Err(Self::wrong_role(n, "read out (it emits no spikes)"));
                }
            }
            ReadoutSource::Projection(p) if p.0 >= self.projections.len() => {
                return Err(GraphError::UnknownProjection(p.0));
            }
            ReadoutSource::Projection(_) => {}
        }
        self.readouts.push((source, Box::new(readout)));
        Ok(ReadoutId {
            index: self.readouts.len() - 1,
            _type: PhantomData,
        })
    }

    /// Records every spike of a population or spike source.
    pub fn record_spikes(&mut self, node: NodeId) -> Result<ReadoutId<SpikeRecorder>, GraphError> {
        self.add_readout(ReadoutSource::Node(node), SpikeRecorder::new())
    }

    /// Records state variable `variable` of `neurons` (all when `None`) of a population every
    /// `every_steps` steps.
    pub fn record_state(
        &mut self,
        population: NodeId,
        variable: &str,
        neurons: Option<Vec<u32>>,
        every_steps: u64,
    ) -> Result<ReadoutId<StateRecorder>, GraphError> {
        let node = self.node(population)?;
        let NodeKind::Population(model) = &node.kind else {
            return Err(Self::wrong_role(
                node,
                "state-recorded (it has no state variables)",
            ));
        };
        let variables = model.variables();
        let var = variables
            .iter()
            .position(|v| *v == variable)
            .ok_or_else(|| GraphError::Model {
                population: node.name.clone(),
                source: crate::ModelError::UnknownVariable {
                    model: model.model_name(),
                    name: variable.to_owned(),
                    available: variables.join(", "),
                },
            })?;
        let neurons = self.checked_neurons(neurons, node.size, &node.name)?;
        self.add_readout(
            ReadoutSource::Node(population),
            StateRecorder::new(var, neurons, every_steps),
        )
    }

    /// Records the synaptic currents of a projection onto `neurons` (all when `None`) every step.
    pub fn record_synaptic_trace(
        &mut self,
        projection: ProjectionId,
        neurons: Option<Vec<u32>>,
    ) -> Result<ReadoutId<SynapticTraceRecorder>, GraphError> {
        let p = self
            .projections
            .get(projection.0)
            .ok_or(GraphError::UnknownProjection(projection.0))?;
        let post = &self.nodes[p.post];
        let neurons = self.checked_neurons(neurons, post.size, &post.name)?;
        self.add_readout(
            ReadoutSource::Projection(projection),
            SynapticTraceRecorder::new(neurons),
        )
    }

    fn checked_neurons(
        &self,
        neurons: Option<Vec<u32>>,
        size: usize,
        name: &str,
    ) -> Result<Vec<u32>, GraphError> {
        let neurons = neurons.unwrap_or_else(|| (0..size as u32).collect());
        if let Some((index, &n)) = neurons
            .iter()
            .enumerate()
            .find(|(_, n)| **n as usize >= size)
        {
            return Err(GraphError::IndexOutOfRange {
                what: format!("recorded neurons of '{name}'"),
                index,
                neuron: n as usize,
                size,
            });
        }
        Ok(neurons)
    }

    /// Checks the description, drops whatever no readout depends on, prepares the rest for
    /// `config.dt_s` and returns the runnable network.
    pub fn build(self, config: NetworkConfig) -> Result<Network, GraphError> {
        let dt_s = config.dt_s;
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(GraphError::InvalidParameter {
                what: "NetworkConfig dt_s".into(),
                value: dt_s,
                expected: "finite and > 0",
            });
        }
        // Walk back from the readouts.
        let mut node_needed = vec![false; self.nodes.len()];
        let mut proj_needed = vec![false; self.projections.len()];
        let mut stack: Vec<usize> = Vec::new();
        for (source, _) in &self.readouts {
            match *source {
                ReadoutSource::Node(n) => stack.push(n.0),
                ReadoutSource::Projection(p) => {
                    proj_needed[p.0] = true;
                    stack.push(self.projections[p.0].pre);
                }
            }
        }
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut node_needed[n], true) {
                continue;
            }
            for (i, p) in self.projections.iter().enumerate() {
                if p.post == n {
                    proj_needed[i] = true;
                    stack.push(p.pre);
                }
            }
            stack.extend(
                self.injections
                    .iter()
                    .filter(|(_, pop)| *pop == n)
                    .map(|(c, _)| *c),
            );
        }

        // Renumber the needed nodes and prepare them.
        let sizes: Vec<usize> = self.nodes.iter().map(|n| n.size).collect();
        let mut runtime_index = vec![None; self.nodes.len()];
        let mut nodes = Vec::new();
        let mut currents = Vec::new();
        let mut pruned = Vec::new();
        for (i, spec) in self.nodes.into_iter().enumerate() {
            if !node_needed[i] {
                pruned.push(spec.name);
                continue;
            }
            let kind = match spec.kind {
                NodeKind::Current(c) => {
                    runtime_index[i] = Some(currents.len());
                    currents.push(c);
                    continue;
                }
                NodeKind::Spikes(mut s) => {
                    s.prepare(dt_s)?;
                    RunningKind::Spikes(s)
                }
                NodeKind::Population(mut m) => {
                    m.prepare(dt_s).map_err(|source| GraphError::Model {
                        population: spec.name.clone(),
                        source,
                    })?;
                    RunningKind::Population(m)
                }
            };
            runtime_index[i] = Some(nodes.len());
            nodes.push(RunningNode {
                name: spec.name,
                size: spec.size,
                kind,
                history: vec![SpikeBuffer::new()],
                input: vec![0.0; spec.size],
                incoming: Vec::new(),
                currents: Vec::new(),
            });
        }
        let mut projections = Vec::new();
        let mut untargeted = Vec::new();
        let mut projection_index = vec![None; self.projections.len()];
        for (i, p) in self.projections.iter().enumerate() {
            if !proj_needed[i] {
                continue;
            }
            let pre =
                runtime_index[p.pre].expect("a needed projection's presynaptic node is needed");
            let delay = p.synapse.delay_steps as usize;
            let history = &mut nodes[pre].history;
            if history.len() < delay + 1 {
                history.resize(delay + 1, SpikeBuffer::new());
            }
            // A projection kept only for a trace readout may have a pruned target.
            match runtime_index[p.post] {
                Some(post) => nodes[post].incoming.push(projections.len()),
                None => untargeted.push(projections.len()),
            }
            projection_index[i] = Some(projections.len());
            projections.push(RunningProjection {
                pre,
                delay,
                decay: (-dt_s / p.synapse.tau_s).exp(),
                wiring: p.connectivity.compile(sizes[p.pre], sizes[p.post]),
                current: vec![0.0; sizes[p.post]],
            });
        }
        for (c, pop) in self.injections {
            if let (Some(c), Some(pop)) = (runtime_index[c], runtime_index[pop]) {
                nodes[pop].currents.push(c);
            }
        }
        let readouts = self
            .readouts
            .into_iter()
            .map(|(source, readout)| {
                let source = match source {
                    ReadoutSource::Node(n) => {
                        RunningSource::Node(runtime_index[n.0].expect("readout sources are needed"))
                    }
                    ReadoutSource::Projection(p) => RunningSource::Projection(
                        projection_index[p.0].expect("read-out projections are needed"),
                    ),
                };
                (source, readout)
            })
            .collect();
        Ok(Network {
            dt_s,
            step: 0,
            nodes,
            currents,
            projections,
            readouts,
            begun: false,
            pruned,
            node_index: runtime_index,
            untargeted,
        })
    }
}

enum RunningKind {
    Spikes(Box<dyn SpikeSource>),
    Population(Box<dyn NeuronModel>),
}

struct RunningNode {
    name: String,
    size: usize,
    kind: RunningKind,
    /// Ring of this node's spikes, one buffer per step, long enough for its largest delay.
    history: Vec<SpikeBuffer>,
    /// Summed input current (populations).
    input: Vec<f64>,
    /// Projections targeting this node.
    incoming: Vec<usize>,
    /// Current sources injected into this node.
    currents: Vec<usize>,
}

enum RunningSource {
    Node(usize),
    Projection(usize),
}

/// What a call to [`Network::run`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunSummary {
    /// Steps advanced by this call.
    pub steps: u64,
    /// `true` when a readout asked to stop before the requested duration.
    pub stopped_early: bool,
}

/// A built, runnable network. See the [module docs](self) for the phase order of a step.
pub struct Network {
    dt_s: f64,
    step: u64,
    nodes: Vec<RunningNode>,
    currents: Vec<CurrentInput>,
    projections: Vec<RunningProjection>,
    readouts: Vec<(RunningSource, Box<dyn Readout>)>,
    begun: bool,
    pruned: Vec<String>,
    node_index: Vec<Option<usize>>,
    /// Projections kept only for a trace readout (their target was pruned): decayed on their own.
    untargeted: Vec<usize>,
}

impl Network {
    /// The time step (s).
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Steps done since build or the last [`reset`](Self::reset).
    pub fn steps_done(&self) -> u64 {
        self.step
    }

    /// Current network time `steps_done · dt` (s).
    pub fn time_s(&self) -> f64 {
        self.step as f64 * self.dt_s
    }

    /// Names of the nodes dropped at build because no readout depends on them.
    pub fn pruned_nodes(&self) -> &[String] {
        &self.pruned
    }

    /// `true` when `node` was kept (some readout depends on it).
    pub fn is_active(&self, node: NodeId) -> bool {
        self.node_index.get(node.0).is_some_and(Option::is_some)
    }

    /// Total number of synapses in the kept projections.
    pub fn n_synapses(&self) -> usize {
        self.projections
            .iter()
            .map(|p| p.n_synapses(self.nodes[p.pre].size))
            .sum()
    }

    /// The readout `id`, typed.
    pub fn readout<T: Readout>(&self, id: ReadoutId<T>) -> &T {
        let any: &dyn Any = self.readouts[id.index].1.as_ref();
        any.downcast_ref::<T>()
            .expect("a ReadoutId<T> always names a readout of type T")
    }

    /// Replaces a spike source (e.g. the next sample's taxel trains) keeping everything else;
    /// the new source must have the same number of channels. Call [`reset`](Self::reset) to
    /// start it from time 0.
    pub fn replace_spike_input(
        &mut self,
        node: NodeId,
        source: impl SpikeSource + 'static,
    ) -> Result<(), GraphError> {
        let i = self
            .node_index
            .get(node.0)
            .copied()
            .flatten()
            .ok_or(GraphError::UnknownNode(node.0))?;
        let n = &mut self.nodes[i];
        if !matches!(n.kind, RunningKind::Spikes(_)) {
            return Err(GraphError::WrongRole {
                node: n.name.clone(),
                kind: "population",
                role: "replaced by a spike source",
            });
        }
        if source.len() != n.size {
            return Err(GraphError::SizeMismatch {
                what: format!("replacement for spike source '{}'", n.name),
                expected: n.size,
                got: source.len(),
            });
        }
        let mut source: Box<dyn SpikeSource> = Box::new(source);
        source.prepare(self.dt_s)?;
        n.kind = RunningKind::Spikes(source);
        Ok(())
    }

    /// Returns to time 0: sources rewound, populations and synaptic currents reset, readouts
    /// begun anew on the next run.
    pub fn reset(&mut self) {
        self.step = 0;
        self.begun = false;
        for n in &mut self.nodes {
            match &mut n.kind {
                RunningKind::Spikes(s) => s.reset(),
                RunningKind::Population(m) => m.reset(),
            }
            n.history.iter_mut().for_each(SpikeBuffer::clear);
        }
        for p in &mut self.projections {
            p.current.iter_mut().for_each(|c| *c = 0.0);
        }
    }

    /// Runs for `duration_s` (rounded to whole steps), then calls every readout's `finish`.
    pub fn run(&mut self, duration_s: f64) -> Result<RunSummary, GraphError> {
        let steps = duration_s / self.dt_s;
        if !(steps.is_finite() && steps >= 0.0) {
            return Err(GraphError::InvalidParameter {
                what: "run duration_s".into(),
                value: duration_s,
                expected: "finite and ≥ 0",
            });
        }
        self.run_steps(steps.round() as u64)
    }

    /// Runs `steps` steps (fewer if a readout asks to stop), then calls every readout's `finish`.
    /// Every 256 steps and at the end, each population's
    /// [`check_divergence`](NeuronModel::check_divergence) runs; a divergence is an error.
    pub fn run_steps(&mut self, steps: u64) -> Result<RunSummary, GraphError> {
        if !self.begun {
            self.begin_readouts();
        }
        let mut done = 0;
        let mut stopped_early = false;
        while done < steps {
            let stop = self.step_once();
            done += 1;
            if stop || done == steps || done % 256 == 0 {
                for n in &self.nodes {
                    if let RunningKind::Population(m) = &n.kind {
                        let population = n.name.clone();
                        m.check_divergence()
                            .map_err(|source| GraphError::Model { population, source })?;
                    }
                }
            }
            if stop {
                stopped_early = done < steps;
                break;
            }
        }
        self.readouts.iter_mut().for_each(|(_, r)| r.finish());
        Ok(RunSummary {
            steps: done,
            stopped_early,
        })
    }

    fn begin_readouts(&mut self) {
        for (source, r) in &mut self.readouts {
            let (source_name, source_size) = match *source {
                RunningSource::Node(n) => (self.nodes[n].name.as_str(), self.nodes[n].size),
                RunningSource::Projection(p) => {
                    let p = &self.projections[p];
                    (self.nodes[p.pre].name.as_str(), p.current.len())
                }
            };
            r.begin(&ReadoutContext {
                source_name,
                source_size,
                dt_s: self.dt_s,
            });
        }
        self.begun = true;
    }

    /// One step in the documented phase order; returns `true` when a readout asked to stop.
    fn step_once(&mut self) -> bool {
        let k = self.step;
        let t_k = k as f64 * self.dt_s;
        // 1. inputs
        for n in &mut self.nodes {
            if let RunningKind::Spikes(s) = &mut n.kind {
                let slot = (k % n.history.len() as u64) as usize;
                n.history[slot].clear();
                s.emit(k, &mut n.history[slot]);
            }
        }
        // 2. synapses
        for p in &mut self.projections {
            if k >= p.delay as u64 {
                let h = &self.nodes[p.pre].history;
                p.deliver(h[((k - p.delay as u64) % h.len() as u64) as usize].indices());
            }
        }
        // 3–4. integration, threshold and reset (synaptic decay fused into the input sum)
        for n in &mut self.nodes {
            if let RunningKind::Population(m) = &mut n.kind {
                if n.incoming.is_empty() {
                    n.input.iter_mut().for_each(|x| *x = 0.0);
                }
                for (j, &p) in n.incoming.iter().enumerate() {
                    self.projections[p].drain_into(&mut n.input, j == 0);
                }
                for &c in &n.currents {
                    self.currents[c].add_into(t_k, &mut n.input);
                }
                let slot = (k % n.history.len() as u64) as usize;
                n.history[slot].clear();
                m.step(&n.input, &mut n.history[slot]);
            }
        }
        for &p in &self.untargeted {
            self.projections[p].decay();
        }
        // 5. readouts
        let mut stop = false;
        let empty = SpikeBuffer::new();
        for (source, r) in &mut self.readouts {
            let view = match *source {
                RunningSource::Node(i) => {
                    let n = &self.nodes[i];
                    StepView {
                        step: k,
                        t_start_s: t_k,
                        dt_s: self.dt_s,
                        spikes: &n.history[(k % n.history.len() as u64) as usize],
                        population: match &n.kind {
                            RunningKind::Population(m) => Some(m.as_ref()),
                            RunningKind::Spikes(_) => None,
                        },
                        synaptic_current: None,
                    }
                }
                RunningSource::Projection(p) => StepView {
                    step: k,
                    t_start_s: t_k,
                    dt_s: self.dt_s,
                    spikes: &empty,
                    population: None,
                    synaptic_current: Some(&self.projections[p].current),
                },
            };
            stop |= r.on_step(&view) == ControlFlow::Break(());
        }
        self.step += 1;
        stop
    }
}

#[cfg(test)]
mod tests;
