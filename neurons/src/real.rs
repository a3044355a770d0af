//! [`Real`]: the floating-point precision a population computes in (`f32` or `f64`).

use num_traits::Float;

/// A floating-point type a population can be instantiated with: `f32` (faster, 7 digits) or
/// `f64` (exact to 16 digits). Parameters are always given in `f64` and converted once.
pub trait Real: Float + Send + Sync + std::fmt::Debug + Default + 'static {
    /// Name for reports (`"f32"` / `"f64"`).
    const NAME: &'static str;

    /// Converts from `f64` (rounding to nearest for `f32`).
    fn of(x: f64) -> Self;

    /// Widens to `f64`.
    fn f64(self) -> f64;
}

impl Real for f32 {
    const NAME: &'static str = "f32";
    #[inline(always)]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn f64(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    const NAME: &'static str = "f64";
    #[inline(always)]
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn f64(self) -> f64 {
        self
    }
}
