//! The LIF parameter record ([`LifParams`]): its fields, defaults and presets (the benchmark
//! neuron, CUBA's), the checks `prepare` runs on it, and the closed-form spike times of a neuron
//! under constant input. The equations are in the [parent module](super).

use crate::population::{
    Fields, check_param, check_representable, check_reset_and_floor, floor, number,
};
use crate::real::Real;
use neurotac_core::ModelError;
use serde_json::{Value, json};

/// The model name in messages.
pub(super) const MODEL: &str = "lif";

/// LIF parameters (see the [module docs](super) for the equations and units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LifParams {
    /// Membrane time constant τ_m (s, > 0). Default 0.01.
    pub tau_m_s: f64,
    /// Resting potential. Default 0.
    pub v_rest: f64,
    /// Threshold. Default 1.
    pub v_th: f64,
    /// Reset potential (< `v_th`). Default 0.
    pub v_reset: f64,
    /// Refractory period (s, ≥ 0). Default 0.
    pub t_ref_s: f64,
    /// Lowest potential kept; default −∞, i.e. only the finite range is enforced.
    pub v_min: f64,
}

impl Default for LifParams {
    fn default() -> Self {
        Self {
            tau_m_s: 0.01,
            v_rest: 0.0,
            v_th: 1.0,
            v_reset: 0.0,
            t_ref_s: 0.0,
            v_min: f64::NEG_INFINITY,
        }
    }
}

impl LifParams {
    /// The benchmark LIF of Brian2's and neurotac's speed tests: `dv/dt = (I − v)/τ`, τ = 10 ms,
    /// threshold 1, reset 0, no refractory period (the defaults).
    pub fn benchmark() -> Self {
        Self::default()
    }

    /// The neurons of the CUBA network (Vogels & Abbott, J. Neurosci. 2005; Brian2's `CUBA`
    /// example), in mV: τ_m = 20 ms, E_l = −49 mV, threshold −50 mV, reset −60 mV, refractory
    /// 5 ms, no floor. Its threshold is below 0, so the fused loop may leave out the floor and
    /// the flush to zero.
    pub fn cuba() -> Self {
        Self {
            tau_m_s: 0.02,
            v_rest: -49.0,
            v_th: -50.0,
            v_reset: -60.0,
            t_ref_s: 5e-3,
            v_min: f64::NEG_INFINITY,
        }
    }

    /// The period `T = τ_m·ln((v∞ − v_reset)/(v∞ − v_th))` (s) of a neuron from `v_reset` under
    /// the constant input `current` (`v∞ = v_rest + current`), without the refractory period;
    /// `None` when `v∞ ≤ v_th` (it never fires). For the defaults, `T = τ·ln(I/(I − 1))`.
    ///
    /// ```
    /// use neurotac_neurons::LifParams;
    /// let t = LifParams::default().closed_form_period_s(1.04).unwrap();
    /// assert!((t - 0.01 * 26f64.ln()).abs() < 1e-15); // 32.58 ms
    /// assert_eq!(LifParams::default().closed_form_period_s(0.9), None);
    /// ```
    pub fn closed_form_period_s(&self, current: f64) -> Option<f64> {
        let v_inf = self.v_rest + current;
        (v_inf > self.v_th)
            .then(|| self.tau_m_s * ((v_inf - self.v_reset) / (v_inf - self.v_th)).ln())
    }

    /// The spike times `t_k = k·T + (k − 1)·t_ref ≤ duration_s` (s) of a neuron starting at
    /// `v_reset` under the constant `current` ([`closed_form_period_s`](Self::closed_form_period_s));
    /// empty when it never fires.
    pub fn closed_form_spike_times(&self, current: f64, duration_s: f64) -> Vec<f64> {
        let Some(period) = self.closed_form_period_s(current) else {
            return Vec::new();
        };
        (1..)
            .map(|k| k as f64 * period + (k - 1) as f64 * self.t_ref_s)
            .take_while(|&t| t <= duration_s)
            .collect()
    }

    /// The `params` object of a LIF population's settings: the fields by name, `v_min` as
    /// `null` when −∞; `None` when another value is not finite (it has no JSON).
    pub(super) fn to_json(self) -> Option<Value> {
        Some(json!({
            "tau_m_s": number(self.tau_m_s)?,
            "v_rest": number(self.v_rest)?,
            "v_th": number(self.v_th)?,
            "v_reset": number(self.v_reset)?,
            "t_ref_s": number(self.t_ref_s)?,
            "v_min": floor(self.v_min)?,
        }))
    }

    /// The parameters from their [`to_json`](Self::to_json) object; `Err` names the field.
    pub(super) fn from_json(value: &Value) -> Result<Self, String> {
        let fields = ["tau_m_s", "v_rest", "v_th", "v_reset", "t_ref_s", "v_min"];
        let f = Fields::new(value, "settings.params", &fields)?;
        Ok(Self {
            tau_m_s: f.number("tau_m_s")?,
            v_rest: f.number("v_rest")?,
            v_th: f.number("v_th")?,
            v_reset: f.number("v_reset")?,
            t_ref_s: f.number("t_ref_s")?,
            v_min: f.floor("v_min")?,
        })
    }

    /// Checks the fields (finite, representable in `F`, consistent); run by `prepare`.
    pub(super) fn validate<F: Real>(&self) -> Result<(), ModelError> {
        for (field, x, positive) in [
            ("tau_m_s", self.tau_m_s, true),
            ("v_rest", self.v_rest, false),
            ("v_th", self.v_th, false),
            ("v_reset", self.v_reset, false),
            ("t_ref_s", self.t_ref_s, false),
        ] {
            check_param(MODEL, field, x, positive)?;
            check_representable::<F>(MODEL, field, x)?;
        }
        if self.t_ref_s < 0.0 {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "t_ref_s",
                value: self.t_ref_s,
                expected: "≥ 0",
            });
        }
        check_reset_and_floor(MODEL, self.v_th, self.v_reset, self.v_min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closed_form_solves_the_sub_threshold_equation() {
        // v(t) = v∞ + (v_reset − v∞)·e^(−t/τ) reaches v_th at T; spikes repeat every T + t_ref.
        let p = LifParams {
            tau_m_s: 0.02,
            v_rest: -0.5,
            v_th: 1.0,
            v_reset: -0.2,
            t_ref_s: 3e-3,
            v_min: f64::NEG_INFINITY,
        };
        let current = 2.0;
        let v_inf = p.v_rest + current;
        let t = p.closed_form_period_s(current).unwrap();
        let v_at = v_inf + (p.v_reset - v_inf) * (-t / p.tau_m_s).exp();
        assert!((v_at - p.v_th).abs() < 1e-12, "{v_at}");
        let times = p.closed_form_spike_times(current, 0.1);
        assert!(times.len() > 2 && times.iter().all(|&s| s <= 0.1));
        assert!((times[0] - t).abs() < 1e-15);
        assert!((times[2] - times[1] - (t + p.t_ref_s)).abs() < 1e-12);
        // v∞ at or below threshold never fires.
        assert_eq!(p.closed_form_period_s(1.5), None);
        assert!(p.closed_form_spike_times(1.5, 10.0).is_empty());
    }
}
