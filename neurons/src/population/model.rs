//! The [`BlockModel`] trait: the per-model part of a block-stepped population — parameters,
//! the state of one block, per-step constants, the fused step of one block, and (optionally)
//! the fused synaptic step and the event-driven steps of single neurons. Everything else is
//! [`BlockPopulation`](super::BlockPopulation)'s, written once.

use super::active::{ActiveNeurons, ActiveStep};
use super::blocks::{BLOCK, BlockStep};
use super::inputs::{Drive, InitialPotential};
use crate::integrate::Integrator;
use crate::real::Real;
#[cfg(doc)]
use neurotac_core::NeuronModel;
use neurotac_core::{ModelError, SynapticDrive};
use num_traits::Float;
use std::fmt;

/// The per-model part of a block-stepped population: parameters, the state of one block,
/// per-step constants and the fused step of one block. Everything else — the builder, block
/// allocation, `prepare`/`reset`/`step`, spike collection and divergence bookkeeping — is
/// [`BlockPopulation`](super::BlockPopulation)'s, written once.
///
/// Implemented by [`LifModel`](crate::lif::LifModel) and
/// [`IzhikevichModel`](crate::izhikevich::IzhikevichModel); the populations are
/// [`Lif`](crate::Lif)` = BlockPopulation<LifModel<F>>` and likewise for Izhikevich.
pub trait BlockModel: Send + Sync + 'static {
    /// Precision of the state.
    type Real: Real;
    /// The parameter record (validated by [`validate`](Self::validate) at `prepare`).
    type Params: Copy + PartialEq + fmt::Debug + Send + Sync;
    /// The state of one block of up to [`BLOCK`] neurons (structure of arrays).
    type State: Clone + fmt::Debug + Send;
    /// Per-step constants computed once by `prepare` in the population's precision.
    type Constants: Copy + Default + fmt::Debug + Send + Sync;

    /// Model name used in messages (e.g. `"lif"`).
    const NAME: &'static str;
    /// Names of the state variables (see [`NeuronModel::variables`]).
    const VARIABLES: &'static [&'static str];
    /// The supported integrators, for the "unsupported integrator" error.
    const SUPPORTED: &'static str;
    /// The integrator a new population starts with.
    const DEFAULT_INTEGRATOR: Integrator;
    /// What the model's divergence criterion detects (for the error message).
    const DIVERGENCE: &'static str;
    /// The activity below which a population of this model is cheaper event-driven
    /// ([`NeuronModel::default_crossover`], used when no crossover is stored). Default 0.05.
    const DEFAULT_CROSSOVER: f64 = 0.05;
    /// Names of the arrays of a block's state (in [`Real`](Self::Real)) that a step reads:
    /// what [`NeuronModel::save_state`] saves besides the population's own counters, each
    /// array the concatenation of the blocks' ([`state_array`](Self::state_array)). What every
    /// step writes for every neuron before reading it (the spike mask, in-step fractions) is
    /// the step's output, not state. Empty (the default): the model cannot be saved.
    const STATE_ARRAYS: &'static [&'static str] = &[];

    /// `true` when the model implements `integrator`.
    fn supports(integrator: Integrator) -> bool;

    /// The initial potential of a new population with `params`.
    fn default_initial(params: &Self::Params) -> InitialPotential;

    /// Validates the parameters (finite, representable in [`Real`](Self::Real), consistent).
    fn validate(params: &Self::Params) -> Result<(), ModelError>;

    /// The per-step constants for `params` at `dt_s` (already validated).
    fn constants(params: &Self::Params, dt_s: f64) -> Self::Constants;

    /// A block starting at the initial potentials `v0` (one per neuron of the block).
    fn new_block(
        params: &Self::Params,
        k: &Self::Constants,
        v0: &[f64],
        interpolate: bool,
    ) -> Self::State;

    /// Advances one block by one step under its part of the drive: the fused update,
    /// threshold and reset loop of the model with `integrator`, then (when `interpolate`) the
    /// rest of the step after each interpolated spike.
    fn step_block(
        k: &Self::Constants,
        integrator: Integrator,
        interpolate: bool,
        state: &mut Self::State,
        drive: Drive<'_>,
    ) -> BlockStep;

    /// `true` when [`step_block_synaptic`](Self::step_block_synaptic) has a fused loop for
    /// these settings. Default `false`: the population drains the currents into its input
    /// buffer and calls [`step_block`](Self::step_block).
    fn fuses_synapses(k: &Self::Constants, integrator: Integrator, interpolate: bool) -> bool {
        let _ = (k, integrator, interpolate);
        false
    }

    /// Advances one block by one step under the synaptic currents `drive` (its part of the
    /// population's; [`NeuronModel::step_synaptic`]), summing and decaying them inside the
    /// update loop. Called only when [`fuses_synapses`](Self::fuses_synapses) holds; it must
    /// give what draining the currents and calling [`step_block`](Self::step_block) gives,
    /// which is what the default does (through a buffer on the stack).
    fn step_block_synaptic(
        k: &Self::Constants,
        integrator: Integrator,
        interpolate: bool,
        state: &mut Self::State,
        drive: SynapticDrive<'_>,
    ) -> BlockStep {
        let mut input = [0.0; BLOCK];
        let input = &mut input[..drive.len()];
        drive.drain_into(input);
        Self::step_block(k, integrator, interpolate, state, Drive::PerNeuron(input))
    }

    /// The block's spike mask of the last step (1 where a neuron spiked).
    fn spike_mask(state: &Self::State) -> &[u8];

    /// The block's in-step spike fractions of the last step (empty unless interpolating).
    fn spike_fractions(state: &Self::State) -> &[Self::Real];

    /// Variable `var` (an index into [`VARIABLES`](Self::VARIABLES)) of neuron `j` of the block.
    fn variable(state: &Self::State, var: usize, j: usize) -> f64;

    /// Array `a` of [`STATE_ARRAYS`](Self::STATE_ARRAYS) of a block (empty when these
    /// settings do not use it, e.g. refractory counters without a refractory period).
    fn state_array(state: &Self::State, a: usize) -> &[Self::Real] {
        let _ = (state, a);
        &[]
    }

    /// Array `a` of [`STATE_ARRAYS`](Self::STATE_ARRAYS) of a block, to restore it.
    fn state_array_mut(state: &mut Self::State, a: usize) -> &mut [Self::Real] {
        let _ = (state, a);
        &mut []
    }

    /// Checks a value `x` of array `a` of a state to be restored: `Err(expected)` when no
    /// step of a population with constants `k` can leave it there. Default: finite.
    fn check_state_value(k: &Self::Constants, a: usize, x: Self::Real) -> Result<(), &'static str> {
        let _ = (k, a);
        if x.is_finite() { Ok(()) } else { Err("finite") }
    }

    /// The parameters as the `params` object of the population's settings
    /// ([`NeuronModel::describe`]): finite numbers only, a floor of −∞ written `null`. `None`
    /// when a parameter has no JSON (not finite), or (the default) when the model cannot be
    /// described.
    fn params_to_json(params: &Self::Params) -> Option<serde_json::Value> {
        let _ = params;
        None
    }

    /// The parameters from the `params` object of the settings (as
    /// [`params_to_json`](Self::params_to_json) writes them); `Err` names the field and says
    /// what was expected (`settings.params.tau_m_s: missing`). Default: refused.
    fn params_from_json(value: &serde_json::Value) -> Result<Self::Params, String> {
        let _ = value;
        Err(format!("{} cannot be made from a description", Self::NAME))
    }

    /// Event-driven stepping ([`NeuronModel::event_driven`]): `true` when, with these settings, a
    /// neuron whose input is 0 and that is [`settled`](Self::settled) can be left alone and
    /// advanced later ([`advance_idle`](Self::advance_idle)), and stepped alone
    /// ([`step_neuron`](Self::step_neuron)) with the arithmetic of
    /// [`step_block`](Self::step_block). Default `false`: clock-driven only.
    fn skips_idle(
        params: &Self::Params,
        k: &Self::Constants,
        integrator: Integrator,
        interpolate: bool,
    ) -> bool {
        let _ = (params, k, integrator, interpolate);
        false
    }

    /// `true` when neuron `j` of the block, left without input from now on, is followed by
    /// [`advance_idle`](Self::advance_idle) (exactly, or within the model's stated tolerance)
    /// when stepped with `integrator`. A neuron that is not settled is stepped clock-driven at
    /// input 0 until it is. Default `true` (a closed form exists from any state).
    fn settled(k: &Self::Constants, integrator: Integrator, state: &Self::State, j: usize) -> bool {
        let _ = (k, integrator, state, j);
        true
    }

    /// Advances settled neuron `j` of the block over `steps` steps of zero input. Called only
    /// when [`skips_idle`](Self::skips_idle) holds; the default leaves the state alone (a
    /// neuron held at its resting point).
    fn advance_idle(k: &Self::Constants, state: &mut Self::State, j: usize, steps: u64) {
        let _ = (k, state, j, steps);
    }

    /// One step of neuron `j` of the block under `input`, with the arithmetic of
    /// [`step_block`](Self::step_block): its spike (0 or 1) and whether the divergence criterion
    /// flagged it. Called only when [`skips_idle`](Self::skips_idle) holds; the default never
    /// spikes.
    fn step_neuron(
        k: &Self::Constants,
        integrator: Integrator,
        state: &mut Self::State,
        j: usize,
        input: f64,
    ) -> BlockStep {
        let _ = (k, integrator, state, j, input);
        BlockStep::default()
    }

    /// One event-driven step of the neurons `active` and of the unsettled ones
    /// ([`NeuronModel::step_active`]): each is first brought up to step `now`
    /// ([`advance_idle`](Self::advance_idle)), then stepped ([`step_neuron`](Self::step_neuron)).
    /// A model may override it to hoist its integrator choice out of the loop.
    fn step_neurons(
        k: &Self::Constants,
        integrator: Integrator,
        active: ActiveNeurons<'_, Self::State>,
    ) -> ActiveStep {
        active.run(
            |s, j, idle| Self::advance_idle(k, s, j, idle),
            |s, j, input| Self::step_neuron(k, integrator, s, j, input),
            |s, j| Self::settled(k, integrator, s, j),
        )
    }
}
