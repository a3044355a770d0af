//! [`BuiltinModels`]: the [`ModelFactory`] that makes this crate's models from their
//! [`ModelDescription`]s, for loading saved networks.

use crate::family::ModelFamily;
use crate::integrate_and_fire::IfModel;
use crate::izhikevich::IzhikevichFamily;
use crate::lif::LifFamily;
use crate::population::{BlockModel, BlockPopulation, precision};
use neurotac_core::{ModelDescription, ModelError, ModelFactory, NeuronModel};

/// Makes LIF, Izhikevich and integrate-and-fire (`"if"`) populations, `f32` or `f64`, with any
/// integrator they support,
/// from the descriptions their [`NeuronModel::describe`] writes (the settings are
/// [`BlockPopulation::from_description`]'s). Another model name is a
/// [`ModelError::UnknownModel`], as are settings that are missing, unknown or wrong (named).
///
/// ```
/// use neurotac_core::{ModelFactory, NeuronModel};
/// use neurotac_neurons::{BuiltinModels, Integrator, Lif, LifParams};
/// let lif = Lif::<f32>::new(3, LifParams::default()).with_integrator(Integrator::Rk2);
/// let description = lif.describe().expect("LIF can be described");
/// assert_eq!(description.settings["params"]["v_min"], serde_json::Value::Null); // −∞
/// let made = BuiltinModels.make(&description)?;
/// assert_eq!(made.describe(), Some(description));
/// # Ok::<(), neurotac_core::ModelError>(())
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct BuiltinModels;

impl ModelFactory for BuiltinModels {
    fn make(&self, description: &ModelDescription) -> Result<Box<dyn NeuronModel>, ModelError> {
        match description.model.as_str() {
            LifFamily::KEY => make::<LifFamily>(description),
            IzhikevichFamily::KEY => make::<IzhikevichFamily>(description),
            <IfModel<f64> as BlockModel>::NAME => {
                make_population::<IfModel<f32>, IfModel<f64>>(description)
            }
            _ => Err(ModelError::UnknownModel {
                model: description.model.clone(),
                reason: format!(
                    "not a built-in model (built in: {}, {}, {})",
                    LifFamily::KEY,
                    IzhikevichFamily::KEY,
                    <IfModel<f64> as BlockModel>::NAME,
                ),
            }),
        }
    }
}

/// A population of the family `Fam` in the precision the settings name.
fn make<Fam: ModelFamily>(
    description: &ModelDescription,
) -> Result<Box<dyn NeuronModel>, ModelError> {
    make_population::<Fam::Model<f32>, Fam::Model<f64>>(description)
}

/// A population of the model `M32` or `M64`, as the settings' precision names.
fn make_population<M32: BlockModel, M64: BlockModel>(
    description: &ModelDescription,
) -> Result<Box<dyn NeuronModel>, ModelError> {
    let refuse = |reason| ModelError::UnknownModel {
        model: description.model.clone(),
        reason,
    };
    Ok(match precision(&description.settings).map_err(refuse)? {
        "f32" => Box::new(BlockPopulation::<M32>::from_description(description)?),
        "f64" => Box::new(BlockPopulation::<M64>::from_description(description)?),
        other => {
            return Err(refuse(format!(
                "settings.precision: '{other}', expected f32 or f64"
            )));
        }
    })
}
