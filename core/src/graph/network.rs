//! [`Network`]: a built network and its run loop, one step in the documented phase order (see
//! the [module docs](super)).

use super::ids::{InputId, NodeId, ReadoutId};
use super::input::{CurrentInput, SpikeSource};
use super::readout::{Readout, ReadoutContext, StepView};
use super::synapse::RunningProjection;
use crate::error::GraphError;
use crate::model::{NeuronModel, SpikeBuffer};
use std::any::Any;
use std::ops::ControlFlow;

pub(super) enum RunningKind {
    Spikes(Box<dyn SpikeSource>),
    Population(Box<dyn NeuronModel>),
}

pub(super) struct RunningNode {
    pub(super) name: String,
    pub(super) size: usize,
    pub(super) kind: RunningKind,
    /// Ring of this node's spikes, one buffer per step, long enough for its largest delay.
    pub(super) history: Vec<SpikeBuffer>,
    /// Summed input current (populations).
    pub(super) input: Vec<f64>,
    /// Projections targeting this node.
    pub(super) incoming: Vec<usize>,
    /// Current sources injected into this node.
    pub(super) currents: Vec<usize>,
}

pub(super) enum RunningSource {
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

/// A built, runnable network. See the [module docs](super) for the phase order of a step.
pub struct Network {
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
    pub fn is_active(&self, node: impl Into<NodeId>) -> bool {
        let node: NodeId = node.into();
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
        node: InputId,
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
