//! The neuron models a `neurotac.NetworkBuilder` population can have, as network-description
//! JSON: `model_description` gives a model's description (its parameters by name, a named
//! preset's, its default integrator and initial state) for the Python builder to adjust, so
//! the parameter names, defaults and presets exist once, in the neurons crate.

use crate::errors::{OrRaise, invalid};
use neurotac_experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision, PresetName};
use neurotac_neurons::Integrator;
use pyo3::prelude::*;

/// The description (JSON: ``{"model", "size", "settings": {"precision", "integrator",
/// "interpolate", "params", "initial"}}``) of `size` neurons of `model` (``"lif"``,
/// ``"izhikevich"``) with the parameters of `preset` (Izhikevich: ``"rs"``, ``"ib"``, ``"ch"``,
/// ``"fs"``, ``"lts"``, ``"tc"``, ``"rz"``; default: the model's defaults), at `precision`
/// (``"f64"``, ``"f32"``) with `integrator` (default: the model's), every neuron starting at
/// rest. An unknown model, preset, precision or integrator raises ``NeurotacValueError``
/// naming the argument and the choices.
#[pyfunction]
#[pyo3(signature = (model, size, preset=None, precision="f64", integrator=None))]
pub(crate) fn model_description(
    model: &str,
    size: usize,
    preset: Option<&str>,
    precision: &str,
    integrator: Option<&str>,
) -> PyResult<String> {
    let kind: NeuronKind = model
        .parse()
        .map_err(|e| invalid(format!("model = '{model}': {e}")))?;
    let precision: Precision = precision
        .parse()
        .map_err(|e| invalid(format!("precision = '{precision}': {e}")))?;
    let preset = match preset {
        None => None,
        Some(name) => {
            let p: PresetName = name
                .parse()
                .map_err(|e| invalid(format!("preset = '{name}': {e}")))?;
            if !kind.presets().contains(&p.as_str()) {
                return Err(invalid(format!(
                    "preset = '{name}': {} has {}",
                    kind.label(),
                    match kind.presets()[..] {
                        [] => "no presets (set its parameters by name)".to_owned(),
                        ref names => format!("the presets {}", names.join(", ")),
                    }
                )));
            }
            Some(p)
        }
    };
    let integrator = match integrator {
        None => kind.default_integrator(),
        Some(name) => {
            let i: Integrator = name
                .parse()
                .map_err(|e| invalid(format!("integrator = '{name}': {e}")))?;
            if !kind.integrators().contains(&i) {
                let names: Vec<String> = kind.integrators().iter().map(|i| i.to_string()).collect();
                return Err(invalid(format!(
                    "integrator = '{name}': {} has {}",
                    kind.label(),
                    names.join(", ")
                )));
            }
            i
        }
    };
    if size == 0 {
        return Err(invalid("size = 0: a population has at least one neuron"));
    }
    let setup = NeuronSetup {
        preset,
        integrator,
        ..NeuronSetup::single(kind, precision)
    };
    let description = setup
        .population(size)
        .describe()
        .ok_or_else(|| invalid(format!("model = '{model}': it has no description")))?;
    serde_json::to_string(&description).or_raise()
}
