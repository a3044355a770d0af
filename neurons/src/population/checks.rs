//! Validation shared by the models' parameter checks: finite (optionally positive) values, and
//! values representable in the population's precision.

use crate::real::Real;
use neurotac_core::ModelError;

/// Refuses a finite `x` that overflows `F` (only `f32` can: `|x| > 3.4·10³⁸`).
pub fn check_representable<F: Real>(
    model: &'static str,
    field: &'static str,
    x: f64,
) -> Result<(), ModelError> {
    if x.is_finite() && !F::of(x).is_finite() {
        return Err(ModelError::InvalidParameter {
            model,
            field,
            value: x,
            expected: "within the f32 range (|x| ≤ 3.4028235e38)",
        });
    }
    Ok(())
}

/// Validates that `x` is finite and, optionally, positive.
pub fn check_param(
    model: &'static str,
    field: &'static str,
    x: f64,
    positive: bool,
) -> Result<(), ModelError> {
    if !x.is_finite() || (positive && x <= 0.0) {
        return Err(ModelError::InvalidParameter {
            model,
            field,
            value: x,
            expected: if positive { "finite and > 0" } else { "finite" },
        });
    }
    Ok(())
}

/// Validates a threshold-and-reset pair and a potential floor: `v_reset < v_th`, and `v_min`
/// (−∞ allowed) at or below `v_reset`.
pub fn check_reset_and_floor(
    model: &'static str,
    v_th: f64,
    v_reset: f64,
    v_min: f64,
) -> Result<(), ModelError> {
    if v_reset >= v_th {
        return Err(ModelError::InvalidParameter {
            model,
            field: "v_reset",
            value: v_reset,
            expected: "< v_th",
        });
    }
    if v_min.is_nan() || v_min > v_reset {
        return Err(ModelError::InvalidParameter {
            model,
            field: "v_min",
            value: v_min,
            expected: "≤ v_reset (−∞ allowed)",
        });
    }
    Ok(())
}
