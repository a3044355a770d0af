//! The Izhikevich parameter record ([`IzhikevichParams`]): its fields, the named presets of
//! Izhikevich (2003), the checks `prepare` runs on it, and the resting point of the equations
//! without input ([`resting_point`]). The equations are in the [parent module](super).

use crate::population::{Fields, check_param, check_representable, floor, number};
use crate::real::Real;
use neurotac_core::ModelError;
use serde_json::{Value, json};

/// The model name in messages.
pub(super) const MODEL: &str = "izhikevich";

/// Izhikevich parameters (see the [module docs](super) for equations and units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IzhikevichParams {
    /// Recovery time scale `a` (1/ms).
    pub a: f64,
    /// Recovery sensitivity `b`.
    pub b: f64,
    /// Reset potential `c` (mV).
    pub c: f64,
    /// Recovery jump `d` after a spike.
    pub d: f64,
    /// Spike peak (mV). Default 30.
    pub v_peak: f64,
    /// Lowest potential kept (mV); default −∞, i.e. only the finite range is enforced.
    pub v_min: f64,
    /// Event-driven stepping (module docs): a neuron without input is held once a step leaves
    /// it unchanged (exact) or, when this is positive, once `v` and `u` are both within this
    /// distance (mV) of the resting point (faster, spikes within the tolerance of the
    /// clock-driven run's). Default [`REST_TOLERANCE_MV`]: 0, exact.
    pub rest_tolerance: f64,
}

/// The default [`IzhikevichParams::rest_tolerance`]: 0 mV, event-driven stepping exactly as
/// clock-driven.
pub const REST_TOLERANCE_MV: f64 = 0.0;

impl Default for IzhikevichParams {
    /// Regular spiking ([`rs`](Self::rs)).
    fn default() -> Self {
        Self::rs()
    }
}

impl IzhikevichParams {
    const fn preset(a: f64, b: f64, c: f64, d: f64) -> Self {
        Self {
            a,
            b,
            c,
            d,
            v_peak: 30.0,
            v_min: f64::NEG_INFINITY,
            rest_tolerance: REST_TOLERANCE_MV,
        }
    }

    /// Regular spiking (cortical excitatory): a = 0.02, b = 0.2, c = −65, d = 8.
    pub const fn rs() -> Self {
        Self::preset(0.02, 0.2, -65.0, 8.0)
    }

    /// Intrinsically bursting: a = 0.02, b = 0.2, c = −55, d = 4.
    pub const fn ib() -> Self {
        Self::preset(0.02, 0.2, -55.0, 4.0)
    }

    /// Chattering: a = 0.02, b = 0.2, c = −50, d = 2.
    pub const fn ch() -> Self {
        Self::preset(0.02, 0.2, -50.0, 2.0)
    }

    /// Fast spiking (inhibitory): a = 0.1, b = 0.2, c = −65, d = 2.
    pub const fn fs() -> Self {
        Self::preset(0.1, 0.2, -65.0, 2.0)
    }

    /// Low-threshold spiking: a = 0.02, b = 0.25, c = −65, d = 2.
    pub const fn lts() -> Self {
        Self::preset(0.02, 0.25, -65.0, 2.0)
    }

    /// Thalamo-cortical: a = 0.02, b = 0.25, c = −65, d = 0.05.
    pub const fn tc() -> Self {
        Self::preset(0.02, 0.25, -65.0, 0.05)
    }

    /// Resonator: a = 0.1, b = 0.26, c = −65, d = 2.
    pub const fn rz() -> Self {
        Self::preset(0.1, 0.26, -65.0, 2.0)
    }

    /// `v*` of the resting point without input (mV), when it exists and is stable
    /// ([`resting_point`]); −70 mV for [`rs`](Self::rs). With it as the initial potential
    /// (`u = b·v`), a population starts at rest.
    pub fn resting_potential(&self) -> Option<f64> {
        resting_point(self.a, self.b).map(|(v, _, _)| v)
    }

    /// The named presets by their lower-case names, in the order of Izhikevich (2003), Fig. 2.
    pub const PRESETS: [(&'static str, Self); 7] = [
        ("rs", Self::rs()),
        ("ib", Self::ib()),
        ("ch", Self::ch()),
        ("fs", Self::fs()),
        ("lts", Self::lts()),
        ("tc", Self::tc()),
        ("rz", Self::rz()),
    ];

    /// The preset of [`PRESETS`](Self::PRESETS) with this (case-insensitive) name: rs, ib, ch,
    /// fs, lts, tc, rz.
    pub fn named(name: &str) -> Option<Self> {
        Self::PRESETS
            .iter()
            .find(|(key, _)| key.eq_ignore_ascii_case(name))
            .map(|&(_, params)| params)
    }

    /// The `params` object of an Izhikevich population's settings: the fields by name,
    /// `v_min` as `null` when −∞; `None` when another value is not finite (it has no JSON).
    pub(super) fn to_json(self) -> Option<Value> {
        Some(json!({
            "a": number(self.a)?,
            "b": number(self.b)?,
            "c": number(self.c)?,
            "d": number(self.d)?,
            "v_peak": number(self.v_peak)?,
            "v_min": floor(self.v_min)?,
            "rest_tolerance": number(self.rest_tolerance)?,
        }))
    }

    /// The parameters from their [`to_json`](Self::to_json) object; `Err` names the field.
    pub(super) fn from_json(value: &Value) -> Result<Self, String> {
        let fields = ["a", "b", "c", "d", "v_peak", "v_min", "rest_tolerance"];
        let f = Fields::new(value, "settings.params", &fields)?;
        Ok(Self {
            a: f.number("a")?,
            b: f.number("b")?,
            c: f.number("c")?,
            d: f.number("d")?,
            v_peak: f.number("v_peak")?,
            v_min: f.floor("v_min")?,
            rest_tolerance: f.number("rest_tolerance")?,
        })
    }

    /// Checks the fields (finite, representable in `F`, consistent); run by `prepare`.
    pub(super) fn validate<F: Real>(&self) -> Result<(), ModelError> {
        for (field, x) in [
            ("a", self.a),
            ("b", self.b),
            ("c", self.c),
            ("d", self.d),
            ("v_peak", self.v_peak),
        ] {
            check_param(MODEL, field, x, false)?;
            check_representable::<F>(MODEL, field, x)?;
        }
        if self.c >= self.v_peak {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "c",
                value: self.c,
                expected: "< v_peak",
            });
        }
        if !(self.rest_tolerance >= 0.0 && self.rest_tolerance.is_finite()) {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "rest_tolerance",
                value: self.rest_tolerance,
                expected: "finite and ≥ 0 (mV)",
            });
        }
        if self.v_min.is_nan() || self.v_min > self.c {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "v_min",
                value: self.v_min,
                expected: "≤ c (−∞ allowed)",
            });
        }
        Ok(())
    }
}

/// The resting point `(v*, u*)` of the equations without input, when it exists and is stable,
/// and the largest decay rate `|λ|` (1/ms) of the linearisation there.
///
/// `u* = b·v*` and `0.04·v*² + (5 − b)·v* + 140 = 0`; the lower root
/// `v* = (−(5 − b) − √D)/0.08`, `D = (5 − b)² − 22.4`, has Jacobian
/// `[[b − √D, −1], [a·b, −a]]`: determinant `a·√D > 0`, stable when the trace
/// `b − √D − a < 0`.
pub fn resting_point(a: f64, b: f64) -> Option<(f64, f64, f64)> {
    let disc = (5.0 - b).powi(2) - 4.0 * 0.04 * 140.0;
    if !(disc > 0.0 && a > 0.0) {
        return None;
    }
    let root = disc.sqrt();
    let v = (-(5.0 - b) - root) / 0.08;
    let (trace, det) = (b - root - a, a * root);
    if trace >= 0.0 {
        return None;
    }
    let split = trace * trace - 4.0 * det;
    let fastest = if split >= 0.0 {
        (-trace + split.sqrt()) / 2.0
    } else {
        det.sqrt()
    };
    Some((v, b * v, fastest))
}
