//! The [`Population`] trait: what block-stepped populations (LIF, Izhikevich) share beyond
//! [`NeuronModel`] — stepping under a [`Drive`], the checked step, and the benchmark path that
//! checks for divergence every [`DIVERGENCE_CHECK_STEPS`] steps.

use super::inputs::Drive;
use neurotac_core::{ModelError, NeuronModel, SpikeBuffer};

/// Steps between two divergence checks in [`Population::run_constant`] (and in the network's
/// run loop): a check costs one call, never a pass over the neurons.
pub const DIVERGENCE_CHECK_STEPS: u64 = 256;

/// What block-stepped populations (LIF, Izhikevich) share beyond [`NeuronModel`]: stepping
/// under a [`Drive`], and the checked and benchmark entry points built on it.
pub trait Population: NeuronModel {
    /// Advances every neuron one step under `drive` and returns the number of spikes, without
    /// recording indices. The population must be prepared.
    fn advance(&mut self, drive: Drive<'_>) -> u64;

    /// The time step the population is prepared for, if it is.
    fn prepared_dt(&self) -> Option<f64>;

    /// Checks one input value for neuron `neuron`: NaN/±∞ and values beyond the population's
    /// precision (e.g. `1e39` for `f32`) are typed errors.
    fn check_input(&self, neuron: usize, value: f64) -> Result<(), ModelError>;

    /// Prepares (if needed) and runs `steps` steps of `dt_s` with the same input `current` for
    /// every neuron, without recording spike indices; returns the number of spikes. This is the
    /// benchmark path; it steps exactly as a network does, and like a network checks for
    /// divergence every [`DIVERGENCE_CHECK_STEPS`] steps and at the end.
    fn run_constant(&mut self, current: f64, dt_s: f64, steps: u64) -> Result<u64, ModelError> {
        self.check_input(0, current)?;
        if self.prepared_dt() != Some(dt_s) {
            self.prepare(dt_s)?;
        }
        let mut spikes = 0;
        for k in 1..=steps {
            spikes += self.advance(Drive::Constant(current));
            if k % DIVERGENCE_CHECK_STEPS == 0 {
                self.check_divergence()?;
            }
        }
        self.check_divergence()?;
        Ok(spikes)
    }

    /// One network-style step with per-neuron input, rejecting input of the wrong length or
    /// with NaN/±∞ values (or values beyond the precision) with a typed error (the state is then
    /// untouched).
    fn step_checked(
        &mut self,
        current: &[f64],
        spikes: &mut SpikeBuffer,
    ) -> Result<(), ModelError> {
        let model = self.model_name();
        for (i, &x) in current.iter().enumerate() {
            self.check_input(i, x)?;
        }
        if current.len() != self.len() {
            return Err(ModelError::InvalidParameter {
                model,
                field: "input length",
                value: current.len() as f64,
                expected: "one value per neuron",
            });
        }
        spikes.clear();
        self.step(current, spikes);
        Ok(())
    }
}
