//! Spike-timing-dependent plasticity on a projection: the rule ([`Stdp`], with its equations)
//! and its run-time traces (`Plasticity`).

use crate::error::GraphError;

/// How the weight change depends on the weight.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WeightDependence {
    /// `Δw` independent of `w`, hard bounds only (Song, Miller & Abbott 2000).
    Additive,
    /// Potentiation ∝ `w_max − w`, depression ∝ `w − w_min` (soft bounds; van Rossum, Bi &
    /// Turrigiano, J. Neurosci. 2000).
    Multiplicative,
}

/// Which earlier spikes a trace sums.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TraceInteraction {
    /// Every earlier spike: `x ← x + 1` at a spike (all-to-all pairing).
    AllToAll,
    /// Only the latest spike: `x ← 1` at a spike (nearest-spike pairing, Morrison et al. 2008).
    Nearest,
}

/// Spike-timing-dependent plasticity on a projection ([`Stdp`]): pair-based STDP with one
/// trace per presynaptic and per postsynaptic neuron (Song, Miller & Abbott, Nat. Neurosci.
/// 2000; the trace formulation of Morrison, Diesmann & Gerstner, Biol. Cybern. 2008).
///
/// ```text
/// x_i(t) = Σ_{pre spikes t_i ≤ t} e^{−(t − t_i)/τ₊}     (all-to-all; nearest: only the latest)
/// y_j(t) = Σ_{post spikes t_j ≤ t} e^{−(t − t_j)/τ₋}
/// pre spike of i arrives at t:  w_ij ← clip(w_ij − a₋·D₋(w_ij)·y_j(t)),  then x_i ← x_i + 1
/// post spike of j at t:         y_j ← y_j + 1,  then w_ij ← clip(w_ij + a₊·D₊(w_ij)·x_i(t))
/// additive:        D₊ = D₋ = 1
/// multiplicative:  D₊(w) = w_max − w,  D₋(w) = w − w_min      (soft bounds; van Rossum et al. 2000)
/// clip(w) = min(max(w, w_min), w_max)
/// ```
///
/// For one pre/post pair `Δt = t_post − t_pre` this is the window `Δw = a₊·e^{−Δt/τ₊}` for
/// `Δt ≥ 0` and `Δw = −a₋·e^{Δt/τ₋}` for `Δt < 0` (additive, inside the bounds:
/// [`Stdp::window`]).
///
/// # Timing on the step grid
/// Spike times are the steps' (a spike of step `k` is at `k·dt`; in-step fractions are not
/// used). A presynaptic spike acts at its **arrival**, `delay` steps after emission, in the
/// synapse phase: its current is delivered with the weight before the update, then the weight
/// is depressed. Postsynaptic spikes act after the step's integration, so a pre spike arriving
/// in the step of a post spike counts as before it (`Δt = 0` potentiates), as in Brian2's
/// `on_pre`/`on_post`.
///
/// Traces are updated only at spikes: each keeps its value and the step it was last
/// updated, and is decayed exactly to any later step by `e^{−n·dt/τ}` (one exponential, no
/// accumulated rounding), so the work follows the spikes and nothing is stepped in between.
///
/// Weights are in the projection's units (the jump of the synaptic current per spike).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stdp {
    /// Time constant τ₊ of the presynaptic trace (potentiation window), s (> 0).
    pub tau_plus_s: f64,
    /// Time constant τ₋ of the postsynaptic trace (depression window), s (> 0).
    pub tau_minus_s: f64,
    /// Potentiation amplitude `a₊ ≥ 0` (weight units when additive, a fraction of
    /// `w_max − w` when multiplicative).
    pub a_plus: f64,
    /// Depression amplitude `a₋ ≥ 0` (subtracted; a fraction of `w − w_min` when
    /// multiplicative).
    pub a_minus: f64,
    /// Lower bound of every weight.
    pub w_min: f64,
    /// Upper bound of every weight (> `w_min`).
    pub w_max: f64,
    /// Additive or multiplicative.
    pub dependence: WeightDependence,
    /// All-to-all or nearest-spike traces.
    pub interaction: TraceInteraction,
}

impl Stdp {
    /// Additive STDP with all-to-all traces and weights in `[0, w_max]` (Song, Miller &
    /// Abbott 2000).
    pub fn additive(
        tau_plus_s: f64,
        tau_minus_s: f64,
        a_plus: f64,
        a_minus: f64,
        w_max: f64,
    ) -> Self {
        Self {
            tau_plus_s,
            tau_minus_s,
            a_plus,
            a_minus,
            w_min: 0.0,
            w_max,
            dependence: WeightDependence::Additive,
            interaction: TraceInteraction::AllToAll,
        }
    }

    /// The same rule, multiplicative.
    pub fn multiplicative(self) -> Self {
        Self {
            dependence: WeightDependence::Multiplicative,
            ..self
        }
    }

    /// The same rule with nearest-spike traces.
    pub fn nearest(self) -> Self {
        Self {
            interaction: TraceInteraction::Nearest,
            ..self
        }
    }

    /// The weight change of one isolated pair, `Δt = t_post − t_pre` (s), additive and inside
    /// the bounds: `a₊·e^{−Δt/τ₊}` for `Δt ≥ 0`, `−a₋·e^{Δt/τ₋}` for `Δt < 0`.
    pub fn window(&self, dt_post_minus_pre_s: f64) -> f64 {
        if dt_post_minus_pre_s >= 0.0 {
            self.a_plus * (-dt_post_minus_pre_s / self.tau_plus_s).exp()
        } else {
            -self.a_minus * (dt_post_minus_pre_s / self.tau_minus_s).exp()
        }
    }

    /// Checks the rule (`what` names the projection in the error).
    pub(crate) fn validate(&self, what: &str) -> Result<(), GraphError> {
        let bad = |field: &str, value: f64, expected: &'static str| GraphError::InvalidParameter {
            what: format!("{what} STDP {field}"),
            value,
            expected,
        };
        for (field, tau) in [
            ("tau_plus_s", self.tau_plus_s),
            ("tau_minus_s", self.tau_minus_s),
        ] {
            if !(tau.is_finite() && tau > 0.0) {
                return Err(bad(field, tau, "finite and > 0"));
            }
        }
        for (field, a) in [("a_plus", self.a_plus), ("a_minus", self.a_minus)] {
            if !(a.is_finite() && a >= 0.0) {
                return Err(bad(field, a, "finite and ≥ 0"));
            }
        }
        if !self.w_min.is_finite() {
            return Err(bad("w_min", self.w_min, "finite"));
        }
        if !(self.w_max.is_finite() && self.w_max > self.w_min) {
            return Err(bad("w_max", self.w_max, "finite and > w_min"));
        }
        let span = self.w_max - self.w_min;
        if !span.is_finite() {
            return Err(bad("w_max", self.w_max, "w_max − w_min finite"));
        }
        if self.dependence == WeightDependence::Multiplicative {
            for (field, a) in [("a_plus", self.a_plus), ("a_minus", self.a_minus)] {
                if !(a * span).is_finite() {
                    return Err(bad(field, a, "a·(w_max − w_min) finite (multiplicative)"));
                }
            }
        }
        Ok(())
    }

    /// The largest value a trace of time constant `tau_s` reaches at time step `dt_s`: 1 with
    /// nearest-spike traces; with all-to-all ones, one spike every step,
    /// `Σ e^{−k·dt/τ} = 1/(1 − e^{−dt/τ})`.
    fn trace_max(&self, tau_s: f64, dt_s: f64) -> f64 {
        match self.interaction {
            TraceInteraction::Nearest => 1.0,
            TraceInteraction::AllToAll => -1.0 / (-dt_s / tau_s).exp_m1(),
        }
    }

    /// Checks the rule at time step `dt_s` (`what` names the projection): the decay exponent
    /// `dt/τ` of each trace finite, and every product a weight update forms — `a·x` with the
    /// largest trace `x`, times `w_max − w_min` when multiplicative, added to a bound — finite,
    /// so no update overflows to ±∞ or NaN.
    pub(crate) fn validate_at(&self, what: &str, dt_s: f64) -> Result<(), GraphError> {
        self.validate(what)?;
        let bad = |field: &str, value: f64, expected: &'static str| GraphError::InvalidParameter {
            what: format!("{what} STDP {field} at dt = {dt_s} s"),
            value,
            expected,
        };
        let span = self.w_max - self.w_min;
        for (tau_field, tau, a_field, a, bound) in [
            (
                "tau_plus_s",
                self.tau_plus_s,
                "a_plus",
                self.a_plus,
                self.w_max,
            ),
            (
                "tau_minus_s",
                self.tau_minus_s,
                "a_minus",
                self.a_minus,
                self.w_min,
            ),
        ] {
            let x_max = self.trace_max(tau, dt_s);
            if !(dt_s / tau).is_finite() || !x_max.is_finite() {
                return Err(bad(
                    tau_field,
                    tau,
                    "dt/τ and the largest trace 1/(1 − e^(−dt/τ)) finite",
                ));
            }
            let change = match self.dependence {
                WeightDependence::Additive => a * x_max,
                WeightDependence::Multiplicative => a * span * x_max,
            };
            if !(change.is_finite() && (bound.abs() + change).is_finite()) {
                return Err(bad(
                    a_field,
                    a,
                    "a weight change (with the largest trace) finite",
                ));
            }
        }
        Ok(())
    }

    /// `w` within the bounds; a NaN stays NaN (it is never turned into a bound).
    #[inline]
    fn clip(&self, w: f64) -> f64 {
        w.clamp(self.w_min, self.w_max)
    }

    /// `w` after a postsynaptic spike with presynaptic trace `x`.
    #[inline]
    fn potentiated(&self, w: f64, x: f64) -> f64 {
        self.clip(match self.dependence {
            WeightDependence::Additive => w + self.a_plus * x,
            WeightDependence::Multiplicative => w + self.a_plus * (self.w_max - w) * x,
        })
    }

    /// `w` after a presynaptic arrival with postsynaptic trace `y`.
    #[inline]
    fn depressed(&self, w: f64, y: f64) -> f64 {
        self.clip(match self.dependence {
            WeightDependence::Additive => w - self.a_minus * y,
            WeightDependence::Multiplicative => w - self.a_minus * (w - self.w_min) * y,
        })
    }
}

/// One trace per neuron, updated only at spikes: its value as of its last update and that
/// step.
#[derive(Debug, Clone)]
pub(crate) struct Traces {
    pub value: Vec<f64>,
    pub at: Vec<u64>,
    /// `−dt/τ`: the exponent of one step's decay.
    rate: f64,
}

impl Traces {
    fn new(n: usize, dt_s: f64, tau_s: f64) -> Self {
        Self {
            value: vec![0.0; n],
            at: vec![0; n],
            rate: -dt_s / tau_s,
        }
    }

    /// The trace of neuron `i` at step `k` (≥ its last update), decayed exactly.
    #[inline]
    fn at_step(&self, i: usize, k: u64) -> f64 {
        let v = self.value[i];
        if v == 0.0 {
            0.0
        } else {
            v * (self.rate * (k - self.at[i]) as f64).exp()
        }
    }

    /// Adds a spike of neuron `i` at step `k`.
    #[inline]
    fn spike(&mut self, i: usize, k: u64, interaction: TraceInteraction) {
        self.value[i] = match interaction {
            TraceInteraction::AllToAll => self.at_step(i, k) + 1.0,
            TraceInteraction::Nearest => 1.0,
        };
        self.at[i] = k;
    }

    fn clear(&mut self) {
        self.value.iter_mut().for_each(|v| *v = 0.0);
        self.at.iter_mut().for_each(|a| *a = 0);
    }
}

/// The run-time plasticity of a projection whose wiring is explicit (CSR by presynaptic
/// neuron, one weight per synapse): the rule, the traces and the index of each postsynaptic
/// neuron's synapses.
#[derive(Debug, Clone)]
pub(crate) struct Plasticity {
    pub rule: Stdp,
    /// `false` when frozen: weights stay, traces still follow the spikes.
    pub learning: bool,
    pub pre: Traces,
    pub post: Traces,
    /// Synapses by postsynaptic neuron: `by_post[col_offsets[j]..col_offsets[j + 1]]` are the
    /// indices (into the CSR arrays) of the synapses onto `j`, ascending.
    col_offsets: Vec<usize>,
    by_post: Vec<usize>,
    /// The presynaptic neuron of each synapse (CSR order).
    pre_of: Vec<u32>,
}

impl Plasticity {
    /// The plasticity of a projection with CSR rows `offsets`/`post` (`n_post` local targets).
    pub fn new(rule: Stdp, dt_s: f64, offsets: &[usize], post: &[u32], n_post: usize) -> Self {
        let n_pre = offsets.len() - 1;
        let mut col_offsets = vec![0usize; n_post + 1];
        post.iter().for_each(|&j| col_offsets[j as usize + 1] += 1);
        for j in 0..n_post {
            col_offsets[j + 1] += col_offsets[j];
        }
        let mut fill = col_offsets.clone();
        let mut by_post = vec![0usize; post.len()];
        for (s, &j) in post.iter().enumerate() {
            by_post[fill[j as usize]] = s;
            fill[j as usize] += 1;
        }
        let mut pre_of = vec![0u32; post.len()];
        for i in 0..n_pre {
            pre_of[offsets[i]..offsets[i + 1]]
                .iter_mut()
                .for_each(|p| *p = i as u32);
        }
        Self {
            rule,
            learning: true,
            pre: Traces::new(n_pre, dt_s, rule.tau_plus_s),
            post: Traces::new(n_post, dt_s, rule.tau_minus_s),
            col_offsets,
            by_post,
            pre_of,
        }
    }

    /// Presynaptic `spikes` arriving in step `k` (after their delivery): depression of their
    /// synapses by the targets' traces, then the presynaptic traces.
    pub fn on_pre(
        &mut self,
        spikes: &[u32],
        k: u64,
        offsets: &[usize],
        post: &[u32],
        weight: &mut [f64],
    ) {
        for &i in spikes {
            let i = i as usize;
            if self.learning {
                for s in offsets[i]..offsets[i + 1] {
                    let y = self.post.at_step(post[s] as usize, k);
                    weight[s] = self.rule.depressed(weight[s], y);
                }
            }
            self.pre.spike(i, k, self.rule.interaction);
        }
    }

    /// Postsynaptic `spikes` (local indices) of step `k`: the postsynaptic traces, then
    /// potentiation of their synapses by the sources' traces.
    pub fn on_post(&mut self, spikes: impl Iterator<Item = usize>, k: u64, weight: &mut [f64]) {
        for j in spikes {
            self.post.spike(j, k, self.rule.interaction);
            if self.learning {
                for &s in &self.by_post[self.col_offsets[j]..self.col_offsets[j + 1]] {
                    let x = self.pre.at_step(self.pre_of[s] as usize, k);
                    weight[s] = self.rule.potentiated(weight[s], x);
                }
            }
        }
    }

    /// Forgets every spike (traces to 0); the weights are the projection's.
    pub fn clear(&mut self) {
        self.pre.clear();
        self.post.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_that_overflow_and_decays_that_are_infinite_are_refused() {
        let rule = Stdp::additive(0.02, 0.02, 0.01, 0.011, 1.0);
        assert!(rule.validate_at("p", 1e-4).is_ok());
        // a₊ = 1e308, multiplicative: a₊·(w_max − w_min) overflows.
        let huge = Stdp {
            a_plus: 1e308,
            w_max: 6.0,
            ..rule.multiplicative()
        };
        let e = huge.validate("p").unwrap_err().to_string();
        assert!(e.contains("a_plus") && e.contains("finite"), "{e}");
        let huge = Stdp {
            a_plus: 1e308,
            ..rule.multiplicative()
        };
        assert!(huge.validate("p").is_ok() && huge.validate_at("p", 1e-4).is_err());
        // τ₊ = 5e-324 passes "finite and > 0" but dt/τ is infinite.
        let tiny = Stdp {
            tau_plus_s: 5e-324,
            ..rule
        };
        assert!(tiny.validate("p").is_ok());
        let e = tiny.validate_at("p", 1e-4).unwrap_err().to_string();
        assert!(e.contains("tau_plus_s") && e.contains("dt/τ"), "{e}");
        // Bounds whose span overflows.
        let wide = Stdp {
            w_min: -1e308,
            w_max: 1e308,
            ..rule
        };
        assert!(wide.validate("p").is_err());
        // An additive change that overflows with the largest trace (τ/dt ≈ 10⁸).
        let big = Stdp {
            a_plus: 1e301,
            tau_plus_s: 1e4,
            ..rule
        };
        assert!(big.validate("p").is_ok() && big.validate_at("p", 1e-4).is_err());
    }

    #[test]
    fn a_nan_is_never_clipped_into_a_bound() {
        let rule = Stdp::additive(0.02, 0.02, 0.01, 0.011, 1.0);
        assert!(rule.potentiated(0.5, f64::NAN).is_nan());
        assert!(rule.depressed(0.5, f64::NAN).is_nan());
        assert_eq!(rule.potentiated(0.5, 1e3), 1.0);
        assert_eq!(rule.depressed(0.5, 1e3), 0.0);
    }
}
