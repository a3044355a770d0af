//! The interface between the network graph and neuron models: [`NeuronModel`] and the
//! per-step [`SpikeBuffer`].
//!
//! Models live in `neurotac-neurons` (LIF, Izhikevich) or in user code. The graph makes one
//! dynamic call per population per step ([`NeuronModel::step`], or
//! [`NeuronModel::step_synaptic`] when the input is one or two projections' synaptic
//! currents); everything inside a step is the model's own, statically dispatched,
//! structure-of-arrays loop.
//!
//! # Spike-time stamp convention
//! A step advances the state from `t_k` to `t_k + dt`. A spike found in that step is pushed with
//! a *fraction* `φ ∈ [0, 1]` and its time is `t_k + φ·dt`. Models that do not interpolate use
//! `φ = 1`: the spike is stamped at the **end** of the step, the first grid time at which the
//! state is known to be past threshold. Interpolating models give the linear threshold crossing
//! inside the step. Spike sources (inputs) give the spike's own time within the step.

use crate::currents::SynapticDrive;
use crate::error::ModelError;
use crate::model_state::{ModelDescription, ModelState};
use std::ops::Range;

/// The spikes of one node in one time step: neuron indices and in-step fractions.
///
/// Cleared and refilled every step; its capacity is kept, so a steady run allocates nothing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpikeBuffer {
    indices: Vec<u32>,
    fractions: Vec<f64>,
}

impl SpikeBuffer {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Removes all spikes, keeping capacity.
    #[inline]
    pub fn clear(&mut self) {
        self.indices.clear();
        self.fractions.clear();
    }

    /// Records a spike of neuron `i` stamped at the end of the step (`φ = 1`).
    #[inline]
    pub fn push(&mut self, i: u32) {
        self.indices.push(i);
        self.fractions.push(1.0);
    }

    /// Records a spike of neuron `i` at fraction `phi ∈ [0, 1]` of the step.
    #[inline]
    pub fn push_at(&mut self, i: u32, phi: f64) {
        self.indices.push(i);
        self.fractions.push(phi);
    }

    /// Number of spikes.
    #[inline]
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// `true` when no neuron spiked.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// Indices of the neurons that spiked, in push order.
    #[inline]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// In-step fractions `φ`, parallel to [`indices`](Self::indices).
    #[inline]
    pub fn fractions(&self) -> &[f64] {
        &self.fractions
    }

    /// Adds `by` to every index: a rank's block-local indices become global ones.
    #[inline]
    pub(crate) fn shift_indices(&mut self, by: u32) {
        self.indices.iter_mut().for_each(|i| *i += by);
    }
}

/// A population of neurons of one model, advanced by the network at a fixed `dt`.
///
/// Life cycle: the builder owns the model with its parameters; `build()` calls
/// [`prepare`](Self::prepare) (validate, allocate state, precompute decay factors) only for
/// populations some readout depends on; the network then calls [`step`](Self::step) once per
/// time step. `step` must not allocate (beyond amortised growth of `spikes`) and must not fail:
/// everything that can be wrong is caught by `prepare`.
pub trait NeuronModel: Send {
    /// Model name used in messages (e.g. `"lif"`).
    fn model_name(&self) -> &'static str;

    /// Number of neurons.
    fn len(&self) -> usize;

    /// `true` for a population of zero neurons.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Names of the state variables a state recorder may read (e.g. `["v", "u"]`).
    fn variables(&self) -> &'static [&'static str];

    /// Validates parameters against `dt_s`, allocates state and precomputes per-step factors.
    fn prepare(&mut self, dt_s: f64) -> Result<(), ModelError>;

    /// Restores the initial state (as right after `prepare`).
    fn reset(&mut self);

    /// Advances every neuron by one step. `current[i]` is neuron `i`'s input (same units as the
    /// membrane potential per unit of the model's time constant, e.g. `R·I` for LIF), held
    /// constant over the step. Spikes are pushed into `spikes` (already cleared).
    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer);

    /// One step whose input is the exponential synaptic currents of the population's
    /// projections ([`SynapticDrive`]): neuron `i`'s input is `Σ_p I_p[i]`, and the step leaves
    /// every current decayed by one step, as the network's own drain would. The network calls
    /// this instead of [`step`](Self::step) for a clock-driven population fed by one or two
    /// projections and nothing else. The default drains the currents into `input` (one value
    /// per neuron, the network's buffer) and calls `step`; a model may instead sum and decay
    /// them inside its own update loop, which must give exactly the same state, spikes and
    /// currents (LIF does, see `neurotac_neurons::lif`).
    fn step_synaptic(
        &mut self,
        drive: SynapticDrive<'_>,
        input: &mut [f64],
        spikes: &mut SpikeBuffer,
    ) {
        drive.drain_into(input);
        self.step(input, spikes);
    }

    /// Reports a numerical divergence detected since `prepare`/`reset` (a typed
    /// [`ModelError::Diverged`] naming the first step flagged). The step itself stays infallible
    /// and only records the first flagged step; the network calls this once every block of
    /// steps and at the end of each run, so checking costs nothing per neuron. Default: models
    /// that cannot diverge return `Ok(())`.
    fn check_divergence(&self) -> Result<(), ModelError> {
        Ok(())
    }

    /// Appends the value of variable `var` (an index into [`variables`](Self::variables)) of
    /// each neuron in `neurons` to `out`.
    fn read_variable(&self, var: usize, neurons: &[u32], out: &mut Vec<f64>);

    /// `true` when the population can be stepped event-driven: a neuron whose input is 0 (and,
    /// for models without a closed form, that is back at rest) is not touched in a step
    /// ([`step_active`](Self::step_active)) and is advanced over the skipped steps when it next
    /// gets input, or at [`settle`](Self::settle). Default `false` (clock-driven; LIF and
    /// Izhikevich say when they can, see their docs).
    fn event_driven(&self) -> bool {
        false
    }

    /// One event-driven step (only called when [`event_driven`](Self::event_driven)): advances
    /// the neurons `active` (ascending), neuron `active[j]` under the input `inputs[j]`, pushing
    /// their spikes; every other neuron's input is 0 this step. Returns the number of neurons
    /// updated: the active ones, plus any the model must still step at input 0 (e.g. an
    /// Izhikevich neuron not yet back at rest). The default steps every neuron (the others at
    /// input 0).
    fn step_active(&mut self, active: &[u32], inputs: &[f64], spikes: &mut SpikeBuffer) -> u64 {
        let mut current = vec![0.0; self.len()];
        for (&i, &x) in active.iter().zip(inputs) {
            current[i as usize] = x;
        }
        self.step(&current, spikes);
        self.len() as u64
    }

    /// Brings every neuron skipped by [`step_active`](Self::step_active) up to the current step
    /// (the network calls it at the end of each run, so state reads after a run are current).
    /// Default: nothing to do.
    fn settle(&mut self) {}

    /// Marks every neuron current as of now, when the network returns the population to
    /// event-driven stepping after clock-driven steps (see
    /// [`Stepping::Auto`](crate::Stepping::Auto)): a model that tracks the step each neuron was
    /// last brought up to, or the neurons still settling, refreshes that bookkeeping here.
    /// (Leaving event-driven stepping calls [`settle`](Self::settle).) Default: nothing to do.
    fn resume_event_driven(&mut self) {}

    /// The activity (fraction of neurons with synaptic input per step) below which this
    /// model's population is cheaper event-driven than clock-driven, used by
    /// [`Stepping::Auto`](crate::Stepping::Auto) when no crossover is stored for the model.
    /// Default 0.05; LIF and Izhikevich state theirs (measured with
    /// `neurotac bench neurons --crossover`).
    fn default_crossover(&self) -> f64 {
        0.05
    }

    /// This population cut down to its neurons `range` (indices of this population), for a
    /// network partitioned over ranks
    /// ([`NetworkBuilder::build_partitioned`](crate::NetworkBuilder::build_partitioned)):
    /// neuron `range.start + i` here is neuron `i` of the result, with exactly the parameters
    /// and initial state it has in the whole population (seeded initial values included), so
    /// that every rank steps its block as one process steps the whole. Called on the unprepared
    /// model, before `prepare`. Spikes must be pushed in ascending neuron order (as LIF and
    /// Izhikevich do) for the gathered spikes to be in one process's order. `None` when the
    /// range does not lie inside the population, or (the default) when the model cannot be
    /// split: building it over more than one rank is then a
    /// [`GraphError::ModelNotPartitionable`](crate::GraphError::ModelNotPartitionable).
    fn restrict(&self, range: Range<usize>) -> Option<Box<dyn NeuronModel>> {
        let _ = range;
        None
    }

    /// What this model is — name, size and settings — for saving the network
    /// ([`Network::save`](crate::Network::save)) or exporting it
    /// ([`Network::describe`](crate::Network::describe)); a
    /// [`ModelFactory`] makes it anew from this. `None` (the default): the
    /// model cannot be saved, and saving a network with it is a [`ModelError::NotSaveable`].
    fn describe(&self) -> Option<ModelDescription> {
        None
    }

    /// Every number the next step of this prepared model depends on (see
    /// [`ModelState`]), as it is: event-driven bookkeeping included, nothing brought up to date
    /// first. `None` (the default) when the model cannot be saved.
    fn save_state(&self) -> Option<ModelState> {
        None
    }

    /// Puts this prepared model (made from the same description, prepared at the same `dt`)
    /// where `state` says, so that it continues bit for bit as the saved one would have. A
    /// state that does not fit (a missing or wrong-length array, a count out of range) is a
    /// [`ModelError::State`] and leaves the model as it was. The default refuses
    /// ([`ModelError::NotSaveable`]).
    fn restore_state(&mut self, state: &ModelState) -> Result<(), ModelError> {
        let _ = state;
        Err(ModelError::NotSaveable {
            model: self.model_name(),
        })
    }
}

/// Makes models from their [`ModelDescription`]s, for loading saved networks.
/// `neurotac_neurons::BuiltinModels` makes LIF and Izhikevich; a user's own model needs a
/// factory of its own (which may fall back on the built-in one).
pub trait ModelFactory {
    /// The model `description` describes, unprepared, or a [`ModelError`] naming what is wrong
    /// ([`ModelError::UnknownModel`] for a model this factory does not make).
    fn make(&self, description: &ModelDescription) -> Result<Box<dyn NeuronModel>, ModelError>;
}
