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

    /// The bits of `|self|` as an unsigned integer of the same width: `≥ INFINITY_BITS` exactly
    /// for ±∞ and NaN. An integer maximum of these is a cheap "anything non-finite?" reduction
    /// that keeps a fused loop vectorised and unrolled.
    fn magnitude_bits(self) -> Self::Bits;

    /// Unsigned integer of the same width.
    type Bits: Copy + Ord + Default + std::fmt::Debug;

    /// [`magnitude_bits`](Self::magnitude_bits) of +∞.
    const INFINITY_BITS: Self::Bits;
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
    fn magnitude_bits(self) -> u32 {
        self.to_bits() & 0x7fff_ffff
    }
    type Bits = u32;
    const INFINITY_BITS: u32 = 0x7f80_0000;
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
    fn magnitude_bits(self) -> u64 {
        self.to_bits() & 0x7fff_ffff_ffff_ffff
    }
    type Bits = u64;
    const INFINITY_BITS: u64 = 0x7ff0_0000_0000_0000;
}
