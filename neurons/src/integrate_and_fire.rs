//! # Integrate-and-fire neuron (perfect integrator, current-based)
//!
//! ```text
//! τ_m · dv/dt = I                         sub-threshold dynamics (no leak)
//! v ≥ v_th   ⇒  spike, v ← v_reset        threshold and reset
//! ```
//!
//! `I` is the step's input in potential units, as for [LIF](crate::lif) (`R·I`): in a network,
//! the sum of the population's exponential synaptic currents and injected currents, held
//! constant over the step. It is the leaky integrate-and-fire neuron without its leak: NIR's
//! `IF` (`dv/dt = R·I`, with `R = 1/τ_m`), Sinabs' `IAF` and Norse's `IAFCell`.
//!
//! | symbol | field | unit | default |
//! |---|---|---|---|
//! | τ_m | [`IfParams::tau_m_s`] | s | 0.01 |
//! | v_th | [`IfParams::v_th`] | potential | 1 |
//! | v_reset | [`IfParams::v_reset`] | potential | 0 |
//! | v_min | [`IfParams::v_min`] | potential | −∞ (only the finite range is enforced) |
//!
//! ## Integrators
//! `exact` (and `euler`, the same step here): `v ← v + h·I` with `h = dt/τ_m`, exact for a
//! constant `I`. With `τ_m = dt` (`h = 1`) a one-step input `I` moves `v` by exactly `I`:
//! what the NIR import uses for spikes that jump the membrane.
//!
//! ## Spike times and extremes
//! On the grid: a spike is stamped at the end of the step in which `v` reached `v_th` (with
//! interpolation too: the in-step fraction is kept at 1). After
//! each step `v` is kept at or above `max(v_min, lowest finite)`; `v ≥ v_th` resets, so the
//! state is always finite and nothing can diverge.
//!
//! ## Event-driven stepping
//! Without input `v` does not move, so an idle neuron is settled from any state and skipping
//! it is exact.

use crate::integrate::Integrator;
use crate::population::{
    BlockModel, BlockPopulation, BlockStep, Drive, Fields, InitialPotential, check_param,
    check_representable, check_reset_and_floor, floor, number,
};
use crate::real::Real;
use neurotac_core::ModelError;
use serde_json::{Value, json};
use std::marker::PhantomData;

/// The model name in messages and descriptions.
const MODEL: &str = "if";

/// Integrate-and-fire parameters (see the [module docs](self) for the equation and units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IfParams {
    /// Input time constant τ_m (s, > 0): a constant input `I` raises `v` by `I·dt/τ_m` per
    /// step. Default 0.01.
    pub tau_m_s: f64,
    /// Threshold. Default 1.
    pub v_th: f64,
    /// Reset potential (< `v_th`). Default 0.
    pub v_reset: f64,
    /// Lowest potential kept; default −∞, i.e. only the finite range is enforced.
    pub v_min: f64,
}

impl Default for IfParams {
    fn default() -> Self {
        Self {
            tau_m_s: 0.01,
            v_th: 1.0,
            v_reset: 0.0,
            v_min: f64::NEG_INFINITY,
        }
    }
}

impl IfParams {
    /// The `params` object of an IF population's settings; `None` when a value is not finite
    /// (a floor of −∞ is `null`).
    fn to_json(self) -> Option<Value> {
        Some(json!({
            "tau_m_s": number(self.tau_m_s)?,
            "v_th": number(self.v_th)?,
            "v_reset": number(self.v_reset)?,
            "v_min": floor(self.v_min)?,
        }))
    }

    /// The parameters from their [`to_json`](Self::to_json) object; `Err` names the field.
    fn from_json(value: &Value) -> Result<Self, String> {
        let f = Fields::new(
            value,
            "settings.params",
            &["tau_m_s", "v_th", "v_reset", "v_min"],
        )?;
        Ok(Self {
            tau_m_s: f.number("tau_m_s")?,
            v_th: f.number("v_th")?,
            v_reset: f.number("v_reset")?,
            v_min: f.floor("v_min")?,
        })
    }

    /// Checks the fields (finite, representable in `F`, consistent); run by `prepare`.
    fn validate<F: Real>(&self) -> Result<(), ModelError> {
        for (field, x, positive) in [
            ("tau_m_s", self.tau_m_s, true),
            ("v_th", self.v_th, false),
            ("v_reset", self.v_reset, false),
        ] {
            check_param(MODEL, field, x, positive)?;
            check_representable::<F>(MODEL, field, x)?;
        }
        check_reset_and_floor(MODEL, self.v_th, self.v_reset, self.v_min)
    }
}

/// The state of one block of integrate-and-fire neurons.
#[derive(Debug, Clone, Default)]
pub struct IfState<F> {
    /// Membrane potentials.
    pub v: Vec<F>,
    /// 1 where the neuron spiked in the last step.
    spiked: Vec<u8>,
    /// In-step spike fractions, all 1 (a spike at the step's end) when interpolating: a
    /// constant input crosses the threshold at the step's end or not at all within it when
    /// `h·I` is the step's whole move, so the grid time is kept (empty otherwise).
    phi: Vec<F>,
}

/// Per-step constants, computed once by `prepare`.
#[derive(Debug, Clone, Copy, Default)]
pub struct IfConstants<F> {
    v_th: F,
    v_reset: F,
    v_floor: F,
    h: F,
}

/// The integrate-and-fire model ([`BlockModel`]) at precision `F`.
#[derive(Debug, Clone, Copy, Default)]
pub struct IfModel<F>(PhantomData<F>);

/// A population of integrate-and-fire neurons.
///
/// ```
/// use neurotac_neurons::{IfParams, IntegrateAndFire, Population};
/// let mut pop = IntegrateAndFire::<f64>::new(4, IfParams::default());
/// // I = 2 for 0.1 ms steps at τ_m = 10 ms raises v by 0.02 per step: a spike every 50 steps.
/// assert_eq!(pop.run_constant(2.0, 1e-4, 1000)?, 4 * 20);
/// # Ok::<(), neurotac_core::ModelError>(())
/// ```
pub type IntegrateAndFire<F> = BlockPopulation<IfModel<F>>;

/// One neuron's step: `v + h·I`, floored, then threshold and reset; whether it spiked.
#[inline(always)]
fn step_one<F: Real>(k: &IfConstants<F>, v: &mut F, input: F) -> bool {
    let raw = *v + k.h * input;
    let kept = if raw > k.v_floor { raw } else { k.v_floor };
    let spike = kept >= k.v_th;
    *v = if spike { k.v_reset } else { kept };
    spike
}

impl<F: Real> BlockModel for IfModel<F> {
    type Real = F;
    type Params = IfParams;
    type State = IfState<F>;
    type Constants = IfConstants<F>;

    const NAME: &'static str = MODEL;
    const VARIABLES: &'static [&'static str] = &["v"];
    const SUPPORTED: &'static str = "exact, euler";
    const DEFAULT_INTEGRATOR: Integrator = Integrator::Exact;
    const DIVERGENCE: &'static str = "nothing: the step is exact and the state stays finite";
    const STATE_ARRAYS: &'static [&'static str] = &["v"];

    fn supports(integrator: Integrator) -> bool {
        matches!(integrator, Integrator::Exact | Integrator::Euler)
    }

    fn default_initial(params: &IfParams) -> InitialPotential {
        InitialPotential::Constant(params.v_reset)
    }

    fn validate(params: &IfParams) -> Result<(), ModelError> {
        params.validate::<F>()
    }

    fn constants(p: &IfParams, dt_s: f64) -> IfConstants<F> {
        IfConstants {
            v_th: F::of(p.v_th),
            v_reset: F::of(p.v_reset),
            v_floor: F::of(p.v_min).max(F::min_value()),
            h: F::of(dt_s / p.tau_m_s),
        }
    }

    fn new_block(
        _params: &IfParams,
        _k: &IfConstants<F>,
        v0: &[f64],
        interpolate: bool,
    ) -> IfState<F> {
        IfState {
            v: v0.iter().map(|&x| F::of(x)).collect(),
            spiked: vec![0; v0.len()],
            phi: if interpolate {
                vec![F::one(); v0.len()]
            } else {
                Vec::new()
            },
        }
    }

    fn step_block(
        k: &IfConstants<F>,
        _integrator: Integrator,
        _interpolate: bool,
        s: &mut IfState<F>,
        drive: Drive<'_>,
    ) -> BlockStep {
        let mut spikes = 0;
        for (j, (v, spiked)) in s.v.iter_mut().zip(&mut s.spiked).enumerate() {
            let spike = step_one(k, v, F::of(drive.at(j)));
            *spiked = u8::from(spike);
            spikes += u64::from(spike);
        }
        BlockStep {
            spikes,
            diverged: 0,
        }
    }

    fn spike_mask(s: &IfState<F>) -> &[u8] {
        &s.spiked
    }

    fn spike_fractions(s: &IfState<F>) -> &[F] {
        &s.phi
    }

    fn variable(s: &IfState<F>, _var: usize, j: usize) -> f64 {
        s.v[j].f64()
    }

    fn state_array(s: &IfState<F>, _a: usize) -> &[F] {
        &s.v
    }

    fn state_array_mut(s: &mut IfState<F>, _a: usize) -> &mut [F] {
        &mut s.v
    }

    fn params_to_json(params: &IfParams) -> Option<Value> {
        params.to_json()
    }

    fn params_from_json(value: &Value) -> Result<IfParams, String> {
        IfParams::from_json(value)
    }

    /// Without input `v` stays where it is: every idle neuron can wait, exactly.
    fn skips_idle(_: &IfParams, _: &IfConstants<F>, _: Integrator, interpolate: bool) -> bool {
        !interpolate
    }

    fn step_neuron(
        k: &IfConstants<F>,
        _integrator: Integrator,
        s: &mut IfState<F>,
        j: usize,
        input: f64,
    ) -> BlockStep {
        BlockStep::one_neuron(step_one(k, &mut s.v[j], F::of(input)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::population::Population;
    use neurotac_core::{ModelFactory, NeuronModel};

    #[test]
    fn a_constant_input_fires_at_the_closed_form_period() {
        // v rises by h·I per step: from 0 to v_th = 1 in ⌈1/(h·I)⌉ steps, then again.
        let p = IfParams::default();
        let mut pop = IntegrateAndFire::<f64>::new(1, p);
        let (dt_s, current) = (1e-4, 0.8);
        let steps_per_spike = (1.0 / (dt_s / p.tau_m_s * current)).ceil() as u64; // 125
        assert_eq!(
            pop.run_constant(current, dt_s, 10 * steps_per_spike)
                .unwrap(),
            10
        );
    }

    #[test]
    fn with_tau_equal_to_dt_a_one_step_input_jumps_the_membrane_by_itself() {
        let p = IfParams {
            tau_m_s: 1e-4,
            ..IfParams::default()
        };
        let k = IfModel::<f64>::constants(&p, 1e-4);
        let mut v = 0.25;
        assert!(!step_one(&k, &mut v, 0.5));
        assert_eq!(v, 0.75);
        assert!(!step_one(&k, &mut v, 0.0), "no leak");
        assert_eq!(v, 0.75);
        assert!(step_one(&k, &mut v, 0.25), "v ≥ v_th fires");
        assert_eq!(v, 0.0);
        // Far below: kept finite.
        let mut v = 0.0;
        step_one(&k, &mut v, f64::MIN);
        step_one(&k, &mut v, f64::MIN);
        assert!(v.is_finite());
    }

    #[test]
    fn parameters_are_checked_and_described_by_name() {
        let bad = IfParams {
            v_reset: 2.0,
            ..IfParams::default()
        };
        assert!(matches!(
            IfModel::<f64>::validate(&bad),
            Err(ModelError::InvalidParameter {
                field: "v_reset",
                ..
            })
        ));
        let pop = IntegrateAndFire::<f32>::new(3, IfParams::default());
        let description = pop.describe().unwrap();
        assert_eq!(description.model, "if");
        let made = crate::BuiltinModels.make(&description).unwrap();
        assert_eq!(made.describe(), Some(description));
    }
}
