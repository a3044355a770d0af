//! Integrators, written once and shared by every model.
//!
//! A model supplies its derivative `f(x, I)` for a state `x ∈ Fᴰ` with the input `I` held
//! constant over the step; [`euler`], [`rk2`] and [`rk4`] advance it by `h`. Exact and
//! exponential-Euler steps exploit a model's linear parts and so live in the model's file.
//!
//! | [`Integrator`] | name | local error | notes |
//! |---|---|---|---|
//! | `Euler` | `euler` | O(h²) | `x + h·f(x)` |
//! | `Exact` | `exact` | 0 for constant input | linear models only (LIF) |
//! | `ExponentialEuler` | `exp-euler` | O(h²) | linear parts exact, the rest Euler |
//! | `Rk2` | `rk2` | O(h³) | Heun: `x + h/2·(k₁ + k₂)` |
//! | `Rk4` | `rk4` | O(h⁵) | classical Runge–Kutta |
//! | `Izhikevich2003` | `izhikevich2003` | O(h²) | Izhikevich (2003): `v` in two half steps, then `u` |

use crate::real::Real;
use std::fmt;
use std::str::FromStr;

/// The integration scheme of a population, chosen per population.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Integrator {
    /// Forward Euler.
    Euler,
    /// Exact solution for input held constant over the step (LIF).
    Exact,
    /// Exponential Euler: exact for the linear parts, Euler for the rest.
    ExponentialEuler,
    /// Second-order Runge–Kutta (Heun's method).
    Rk2,
    /// Classical fourth-order Runge–Kutta.
    Rk4,
    /// Izhikevich's 2003 scheme: two half steps of `v`, then one step of `u` with the new `v`.
    Izhikevich2003,
}

impl Integrator {
    /// Every integrator, in the order of the table above.
    pub const ALL: [Integrator; 6] = [
        Integrator::Euler,
        Integrator::Exact,
        Integrator::ExponentialEuler,
        Integrator::Rk2,
        Integrator::Rk4,
        Integrator::Izhikevich2003,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Euler => "euler",
            Integrator::Exact => "exact",
            Integrator::ExponentialEuler => "exp-euler",
            Integrator::Rk2 => "rk2",
            Integrator::Rk4 => "rk4",
            Integrator::Izhikevich2003 => "izhikevich2003",
        }
    }
}

impl fmt::Display for Integrator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An integrator name that is not one of [`Integrator::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown integrator '{0}' (expected one of: euler, exact, exp-euler, rk2, rk4, izhikevich2003)"
)]
pub struct UnknownIntegrator(pub String);

impl FromStr for Integrator {
    type Err = UnknownIntegrator;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Integrator::ALL
            .into_iter()
            .find(|i| {
                i.name() == s || (s == "exponential-euler" && *i == Integrator::ExponentialEuler)
            })
            .ok_or_else(|| UnknownIntegrator(s.to_owned()))
    }
}

#[inline(always)]
fn axpy<F: Real, const D: usize>(x: [F; D], h: F, k: [F; D]) -> [F; D] {
    let mut out = x;
    for d in 0..D {
        out[d] = x[d] + h * k[d];
    }
    out
}

/// One forward-Euler step: `x + h·f(x)`.
#[inline(always)]
pub fn euler<F: Real, const D: usize>(x: [F; D], h: F, f: impl Fn([F; D]) -> [F; D]) -> [F; D] {
    axpy(x, h, f(x))
}

/// One Heun (RK2) step: `k₁ = f(x)`, `k₂ = f(x + h·k₁)`, `x + h/2·(k₁ + k₂)`.
#[inline(always)]
pub fn rk2<F: Real, const D: usize>(x: [F; D], h: F, f: impl Fn([F; D]) -> [F; D]) -> [F; D] {
    let k1 = f(x);
    let k2 = f(axpy(x, h, k1));
    let half = h * F::of(0.5);
    let mut out = x;
    for d in 0..D {
        out[d] = x[d] + half * (k1[d] + k2[d]);
    }
    out
}

/// One classical RK4 step: `x + h/6·(k₁ + 2k₂ + 2k₃ + k₄)`.
#[inline(always)]
pub fn rk4<F: Real, const D: usize>(x: [F; D], h: F, f: impl Fn([F; D]) -> [F; D]) -> [F; D] {
    let half = h * F::of(0.5);
    let k1 = f(x);
    let k2 = f(axpy(x, half, k1));
    let k3 = f(axpy(x, half, k2));
    let k4 = f(axpy(x, h, k3));
    let sixth = h / F::of(6.0);
    let two = F::of(2.0);
    let mut out = x;
    for d in 0..D {
        out[d] = x[d] + sixth * (k1[d] + two * (k2[d] + k3[d]) + k4[d]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    type Step = fn([f64; 1], f64, &dyn Fn([f64; 1]) -> [f64; 1]) -> [f64; 1];

    /// dx/dt = −x from x = 1 to t = 1; error at the integrator's global order.
    fn global_error(step: Step, n: usize) -> f64 {
        let h = 1.0 / n as f64;
        let mut x = [1.0];
        for _ in 0..n {
            x = step(x, h, &|x: [f64; 1]| [-x[0]]);
        }
        (x[0] - (-1.0f64).exp()).abs()
    }

    #[test]
    fn errors_shrink_at_each_integrators_order() {
        let order = |step: Step| (global_error(step, 64) / global_error(step, 128)).log2();
        let e = order(|x, h, f| euler(x, h, f));
        let r2 = order(|x, h, f| rk2(x, h, f));
        let r4 = order(|x, h, f| rk4(x, h, f));
        assert!((e - 1.0).abs() < 0.05, "euler order {e}");
        assert!((r2 - 2.0).abs() < 0.05, "rk2 order {r2}");
        assert!((r4 - 4.0).abs() < 0.1, "rk4 order {r4}");
    }

    #[test]
    fn names_round_trip() {
        for i in Integrator::ALL {
            assert_eq!(i.name().parse::<Integrator>().unwrap(), i);
        }
        assert!(
            "leapfrog"
                .parse::<Integrator>()
                .unwrap_err()
                .to_string()
                .contains("leapfrog")
        );
    }
}
