//! The lanes of the sweep's inner loop: how many windows Δ one block computes at once
//! ([`LANES`]), and the wrapping integer type each lane holds ([`Lane`]: `i32` when the
//! distances fit, `i64` otherwise).

/// Δ values per block (lanes of the inner loop): the paper's 200 windows in one block of
/// 16-lane vectors.
pub const LANES: usize = 208;

/// Wrapping integer lanes (`i32` when the distances fit, `i64` otherwise).
pub(super) trait Lane: Copy + Default + PartialOrd + Send + Sync + 'static {
    const MIN: Self;
    const MAX: Self;
    fn wadd(self, o: Self) -> Self;
    fn wsub(self, o: Self) -> Self;
    fn wmul(self, o: Self) -> Self;
    fn from_i64(x: i64) -> Self;
    fn to_i64(self) -> i64;
}

macro_rules! lane {
    ($($t:ty),*) => {$(
        impl Lane for $t {
            const MIN: Self = <$t>::MIN;
            const MAX: Self = <$t>::MAX;
            #[inline(always)]
            fn wadd(self, o: Self) -> Self { self.wrapping_add(o) }
            #[inline(always)]
            fn wsub(self, o: Self) -> Self { self.wrapping_sub(o) }
            #[inline(always)]
            fn wmul(self, o: Self) -> Self { self.wrapping_mul(o) }
            #[inline(always)]
            fn from_i64(x: i64) -> Self { x as $t }
            #[inline(always)]
            fn to_i64(self) -> i64 { self as i64 }
        }
    )*};
}
lane!(i32, i64);
