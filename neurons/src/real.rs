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

    /// A word whose top bit is set exactly when `self` is ±∞ or NaN: the bits of `|self|`
    /// plus `2^(w−1) − bits(+∞)`, which carries into the top bit from +∞ upwards. An OR of
    /// these is a cheap "anything non-finite?" reduction that keeps a fused loop vectorised:
    /// AND, ADD and OR are single instructions on `f32` and `f64` lanes alike (an integer
    /// maximum of 64-bit lanes, the obvious alternative, has no AVX2 instruction).
    fn non_finite_flag(self) -> Self::Bits;

    /// Whether an OR of [`non_finite_flag`](Self::non_finite_flag)s flags a non-finite value.
    fn any_non_finite(flags: Self::Bits) -> bool;

    /// Unsigned integer of the same width.
    type Bits: Copy + Default + std::fmt::Debug + std::ops::BitOr<Output = Self::Bits>;
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
    #[inline(always)]
    fn non_finite_flag(self) -> u32 {
        (self.to_bits() & 0x7fff_ffff) + (0x8000_0000 - 0x7f80_0000)
    }
    #[inline(always)]
    fn any_non_finite(flags: u32) -> bool {
        flags >> 31 != 0
    }
    type Bits = u32;
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
    #[inline(always)]
    fn non_finite_flag(self) -> u64 {
        (self.to_bits() & 0x7fff_ffff_ffff_ffff) + (0x8000_0000_0000_0000 - 0x7ff0_0000_0000_0000)
    }
    #[inline(always)]
    fn any_non_finite(flags: u64) -> bool {
        flags >> 63 != 0
    }
    type Bits = u64;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flags<F: Real>(values: &[F]) -> bool {
        F::any_non_finite(
            values
                .iter()
                .fold(F::Bits::default(), |acc, v| acc | v.non_finite_flag()),
        )
    }

    #[test]
    fn the_non_finite_flag_marks_exactly_infinities_and_nan() {
        assert!(!flags(&[
            0.0f32,
            -0.0,
            1.0,
            -f32::MAX,
            f32::MAX,
            f32::MIN_POSITIVE,
            1e-45
        ]));
        assert!(!flags(&[0.0f64, -0.0, 1.0, -f64::MAX, f64::MAX, 5e-324]));
        for bad in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN, -f32::NAN] {
            assert!(flags(&[1.0, bad, 2.0]), "{bad}");
        }
        for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, -f64::NAN] {
            assert!(flags(&[1.0, bad, 2.0]), "{bad}");
        }
    }
}
