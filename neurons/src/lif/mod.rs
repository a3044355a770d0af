//! # Leaky integrate-and-fire neuron (current-based)
//!
//! ```text
//! τ_m · dv/dt = (v_rest − v) + I          sub-threshold dynamics
//! v ≥ v_th   ⇒  spike, v ← v_reset         threshold and reset
//! then v is held at v_reset for t_ref      refractory period
//! ```
//!
//! `I` is the step's input in potential units (`R·I`): in a network, the sum of the
//! population's exponential synaptic currents ([`neurotac_core::ExpSynapse`]) and injected
//! currents, held constant over the step. The synaptic currents themselves are recorded with
//! [`neurotac_core::NetworkBuilder::record_synaptic_trace`].
//!
//! | symbol | field | unit | default |
//! |---|---|---|---|
//! | τ_m | [`LifParams::tau_m_s`] | s | 0.01 |
//! | v_rest | [`LifParams::v_rest`] | potential | 0 |
//! | v_th | [`LifParams::v_th`] | potential | 1 |
//! | v_reset | [`LifParams::v_reset`] | potential | 0 |
//! | t_ref | [`LifParams::t_ref_s`] | s | 0 |
//! | v_min | [`LifParams::v_min`] | potential | −∞ (only the finite range is enforced) |
//!
//! ## Integrators
//! With `v∞ = v_rest + I` and `h = dt/τ_m`:
//! - `exact` (and `exp-euler`, identical here): `v ← v∞ + (v − v∞)·e^(−h)`, exact for constant `I`;
//! - `euler`: `v ← v + h·(v∞ − v)`; `rk2`, `rk4`: the shared Runge–Kutta steps of
//!   [`crate::integrate`] on `dv/dh = v∞ − v`;
//! - `izhikevich2003` is for the Izhikevich model only (a build-time error here).
//!
//! ## Spike times
//! On the grid, a spike is stamped at the end of the step in which `v` crossed `v_th`. With
//! interpolation, the crossing is placed linearly, `φ = (v_th − v_old)/(v_new − v_old)`, and the
//! neuron integrates from `v_reset` over the rest of the step, `(1 − φ)·dt` (without a
//! refractory period), so the next spike keeps its phase.
//!
//! ## Extremes
//! After each step `v` is clamped to `[max(v_min, lowest finite), ∞)`; `v ≥ v_th` resets, so the
//! state is always finite, even for Euler with `dt > 2τ_m` (unstable but never NaN). Values
//! below the smallest normal number in magnitude are flushed to 0, so a long silence never
//! leaves subnormal numbers in the loop.
//!
//! ## Synaptic input
//! In a network, a clock-driven LIF population fed by one or two projections and nothing else
//! ([`NeuronModel::step_synaptic`]) sums and decays their currents inside the fused loop, so
//! the input never goes through memory (not with interpolation, which reads the input again
//! after the loop, nor for the steps that carry a divergence check). When the floor and the
//! flush provably change nothing (exact step, `v_min = −∞`, a threshold below 0 and a proven
//! bound on the currents, as in CUBA; see `floor_and_flush_are_no_ops`) the loop leaves them
//! out. States, spikes and currents are bit for bit those of the unfused step.
//!
//! ## Divergence
//! From `v < v_th` the solution approaches `v∞` monotonically, so it can reach `v_th` only if
//! `v∞ ≥ v_th`. A step is flagged as diverged when a neuron spikes from `v_old < v_th` under a
//! drive with `v∞ < v_th` (an explicit step overshooting, e.g. Euler with `dt > τ_m`), or when
//! its update is not finite. Neither can happen when the step moves `v` monotonically towards
//! `v∞` (the exact step always; Euler for `dt ≤ τ_m`, RK2 for `dt ≤ 2τ_m`, RK4 for
//! `dt ≤ 2.78τ_m`), so the fused loop carries the check only for the other steps: it marks
//! such a spike in the spike mask and ORs a non-finite flag of every update
//! ([`Real::non_finite_flag`]); [`NeuronModel::check_divergence`] turns it into [`ModelError::Diverged`] naming the step.
//!
//! ## Closed form
//! From `v_reset` under constant `I` with `v∞ > v_th`, the `k`-th spike is at
//! `t_k = k·T + (k − 1)·t_ref` with `T = τ_m·ln((v∞ − v_reset)/(v∞ − v_th))`
//! ([`LifParams::closed_form_period_s`], [`LifParams::closed_form_spike_times`]); for the defaults
//! `T = τ·ln(I/(I − 1))`.

use crate::integrate::{self, Integrator};
use crate::population::{
    ActiveNeurons, ActiveStep, BlockModel, BlockPopulation, BlockStep, DIVERGED_BIT, Drive,
    InitialPotential, count_ones, for_each_spike, take_diverged, unit_fraction,
};
use crate::real::Real;
#[cfg(doc)]
use neurotac_core::NeuronModel;
use neurotac_core::{DecayingCurrents, ModelError, SynapticDrive};
use serde_json::Value;
#[cfg(target_arch = "x86_64")]
use std::any::Any;
use std::marker::PhantomData;

#[cfg(target_arch = "x86_64")]
mod avx512;
mod family;
mod params;
#[cfg(all(test, target_arch = "x86_64"))]
mod tests;

pub use family::LifFamily;
pub use params::LifParams;
use params::MODEL;

/// Longest refractory period in steps (2²⁴: whole numbers are exact up to it in f32); a longer
/// `t_ref` is held this many steps (over 27 minutes at dt = 0.1 ms).
const REFRACTORY_MAX: f64 = 16_777_216.0;
const SUPPORTED: &str = "exact, exp-euler, euler, rk2, rk4";

/// The state of one block of up to [`BLOCK`](crate::population::BLOCK) LIF neurons, structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct LifState<F> {
    /// Membrane potentials.
    pub v: Vec<F>,
    /// Refractory steps left (empty when `t_ref = 0`): the neuron is held at `v_reset` while
    /// this is positive. Set to the refractory period at a spike and decreased by one every
    /// step, through 0 and below (a clamp at 0 would cost the fused loop two operations per
    /// neuron; a value ≤ 0 means not refractory). Whole numbers held in `F`, the width of `v`,
    /// so that the fused loop vectorises (exact to ±2²⁴ in f32, where the count then stays).
    pub refractory_steps: Vec<F>,
    /// In-step spike fractions of the last step (empty unless interpolating).
    phi: Vec<F>,
    /// 1 where the neuron spiked in the last step.
    spiked: Vec<u8>,
}

/// Per-step constants, computed once by `prepare` in the population's precision.
#[derive(Debug, Clone, Copy, Default)]
pub struct LifConstants<F> {
    v_rest: F,
    v_th: F,
    v_reset: F,
    v_floor: F,
    h: F,
    decay: F,
    refractory_steps: u32,
    /// `refractory_steps` in `F` (at most 2²⁴, exact in f32).
    refractory: F,
}

/// Advances one block by one step: fused update, threshold, reset and refractory, writing the
/// spike mask; returns the number of spikes and of flagged updates (module docs, Divergence).
/// `update(v, v∞)` is the integrator; `guarded` is false when it contracts towards v∞
/// ([`contracts`]), which leaves nothing to check.
#[inline(always)]
fn step_block<F: Real, const REFRACTORY: bool, const INTERPOLATE: bool>(
    s: &mut LifState<F>,
    drive: Drive<'_>,
    k: &LifConstants<F>,
    update: &impl Fn(F, F) -> F,
    guarded: bool,
) -> BlockStep {
    match drive {
        Drive::Constant(c) => {
            let v_inf = k.v_rest + F::of(c);
            if guarded {
                step_block_with::<F, REFRACTORY, INTERPOLATE, true, true>(s, k, update, |_| v_inf)
            } else {
                step_block_with::<F, REFRACTORY, INTERPOLATE, false, true>(s, k, update, |_| v_inf)
            }
        }
        Drive::PerNeuron(x) => {
            let x = &x[..s.v.len()];
            let v_inf = |j: usize| k.v_rest + F::of(x[j]);
            if guarded {
                step_block_with::<F, REFRACTORY, INTERPOLATE, true, true>(s, k, update, v_inf)
            } else {
                step_block_with::<F, REFRACTORY, INTERPOLATE, false, true>(s, k, update, v_inf)
            }
        }
    }
}

/// Whether one step of `integrator` with `h = dt/τ_m` moves `v` monotonically towards v∞:
/// `v_new − v∞ = R(h)·(v_old − v∞)` with `0 ≤ R(h) ≤ 1` (exact: `R = e^(−h)`, always; Euler:
/// `R = 1 − h`, h ≤ 1; RK2 and RK4: R is the Taylor polynomial of `e^(−h)` of degree 2 or 4,
/// positive for every h, and ≤ 1 for h ≤ 2 and h ≤ 2.78). Then `v_new` lies between `v_old`
/// and v∞, so a step can neither leave the finite range nor cross a threshold that both lie
/// below: there is nothing to check.
fn contracts(integrator: Integrator, h: f64) -> bool {
    match integrator {
        Integrator::Exact | Integrator::ExponentialEuler => true,
        Integrator::Euler => h <= 1.0,
        Integrator::Rk2 => h <= 2.0,
        Integrator::Rk4 => h <= 2.78,
        Integrator::Izhikevich2003 => false,
    }
}

/// The fused loop. `CHECKED` keeps the floor and the subnormal flush (module docs, Extremes);
/// without it they are left out, which [`floor_and_flush_are_no_ops`] proves harmless.
#[inline(always)]
fn step_block_with<
    F: Real,
    const REFRACTORY: bool,
    const INTERPOLATE: bool,
    const GUARDED: bool,
    const CHECKED: bool,
>(
    s: &mut LifState<F>,
    k: &LifConstants<F>,
    update: &impl Fn(F, F) -> F,
    mut v_inf: impl FnMut(usize) -> F,
) -> BlockStep {
    let n = s.v.len();
    let LifState {
        v,
        refractory_steps,
        phi,
        spiked,
    } = s;
    let (v, spiked) = (&mut v[..n], &mut spiked[..n]);
    let refractory_steps = if REFRACTORY {
        &mut refractory_steps[..n]
    } else {
        &mut refractory_steps[..0]
    };
    let phi = if INTERPOLATE {
        &mut phi[..n]
    } else {
        &mut phi[..0]
    };
    // Constants as locals: selects between values, not between addresses (which LLVM would
    // turn into gathers).
    let LifConstants {
        v_th,
        v_reset,
        v_floor,
        refractory: n_ref,
        ..
    } = *k;
    let tiny = F::min_positive_value();
    let mut count = 0u32;
    // Whether an update left the finite range, without a test per neuron
    // ([`Real::non_finite_flag`]).
    let mut non_finite = F::Bits::default();
    for i in 0..n {
        let v_old = v[i];
        let v_target = v_inf(i);
        let v_raw = update(v_old, v_target);
        let mut v_new = v_raw;
        if CHECKED {
            // One compare + select: NaN and −∞ (unstable Euler) become the floor, never the
            // state.
            v_new = if v_new > v_floor { v_new } else { v_floor };
            // Flush subnormals to 0: a long silence decays v towards v_rest = 0 through the
            // subnormal range, where x86 arithmetic is 10–100× slower.
            v_new = if v_new.abs() >= tiny {
                v_new
            } else {
                F::zero()
            };
        }
        if REFRACTORY {
            v_new = if refractory_steps[i] <= F::zero() {
                v_new
            } else {
                v_reset
            };
        }
        let spike = v_new >= v_th;
        // Divergence: a spike from below threshold under a drive that cannot reach it, or an
        // update that left the finite range.
        let unreachable = GUARDED && spike & (v_target < v_th) & (v_old < v_th);
        if GUARDED {
            non_finite = non_finite | v_raw.non_finite_flag();
        }
        if INTERPOLATE {
            phi[i] = if spike {
                (v_th - v_old) / (v_new - v_old)
            } else {
                F::one()
            };
        }
        v[i] = if spike { v_reset } else { v_new };
        if REFRACTORY {
            let left = refractory_steps[i] - F::one();
            refractory_steps[i] = if spike { n_ref } else { left };
        }
        // The flag rides in the mask byte and is collected once per block (`take_diverged`):
        // a reduction here would cost the loop its unrolling.
        spiked[i] = spike as u8 | if unreachable { DIVERGED_BIT } else { 0 };
        if GUARDED {
            count += spike as u32;
        }
    }
    if !GUARDED {
        // Unguarded, the mask is 0/1: its bytes are counted after the loop, more cheaply
        // than in it (`count_ones`), and carry no divergence flags.
        return BlockStep {
            spikes: count_ones(spiked),
            diverged: 0,
        };
    }
    BlockStep {
        spikes: count as u64,
        diverged: take_diverged(spiked) + u64::from(F::any_non_finite(non_finite)),
    }
}

/// Whether the floor and the subnormal flush of the fused loop provably change nothing in a
/// step whose inputs are at most `bound` in magnitude, so that the loop may leave them out:
///
/// - the step is exact (`exact`, `exp-euler`) and `v_min = −∞`, and `|v_rest| + bound ≤
///   max/2` of the precision: then `v∞ = v_rest + I` is finite and below max/2, and
///   `v·e^(−h) + v∞·(1 − e^(−h))` from a finite `v` (every state is finite) cannot overflow
///   or be NaN, so it is above the floor, the lowest finite number;
/// - `v_th ≤ −`(smallest normal number): a subnormal `v_new` is at or above threshold, as 0
///   is, so it resets to `v_reset` whether flushed or not, and every state a step leaves is
///   `v_reset` or below `v_th`, never subnormal.
///
/// CUBA's populations qualify (mV, threshold −50, exponential synapses with a proven bound:
/// [`DecayingCurrents::bound`]); the dimensionless convention (`v_th = 1`) keeps the flush.
fn floor_and_flush_are_no_ops<F: Real>(
    k: &LifConstants<F>,
    integrator: Integrator,
    bound: f64,
) -> bool {
    matches!(integrator, Integrator::Exact | Integrator::ExponentialEuler)
        && k.v_floor == F::min_value()
        && k.v_th <= -F::min_positive_value()
        && k.v_rest.f64().abs() + bound <= F::max_value().f64() / 2.0
}

/// The fused loop of one block under the synaptic currents `currents`
/// ([`BlockModel::step_block_synaptic`]): neuron `i`'s `v∞ = v_rest + Σ_p I_p[i]`, the
/// currents decayed in the same pass. `EXACT` marks the exact step, the only one for which the
/// floor and flush may be left out ([`floor_and_flush_are_no_ops`]).
#[inline(always)]
fn step_block_synaptic<F: Real, const N: usize, const EXACT: bool>(
    s: &mut LifState<F>,
    k: &LifConstants<F>,
    update: &impl Fn(F, F) -> F,
    currents: DecayingCurrents<'_, N>,
) -> BlockStep {
    let unchecked = EXACT && floor_and_flush_are_no_ops(k, Integrator::Exact, currents.bound());
    // Cut to the block's length, so the loop's indexing needs no bounds checks.
    let (mut currents, _) = currents.split_at(s.v.len());
    let v_rest = k.v_rest;
    let v_inf = |i: usize| v_rest + F::of(currents.take(i));
    // Only contracting steps are fused (`fuses_synapses`): nothing to guard.
    match (k.refractory_steps > 0, unchecked) {
        (false, false) => step_block_with::<F, false, false, false, true>(s, k, update, v_inf),
        (true, false) => step_block_with::<F, true, false, false, true>(s, k, update, v_inf),
        (false, true) => step_block_with::<F, false, false, false, false>(s, k, update, v_inf),
        (true, true) => step_block_with::<F, true, false, false, false>(s, k, update, v_inf),
    }
}

/// One exact step of the f64 block `s` under `currents` by the AVX-512 loop (`avx512`): the
/// same states, currents and spikes as the portable fused loop.
///
/// # Safety
/// The CPU must have what [`crate::avx512::available`] checks.
#[cfg(target_arch = "x86_64")]
unsafe fn step_block_exact_synaptic_avx512<const N: usize>(
    s: &mut LifState<f64>,
    k: &LifConstants<f64>,
    currents: DecayingCurrents<'_, N>,
) -> BlockStep {
    let checked = !floor_and_flush_are_no_ops(k, Integrator::Exact, currents.bound());
    let refractory = k.refractory_steps > 0;
    let constants = avx512::ExactConstants {
        v_rest: k.v_rest,
        decay: k.decay,
        v_th: k.v_th,
        v_reset: k.v_reset,
        v_floor: k.v_floor,
        refractory: k.refractory,
    };
    let (v, r, spiked, k) = (&mut s.v, &mut s.refractory_steps, &mut s.spiked, &constants);
    // SAFETY (each arm): the caller checked the CPU.
    let spikes = unsafe {
        match (refractory, checked) {
            (false, false) => avx512::exact_synaptic::<N, false, false>(v, r, spiked, k, currents),
            (true, false) => avx512::exact_synaptic::<N, true, false>(v, r, spiked, k, currents),
            (false, true) => avx512::exact_synaptic::<N, false, true>(v, r, spiked, k, currents),
            (true, true) => avx512::exact_synaptic::<N, true, true>(v, r, spiked, k, currents),
        }
    };
    BlockStep {
        spikes,
        diverged: 0,
    }
}

/// The LIF model's part of a [`BlockPopulation`] in precision `F`: parameters, block state,
/// constants and the fused step (see the module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct LifModel<F>(PhantomData<F>);

/// A population of LIF neurons in precision `F` (`f32` or `f64`); built with
/// [`new`](BlockPopulation::new) and the `with_*` methods of [`BlockPopulation`].
///
/// ```
/// use neurotac_neurons::{Integrator, Lif, LifParams, Population};
/// let mut lif = Lif::<f64>::new(100, LifParams::default()).with_integrator(Integrator::Exact);
/// let spikes = lif.run_constant(1.04, 1e-4, 10_000)?; // 1 s at 0.1 ms
/// // Closed form: period τ·ln(I/(I−1)) = 10 ms · ln 26 = 32.58 ms → 30 spikes per neuron in 1 s.
/// assert_eq!(spikes, 100 * 30);
/// # Ok::<(), neurotac_core::ModelError>(())
/// ```
pub type Lif<F> = BlockPopulation<LifModel<F>>;

impl<F: Real> Lif<F> {
    /// Membrane potential of neuron `i` (after `prepare`).
    pub fn potential(&self, i: usize) -> f64 {
        self.variable(0, i)
    }
}

impl<F: Real> LifModel<F> {
    fn step_with(
        k: &LifConstants<F>,
        integrator: Integrator,
        interpolate: bool,
        s: &mut LifState<F>,
        d: Drive<'_>,
        update: impl Fn(F, F) -> F,
    ) -> BlockStep {
        let guarded = !contracts(integrator, k.h.f64());
        match (k.refractory_steps > 0, interpolate) {
            (false, false) => step_block::<F, false, false>(s, d, k, &update, guarded),
            (true, false) => step_block::<F, true, false>(s, d, k, &update, guarded),
            (false, true) => {
                let step = step_block::<F, false, true>(s, d, k, &update, guarded);
                if step.spikes > 0 {
                    finish_interpolated_spikes(s, d, k, integrator);
                }
                step
            }
            (true, true) => step_block::<F, true, true>(s, d, k, &update, guarded),
        }
    }
}

impl<F: Real> BlockModel for LifModel<F> {
    type Real = F;
    type Params = LifParams;
    type State = LifState<F>;
    type Constants = LifConstants<F>;

    const NAME: &'static str = MODEL;
    const VARIABLES: &'static [&'static str] = &["v"];
    const SUPPORTED: &'static str = SUPPORTED;
    const DEFAULT_INTEGRATOR: Integrator = Integrator::Exact;
    const DIVERGENCE: &'static str = "the membrane reached threshold under an input whose steady state v∞ lies below it, or left the finite range";
    const DEFAULT_CROSSOVER: f64 = 0.08; // 0.080: `bench neurons --crossover --n 10000` on the 2-core VM

    /// The potentials and (with a refractory period) the refractory counts.
    const STATE_ARRAYS: &'static [&'static str] = &["v", "refractory_steps"];

    fn supports(integrator: Integrator) -> bool {
        integrator != Integrator::Izhikevich2003
    }

    fn state_array(s: &LifState<F>, a: usize) -> &[F] {
        [&s.v, &s.refractory_steps][a]
    }

    fn state_array_mut(s: &mut LifState<F>, a: usize) -> &mut [F] {
        if a == 0 {
            &mut s.v
        } else {
            &mut s.refractory_steps
        }
    }

    /// Potentials are finite; refractory counts are whole numbers up to the refractory period
    /// (they count down through 0 and below).
    fn check_state_value(k: &LifConstants<F>, a: usize, x: F) -> Result<(), &'static str> {
        match a {
            0 if x.is_finite() => Ok(()),
            0 => Err("finite"),
            _ if x.is_finite() && x.trunc() == x && x <= k.refractory => Ok(()),
            _ => Err("a whole number of steps up to the refractory period"),
        }
    }

    fn params_to_json(params: &LifParams) -> Option<Value> {
        params.to_json()
    }

    fn params_from_json(value: &Value) -> Result<LifParams, String> {
        LifParams::from_json(value)
    }

    fn default_initial(params: &LifParams) -> InitialPotential {
        InitialPotential::Constant(params.v_rest)
    }

    fn validate(params: &LifParams) -> Result<(), ModelError> {
        params.validate::<F>()
    }

    fn constants(p: &LifParams, dt_s: f64) -> LifConstants<F> {
        let h = dt_s / p.tau_m_s;
        LifConstants {
            v_rest: F::of(p.v_rest),
            v_th: F::of(p.v_th),
            v_reset: F::of(p.v_reset),
            v_floor: F::of(p.v_min).max(F::min_value()),
            h: F::of(h),
            decay: F::of((-h).exp()),
            refractory_steps: (p.t_ref_s / dt_s).round().min(REFRACTORY_MAX) as u32,
            refractory: F::of((p.t_ref_s / dt_s).round().min(REFRACTORY_MAX)),
        }
    }

    fn new_block(
        _params: &LifParams,
        k: &LifConstants<F>,
        v0: &[f64],
        interpolate: bool,
    ) -> LifState<F> {
        let len = v0.len();
        LifState {
            v: v0.iter().map(|&x| F::of(x)).collect(),
            refractory_steps: if k.refractory_steps > 0 {
                vec![F::zero(); len]
            } else {
                Vec::new()
            },
            phi: if interpolate {
                vec![F::one(); len]
            } else {
                Vec::new()
            },
            spiked: vec![0; len],
        }
    }

    /// LIF skips idle neurons when the step contracts towards v∞ (no divergence check to
    /// carry: exact always, Euler/RK for small h), spikes are on the grid (no interpolation)
    /// and `v_rest < v_th` (a neuron without input cannot fire).
    fn skips_idle(
        _params: &LifParams,
        k: &LifConstants<F>,
        integrator: Integrator,
        interpolate: bool,
    ) -> bool {
        !interpolate && contracts(integrator, k.h.f64()) && k.v_rest < k.v_th
    }

    /// Without input `v∞ = v_rest`: the refractory steps left hold `v_reset`, then
    /// `v ← v_rest + (v − v_rest)·e^{−n·h}` over the other `n` steps (the exact solution; the
    /// clock-driven steps agree with it up to rounding), floored and flushed as a step does.
    fn advance_idle(k: &LifConstants<F>, s: &mut LifState<F>, j: usize, steps: u64) {
        let mut n = steps;
        if k.refractory_steps > 0 {
            let left = s.refractory_steps[j].f64();
            if left > 0.0 {
                s.v[j] = k.v_reset;
                n -= (left as u64).min(n);
            }
            s.refractory_steps[j] = F::of(left - steps as f64);
        }
        if n == 0 {
            return;
        }
        let decay = F::of((-(n as f64) * k.h.f64()).exp());
        let v = k.v_rest + (s.v[j] - k.v_rest) * decay;
        let v = if v > k.v_floor { v } else { k.v_floor };
        s.v[j] = if v.abs() >= F::min_positive_value() {
            v
        } else {
            F::zero()
        };
    }

    /// The fused loop's update, floor, flush, refractory hold, threshold and reset for one
    /// neuron (the event-driven tests check both give the same spikes).
    #[inline]
    fn step_neuron(
        k: &LifConstants<F>,
        integrator: Integrator,
        s: &mut LifState<F>,
        j: usize,
        input: f64,
    ) -> BlockStep {
        BlockStep::one_neuron(step_one(k, s, j, input, |v, v_inf| {
            advance_potential(integrator, v, v_inf, k.h, k.decay)
        }))
    }

    /// The exact step (the event-driven default) gets its own loop, the others share one.
    fn step_neurons(
        k: &LifConstants<F>,
        integrator: Integrator,
        active: ActiveNeurons<'_, LifState<F>>,
    ) -> ActiveStep {
        let idle = |s: &mut LifState<F>, j, steps| Self::advance_idle(k, s, j, steps);
        // The closed form holds from any state: every neuron is settled.
        let settled = |_: &LifState<F>, _| true;
        match integrator {
            Integrator::Exact | Integrator::ExponentialEuler => {
                let update =
                    |v, v_inf| advance_potential(Integrator::Exact, v, v_inf, k.h, k.decay);
                active.run(
                    idle,
                    |s, j, input| BlockStep::one_neuron(step_one(k, s, j, input, update)),
                    settled,
                )
            }
            _ => active.run(
                idle,
                |s, j, input| Self::step_neuron(k, integrator, s, j, input),
                settled,
            ),
        }
    }

    fn step_block(
        k: &LifConstants<F>,
        integrator: Integrator,
        interpolate: bool,
        s: &mut LifState<F>,
        d: Drive<'_>,
    ) -> BlockStep {
        let (h, decay) = (k.h, k.decay);
        // One closure per integrator, so each gets its own vectorised loop.
        macro_rules! with {
            ($integrator:expr) => {
                Self::step_with(
                    k,
                    integrator,
                    interpolate,
                    s,
                    d,
                    #[inline(always)]
                    move |v, v_inf| advance_potential($integrator, v, v_inf, h, decay),
                )
            };
        }
        match integrator {
            Integrator::Exact | Integrator::ExponentialEuler => with!(Integrator::Exact),
            Integrator::Euler => with!(Integrator::Euler),
            Integrator::Rk2 => with!(Integrator::Rk2),
            Integrator::Rk4 => with!(Integrator::Rk4),
            Integrator::Izhikevich2003 => unreachable!("rejected by prepare"),
        }
    }

    /// Without interpolation (which reads the input again after the loop) and for a step that
    /// contracts towards v∞ (module docs, Divergence).
    fn fuses_synapses(k: &LifConstants<F>, integrator: Integrator, interpolate: bool) -> bool {
        !interpolate && contracts(integrator, k.h.f64())
    }

    /// The fused loop with `v∞ = v_rest + Σ_p I_p` and the currents decayed in the same pass;
    /// for the exact step, without the floor and flush when they are provably no-ops
    /// (module docs, Synaptic input). Same states, spikes and currents as the unfused step.
    fn step_block_synaptic(
        k: &LifConstants<F>,
        integrator: Integrator,
        _interpolate: bool,
        s: &mut LifState<F>,
        drive: SynapticDrive<'_>,
    ) -> BlockStep {
        #[cfg(target_arch = "x86_64")]
        if matches!(integrator, Integrator::Exact | Integrator::ExponentialEuler)
            && crate::avx512::available()
        {
            let (s, k): (&mut dyn Any, &dyn Any) = (s, k);
            if let (Some(s), Some(k)) = (s.downcast_mut(), k.downcast_ref()) {
                // SAFETY: `available()` checked the CPU.
                return unsafe {
                    match drive {
                        SynapticDrive::One(c) => step_block_exact_synaptic_avx512(s, k, c),
                        SynapticDrive::Two(c) => step_block_exact_synaptic_avx512(s, k, c),
                    }
                };
            }
        }
        let (h, decay) = (k.h, k.decay);
        macro_rules! with {
            ($integrator:expr, $exact:literal) => {{
                let update = move |v, v_inf| advance_potential($integrator, v, v_inf, h, decay);
                match drive {
                    SynapticDrive::One(c) => step_block_synaptic::<F, 1, $exact>(s, k, &update, c),
                    SynapticDrive::Two(c) => step_block_synaptic::<F, 2, $exact>(s, k, &update, c),
                }
            }};
        }
        match integrator {
            Integrator::Exact | Integrator::ExponentialEuler => with!(Integrator::Exact, true),
            Integrator::Euler => with!(Integrator::Euler, false),
            Integrator::Rk2 => with!(Integrator::Rk2, false),
            Integrator::Rk4 => with!(Integrator::Rk4, false),
            Integrator::Izhikevich2003 => unreachable!("rejected by prepare"),
        }
    }

    fn spike_mask(s: &LifState<F>) -> &[u8] {
        &s.spiked
    }

    fn spike_fractions(s: &LifState<F>) -> &[F] {
        &s.phi
    }

    fn variable(s: &LifState<F>, _var: usize, j: usize) -> f64 {
        s.v[j].f64()
    }
}

/// One step of `h = dt/τ_m` with `integrator` towards `v∞`; `decay = e^(−h)` (exact step).
#[inline(always)]
fn advance_potential<F: Real>(integrator: Integrator, v: F, v_inf: F, h: F, decay: F) -> F {
    let f = |x: [F; 1]| [v_inf - x[0]];
    match integrator {
        Integrator::Exact | Integrator::ExponentialEuler => v * decay + v_inf * (F::one() - decay),
        Integrator::Euler => integrate::euler([v], h, f)[0],
        Integrator::Rk2 => integrate::rk2([v], h, f)[0],
        Integrator::Rk4 => integrate::rk4([v], h, f)[0],
        Integrator::Izhikevich2003 => unreachable!("rejected by prepare"),
    }
}

/// One neuron's step with `update(v, v∞)`: the fused loop's floor, flush, refractory hold,
/// threshold and reset ([`BlockModel::step_neuron`]).
#[inline(always)]
fn step_one<F: Real>(
    k: &LifConstants<F>,
    s: &mut LifState<F>,
    j: usize,
    input: f64,
    update: impl Fn(F, F) -> F,
) -> bool {
    let v_inf = k.v_rest + F::of(input);
    let v_raw = update(s.v[j], v_inf);
    let v_new = if v_raw > k.v_floor { v_raw } else { k.v_floor };
    let mut v_new = if v_new.abs() >= F::min_positive_value() {
        v_new
    } else {
        F::zero()
    };
    let refractory = k.refractory_steps > 0;
    if refractory && s.refractory_steps[j] > F::zero() {
        v_new = k.v_reset;
    }
    let spike = v_new >= k.v_th;
    s.v[j] = if spike { k.v_reset } else { v_new };
    if refractory {
        let left = s.refractory_steps[j] - F::one();
        s.refractory_steps[j] = if spike { k.refractory } else { left };
    }
    spike
}

/// After an interpolated spike at fraction φ, integrates from `v_reset` over `(1 − φ)·dt`.
fn finish_interpolated_spikes<F: Real>(
    s: &mut LifState<F>,
    drive: Drive<'_>,
    k: &LifConstants<F>,
    integrator: Integrator,
) {
    let LifState { v, phi, spiked, .. } = s;
    for_each_spike(spiked, |i| {
        let f = F::of(unit_fraction(phi[i].f64()));
        phi[i] = f;
        let h = k.h * (F::one() - f);
        let v_inf = k.v_rest + F::of(drive.at(i));
        let v_next = advance_potential(integrator, k.v_reset, v_inf, h, (-h).exp());
        v[i] = if v_next > k.v_floor {
            v_next
        } else {
            k.v_floor
        };
    });
}
