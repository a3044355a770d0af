//! [`Network`]: a built network and its run loop, one step in the documented phase order (see
//! the [module docs](super)).

use super::exchange::{pack_epoch, unpack_epoch};
use super::ids::{InputId, NodeId, ReadoutId, checked_index};
use super::input::{CurrentInput, SpikeSource};
use super::limits::{MAX_RUN_STEPS, MAX_STEPS};
use super::readout::{Readout, ReadoutContext, StepView};
use super::running::{RunningKind, RunningNode, RunningSource};
use super::stepping::{ActiveSet, EventStepping, PopulationStepping, SteppingMode};
use super::synapse::RunningProjection;
use crate::currents::{DecayingCurrents, SynapticDrive, flush};
use crate::error::GraphError;
use crate::model::{NeuronModel, SpikeBuffer};
use crate::ranks::Ranks;
use std::any::Any;
use std::ops::ControlFlow;
use std::time::Instant;

/// Steps per epoch of a network partitioned over ranks that has no population → population
/// projection (otherwise the epoch is the smallest delay of such a projection, in steps).
pub const DEFAULT_EPOCH_STEPS: u64 = 64;

/// Which rank of how many a network was built for, and its epoch.
pub(super) struct Partition {
    pub(super) rank: usize,
    pub(super) size: usize,
    /// Steps between two spike exchanges (see [`Network::epoch_steps`]).
    pub(super) epoch_steps: u64,
    /// The nodes whose spikes are exchanged: every population when `size > 1`, else none.
    pub(super) exchanged: Vec<usize>,
}

/// The cost of the spike exchanges since build or the last reset.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ExchangeStats {
    pub(super) seconds: f64,
    pub(super) count: u64,
}

/// What a call to [`Network::run`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunSummary {
    /// Steps advanced by this call.
    pub steps: u64,
    /// `true` when a readout asked to stop before the requested duration.
    pub stopped_early: bool,
}

/// A built, runnable network. See the [module docs](super) for the phase order of a step.
pub struct Network {
    /// The brand of the builder this network was built from: the ids it accepts.
    pub(super) brand: u64,
    pub(super) dt_s: f64,
    pub(super) step: u64,
    pub(super) nodes: Vec<RunningNode>,
    pub(super) currents: Vec<CurrentInput>,
    pub(super) projections: Vec<RunningProjection>,
    pub(super) readouts: Vec<(RunningSource, Box<dyn Readout>)>,
    pub(super) begun: bool,
    pub(super) pruned: Vec<String>,
    pub(super) node_index: Vec<Option<usize>>,
    /// Projections kept only for a trace readout (their target was pruned): decayed on their own.
    pub(super) untargeted: Vec<usize>,
    /// Neuron updates done since build or the last reset.
    pub(super) neuron_updates: u64,
    /// Presynaptic spikes of one delivery (reused, so a step allocates nothing).
    pub(super) scratch: Vec<u32>,
    pub(super) partition: Partition,
    pub(super) exchange: ExchangeStats,
    /// This rank's message of one exchange (reused).
    pub(super) packed: Vec<u8>,
    /// The run-time index of each of the builder's projections (`None` when pruned).
    pub(super) projection_index: Vec<Option<usize>>,
    /// The names of the kept current sources (`currents`' order).
    pub(super) current_names: Vec<String>,
    /// How the populations are stepped (as the builder was told).
    pub(super) stepping: super::Stepping,
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

    /// `true` when `node` was kept (some readout depends on it). An id of another builder is a
    /// [`GraphError::ForeignId`].
    pub fn is_active(&self, node: impl Into<NodeId>) -> Result<bool, GraphError> {
        let index = checked_index(node.into(), self.brand)?;
        Ok(self.node_index.get(index).is_some_and(Option::is_some))
    }

    /// Neuron updates done since build or the last [`reset`](Self::reset): every neuron of a
    /// clock-driven population each step, only the neurons with input (and those still settling
    /// back to rest) of an event-driven one
    /// ([`NetworkBuilder::event_driven`](super::NetworkBuilder::event_driven)).
    pub fn neuron_updates(&self) -> u64 {
        self.neuron_updates
    }

    /// The rank this network was built for ([`NetworkBuilder::build_partitioned`]; 0 in one
    /// process).
    ///
    /// [`NetworkBuilder::build_partitioned`]: super::NetworkBuilder::build_partitioned
    pub fn rank(&self) -> usize {
        self.partition.rank
    }

    /// The number of ranks this network was built for (1 in one process).
    pub fn n_ranks(&self) -> usize {
        self.partition.size
    }

    /// Steps per epoch of a partitioned run ([`run`](Self::run)): the smallest delay of
    /// a kept population → population projection, or [`DEFAULT_EPOCH_STEPS`] without one.
    /// Ranks exchange spikes once per epoch.
    pub fn epoch_steps(&self) -> u64 {
        self.partition.epoch_steps
    }

    /// Wall time (s) spent in spike exchanges since build or the last [`reset`](Self::reset):
    /// packing this rank's spikes, the all-gather (waiting for the other ranks included) and
    /// unpacking every rank's. 0 in one process.
    pub fn exchange_s(&self) -> f64 {
        self.exchange.seconds
    }

    /// Spike exchanges done since build or the last [`reset`](Self::reset) (one per epoch, and
    /// one at the end of each run; 0 in one process).
    pub fn exchanges(&self) -> u64 {
        self.exchange.count
    }

    /// Names of the populations stepped event-driven now (with [`Stepping::Auto`], the mode
    /// can change as the run goes: see [`stepping_report`](Self::stepping_report)).
    ///
    /// [`Stepping::Auto`]: super::Stepping::Auto
    pub fn event_driven_populations(&self) -> Vec<&str> {
        self.nodes
            .iter()
            .filter(|n| n.active.as_ref().is_some_and(|a| a.event))
            .map(|n| n.name.as_str())
            .collect()
    }

    /// Each population's stepping, in build order: its current mode, its crossover when it
    /// chooses automatically, its measured activity and its switches (see
    /// [`NetworkBuilder::stepping`](super::NetworkBuilder::stepping)).
    pub fn stepping_report(&self) -> Vec<PopulationStepping> {
        self.nodes
            .iter()
            .filter_map(|n| match &n.kind {
                RunningKind::Population(m) => Some((n, m.model_name())),
                RunningKind::Spikes(_) => None,
            })
            .map(|(n, model)| {
                let a = n.active.as_ref();
                PopulationStepping {
                    population: n.name.clone(),
                    model,
                    mode: match a {
                        Some(a) if a.event => SteppingMode::Event,
                        _ => SteppingMode::Clock,
                    },
                    crossover: a.and_then(|a| a.crossover),
                    activity: a.and_then(EventStepping::activity),
                    switches: a.map_or(0, |a| a.switches),
                }
            })
            .collect()
    }

    /// Total number of synapses in the kept projections (on this rank: the synapses onto its
    /// own neurons, when partitioned).
    pub fn n_synapses(&self) -> usize {
        self.projections
            .iter()
            .map(|p| p.n_synapses(self.nodes[p.pre].size))
            .sum()
    }

    /// The readout `id`, typed. An id of another builder is a [`GraphError::ForeignId`].
    pub fn readout<T: Readout>(&self, id: ReadoutId<T>) -> Result<&T, GraphError> {
        let index = checked_index(id, self.brand)?;
        let any: &dyn Any = self.readouts[index].1.as_ref();
        Ok(any
            .downcast_ref::<T>()
            .expect("a ReadoutId<T> of this network's builder names a readout of type T"))
    }

    /// Replaces a spike source (e.g. the next sample's taxel trains) keeping everything else;
    /// the new source must have the same number of channels. Call [`reset`](Self::reset) to
    /// start it from time 0. An id of another builder is a [`GraphError::ForeignId`].
    pub fn replace_spike_input(
        &mut self,
        node: InputId,
        source: impl SpikeSource + 'static,
    ) -> Result<(), GraphError> {
        let index = checked_index(node, self.brand)?;
        let i = self
            .node_index
            .get(index)
            .copied()
            .flatten()
            .ok_or(GraphError::UnknownNode(index))?;
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

    /// Returns to time 0: sources rewound, populations and synaptic currents reset, plasticity
    /// traces cleared, readouts begun anew on the next run. Weights stay as they are (what a
    /// plastic projection learned is kept; [`set_weights`](Self::set_weights) restores others).
    pub fn reset(&mut self) {
        self.step = 0;
        self.begun = false;
        for n in &mut self.nodes {
            match &mut n.kind {
                RunningKind::Spikes(s) => s.reset(),
                RunningKind::Population(m) => m.reset(),
            }
            n.history.iter_mut().for_each(SpikeBuffer::clear);
            if let Some(a) = &mut n.active {
                a.set.clear();
                a.reset_counts();
            }
        }
        self.neuron_updates = 0;
        self.exchange = ExchangeStats::default();
        for p in &mut self.projections {
            p.current.iter_mut().for_each(|c| *c = 0.0);
            if let Some(plasticity) = &mut p.plasticity {
                plasticity.clear();
            }
        }
    }

    /// [`run_steps`](Self::run_steps) of a network built for one process, asking
    /// `interrupted` every 256 steps.
    fn run_steps_in_one_process(
        &mut self,
        steps: u64,
        interrupted: &mut dyn FnMut() -> bool,
    ) -> Result<RunSummary, GraphError> {
        if !self.begun {
            self.begin_readouts();
        }
        let mut done = 0;
        let mut stopped_early = false;
        while done < steps {
            let mut stop = self.step_once();
            done += 1;
            if done % 256 == 0 && done < steps && interrupted() {
                stop = true;
            }
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
        Ok(self.end_run(done, stopped_early))
    }

    /// The end of every run: event-driven populations brought up to date, readouts finished.
    fn end_run(&mut self, steps: u64, stopped_early: bool) -> RunSummary {
        for n in &mut self.nodes {
            if let (RunningKind::Population(m), Some(a)) = (&mut n.kind, &n.active)
                && a.event
            {
                m.settle();
            }
        }
        self.readouts.iter_mut().for_each(|(_, r)| r.finish());
        RunSummary {
            steps,
            stopped_early,
        }
    }

    /// Runs for `duration_s` (rounded to whole steps), then calls every readout's `finish`.
    ///
    /// `ranks` is the group of ranks the network was built for: [`OneProcess`](crate::OneProcess)
    /// for [`NetworkBuilder::build`](super::NetworkBuilder::build), the group of
    /// [`NetworkBuilder::build_partitioned`](super::NetworkBuilder::build_partitioned) otherwise,
    /// every rank of which must call it with the same duration.
    pub fn run(&mut self, duration_s: f64, ranks: &dyn Ranks) -> Result<RunSummary, GraphError> {
        let steps = self.steps_for(duration_s)?;
        self.run_steps(steps, ranks)
    }

    /// The steps [`run`](Self::run) takes for `duration_s` (rounded to whole steps): refused
    /// when the duration is not finite and ≥ 0, or the steps are more than one run may take
    /// ([`MAX_RUN_STEPS`]: a `dt` of 10⁻³⁰⁰ s makes any duration such a run) or than the
    /// network may do in all ([`MAX_STEPS`]).
    pub fn steps_for(&self, duration_s: f64) -> Result<u64, GraphError> {
        let steps = (duration_s / self.dt_s).round();
        if !(duration_s.is_finite() && steps >= 0.0) {
            return Err(GraphError::InvalidParameter {
                what: "run duration_s".into(),
                value: duration_s,
                expected: "finite and ≥ 0",
            });
        }
        if steps > MAX_RUN_STEPS as f64 {
            return Err(GraphError::InvalidParameter {
                what: format!("run of {duration_s} s at dt = {} s: steps", self.dt_s),
                value: steps,
                expected: "at most 2⁴⁰ steps in one run (limits::MAX_RUN_STEPS)",
            });
        }
        let steps = steps as u64;
        self.check_step_budget(steps)?;
        Ok(steps)
    }

    /// Refuses `steps` more steps when they would take the network past [`MAX_STEPS`].
    fn check_step_budget(&self, steps: u64) -> Result<(), GraphError> {
        match self.step.checked_add(steps) {
            Some(end) if end <= MAX_STEPS => Ok(()),
            _ => Err(GraphError::InvalidParameter {
                what: format!("{steps} more steps after step {}: steps", self.step),
                value: self.step as f64 + steps as f64,
                expected: "at most 2⁵³ steps in all (limits::MAX_STEPS)",
            }),
        }
    }

    /// Runs `steps` steps (fewer if a readout asks to stop), then calls every readout's `finish`.
    /// Every 256 steps and at the end, each population's
    /// [`check_divergence`](crate::NeuronModel::check_divergence) runs; a divergence is an error.
    ///
    /// `ranks` is the group of ranks the network was built for ([`OneProcess`](crate::OneProcess)
    /// for one process); every rank of the group must call it with the same `steps`. A group
    /// other than the build's is a [`GraphError::RanksMismatch`].
    ///
    /// # Epochs
    /// Over several ranks the run advances in epochs of [`epoch_steps`](Self::epoch_steps)
    /// steps `E` (the last one of a run may be shorter). Within an epoch each rank steps its
    /// own neurons and writes their spikes, with global indices, into its populations' spike
    /// histories; deliveries need no other rank's spikes, since they read spikes at least
    /// `delay ≥ E` steps old, all exchanged in earlier epochs. At the end of the epoch every
    /// rank all-gathers its spikes of the epoch's steps (indices, with in-step fractions when
    /// any is not 1) and the histories of those steps are refilled with every rank's spikes in
    /// rank order: ascending global index, as in one process. Then the readouts see the epoch's
    /// steps one by one (deferred), so each rank's readouts end as in one process (they see
    /// spikes only: [`StepView::population`] is `None`, since each rank holds a block of the
    /// state); a readout's stop request takes effect at the end of the epoch (the readouts still see its remaining
    /// steps, and [`RunSummary::steps`] counts them). Divergence is checked before every
    /// exchange on each rank, and reported to all: the rank that diverged returns its
    /// [`GraphError::Model`], the others [`GraphError::PeerDiverged`].
    pub fn run_steps(&mut self, steps: u64, ranks: &dyn Ranks) -> Result<RunSummary, GraphError> {
        self.run_steps_until(steps, ranks, &mut || false)
    }

    /// [`run_steps`](Self::run_steps) that can be interrupted: in one process `interrupted` is
    /// asked every 256 steps, and the run ends there (as a readout's stop request ends it,
    /// [`RunSummary::stopped_early`]) when it answers `true` — Ctrl-C in a binding. Over
    /// several ranks it is not asked (the ranks could not agree where to stop).
    pub fn run_steps_until(
        &mut self,
        steps: u64,
        ranks: &dyn Ranks,
        interrupted: &mut dyn FnMut() -> bool,
    ) -> Result<RunSummary, GraphError> {
        self.check_ranks(ranks.rank(), ranks.size())?;
        self.check_step_budget(steps)?;
        if self.partition.size == 1 {
            return self.run_steps_in_one_process(steps, interrupted);
        }
        if !self.begun {
            self.begin_readouts();
        }
        let (mut done, mut stop) = (0, false);
        while done < steps && !stop {
            let from = self.step;
            let epoch = self.partition.epoch_steps.min(steps - done);
            for _ in 0..epoch {
                self.advance();
            }
            done += epoch;
            self.exchange_epoch(from, ranks)?;
            for k in from..self.step {
                stop |= self.read_out(k, false);
            }
        }
        Ok(self.end_run(done, stop && done < steps))
    }

    fn check_ranks(&self, rank: usize, size: usize) -> Result<(), GraphError> {
        let Partition {
            rank: built_rank,
            size: built_size,
            ..
        } = self.partition;
        if (rank, size) == (built_rank, built_size) {
            return Ok(());
        }
        Err(GraphError::RanksMismatch {
            built_rank,
            built_size,
            rank,
            size,
        })
    }

    /// Exchanges the spikes of steps `from..self.step` of every partitioned population between
    /// the ranks (see [`run_steps`](Self::run_steps)), timing it.
    fn exchange_epoch(&mut self, from: u64, ranks: &dyn Ranks) -> Result<(), GraphError> {
        let start = Instant::now();
        let to = self.step;
        let mut diverged = None;
        for n in &self.nodes {
            if let RunningKind::Population(m) = &n.kind
                && let Err(source) = m.check_divergence()
            {
                let population = n.name.clone();
                diverged = Some(GraphError::Model { population, source });
                break;
            }
        }
        let steps = from..to;
        pack_epoch(
            &self.nodes,
            &self.partition.exchanged,
            steps.clone(),
            diverged.is_some(),
            &mut self.packed,
        );
        let blocks = ranks
            .all_gather_bytes(&self.packed)
            .map_err(|e| GraphError::Exchange {
                step: to,
                reason: e.to_string(),
            })?;
        if let Some(e) = diverged {
            return Err(e);
        }
        unpack_epoch(&mut self.nodes, &self.partition.exchanged, steps, &blocks)?;
        self.exchange.seconds += start.elapsed().as_secs_f64();
        self.exchange.count += 1;
        Ok(())
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
        self.advance();
        self.read_out(k, true)
    }

    /// Phases 1–4 of one step (everything but the readouts), then the next step.
    fn advance(&mut self) {
        let k = self.step;
        let t_k = k as f64 * self.dt_s;
        // 0. automatic populations switch mode when their activity calls for it
        for n in &mut self.nodes {
            if let (RunningKind::Population(m), Some(a)) = (&mut n.kind, &mut n.active)
                && let Some(event) = a.decide(k)
            {
                switch_mode(m.as_mut(), a, &self.projections, &n.incoming, event);
            }
        }
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
                let spikes = h[((k - p.delay as u64) % h.len() as u64) as usize].indices();
                p.deliver(spikes);
                p.learn_from_pre(spikes, k);
                let event =
                    |post: &usize| self.nodes[*post].active.as_ref().is_some_and(|a| a.event);
                if let Some(post) = p.post.filter(event) {
                    self.scratch.clear();
                    self.scratch.extend_from_slice(spikes);
                    let active = &mut self.nodes[post].active.as_mut().expect("checked").set;
                    p.for_each_target(&self.scratch, |j| active.mark(j));
                }
            }
        }
        // 3–4. integration, threshold and reset (synaptic decay fused into the input sum)
        for n in &mut self.nodes {
            if let (RunningKind::Population(m), Some(stepping)) = (&mut n.kind, &mut n.active)
                && stepping.event
            {
                stepping.count(stepping.set.list.len(), n.local.len());
                let active = &mut stepping.set;
                // Event-driven: only the neurons with synaptic current, summed in the
                // clock-driven order (so equal inputs give equal states), gathered in list order.
                if !active.sorted {
                    active.list.sort_unstable();
                    active.sorted = true;
                }
                // In the same pass, the neurons whose current survives this step's decay
                // (the others leave the set after this step).
                let ActiveSet {
                    list, next, flag, ..
                } = active;
                next.clear();
                let mut keep = |j: u32, live: bool| {
                    if live {
                        next.push(j);
                    } else {
                        flag[j as usize] = false;
                    }
                };
                if let [only] = n.incoming[..] {
                    // One projection (the afferent pipeline): a tight loop.
                    let p = &mut self.projections[only];
                    let (current, decay) = (&mut p.current[..], p.decay);
                    for (&j, x) in list.iter().zip(n.input.iter_mut()) {
                        let c = &mut current[j as usize];
                        *x = *c;
                        *c = flush(*c * decay);
                        keep(j, *c != 0.0);
                    }
                } else {
                    for (&j, input) in list.iter().zip(n.input.iter_mut()) {
                        let (mut x, mut live) = (0.0, false);
                        for &p in &n.incoming {
                            let p = &mut self.projections[p];
                            let c = &mut p.current[j as usize];
                            x += *c;
                            *c = flush(*c * p.decay);
                            live |= *c != 0.0;
                        }
                        *input = x;
                        keep(j, live);
                    }
                }
                let slot = (k % n.history.len() as u64) as usize;
                n.history[slot].clear();
                // `input` holds the active neurons' inputs in list order (it has room for all).
                self.neuron_updates +=
                    m.step_active(list, &n.input[..list.len()], &mut n.history[slot]);
                std::mem::swap(list, next);
                if n.local.start > 0 {
                    n.history[slot].shift_indices(n.local.start as u32);
                }
                continue;
            }
            if let RunningKind::Population(m) = &mut n.kind {
                if let Some(a) = n.active.as_mut().filter(|a| a.samples(k)) {
                    let len = n.input.len();
                    let active = match n.incoming[..] {
                        // One projection: a loop the compiler vectorises.
                        [only] => (self.projections[only].current[..len].iter())
                            .filter(|&&c| c != 0.0)
                            .count(),
                        _ => active_neurons(&self.projections, &n.incoming, len).count(),
                    };
                    a.count(active, len);
                }
                self.neuron_updates += n.input.len() as u64;
                let slot = (k % n.history.len() as u64) as usize;
                n.history[slot].clear();
                // Fed by one or two projections and nothing else (as CUBA's populations): the
                // model drains the currents inside its own update loop.
                let synaptic = if n.currents.is_empty() {
                    synaptic_drive(&mut self.projections, &n.incoming)
                } else {
                    None
                };
                if let Some(drive) = synaptic {
                    m.step_synaptic(drive, &mut n.input, &mut n.history[slot]);
                } else {
                    if n.incoming.is_empty() {
                        n.input.iter_mut().for_each(|x| *x = 0.0);
                    }
                    for (j, &p) in n.incoming.iter().enumerate() {
                        self.projections[p].drain_into(&mut n.input, j == 0);
                    }
                    for &c in &n.currents {
                        self.currents[c].add_into(t_k, &mut n.input);
                    }
                    m.step(&n.input, &mut n.history[slot]);
                }
                if n.local.start > 0 {
                    n.history[slot].shift_indices(n.local.start as u32);
                }
            }
        }
        // 4b. plasticity: this step's postsynaptic spikes
        for p in &mut self.projections {
            if let (Some(_), Some(post)) = (&p.plasticity, p.post) {
                let n = &self.nodes[post];
                let spikes = n.history[(k % n.history.len() as u64) as usize].indices();
                p.learn_from_post(spikes, n.local.start, k);
            }
        }
        for &p in &self.untargeted {
            self.projections[p].decay();
        }
        self.step += 1;
    }

    /// Phase 5 of step `k`, whose spikes are still in the histories: every readout sees it
    /// (the population's state only when `with_state`: in one process, right after the step).
    /// Returns `true` when a readout asked to stop.
    fn read_out(&mut self, k: u64, with_state: bool) -> bool {
        let t_k = k as f64 * self.dt_s;
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
                            RunningKind::Population(m) if with_state => Some(m.as_ref()),
                            _ => None,
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
        stop
    }
}

/// The neurons `0..n` with a nonzero synaptic current in one of the projections `incoming`,
/// ascending.
pub(super) fn active_neurons<'a>(
    projections: &'a [RunningProjection],
    incoming: &'a [usize],
    n: usize,
) -> impl Iterator<Item = u32> + 'a {
    (0..n as u32).filter(move |&j| {
        incoming
            .iter()
            .any(|&p| projections[p].current[j as usize] != 0.0)
    })
}

/// Switches population `m` to event-driven stepping (`event`) or to clock-driven stepping, at
/// the start of a step (see [`Stepping`](super::Stepping)): leaving event-driven, every
/// skipped neuron is brought up to date and the active list dropped; returning to it, every
/// neuron is marked current and the active list rebuilt from the nonzero currents.
fn switch_mode(
    m: &mut dyn NeuronModel,
    stepping: &mut EventStepping,
    projections: &[RunningProjection],
    incoming: &[usize],
    event: bool,
) {
    stepping.set.clear();
    if event {
        m.resume_event_driven();
        let n = stepping.set.flag.len();
        for j in active_neurons(projections, incoming, n) {
            stepping.set.mark(j);
        }
    } else {
        m.settle();
    }
    stepping.event = event;
    stepping.switches += 1;
}

/// The drive of a population fed by the projections `incoming`, when there are one or two
/// ([`SynapticDrive`]); `None` otherwise.
fn synaptic_drive<'a>(
    projections: &'a mut [RunningProjection],
    incoming: &[usize],
) -> Option<SynapticDrive<'a>> {
    match *incoming {
        [a] => {
            let p = &mut projections[a];
            DecayingCurrents::new([&mut p.current[..]], [p.decay], p.bound).map(SynapticDrive::One)
        }
        [a, b] if a != b => {
            let (pa, pb) = if a < b {
                let (lo, hi) = projections.split_at_mut(b);
                (&mut lo[a], &mut hi[0])
            } else {
                let (lo, hi) = projections.split_at_mut(a);
                (&mut hi[0], &mut lo[b])
            };
            DecayingCurrents::new(
                [&mut pa.current[..], &mut pb.current[..]],
                [pa.decay, pb.decay],
                pa.bound + pb.bound,
            )
            .map(SynapticDrive::Two)
        }
        _ => None,
    }
}
