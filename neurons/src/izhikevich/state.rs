//! The Izhikevich model's state (structure of arrays) and per-step constants, and the update of
//! one neuron: the derivative, one step of each integrator and the clamps, threshold and reset
//! (equations in the [module docs](super)).

use crate::integrate::{self, Integrator};
use crate::real::Real;

/// The state of one block of up to [`BLOCK`](crate::population::BLOCK) Izhikevich neurons, structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct IzhikevichState<F> {
    /// Membrane potentials (mV).
    pub v: Vec<F>,
    /// Recovery variables.
    pub u: Vec<F>,
    /// In-step spike fractions of the last step (empty unless interpolating).
    pub(super) phi: Vec<F>,
    /// `u` at the interpolated crossing (empty unless interpolating).
    pub(super) u_at_spike: Vec<F>,
    /// 1 where the neuron spiked in the last step.
    pub(super) spiked: Vec<u8>,
}

/// Per-step constants, computed once by `prepare` in the population's precision.
#[derive(Debug, Clone, Copy, Default)]
pub struct IzhikevichConstants<F> {
    pub(super) a: F,
    pub(super) b: F,
    pub(super) c: F,
    pub(super) d: F,
    pub(super) v_peak: F,
    pub(super) v_floor: F,
    pub(super) h: F,
    pub(super) u_decay: F,
    /// `0.04·(v_peak − m)²`: `g(v_peak) − q` of the divergence criterion.
    pub(super) peak_rate: F,
    /// The resting point `(v*, u*)` without input, and the tolerance within which a neuron
    /// counts as at rest (module docs, Event-driven stepping).
    pub(super) v_rest: F,
    pub(super) u_rest: F,
    pub(super) rest_tolerance: F,
    /// `true` when the resting point exists, is stable and the step resolves its fastest decay
    /// (`h·|λ| < 1`).
    pub(super) holds_at_rest: bool,
}

/// `(dv/dt, du/dt)` at `(v, u)` for input `i`.
#[inline(always)]
pub(super) fn derivative<F: Real>(k: &IzhikevichConstants<F>, x: [F; 2], i: F) -> [F; 2] {
    let v = x[0];
    [
        F::of(0.04) * v * v + F::of(5.0) * v + F::of(140.0) - x[1] + i,
        k.a * (k.b * v - x[1]),
    ]
}

/// One step of length `h` (ms) with `integrator`; `u_decay = e^(−a·h)` (used by exp-euler).
#[inline(always)]
pub(super) fn advance_state<F: Real>(
    integrator: Integrator,
    k: &IzhikevichConstants<F>,
    (v, u): (F, F),
    i: F,
    h: F,
    u_decay: F,
) -> (F, F) {
    let pair = |x: [F; 2]| (x[0], x[1]);
    match integrator {
        Integrator::Izhikevich2003 => {
            let half = h * F::of(0.5);
            let v1 = v + half * derivative(k, [v, u], i)[0];
            let v2 = v1 + half * derivative(k, [v1, u], i)[0];
            (v2, u + h * k.a * (k.b * v2 - u))
        }
        Integrator::ExponentialEuler => {
            let u_inf = k.b * v;
            (
                v + h * derivative(k, [v, u], i)[0],
                u_inf + (u - u_inf) * u_decay,
            )
        }
        Integrator::Euler => pair(integrate::euler([v, u], h, |x| derivative(k, x, i))),
        Integrator::Rk2 => pair(integrate::rk2([v, u], h, |x| derivative(k, x, i))),
        Integrator::Rk4 => pair(integrate::rk4([v, u], h, |x| derivative(k, x, i))),
        Integrator::Exact => unreachable!("rejected by prepare"),
    }
}

/// The clamps, threshold and reset of one neuron after its integrator's raw update
/// `(v_raw, u_raw)`: `(v, u)` after the step, `u` before the reset, and the spike. One compare +
/// select each: anything not below the peak (NaN and +∞ included) becomes the peak, and so a
/// spike; `u` outside the finite range (NaN included) becomes a bound. The constants come as
/// values, not through `k` (selects between values, not between addresses, which LLVM would
/// turn into gathers).
#[inline(always)]
pub(super) fn clamp_and_reset<F: Real>(
    v_raw: F,
    u_raw: F,
    c: F,
    d: F,
    v_peak: F,
    v_floor: F,
) -> (F, F, F, bool) {
    let (u_max, u_min) = (F::max_value(), F::min_value());
    let v_new = if v_raw < v_peak { v_raw } else { v_peak };
    let v_new = if v_new > v_floor { v_new } else { v_floor };
    let u_new = if u_raw < u_max { u_raw } else { u_max };
    let u_new = if u_new > u_min { u_new } else { u_min };
    let spike = v_new >= v_peak;
    let u_reset = u_new + d;
    let u_reset = if u_reset < u_max { u_reset } else { u_max };
    (
        if spike { c } else { v_new },
        if spike { u_reset } else { u_new },
        u_new,
        spike,
    )
}
