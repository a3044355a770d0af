//! [`NetworkBuilder`]: the network described node by node, checked, pruned to what the
//! readouts need and prepared into a [`Network`] (see the [module docs](super)).

use super::ids::{
    Branded, CurrentId, InputId, NetworkConfig, NodeId, PopulationId, ProjectionId, ReadoutId,
    ReadoutSource, SpikingNode, checked_index, fresh_brand,
};
use super::input::{CurrentInput, SpikeSource};
use super::limits::{MAX_DELAY_STEPS, check_allocatable, check_node_size};
use super::network::{DEFAULT_EPOCH_STEPS, ExchangeStats, Network, Partition};
use super::readout::{Readout, SpikeRecorder, StateRecorder, SynapticTraceRecorder};
use super::running::{RunningKind, RunningNode, RunningSource};
use super::snapshot::NetworkState;
use super::stepping::{EventStepping, Stepping};
use super::synapse::{Connectivity, ExpSynapse, Plasticity, RunningProjection, Stdp, Wiring};
use crate::error::GraphError;
use crate::model::{NeuronModel, SpikeBuffer};
use crate::ranks::even_block;
use std::marker::PhantomData;

pub(super) enum NodeKind {
    Spikes(Box<dyn SpikeSource>),
    Current(CurrentInput),
    Population(Box<dyn NeuronModel>),
}

impl NodeKind {
    pub(super) fn describe(&self) -> &'static str {
        match self {
            NodeKind::Spikes(_) => "spike source",
            NodeKind::Current(_) => "current source",
            NodeKind::Population(_) => "population",
        }
    }
}

pub(super) struct NodeSpec {
    pub(super) name: String,
    pub(super) size: usize,
    pub(super) kind: NodeKind,
}

pub(super) struct ProjectionSpec {
    pub(super) pre: usize,
    pub(super) post: usize,
    connectivity: Connectivity,
    synapse: ExpSynapse,
    plasticity: Option<Stdp>,
}

/// Describes a network node by node; [`build`](Self::build) checks it and prunes it.
///
/// Each builder brands the ids it hands out with a number of its own, which the network it
/// builds keeps: an id of another builder is refused ([`GraphError::ForeignId`]).
pub struct NetworkBuilder {
    /// This builder's brand, carried by every id it hands out.
    pub(super) brand: u64,
    pub(super) nodes: Vec<NodeSpec>,
    pub(super) projections: Vec<ProjectionSpec>,
    /// `(current node, population)` injections.
    injections: Vec<(usize, usize)>,
    pub(super) readouts: Vec<(ReadoutSource, Box<dyn Readout>)>,
    stepping: Stepping,
    /// The saved network this builder was loaded from.
    pub(super) saved: Option<Saved>,
}

/// A saved network's time step and state, and its file (named in every error of its restore).
pub(super) struct Saved {
    pub(super) dt_s: f64,
    pub(super) state: Box<NetworkState>,
    pub(super) path: std::path::PathBuf,
}

impl Default for NetworkBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl NetworkBuilder {
    /// An empty network description, with a brand of its own for the ids it hands out.
    pub fn new() -> Self {
        Self {
            brand: fresh_brand(),
            nodes: Vec::new(),
            projections: Vec::new(),
            injections: Vec::new(),
            readouts: Vec::new(),
            stepping: Stepping::Clock,
            saved: None,
        }
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
        Ok(NodeId {
            index: self.nodes.len() - 1,
            brand: self.brand,
        })
    }

    /// The node `id` names: refused when another builder handed it out
    /// ([`GraphError::ForeignId`], naming the id's kind) or it is out of range.
    fn node(&self, id: impl Branded + Into<NodeId>) -> Result<&NodeSpec, GraphError> {
        let index = checked_index(id, self.brand)?;
        self.nodes.get(index).ok_or(GraphError::UnknownNode(index))
    }

    /// The projection `id` names (refused as [`node`](Self::node) refuses a node id).
    fn projection(&self, id: ProjectionId) -> Result<&ProjectionSpec, GraphError> {
        let index = checked_index(id, self.brand)?;
        self.projections
            .get(index)
            .ok_or(GraphError::UnknownProjection(index))
    }

    pub(super) fn wrong_role(node: &NodeSpec, role: &'static str) -> GraphError {
        GraphError::WrongRole {
            node: node.name.clone(),
            kind: node.kind.describe(),
            role,
        }
    }

    /// Steps populations event-driven where possible ("model only what a scene requires"): a
    /// neuron whose synaptic input is 0 (no current left above
    /// [`FLUSH_TO_ZERO`](super::FLUSH_TO_ZERO)) is not touched in a step, and is advanced over
    /// the skipped steps in closed form when input next reaches it
    /// ([`NeuronModel::step_active`]), so work follows activity
    /// ([`Network::neuron_updates`]). A model without a closed form (Izhikevich) keeps stepping
    /// a neuron at input 0 after its input ends until it is back at its resting point within a
    /// stated tolerance, and holds it there. Applies to populations whose model supports it
    /// with its settings ([`NeuronModel::event_driven`]: LIF with a contracting integrator and
    /// grid spike times; Izhikevich with a stable resting point and grid spike times), with no
    /// injected current and no readout of their state; the others stay clock-driven. Spikes
    /// equal the clock-driven ones except where the closed-form decay and the step-by-step one
    /// round differently (LIF), or the held state's offset (Izhikevich, ≤ the tolerance)
    /// decides, a threshold crossing. Default: off. `event_driven(on)` is
    /// [`stepping`](Self::stepping)`(if on { Stepping::Event } else { Stepping::Clock })`.
    pub fn event_driven(&mut self, on: bool) -> &mut Self {
        self.stepping(if on { Stepping::Event } else { Stepping::Clock })
    }

    /// How the populations that can be stepped event-driven (see
    /// [`event_driven`](Self::event_driven)) are stepped: always clock-driven, always
    /// event-driven, or [`Stepping::Auto`]: each chooses from its measured activity and its
    /// model's crossover, and re-decides as the run goes (see [`Stepping`] and
    /// [`Network::stepping_report`](super::Network::stepping_report)). Default
    /// [`Stepping::Clock`].
    pub fn stepping(&mut self, stepping: Stepping) -> &mut Self {
        self.stepping = stepping;
        self
    }

    /// Adds a population of neurons; `model` carries its size and parameters.
    pub fn add_population(
        &mut self,
        name: &str,
        model: impl NeuronModel + 'static,
    ) -> Result<PopulationId, GraphError> {
        self.add_boxed_population(name, Box::new(model))
    }

    /// [`add_population`](Self::add_population) of a boxed model (as a
    /// [`ModelFactory`](crate::ModelFactory) makes them).
    pub fn add_boxed_population(
        &mut self,
        name: &str,
        model: Box<dyn NeuronModel>,
    ) -> Result<PopulationId, GraphError> {
        let size = model.len();
        check_node_size(name, size)?;
        self.add(name, size, NodeKind::Population(model))
            .map(|n| PopulationId {
                index: n.index,
                brand: n.brand,
            })
    }

    /// Adds a spike source (recorded trains, Poisson, or your own [`SpikeSource`]).
    pub fn add_spike_input(
        &mut self,
        name: &str,
        source: impl SpikeSource + 'static,
    ) -> Result<InputId, GraphError> {
        self.add_boxed_spike_input(name, Box::new(source))
    }

    /// [`add_spike_input`](Self::add_spike_input) of a boxed source.
    pub fn add_boxed_spike_input(
        &mut self,
        name: &str,
        source: Box<dyn SpikeSource>,
    ) -> Result<InputId, GraphError> {
        let size = source.len();
        check_node_size(name, size)?;
        self.add(name, size, NodeKind::Spikes(source))
            .map(|n| InputId {
                index: n.index,
                brand: n.brand,
            })
    }

    /// Adds a current source; attach it to populations with [`inject`](Self::inject).
    pub fn add_current_input(
        &mut self,
        name: &str,
        current: CurrentInput,
    ) -> Result<CurrentId, GraphError> {
        current.validate(name)?;
        let size = current.len();
        self.add(name, size, NodeKind::Current(current))
            .map(|n| CurrentId {
                index: n.index,
                brand: n.brand,
            })
    }

    /// Feeds a current source into a population. The source must have one value per neuron or
    /// a single broadcast value.
    pub fn inject(
        &mut self,
        current: CurrentId,
        population: PopulationId,
    ) -> Result<(), GraphError> {
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
        self.injections.push((current.index, population.index));
        Ok(())
    }

    /// Connects a spike-emitting node (`pre`: a [`PopulationId`] or an [`InputId`]) to a
    /// population (`post`) through exponential current synapses.
    ///
    /// **Delay rule** ([`ExpSynapse::with_delay`]): from a population the delay is at least one
    /// step — a population's spikes of step `k` exist only after its integration in step `k`,
    /// so they reach their targets in step `k + delay`; from a spike input, delay 0 delivers a
    /// spike in the step it is emitted. A population → population projection with delay 0 is
    /// an error ([`GraphError::InvalidParameter`] naming the projection).
    pub fn connect(
        &mut self,
        pre: impl SpikingNode,
        post: PopulationId,
        connectivity: Connectivity,
        synapse: ExpSynapse,
    ) -> Result<ProjectionId, GraphError> {
        self.add_projection(pre, post, connectivity, synapse, None)
    }

    /// [`connect`](Self::connect) with plastic weights: the projection learns by `stdp` (pair-based
    /// STDP with traces, see [`Stdp`]) while the network runs, clock- or event-driven, with any
    /// connectivity and delay; [`Network::set_learning`](super::Network::set_learning) freezes it.
    /// Every initial weight must lie in `[stdp.w_min, stdp.w_max]`
    /// ([`GraphError::InvalidParameter`] otherwise).
    pub fn connect_plastic(
        &mut self,
        pre: impl SpikingNode,
        post: PopulationId,
        connectivity: Connectivity,
        synapse: ExpSynapse,
        stdp: Stdp,
    ) -> Result<ProjectionId, GraphError> {
        self.add_projection(pre, post, connectivity, synapse, Some(stdp))
    }

    pub(super) fn add_projection(
        &mut self,
        pre: impl SpikingNode,
        post: PopulationId,
        connectivity: Connectivity,
        synapse: ExpSynapse,
        plasticity: Option<Stdp>,
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
        if synapse.delay_steps > MAX_DELAY_STEPS {
            return Err(GraphError::InvalidParameter {
                what: format!("{what} delay_steps"),
                value: f64::from(synapse.delay_steps),
                expected: "at most 2²⁰ steps (limits::MAX_DELAY_STEPS)",
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
        if let Some(stdp) = &plasticity {
            stdp.validate(&what)?;
            connectivity.check_weights_within(&what, stdp.w_min, stdp.w_max)?;
        }
        let (pre, post) = (pre.index(), post.index);
        self.projections.push(ProjectionSpec {
            pre,
            post,
            connectivity,
            synapse,
            plasticity,
        });
        Ok(ProjectionId {
            index: self.projections.len() - 1,
            brand: self.brand,
        })
    }

    /// Attaches any readout to a population, a spike input or a projection (any of their ids,
    /// or a [`ReadoutSource`]). Node sources must emit spikes.
    pub fn add_readout<R: Readout>(
        &mut self,
        source: impl Into<ReadoutSource>,
        readout: R,
    ) -> Result<ReadoutId<R>, GraphError> {
        let source = source.into();
        match source {
            ReadoutSource::Node(id) => {
                let n = self.node(id)?;
                if matches!(n.kind, NodeKind::Current(_)) {
                    return Err(Self::wrong_role(n, "read out (it emits no spikes)"));
                }
            }
            ReadoutSource::Projection(p) => {
                self.projection(p)?;
            }
        }
        self.readouts.push((source, Box::new(readout)));
        Ok(ReadoutId {
            index: self.readouts.len() - 1,
            brand: self.brand,
            _type: PhantomData,
        })
    }

    /// Records every spike of a population or spike source.
    pub fn record_spikes(
        &mut self,
        node: impl SpikingNode,
    ) -> Result<ReadoutId<SpikeRecorder>, GraphError> {
        // Checked here too, so that a foreign id's error names its kind, not just "node".
        self.node(node)?;
        self.add_readout(ReadoutSource::Node(node.into()), SpikeRecorder::new())
    }

    /// Records state variable `variable` of `neurons` (all when `None`) of a population every
    /// `every_steps` steps.
    pub fn record_state(
        &mut self,
        population: PopulationId,
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
        self.add_readout(population, StateRecorder::new(var, neurons, every_steps))
    }

    /// Records the synaptic currents of a projection onto `neurons` (all when `None`) every step.
    pub fn record_synaptic_trace(
        &mut self,
        projection: ProjectionId,
        neurons: Option<Vec<u32>>,
    ) -> Result<ReadoutId<SynapticTraceRecorder>, GraphError> {
        let p = self.projection(projection)?;
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
    /// `config.dt_s` and returns the runnable network (one process: every neuron here).
    pub fn build(self, config: NetworkConfig) -> Result<Network, GraphError> {
        self.build_partitioned(config, 0, 1)
    }

    /// [`build`](Self::build), for rank `rank` of `size` ranks that compute the network
    /// together ([`Network::run`]; the scheme of NEST and Arbor):
    /// - every population of `N` neurons is split into contiguous blocks
    ///   ([`even_block`](crate::ranks::even_block)`(N, rank, size)`), and this rank instantiates
    ///   only its block ([`NeuronModel::restrict`]; a model that cannot be restricted is a
    ///   [`GraphError::ModelNotPartitionable`]). A block may be empty (more ranks than neurons);
    /// - spike sources and current sources are replicated: every rank computes them in full;
    /// - each projection keeps only the synapses onto this rank's neurons: exactly those of the
    ///   whole network (random pairs are drawn from the same seeded stream, which every rank
    ///   walks in full, keeping only its own), so memory holds only the local synapses;
    /// - readouts see every rank's spikes (global indices), so each rank's readouts end as in
    ///   one process; readouts that need state held by one rank (a population's state,
    ///   [`Readout::reads_population_state`]; a projection's synaptic currents) are a
    ///   [`GraphError::ReadoutNotPartitionable`] when `size > 1`.
    ///
    /// With `size == 1` this is [`build`](Self::build). `rank ≥ size` or `size == 0` is a
    /// [`GraphError::InvalidPartition`].
    pub fn build_partitioned(
        mut self,
        config: NetworkConfig,
        rank: usize,
        size: usize,
    ) -> Result<Network, GraphError> {
        let dt_s = config.dt_s;
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(GraphError::InvalidParameter {
                what: "NetworkConfig dt_s".into(),
                value: dt_s,
                expected: "finite and > 0",
            });
        }
        if size == 0 || rank >= size {
            return Err(GraphError::InvalidPartition { rank, size });
        }
        let partitioned = size > 1;
        if partitioned {
            self.check_partitionable_readouts(size)?;
        }
        let saved = self.saved.take();
        if let Some(Saved { dt_s: saved_dt, .. }) = &saved {
            if *saved_dt != dt_s {
                return Err(GraphError::InvalidParameter {
                    what: format!("NetworkConfig dt_s of a network saved at dt = {saved_dt} s"),
                    value: dt_s,
                    expected: "the saved time step (NetworkBuilder::saved_dt_s)",
                });
            }
            if partitioned {
                return Err(GraphError::NotSaveable {
                    node: "a saved network".into(),
                    reason: "it continues in one process only (build it with build)".into(),
                });
            }
        }
        // Walk back from the readouts.
        let mut node_needed = vec![false; self.nodes.len()];
        let mut proj_needed = vec![false; self.projections.len()];
        let mut stack: Vec<usize> = Vec::new();
        for (source, _) in &self.readouts {
            match *source {
                ReadoutSource::Node(n) => stack.push(n.index),
                ReadoutSource::Projection(p) => {
                    proj_needed[p.index] = true;
                    stack.push(self.projections[p.index].pre);
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

        // Renumber the needed nodes, restrict populations to this rank's block, prepare them.
        let sizes: Vec<usize> = self.nodes.iter().map(|n| n.size).collect();
        let block = |n: usize| even_block(n, rank, size);
        let mut runtime_index = vec![None; self.nodes.len()];
        let mut nodes = Vec::new();
        let mut currents = Vec::new();
        let mut current_names = Vec::new();
        let mut pruned = Vec::new();
        for (i, spec) in self.nodes.into_iter().enumerate() {
            if !node_needed[i] {
                pruned.push(spec.name);
                continue;
            }
            let mut local = 0..spec.size;
            // Its input, spike buffer and (a population's) state: a few numbers per neuron.
            check_allocatable(|| format!("node '{}'", spec.name), spec.size as u64, 64)?;
            let kind = match spec.kind {
                NodeKind::Current(c) => {
                    runtime_index[i] = Some(currents.len());
                    current_names.push(spec.name);
                    currents.push(if partitioned {
                        c.restrict(block(c.len()))
                    } else {
                        c
                    });
                    continue;
                }
                NodeKind::Spikes(mut s) => {
                    s.prepare(dt_s)?;
                    RunningKind::Spikes(s)
                }
                NodeKind::Population(m) => {
                    let mut m = if partitioned {
                        local = block(spec.size);
                        Self::restricted(m, local.clone(), &spec.name)?
                    } else {
                        m
                    };
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
                input: vec![0.0; local.len()],
                local,
                kind,
                history: vec![SpikeBuffer::new()],
                incoming: Vec::new(),
                currents: Vec::new(),
                active: None,
            });
        }
        let mut projections = Vec::new();
        let mut untargeted = Vec::new();
        let mut projection_index = vec![None; self.projections.len()];
        // The epoch: the smallest delay of a population → population projection (spikes of a
        // population reach no one sooner), or DEFAULT_EPOCH_STEPS.
        let mut epoch_steps = DEFAULT_EPOCH_STEPS;
        for (i, p) in self.projections.iter().enumerate() {
            if !proj_needed[i] {
                continue;
            }
            let pre =
                runtime_index[p.pre].expect("a needed projection's presynaptic node is needed");
            let delay = p.synapse.delay_steps as usize;
            if matches!(nodes[pre].kind, RunningKind::Population(_)) {
                epoch_steps = epoch_steps.min(delay as u64);
            }
            let history = &mut nodes[pre].history;
            if history.len() < delay + 1 {
                let slots = (delay + 1 - history.len()) as u64;
                check_allocatable(
                    || {
                        format!(
                            "the spike history of '{}' ({delay} steps of delay)",
                            nodes[pre].name
                        )
                    },
                    slots,
                    size_of::<SpikeBuffer>() as u64,
                )?;
                let history = &mut nodes[pre].history;
                history.resize(delay + 1, SpikeBuffer::new());
            }
            // A projection kept only for a trace readout may have a pruned target.
            match runtime_index[p.post] {
                Some(post) => nodes[post].incoming.push(projections.len()),
                None => untargeted.push(projections.len()),
            }
            let post_block = block(sizes[p.post]);
            projection_index[i] = Some(projections.len());
            let n_local = post_block.len();
            let what = || {
                format!(
                    "projection '{}' → '{}'",
                    nodes[pre].name,
                    runtime_index[p.post].map_or("(pruned)", |j| nodes[j].name.as_str())
                )
            };
            // Explicit synapses (4-byte target, 8-byte weight; a plastic one's two indices too).
            let (synapses, per_synapse) = match p.plasticity {
                Some(_) => (p.connectivity.max_synapses(sizes[p.pre], n_local), 36),
                None => (p.connectivity.stored_synapses(sizes[p.pre], n_local), 12),
            };
            check_allocatable(what, synapses, per_synapse)?;
            check_allocatable(what, (sizes[p.pre] + n_local) as u64, 24)?;
            let mut wiring = p
                .connectivity
                .compile(sizes[p.pre], sizes[p.post], post_block);
            let mut plasticity = None;
            if let Some(rule) = p.plasticity {
                rule.validate_at(&what(), dt_s)?;
                wiring = wiring.explicit(sizes[p.pre], n_local);
                if let Wiring::Csr { offsets, post, .. } = &wiring {
                    plasticity = Some(Box::new(Plasticity::new(
                        rule, dt_s, offsets, post, n_local,
                    )));
                }
            }
            let mut projection = RunningProjection {
                pre,
                post: runtime_index[p.post],
                delay,
                tau_s: p.synapse.tau_s,
                decay: (-dt_s / p.synapse.tau_s).exp(),
                current: vec![0.0; n_local],
                wiring,
                bound: f64::INFINITY,
                plasticity,
            };
            let from_population = matches!(nodes[pre].kind, RunningKind::Population(_));
            projection.bound = projection.current_bound(sizes[p.pre], from_population);
            projections.push(projection);
        }
        if partitioned {
            // An epoch's spikes stay in the rings until they are exchanged and read out.
            for n in &mut nodes {
                if n.history.len() < epoch_steps as usize {
                    n.history.resize(epoch_steps as usize, SpikeBuffer::new());
                }
            }
        }
        for (c, pop) in self.injections {
            if let (Some(c), Some(pop)) = (runtime_index[c], runtime_index[pop]) {
                nodes[pop].currents.push(c);
            }
        }
        // Event-driven populations: asked for, supported by the model with its settings, fed
        // by projections only (an injected current reaches every neuron) and read by no readout
        // that looks at their state (which would see skipped neurons before they are settled).
        if self.stepping != Stepping::Clock {
            for (i, node) in nodes.iter_mut().enumerate() {
                let RunningKind::Population(m) = &node.kind else {
                    continue;
                };
                let state_read = self.readouts.iter().any(|(source, r)| {
                    matches!(*source, ReadoutSource::Node(n) if runtime_index[n.index] == Some(i))
                        && r.reads_population_state()
                });
                if m.event_driven() && node.currents.is_empty() && !state_read {
                    let crossover = match &self.stepping {
                        Stepping::Auto(c) => Some(
                            c.get(m.model_name())
                                .unwrap_or_else(|| m.default_crossover()),
                        ),
                        _ => None,
                    };
                    node.active = Some(EventStepping::new(node.local.len(), crossover));
                }
            }
        }
        let readouts = self
            .readouts
            .into_iter()
            .map(|(source, readout)| {
                let source = match source {
                    ReadoutSource::Node(n) => RunningSource::Node(
                        runtime_index[n.index].expect("readout sources are needed"),
                    ),
                    ReadoutSource::Projection(p) => RunningSource::Projection(
                        projection_index[p.index].expect("read-out projections are needed"),
                    ),
                };
                (source, readout)
            })
            .collect();
        let exchanged = if partitioned {
            (0..nodes.len())
                .filter(|&i| matches!(nodes[i].kind, RunningKind::Population(_)))
                .collect()
        } else {
            Vec::new()
        };
        let mut network = Network {
            brand: self.brand,
            dt_s,
            step: 0,
            nodes,
            currents,
            projections,
            readouts,
            begun: false,
            pruned,
            node_index: runtime_index,
            neuron_updates: 0,
            scratch: Vec::new(),
            untargeted,
            partition: Partition {
                rank,
                size,
                epoch_steps,
                exchanged,
            },
            exchange: ExchangeStats::default(),
            packed: Vec::new(),
            projection_index,
            current_names,
            stepping: self.stepping,
        };
        if let Some(saved) = saved {
            network
                .restore(&saved.state)
                .map_err(|source| GraphError::Saved {
                    path: saved.path,
                    source: Box::new(source),
                })?;
        }
        Ok(network)
    }
}
