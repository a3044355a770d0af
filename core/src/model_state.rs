//! Saving and restoring neuron models: what a model is ([`ModelDescription`]: its name, size
//! and settings, enough to make it anew) and where it is ([`ModelState`]: every number its
//! next step depends on), and the factory that makes models from descriptions when a
//! saved network is loaded ([`NetworkBuilder::load`](crate::NetworkBuilder::load); the
//! factory trait is [`ModelFactory`](crate::ModelFactory)).
//!
//! A model that can be saved implements [`NeuronModel::describe`],
//! [`NeuronModel::save_state`] and [`NeuronModel::restore_state`] so that
//! `describe → make → prepare → restore_state(save_state())` continues bit for bit as the
//! original would have: the state holds the model's own numbers as they are, in its own
//! precision widened to `f64` (exact for `f32`), never recomputed.
//!
//! [`NeuronModel::describe`]: crate::NeuronModel::describe
//! [`NeuronModel::save_state`]: crate::NeuronModel::save_state
//! [`NeuronModel::restore_state`]: crate::NeuronModel::restore_state

use crate::error::ModelError;
use serde::{Deserialize, Serialize};

/// What a population's model is: enough to make it anew with a
/// [`ModelFactory`](crate::ModelFactory).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelDescription {
    /// The model's name ([`NeuronModel::model_name`](crate::NeuronModel::model_name)): the key
    /// the factory makes it by.
    pub model: String,
    /// Number of neurons.
    pub size: usize,
    /// The model's own settings as JSON (parameters, integrator, precision, initial state…):
    /// each model documents its fields. Finite numbers only (JSON has no infinities).
    pub settings: serde_json::Value,
}

/// Where a prepared model is: named counters and named arrays, every number its next step
/// depends on (see the [module docs](self)).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ModelState {
    /// Whole-number state (steps done, the step a divergence was first flagged + 1 or 0, …).
    pub counters: Vec<(String, u64)>,
    /// Per-neuron (or per-block) arrays, in the model's precision widened to `f64`.
    pub arrays: Vec<(String, Vec<f64>)>,
    /// Index lists (neurons still settling, the step each neuron is current to, …).
    pub indices: Vec<(String, Vec<u64>)>,
}

impl ModelState {
    /// The counter `name`, or a [`ModelError::State`] naming it.
    pub fn counter(&self, model: &'static str, name: &str) -> Result<u64, ModelError> {
        find(&self.counters, model, name).copied()
    }

    /// The array `name` with exactly `len` values, or a [`ModelError::State`].
    pub fn array(&self, model: &'static str, name: &str, len: usize) -> Result<&[f64], ModelError> {
        let a = find(&self.arrays, model, name)?;
        check_len(model, name, a.len(), len)?;
        Ok(a)
    }

    /// The index list `name` with exactly `len` entries (any length when `None`), or a
    /// [`ModelError::State`].
    pub fn index_list(
        &self,
        model: &'static str,
        name: &str,
        len: Option<usize>,
    ) -> Result<&[u64], ModelError> {
        let a = find(&self.indices, model, name)?;
        if let Some(len) = len {
            check_len(model, name, a.len(), len)?;
        }
        Ok(a)
    }
}

fn find<'a, T>(
    list: &'a [(String, T)],
    model: &'static str,
    name: &str,
) -> Result<&'a T, ModelError> {
    list.iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v)
        .ok_or_else(|| ModelError::State {
            model,
            reason: format!("the saved state has no '{name}'"),
        })
}

fn check_len(
    model: &'static str,
    name: &str,
    got: usize,
    expected: usize,
) -> Result<(), ModelError> {
    if got == expected {
        Ok(())
    } else {
        Err(ModelError::State {
            model,
            reason: format!("'{name}' holds {got} values, expected {expected}"),
        })
    }
}
