//! What the models' AVX-512 loops share: the run-time check and the lane helpers.
//!
//! LLVM vectorises the portable fused loops with 256-bit vectors even on CPUs with 512-bit
//! ones (its tuning for Intel server cores prefers 256 bits, and rustc has no stable switch to
//! change that), so the loops run at half the lanes the core has. The hottest f64 loops
//! therefore also exist as AVX-512 loops written with intrinsics (`lif::avx512`,
//! `izhikevich::avx512`), chosen at run time when the CPU has AVX-512 (F, BW, VL). Each
//! performs the portable loop's IEEE operations in the same order, without contraction into
//! fused multiply-adds (`if a < b { a } else { b }` is `vminpd`, `if a > b { a } else { b }`
//! `vmaxpd`, NaN included), so its states and spikes are the portable loop's bit for bit: the
//! spike identity tests pin both, and each model's tests compare the two on random states.

use std::arch::x86_64::*;

/// f64 lanes of one 512-bit vector.
pub(crate) const LANES: usize = 8;

/// Whether this CPU runs the AVX-512 loops.
#[inline]
pub(crate) fn available() -> bool {
    use std::arch::is_x86_feature_detected as has;
    has!("avx512f") && has!("avx512bw") && has!("avx512vl")
}

/// The lanes of the last, partial vector of `n` neurons (`n % 8 > 0`).
pub(crate) fn tail_lanes(n: usize) -> __mmask8 {
    ((1u32 << (n % LANES)) - 1) as __mmask8
}

/// `if when { a } else { b }` per lane.
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn select(when: __mmask8, a: __m512d, b: __m512d) -> __m512d {
    _mm512_mask_blend_pd(when, b, a)
}

/// `a >= b` per lane (false when either is NaN, as Rust's `>=`).
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn ge(a: __m512d, b: __m512d) -> __mmask8 {
    _mm512_cmp_pd_mask::<_CMP_GE_OQ>(a, b)
}

/// `a <= b` per lane (false when either is NaN).
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) fn le(a: __m512d, b: __m512d) -> __mmask8 {
    _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a, b)
}

/// The lanes `lanes` of `x[j..]` (0 elsewhere); all 8 lanes compile to a plain load.
///
/// # Safety
/// Every lane in `lanes` must lie in `x`.
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn load(x: &[f64], j: usize, lanes: __mmask8) -> __m512d {
    debug_assert!(j + (8 - lanes.leading_zeros() as usize) <= x.len());
    unsafe { _mm512_maskz_loadu_pd(lanes, x.as_ptr().add(j)) }
}

/// Stores the lanes `lanes` of `v` to `x[j..]`.
///
/// # Safety
/// Every lane in `lanes` must lie in `x`.
#[inline]
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn store(x: &mut [f64], j: usize, lanes: __mmask8, v: __m512d) {
    debug_assert!(j + (8 - lanes.leading_zeros() as usize) <= x.len());
    unsafe { _mm512_mask_storeu_pd(x.as_mut_ptr().add(j), lanes, v) }
}

/// Writes the spike-mask bytes of the `lanes` lanes from neuron `j` on: 1 where `spikes`
/// has the lane, else 0.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vl")]
pub(crate) fn store_mask_bytes(mask: &mut [u8], j: usize, lanes: __mmask8, spikes: __mmask8) {
    let bytes = _mm_maskz_mov_epi8(u16::from(spikes), _mm_set1_epi8(1));
    if lanes == 0xff {
        let at = &mut mask[j..j + LANES];
        // SAFETY: `at` holds the 8 bytes written.
        unsafe { _mm_storel_epi64(at.as_mut_ptr().cast(), bytes) };
    } else {
        let count = lanes.count_ones() as usize;
        for (b, m) in mask[j..j + count].iter_mut().enumerate() {
            *m = (spikes >> b) & 1;
        }
    }
}
