//! The JSON of a population's settings ([`ModelDescription::settings`]): reading an object's
//! fields with errors that name the field ([`Fields`]), the no-floor `null` of `v_min`, and
//! the initial potentials ([`InitialPotential`]) as JSON.
//!
//! Settings hold finite numbers only (JSON has no infinities): a non-finite value has no
//! JSON, except a floor (`v_min`) of −∞, which is written `null`.
//!
//! [`ModelDescription::settings`]: neurotac_core::ModelDescription::settings

use super::inputs::InitialPotential;
use serde_json::{Map, Number, Value, json};

/// `x` as a JSON number; `None` when it is not finite.
pub(crate) fn number(x: f64) -> Option<Value> {
    Number::from_f64(x).map(Value::Number)
}

/// A floor as JSON: `null` for −∞ (no floor), a number when finite, `None` otherwise.
pub(crate) fn floor(x: f64) -> Option<Value> {
    if x == f64::NEG_INFINITY {
        Some(Value::Null)
    } else {
        number(x)
    }
}

/// The fields of one JSON object of the settings, read by name; every error names the field
/// by its path (`settings.params.tau_m_s`) and says what was expected.
pub(crate) struct Fields<'a> {
    object: &'a Map<String, Value>,
    path: String,
}

impl<'a> Fields<'a> {
    /// The object `value` at `path`, which must have exactly the fields `names`.
    pub(crate) fn new(value: &'a Value, path: &str, names: &[&str]) -> Result<Self, String> {
        let object = value
            .as_object()
            .ok_or_else(|| format!("{path}: expected an object, got {value}"))?;
        if let Some(extra) = object.keys().find(|k| !names.contains(&k.as_str())) {
            return Err(format!(
                "{path}.{extra}: not a field here (expected: {})",
                names.join(", ")
            ));
        }
        Ok(Self {
            object,
            path: path.to_owned(),
        })
    }

    /// The path of field `name`.
    pub(crate) fn path(&self, name: &str) -> String {
        format!("{}.{name}", self.path)
    }

    /// Field `name`, which must be present.
    pub(crate) fn get(&self, name: &str) -> Result<&'a Value, String> {
        self.object
            .get(name)
            .ok_or_else(|| format!("{}: missing", self.path(name)))
    }

    fn expected(&self, name: &str, what: &str, got: &Value) -> String {
        format!("{}: expected {what}, got {got}", self.path(name))
    }

    /// Field `name` as a (finite) number.
    pub(crate) fn number(&self, name: &str) -> Result<f64, String> {
        let v = self.get(name)?;
        v.as_f64().ok_or_else(|| self.expected(name, "a number", v))
    }

    /// Field `name` as a floor: a number, or `null` for −∞ (no floor).
    pub(crate) fn floor(&self, name: &str) -> Result<f64, String> {
        match self.get(name)? {
            Value::Null => Ok(f64::NEG_INFINITY),
            v => v
                .as_f64()
                .ok_or_else(|| self.expected(name, "a number or null (no floor)", v)),
        }
    }

    /// Field `name` as a whole number ≥ 0.
    pub(crate) fn whole(&self, name: &str) -> Result<u64, String> {
        let v = self.get(name)?;
        v.as_u64()
            .ok_or_else(|| self.expected(name, "a whole number ≥ 0", v))
    }

    /// Field `name` as `true` or `false`.
    pub(crate) fn bool(&self, name: &str) -> Result<bool, String> {
        let v = self.get(name)?;
        v.as_bool()
            .ok_or_else(|| self.expected(name, "true or false", v))
    }

    /// Field `name` as a string.
    pub(crate) fn str(&self, name: &str) -> Result<&'a str, String> {
        let v = self.get(name)?;
        v.as_str().ok_or_else(|| self.expected(name, "a string", v))
    }
}

/// The initial potentials as JSON: `{"constant": v}`, `{"uniform": {"low", "high", "seed"}}`
/// or `{"values": [v, …]}`; `None` when a value is not finite.
pub(crate) fn initial_to_json(initial: &InitialPotential) -> Option<Value> {
    Some(match initial {
        InitialPotential::Constant(v) => json!({ "constant": number(*v)? }),
        InitialPotential::Uniform { low, high, seed } => json!({
            "uniform": { "low": number(*low)?, "high": number(*high)?, "seed": seed }
        }),
        InitialPotential::Values(v) => {
            let values: Option<Vec<Value>> = v.iter().map(|&x| number(x)).collect();
            json!({ "values": values? })
        }
    })
}

/// The initial potentials of a population of `n` neurons from their JSON at `path`
/// ([`initial_to_json`]): a list must have `n` values, a uniform range `low ≤ high`.
pub(crate) fn initial_from_json(
    value: &Value,
    path: &str,
    n: usize,
) -> Result<InitialPotential, String> {
    let kind = Fields::new(value, path, &["constant", "uniform", "values"])?;
    if kind.object.len() != 1 {
        return Err(format!(
            "{path}: expected one of constant, uniform or values, got {value}"
        ));
    }
    if kind.object.contains_key("constant") {
        return Ok(InitialPotential::Constant(kind.number("constant")?));
    }
    if let Some(uniform) = kind.object.get("uniform") {
        let f = Fields::new(uniform, &kind.path("uniform"), &["low", "high", "seed"])?;
        let (low, high) = (f.number("low")?, f.number("high")?);
        if low > high {
            return Err(format!("{}: low {low} > high {high}", kind.path("uniform")));
        }
        let seed = f.whole("seed")?;
        return Ok(InitialPotential::Uniform { low, high, seed });
    }
    let path = kind.path("values");
    let list = kind
        .get("values")?
        .as_array()
        .ok_or_else(|| format!("{path}: expected a list of numbers"))?;
    if list.len() != n {
        return Err(format!(
            "{path}: {} values for a population of {n}",
            list.len()
        ));
    }
    list.iter()
        .enumerate()
        .map(|(i, x)| {
            x.as_f64()
                .ok_or_else(|| format!("{path}[{i}]: expected a number, got {x}"))
        })
        .collect::<Result<_, _>>()
        .map(InitialPotential::Values)
}
