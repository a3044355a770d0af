//! Readouts (monitors): push sinks that see one node or projection every step.
//!
//! A readout implements [`Readout`]: [`begin`](Readout::begin) once before the first step,
//! [`on_step`](Readout::on_step) after every step (it may ask the run to stop), and
//! [`finish`](Readout::finish) when a run ends. The bundled ones are [`SpikeRecorder`],
//! [`StateRecorder`] and [`SynapticTraceRecorder`] (both a [`TraceRecorder`], differing only in
//! their [`TraceSampler`]); the codings of the paper are readouts too.

use crate::model::{NeuronModel, SpikeBuffer};
use crate::spikes::MultiSpikeTrain;
use std::any::Any;
use std::ops::ControlFlow;

/// What a readout learns about its source before the first step.
#[derive(Debug, Clone, Copy)]
pub struct ReadoutContext<'a> {
    /// Name of the source node or projection.
    pub source_name: &'a str,
    /// Neurons (channels) of the source; for a projection, its postsynaptic size.
    pub source_size: usize,
    /// The network's time step in seconds.
    pub dt_s: f64,
}

/// What a readout sees after step `step`, which advanced the network from `t_start_s` to
/// `t_start_s + dt_s`.
pub struct StepView<'a> {
    /// Step index, from 0.
    pub step: u64,
    /// Start time of the step (s).
    pub t_start_s: f64,
    /// Time step (s).
    pub dt_s: f64,
    /// Spikes of the source in this step (empty for a projection source).
    pub spikes: &'a SpikeBuffer,
    /// The source population after the step (`None` for inputs and projections).
    pub population: Option<&'a dyn NeuronModel>,
    /// A projection source's synaptic currents at the end of the step, `t_start + dt`: this
    /// step's delivery decayed by one step (`None` for node sources).
    pub synaptic_current: Option<&'a [f64]>,
}

/// A monitor attached to one node or projection of a network.
pub trait Readout: Any + Send {
    /// Called once before the first step (and again after [`Network::reset`](crate::Network::reset)).
    fn begin(&mut self, context: &ReadoutContext<'_>) {
        let _ = context;
    }

    /// Called after every step; return `ControlFlow::Break(())` to stop the run cleanly after
    /// this step. (Over several ranks, called for each step of an epoch after the epoch's
    /// spike exchange, and a stop takes effect at the end of the epoch; see
    /// [`Network::run_steps`](crate::Network::run_steps).)
    fn on_step(&mut self, view: &StepView<'_>) -> ControlFlow<()>;

    /// Called when a run ends (normally or by a stop request).
    fn finish(&mut self) {}

    /// `true` when the readout looks at its source population's state
    /// ([`StepView::population`]). An event-driven population skips neurons without input, so
    /// a population with such a readout is stepped clock-driven, and cannot be built
    /// partitioned over several ranks (each holds only a block of the state). Default `true`
    /// (the safe answer); spike readouts say `false`.
    fn reads_population_state(&self) -> bool {
        true
    }
}

/// Records every spike of a node as `(neuron, time)`.
#[derive(Debug, Clone, Default)]
pub struct SpikeRecorder {
    n: usize,
    spikes: Vec<(u32, f64)>,
}

impl SpikeRecorder {
    /// An empty recorder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Recorded spikes in recording order as `(neuron, time_s)`.
    pub fn spikes(&self) -> &[(u32, f64)] {
        &self.spikes
    }

    /// Spike count per neuron.
    pub fn counts(&self) -> Vec<usize> {
        let mut c = vec![0; self.n];
        for &(i, _) in &self.spikes {
            c[i as usize] += 1;
        }
        c
    }

    /// The recorded spikes as one train per neuron.
    pub fn to_spike_trains(&self) -> MultiSpikeTrain {
        MultiSpikeTrain::from_labelled_spikes(self.n, &self.spikes)
            .expect("recorded spikes have finite times and valid neuron indices")
    }
}

impl Readout for SpikeRecorder {
    fn reads_population_state(&self) -> bool {
        false
    }

    fn begin(&mut self, context: &ReadoutContext<'_>) {
        self.n = context.source_size;
        self.spikes.clear();
    }

    fn on_step(&mut self, view: &StepView<'_>) -> ControlFlow<()> {
        let s = view.spikes;
        self.spikes.extend(
            s.indices()
                .iter()
                .zip(s.fractions())
                .map(|(&i, &phi)| (i, view.t_start_s + phi * view.dt_s)),
        );
        ControlFlow::Continue(())
    }
}

/// Records chosen neurons' values at the end of steps (time `t_start + dt`): the scaffolding of
/// [`StateRecorder`] and [`SynapticTraceRecorder`]; `S` says what is sampled and when.
#[derive(Debug, Clone)]
pub struct TraceRecorder<S> {
    sampler: S,
    neurons: Vec<u32>,
    times: Vec<f64>,
    values: Vec<f64>,
}

/// What a [`TraceRecorder`] samples: one value per recorded neuron after a step, or nothing in
/// a step it skips.
pub trait TraceSampler: Send + 'static {
    /// Appends the value of each of `neurons` (in order) after the step `view` to `values` and
    /// returns `true`, or leaves `values` alone and returns `false` to skip this step.
    fn sample(&self, view: &StepView<'_>, neurons: &[u32], values: &mut Vec<f64>) -> bool;
}

/// Samples one state variable of chosen neurons every `every_steps` steps, at the end of the
/// step (time `t_start + dt`).
pub type StateRecorder = TraceRecorder<StateSampler>;

/// Records a projection's synaptic currents onto chosen target neurons at the end of every step
/// (time `t_start + dt`, the current the next step starts from before its own delivery).
pub type SynapticTraceRecorder = TraceRecorder<SynapticCurrentSampler>;

/// [`StateRecorder`]'s sampler: state variable `variable` of the source population, every
/// `every_steps` steps (nothing for sources without a population).
#[derive(Debug, Clone)]
pub struct StateSampler {
    variable: usize,
    every_steps: u64,
}

impl TraceSampler for StateSampler {
    fn sample(&self, view: &StepView<'_>, neurons: &[u32], values: &mut Vec<f64>) -> bool {
        match view.population {
            Some(p) if (view.step + 1).is_multiple_of(self.every_steps) => {
                p.read_variable(self.variable, neurons, values);
                true
            }
            _ => false,
        }
    }
}

/// [`SynapticTraceRecorder`]'s sampler: a projection's synaptic currents, every step (nothing
/// for node sources).
#[derive(Debug, Clone, Copy, Default)]
pub struct SynapticCurrentSampler;

impl TraceSampler for SynapticCurrentSampler {
    fn sample(&self, view: &StepView<'_>, neurons: &[u32], values: &mut Vec<f64>) -> bool {
        let Some(current) = view.synaptic_current else {
            return false;
        };
        values.extend(neurons.iter().map(|&i| current[i as usize]));
        true
    }
}

impl<S> TraceRecorder<S> {
    fn with_sampler(sampler: S, neurons: Vec<u32>) -> Self {
        Self {
            sampler,
            neurons,
            times: Vec::new(),
            values: Vec::new(),
        }
    }

    /// Sample times (s).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The recorded neurons, in column order.
    pub fn neurons(&self) -> &[u32] {
        &self.neurons
    }

    /// Values, row-major: sample `k`, neuron column `j` is `values()[k * neurons().len() + j]`.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The trace of the `j`-th recorded neuron.
    pub fn trace(&self, j: usize) -> Vec<f64> {
        let n = self.neurons.len();
        self.values
            .iter()
            .skip(j)
            .step_by(n.max(1))
            .copied()
            .collect()
    }
}

impl StateRecorder {
    pub(crate) fn new(variable: usize, neurons: Vec<u32>, every_steps: u64) -> Self {
        let sampler = StateSampler {
            variable,
            every_steps: every_steps.max(1),
        };
        Self::with_sampler(sampler, neurons)
    }
}

impl SynapticTraceRecorder {
    pub(crate) fn new(neurons: Vec<u32>) -> Self {
        Self::with_sampler(SynapticCurrentSampler, neurons)
    }
}

impl<S: TraceSampler> Readout for TraceRecorder<S> {
    fn begin(&mut self, _context: &ReadoutContext<'_>) {
        self.times.clear();
        self.values.clear();
    }

    fn on_step(&mut self, view: &StepView<'_>) -> ControlFlow<()> {
        if self.sampler.sample(view, &self.neurons, &mut self.values) {
            self.times.push(view.t_start_s + view.dt_s);
        }
        ControlFlow::Continue(())
    }
}
