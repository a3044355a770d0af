//! LIF as a [`ModelFamily`] ([`LifFamily`]): the model at every precision with its benchmark
//! case, its afferent set-up, the cost of one update and its closed-form spike times.

use super::{LifModel, LifParams};
use crate::family::{AfferentPreset, Benchmark, ModelFamily, UpdateCost};
use crate::integrate::Integrator;
use crate::population::InitialPotential;
use crate::real::Real;

/// LIF at every precision, with its benchmark, afferent and closed form ([`ModelFamily`]);
/// `Model<F>` is [`LifModel<F>`].
#[derive(Debug, Clone, Copy, Default)]
pub struct LifFamily;

impl ModelFamily for LifFamily {
    type Params = LifParams;
    type Model<F: Real> = LifModel<F>;

    const LABEL: &'static str = "LIF";
    /// exp-euler is left out: for LIF it is the exact step.
    const INTEGRATORS: &'static [Integrator] = &[
        Integrator::Exact,
        Integrator::Euler,
        Integrator::Rk2,
        Integrator::Rk4,
    ];

    /// Brian2's LIF benchmark, `dv/dt = (I − v)/τ`: [`LifParams::benchmark`] (τ = 10 ms,
    /// threshold 1, reset 0) under `I = 1.04` (period τ·ln 26 = 32.58 ms), `v₀` uniform in
    /// [0, 1) — between reset and threshold — seed 2020.
    fn benchmark() -> Benchmark<LifParams> {
        Benchmark {
            params: LifParams::benchmark(),
            current: 1.04,
            initial: InitialPotential::Uniform {
                low: 0.0,
                high: 1.0,
                seed: 2020,
            },
        }
    }

    /// [`LifParams::default`] (τ_m = 10 ms, threshold 1, reset 0), from rest (`v = 0`), exact
    /// step, weight 5 (potential units): with the afferents' 5 ms synapse, one taxel spike gives
    /// the PSP `w·τ_s/(τ_m − τ_s)·(e^(−t/τ_m) − e^(−t/τ_s))`, peaking at `0.25·w = 1.25·v_th` at
    /// `t = τ_m·ln 2 = 6.9 ms` — a lone taxel event makes exactly one afferent spike, ~3 ms
    /// later.
    fn afferent() -> AfferentPreset<LifParams> {
        let params = LifParams::default();
        AfferentPreset {
            params,
            initial: Self::at_rest(&params),
            weight: 5.0,
            description: "LIF afferents (event-driven)",
            bench_description: "LIF afferents (exact, f64)",
        }
    }

    /// LIF integrates `dv/dh = v∞ − v` (one subtraction; `v∞` is a per-step constant under
    /// the benchmark's constant input), with `axpy(x, s, y) = x + s·y` two flops:
    /// - exact: `v·e^(−h) + v∞·(1 − e^(−h))`, the second term per step: 1 mul + 1 add = **2**;
    /// - euler: `v + h·(v∞ − v)`: 1 + 2 = **3**;
    /// - rk2: `k₁ = f(v)` (1), `k₂ = f(v + h·k₁)` (2 + 1), `v + h/2·(k₁ + k₂)` (3): **7**;
    /// - rk4: `k₁` (1), `k₂`, `k₃`, `k₄` (3 each: an axpy and `f`),
    ///   `v + h/6·(k₁ + 2·(k₂ + k₃) + k₄)` (6): **16**.
    ///
    /// Floor, flush, threshold and reset are compares and selects (0). One state variable:
    /// 9 bytes per update in `f32`, 17 in `f64`.
    fn update_cost<F: Real>(integrator: Integrator) -> Option<UpdateCost> {
        let flops = match integrator {
            Integrator::Exact | Integrator::ExponentialEuler => 2,
            Integrator::Euler => 3,
            Integrator::Rk2 => 7,
            Integrator::Rk4 => 16,
            Integrator::Izhikevich2003 => return None,
        };
        Some(UpdateCost::of::<F>(flops, 1))
    }

    /// [`LifParams::closed_form_spike_times`], which counts from `v_reset`: the rest when
    /// `v_reset = v_rest` (the benchmark), else `None`.
    fn exact_spike_times(params: &LifParams, current: f64, duration_s: f64) -> Option<Vec<f64>> {
        (params.v_reset == params.v_rest)
            .then(|| params.closed_form_spike_times(current, duration_s))
    }
}
