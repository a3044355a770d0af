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

use crate::integrate::{self, Integrator};
use crate::population::{
    BLOCK, Drive, InitialPotential, Population, block_len, check_dt, check_param,
    collect_block_spikes, for_blocks, for_each_spike, n_blocks, unit_fraction,
};
use crate::real::Real;
use neurotac_core::{ModelError, NeuronModel, SpikeBuffer};

const MODEL: &str = "lif";
const SUPPORTED: &str = "exact, exp-euler, euler, rk2, rk4";

/// LIF parameters (see the module docs for the equations and units).
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

    fn validate(&self) -> Result<(), ModelError> {
        check_param(MODEL, "tau_m_s", self.tau_m_s, true)?;
        check_param(MODEL, "v_rest", self.v_rest, false)?;
        check_param(MODEL, "v_th", self.v_th, false)?;
        check_param(MODEL, "v_reset", self.v_reset, false)?;
        check_param(MODEL, "t_ref_s", self.t_ref_s, false)?;
        if self.t_ref_s < 0.0 {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "t_ref_s",
                value: self.t_ref_s,
                expected: "≥ 0",
            });
        }
        if self.v_reset >= self.v_th {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "v_reset",
                value: self.v_reset,
                expected: "< v_th",
            });
        }
        if self.v_min.is_nan() || self.v_min > self.v_reset {
            return Err(ModelError::InvalidParameter {
                model: MODEL,
                field: "v_min",
                value: self.v_min,
                expected: "≤ v_reset (−∞ allowed)",
            });
        }
        Ok(())
    }
}

/// The state of one block of up to [`BLOCK`] LIF neurons, structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct LifState<F> {
    /// Membrane potentials.
    pub v: Vec<F>,
    /// Remaining refractory steps (empty when `t_ref = 0`).
    pub refractory_steps: Vec<u32>,
    /// In-step spike fractions of the last step (empty unless interpolating).
    phi: Vec<F>,
    /// 1 where the neuron spiked in the last step.
    spiked: Vec<u8>,
}

/// Per-step constants, computed once by `prepare` in the population's precision.
#[derive(Debug, Clone, Copy, Default)]
struct LifConstants<F> {
    v_rest: F,
    v_th: F,
    v_reset: F,
    v_floor: F,
    h: F,
    decay: F,
    refractory_steps: u32,
}

/// Advances one block by one step: fused update, threshold, reset and refractory, writing the
/// spike mask; returns the number of spikes. `update(v, v∞)` is the integrator.
#[inline(always)]
fn step_block<F: Real, const REFRACTORY: bool, const INTERPOLATE: bool>(
    s: &mut LifState<F>,
    drive: Drive<'_>,
    k: &LifConstants<F>,
    update: &impl Fn(F, F) -> F,
) -> u64 {
    match drive {
        Drive::Constant(c) => {
            let v_inf = k.v_rest + F::of(c);
            step_block_with::<F, REFRACTORY, INTERPOLATE>(s, k, update, |_| v_inf)
        }
        Drive::PerNeuron(x) => {
            let x = &x[..s.v.len()];
            step_block_with::<F, REFRACTORY, INTERPOLATE>(s, k, update, |j| k.v_rest + F::of(x[j]))
        }
    }
}

#[inline(always)]
fn step_block_with<F: Real, const REFRACTORY: bool, const INTERPOLATE: bool>(
    s: &mut LifState<F>,
    k: &LifConstants<F>,
    update: &impl Fn(F, F) -> F,
    v_inf: impl Fn(usize) -> F,
) -> u64 {
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
        refractory_steps: n_ref,
        ..
    } = *k;
    let tiny = F::min_positive_value();
    let mut count = 0u32;
    for i in 0..n {
        let v_old = v[i];
        let v_raw = update(v_old, v_inf(i));
        // One compare + select: NaN and −∞ (unstable Euler) become the floor, never the state.
        let v_new = if v_raw > v_floor { v_raw } else { v_floor };
        // Flush subnormals to 0: a long silence decays v towards v_rest = 0 through the
        // subnormal range, where x86 arithmetic is 10–100× slower.
        let mut v_new = if v_new.abs() >= tiny {
            v_new
        } else {
            F::zero()
        };
        if REFRACTORY {
            v_new = if refractory_steps[i] == 0 {
                v_new
            } else {
                v_reset
            };
        }
        let spike = v_new >= v_th;
        if INTERPOLATE {
            phi[i] = if spike {
                (v_th - v_old) / (v_new - v_old)
            } else {
                F::one()
            };
        }
        v[i] = if spike { v_reset } else { v_new };
        if REFRACTORY {
            refractory_steps[i] = if spike {
                n_ref
            } else {
                refractory_steps[i].saturating_sub(1)
            };
        }
        spiked[i] = spike as u8;
        count += spike as u32;
    }
    count as u64
}

/// A population of LIF neurons in precision `F` (`f32` or `f64`).
///
/// ```
/// use neurotac_neurons::{Integrator, Lif, LifParams, Population};
/// let mut lif = Lif::<f64>::new(100, LifParams::default()).with_integrator(Integrator::Exact);
/// let spikes = lif.run_constant(1.04, 1e-4, 10_000)?; // 1 s at 0.1 ms
/// // Closed form: period τ·ln(I/(I−1)) = 10 ms · ln 26 = 32.58 ms → 30 spikes per neuron in 1 s.
/// assert_eq!(spikes, 100 * 30);
/// # Ok::<(), neurotac_core::ModelError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Lif<F: Real> {
    n: usize,
    params: LifParams,
    integrator: Integrator,
    interpolate: bool,
    initial: InitialPotential,
    blocks: Vec<LifState<F>>,
    k: LifConstants<F>,
    dt_s: f64,
}

impl<F: Real> Lif<F> {
    /// `n` neurons with `params`, the exact integrator, grid spike times and `v = v_rest` at start.
    pub fn new(n: usize, params: LifParams) -> Self {
        Self {
            n,
            params,
            integrator: Integrator::Exact,
            interpolate: false,
            initial: InitialPotential::Constant(params.v_rest),
            blocks: Vec::new(),
            k: LifConstants::default(),
            dt_s: 0.0,
        }
    }

    /// Chooses the integrator (checked by `prepare`).
    pub fn with_integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = integrator;
        self
    }

    /// Interpolates spike times inside the step (see the module docs).
    pub fn with_interpolation(mut self, interpolate: bool) -> Self {
        self.interpolate = interpolate;
        self
    }

    /// Sets the initial membrane potentials.
    pub fn with_initial_potential(mut self, initial: InitialPotential) -> Self {
        self.initial = initial;
        self
    }

    /// The parameters.
    pub fn params(&self) -> &LifParams {
        &self.params
    }

    /// The integrator.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Membrane potential of neuron `i` (after `prepare`).
    pub fn potential(&self, i: usize) -> f64 {
        self.blocks[i / BLOCK].v[i % BLOCK].f64()
    }

    fn advance_blocks(&mut self, drive: Drive<'_>) -> u64 {
        let k = self.k;
        // One closure per integrator, so each gets its own vectorised loop.
        macro_rules! with {
            ($integrator:expr) => {
                self.advance_with(
                    drive,
                    #[inline(always)]
                    move |v, v_inf| advance_potential($integrator, v, v_inf, k.h, k.decay),
                )
            };
        }
        match self.integrator {
            Integrator::Exact | Integrator::ExponentialEuler => with!(Integrator::Exact),
            Integrator::Euler => with!(Integrator::Euler),
            Integrator::Rk2 => with!(Integrator::Rk2),
            Integrator::Rk4 => with!(Integrator::Rk4),
            Integrator::Izhikevich2003 => unreachable!("rejected by prepare"),
        }
    }

    fn advance_with(&mut self, drive: Drive<'_>, update: impl Fn(F, F) -> F + Sync) -> u64 {
        let (n, k, integrator) = (self.n, self.k, self.integrator);
        let refractory = k.refractory_steps > 0;
        let interpolate = self.interpolate;
        for_blocks(&mut self.blocks, n, |b, s| {
            let d = drive.block(b, s.v.len());
            match (refractory, interpolate) {
                (false, false) => step_block::<F, false, false>(s, d, &k, &update),
                (true, false) => step_block::<F, true, false>(s, d, &k, &update),
                (false, true) => {
                    let count = step_block::<F, false, true>(s, d, &k, &update);
                    if count > 0 {
                        finish_interpolated_spikes(s, d, &k, integrator);
                    }
                    count
                }
                (true, true) => step_block::<F, true, true>(s, d, &k, &update),
            }
        })
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

impl<F: Real> Population for Lif<F> {
    fn advance(&mut self, drive: Drive<'_>) -> u64 {
        self.advance_blocks(drive)
    }

    fn prepared_dt(&self) -> Option<f64> {
        (self.dt_s > 0.0 && self.blocks.len() == n_blocks(self.n)).then_some(self.dt_s)
    }
}

impl<F: Real> NeuronModel for Lif<F> {
    fn model_name(&self) -> &'static str {
        MODEL
    }

    fn len(&self) -> usize {
        self.n
    }

    fn variables(&self) -> &'static [&'static str] {
        &["v"]
    }

    fn prepare(&mut self, dt_s: f64) -> Result<(), ModelError> {
        check_dt(MODEL, dt_s)?;
        self.params.validate()?;
        if self.integrator == Integrator::Izhikevich2003 {
            return Err(ModelError::UnsupportedIntegrator {
                model: MODEL,
                integrator: self.integrator.name(),
                supported: SUPPORTED,
            });
        }
        let p = &self.params;
        let h = dt_s / p.tau_m_s;
        let refractory_steps = (p.t_ref_s / dt_s).round().min(u32::MAX as f64) as u32;
        self.k = LifConstants {
            v_rest: F::of(p.v_rest),
            v_th: F::of(p.v_th),
            v_reset: F::of(p.v_reset),
            v_floor: F::of(p.v_min).max(F::min_value()),
            h: F::of(h),
            decay: F::of((-h).exp()),
            refractory_steps,
        };
        let v0 = self.initial.values(MODEL, self.n)?;
        self.blocks = (0..n_blocks(self.n))
            .map(|b| {
                let len = block_len(self.n, b);
                LifState {
                    v: v0[b * BLOCK..b * BLOCK + len]
                        .iter()
                        .map(|&x| F::of(x))
                        .collect(),
                    refractory_steps: if refractory_steps > 0 {
                        vec![0; len]
                    } else {
                        Vec::new()
                    },
                    phi: if self.interpolate {
                        vec![F::one(); len]
                    } else {
                        Vec::new()
                    },
                    spiked: vec![0; len],
                }
            })
            .collect();
        self.dt_s = dt_s;
        Ok(())
    }

    fn reset(&mut self) {
        // `prepare` succeeded before, so this cannot fail.
        let _ = self.prepare(self.dt_s);
    }

    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer) {
        if self.advance_blocks(Drive::PerNeuron(current)) == 0 {
            return;
        }
        let interpolate = self.interpolate;
        for (b, s) in self.blocks.iter().enumerate() {
            collect_block_spikes(b, &s.spiked, interpolate.then_some(&s.phi[..]), spikes);
        }
    }

    fn read_variable(&self, _var: usize, neurons: &[u32], out: &mut Vec<f64>) {
        out.extend(neurons.iter().map(|&i| self.potential(i as usize)));
    }
}
