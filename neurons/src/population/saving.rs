//! Saving a [`BlockPopulation`], written once for every model: what it is (its
//! [`ModelDescription`], and the population made anew from one) and where it is (its
//! [`ModelState`], saved and restored), from the model's hooks
//! ([`BlockModel::params_to_json`], [`BlockModel::STATE_ARRAYS`]).
//!
//! The settings are documented on [`BlockPopulation::from_description`], the state on
//! [`BlockPopulation`]'s [`NeuronModel::save_state`].

use super::block_population::BlockPopulation;
use super::inputs::InitialPotential;
use super::model::BlockModel;
use super::settings::{Fields, initial_from_json, initial_to_json};
use super::stepping::Population;
use crate::integrate::{Integrator, UnknownIntegrator};
use crate::real::Real;
#[cfg(doc)]
use neurotac_core::NeuronModel;
use neurotac_core::graph::limits::MAX_STEPS;
use neurotac_core::{ModelDescription, ModelError, ModelState};
use serde_json::{Value, json};

/// The fields of a population's settings.
const SETTINGS: [&str; 5] = [
    "precision",
    "integrator",
    "interpolate",
    "params",
    "initial",
];

/// The `precision` of a description's settings (`"f32"` or `"f64"`, not checked), or what is
/// wrong with the settings object or the field.
pub(crate) fn precision(settings: &Value) -> Result<&str, String> {
    Fields::new(settings, "settings", &SETTINGS)?.str("precision")
}

impl<M: BlockModel> BlockPopulation<M> {
    /// The population `description` describes (as [`NeuronModel::describe`] writes it),
    /// unprepared. Its settings:
    /// ```json
    /// {"precision": "f64", "integrator": "exact", "interpolate": false,
    ///  "params": {…the model's parameters…},
    ///  "initial": {"constant": 0.0} | {"uniform": {"low": 0, "high": 1, "seed": 7}} | {"values": […]}}
    /// ```
    /// `params` holds the fields of the model's parameter record by name, finite numbers
    /// only; a floor `v_min` of −∞ is `null` ([`LifParams`](crate::LifParams),
    /// [`IzhikevichParams`](crate::IzhikevichParams)). Every field is required and no other is
    /// allowed. A description of another model, or settings that are missing, unknown, of the
    /// wrong type or precision, or parameters `prepare` would refuse, are a
    /// [`ModelError::UnknownModel`] naming the field (`settings.params.tau_m_s = -1: …`).
    pub fn from_description(description: &ModelDescription) -> Result<Self, ModelError> {
        let refuse = |reason| ModelError::UnknownModel {
            model: description.model.clone(),
            reason,
        };
        if description.model != M::NAME {
            return Err(refuse(format!("not a '{}' description", M::NAME)));
        }
        // Neuron indices are u32.
        if description.size > u32::MAX as usize {
            return Err(refuse(format!(
                "size {} is more than {} neurons",
                description.size,
                u32::MAX
            )));
        }
        Self::from_settings(description.size, &description.settings).map_err(refuse)
    }

    fn from_settings(n: usize, settings: &Value) -> Result<Self, String> {
        let f = Fields::new(settings, "settings", &SETTINGS)?;
        let precision = f.str("precision")?;
        if precision != M::Real::NAME {
            return Err(format!(
                "{}: '{precision}' for a population in {}",
                f.path("precision"),
                M::Real::NAME
            ));
        }
        let name = f.str("integrator")?;
        let integrator: Integrator = name
            .parse()
            .map_err(|e: UnknownIntegrator| format!("{}: {e}", f.path("integrator")))?;
        if !M::supports(integrator) {
            return Err(format!(
                "{}: {} has no '{name}' integrator (supported: {})",
                f.path("integrator"),
                M::NAME,
                M::SUPPORTED
            ));
        }
        let params = M::params_from_json(f.get("params")?)?;
        M::validate(&params).map_err(|e| match e {
            ModelError::InvalidParameter {
                field,
                value,
                expected,
                ..
            } => format!(
                "{}.{field} = {value}: expected {expected}",
                f.path("params")
            ),
            other => other.to_string(),
        })?;
        let initial = initial_from_json(f.get("initial")?, &f.path("initial"), n)?;
        Ok(Self::new(n, params)
            .with_integrator(integrator)
            .with_interpolation(f.bool("interpolate")?)
            .with_initial_potential(initial))
    }

    /// [`NeuronModel::describe`]: `None` when the model has no parameter JSON
    /// ([`BlockModel::params_to_json`]) or a setting is not finite.
    pub(super) fn description(&self) -> Option<ModelDescription> {
        let params = M::params_to_json(&self.params)?;
        let initial = if self.first == 0 && self.whole == self.n {
            self.initial.clone()
        } else {
            let block = self.first..self.first + self.n;
            InitialPotential::Values(self.initial.values(M::NAME, self.whole, block).ok()?)
        };
        Some(ModelDescription {
            model: M::NAME.to_owned(),
            size: self.n,
            settings: json!({
                "precision": M::Real::NAME,
                "integrator": self.integrator.name(),
                "interpolate": self.interpolate,
                "params": params,
                "initial": initial_to_json(&initial)?,
            }),
        })
    }

    /// [`NeuronModel::save_state`]: `None` before `prepare` (there is no state yet) or when the
    /// model lists no state arrays.
    pub(super) fn saved_state(&self) -> Option<ModelState> {
        let dt_s = self.prepared_dt()?;
        if M::STATE_ARRAYS.is_empty() {
            return None;
        }
        let mut arrays: Vec<(String, Vec<f64>)> = (M::STATE_ARRAYS.iter().enumerate())
            .map(|(a, &name)| {
                let values = self.blocks.iter().flat_map(|s| M::state_array(s, a));
                (name.to_owned(), values.map(|x| x.f64()).collect())
            })
            .collect();
        arrays.push(("dt_s".to_owned(), vec![dt_s]));
        let restless = self.restless.iter().map(|&i| u64::from(i)).collect();
        Some(ModelState {
            counters: vec![
                ("steps".to_owned(), self.steps),
                (
                    "diverged_at".to_owned(),
                    self.diverged_at.map_or(0, |s| s + 1),
                ),
            ],
            arrays,
            indices: vec![
                ("current_to".to_owned(), self.current_to.clone()),
                ("restless".to_owned(), restless),
            ],
        })
    }

    /// [`NeuronModel::restore_state`]: every part of `state` is checked against this prepared
    /// population before any is written.
    pub(super) fn restore(&mut self, state: &ModelState) -> Result<(), ModelError> {
        let model = M::NAME;
        let misfit = |reason: String| ModelError::State { model, reason };
        if M::STATE_ARRAYS.is_empty() {
            return Err(ModelError::NotSaveable { model });
        }
        let Some(dt_s) = self.prepared_dt() else {
            return Err(misfit("the population is not prepared".to_owned()));
        };
        let saved_dt = state.array(model, "dt_s", 1)?[0];
        if saved_dt.to_bits() != dt_s.to_bits() {
            return Err(misfit(format!(
                "saved at dt = {saved_dt} s, prepared at dt = {dt_s} s"
            )));
        }
        let steps = state.counter(model, "steps")?;
        if steps > MAX_STEPS {
            return Err(misfit(format!(
                "'steps' is {steps}, beyond the {MAX_STEPS} steps a network may do"
            )));
        }
        let diverged = state.counter(model, "diverged_at")?;
        if diverged > steps {
            return Err(misfit(format!(
                "'diverged_at' is {diverged}, after the {steps} steps done"
            )));
        }
        let current_to = state.index_list(model, "current_to", Some(self.current_to.len()))?;
        if let Some(i) = current_to.iter().position(|&t| t > steps) {
            return Err(misfit(format!(
                "'current_to'[{i}] = {}, after the {steps} steps done",
                current_to[i]
            )));
        }
        let restless = state.index_list(model, "restless", None)?;
        self.check_restless(restless, !current_to.is_empty())
            .map_err(misfit)?;
        let arrays = (0..M::STATE_ARRAYS.len())
            .map(|a| self.checked_array(state, a))
            .collect::<Result<Vec<_>, _>>()?;
        // Everything fits: write.
        for (a, values) in arrays.into_iter().enumerate() {
            let mut rest = values;
            for s in &mut self.blocks {
                let block = M::state_array_mut(s, a);
                let (head, tail) = rest.split_at(block.len());
                block
                    .iter_mut()
                    .zip(head)
                    .for_each(|(x, &y)| *x = M::Real::of(y));
                rest = tail;
            }
        }
        self.steps = steps;
        self.diverged_at = diverged.checked_sub(1);
        self.current_to.copy_from_slice(current_to);
        self.restless.clear();
        self.restless.extend(restless.iter().map(|&i| i as u32));
        Ok(())
    }

    /// The neurons still settling must be ascending neurons of the population, and there are
    /// none without event-driven bookkeeping.
    fn check_restless(&self, restless: &[u64], event_driven: bool) -> Result<(), String> {
        if !event_driven && !restless.is_empty() {
            return Err(format!(
                "'restless' lists {} neurons of a population stepped clock-driven",
                restless.len()
            ));
        }
        let bad = restless
            .iter()
            .enumerate()
            .find(|&(i, &x)| x >= self.n as u64 || (i > 0 && x <= restless[i - 1]));
        match bad {
            Some((i, x)) => Err(format!(
                "'restless'[{i}] = {x}: expected ascending neurons below {}",
                self.n
            )),
            None => Ok(()),
        }
    }

    /// Array `a` of `state`, with this population's length for it, every value representable
    /// in its precision and one a step can leave there ([`BlockModel::check_state_value`]).
    fn checked_array<'s>(&self, state: &'s ModelState, a: usize) -> Result<&'s [f64], ModelError> {
        let (model, name) = (M::NAME, M::STATE_ARRAYS[a]);
        let len = self.blocks.iter().map(|s| M::state_array(s, a).len()).sum();
        let values = state.array(model, name, len)?;
        for (i, &x) in values.iter().enumerate() {
            let y = M::Real::of(x);
            let check = if y.f64().to_bits() == x.to_bits() || (x.is_nan() && y.f64().is_nan()) {
                M::check_state_value(&self.k, a, y)
            } else {
                Err("a value representable in the population's precision")
            };
            if let Err(expected) = check {
                return Err(ModelError::State {
                    model,
                    reason: format!(
                        "'{name}'[{i}] = {x}: expected {expected} ({})",
                        M::Real::NAME
                    ),
                });
            }
        }
        Ok(values)
    }
}
