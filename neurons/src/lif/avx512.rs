//! The exact step of an f64 block under its synaptic currents in AVX-512 ([`crate::avx512`]):
//! the portable fused loop (`step_block_synaptic` with the exact update) on 8 neurons at a
//! time — the currents summed in projection order, decayed and flushed
//! ([`DecayingCurrents::take`]), the update `v·e^(−h) + v∞·(1 − e^(−h))`, the optional floor
//! and flush, refractory hold, threshold and reset — in the same order, so the same states,
//! currents and spikes bit for bit.

use crate::avx512::{LANES, ge, le, load, select, store, store_mask_bytes, tail_lanes};
use crate::population::count_ones;
use neurotac_core::DecayingCurrents;
use neurotac_core::graph::FLUSH_TO_ZERO;
use std::arch::x86_64::*;

/// The constants of the exact step (`LifConstants` in f64).
#[derive(Debug, Clone, Copy)]
pub(super) struct ExactConstants {
    pub(super) v_rest: f64,
    pub(super) decay: f64,
    pub(super) v_th: f64,
    pub(super) v_reset: f64,
    pub(super) v_floor: f64,
    /// Refractory steps set at a spike.
    pub(super) refractory: f64,
}

/// The fused loop over the block's potentials `v`, refractory counts and spike mask;
/// `CHECKED` keeps the floor and the subnormal flush. Returns the spikes. The CPU must have
/// what [`crate::avx512::available`] checks (the caller's `unsafe`).
#[target_feature(enable = "avx512f,avx512bw,avx512vl")]
pub(super) fn exact_synaptic<const N: usize, const REFRACTORY: bool, const CHECKED: bool>(
    v: &mut [f64],
    refractory_steps: &mut [f64],
    spiked: &mut [u8],
    k: &ExactConstants,
    mut currents: DecayingCurrents<'_, N>,
) -> u64 {
    let n = v.len();
    let (currents, decays) = currents.parts_mut();
    assert!(currents.iter().all(|c| c.len() >= n) && spiked.len() == n);
    assert!(!REFRACTORY || refractory_steps.len() == n);
    let splat = |x| _mm512_set1_pd(x);
    let (v_rest, decay, rise) = (splat(k.v_rest), splat(k.decay), splat(1.0 - k.decay));
    let (v_th, v_reset, v_floor) = (splat(k.v_th), splat(k.v_reset), splat(k.v_floor));
    let (tiny, zero, one) = (splat(f64::MIN_POSITIVE), splat(0.0), splat(1.0));
    let (n_ref, flush_below) = (splat(k.refractory), splat(FLUSH_TO_ZERO));
    let decays = decays.map(splat);
    // `currents::flush`: x, or exactly 0 when |x| < FLUSH_TO_ZERO (NaN kept).
    let flush = |x| {
        let keep = _mm512_cmp_pd_mask::<_CMP_NLT_UQ>(_mm512_abs_pd(x), flush_below);
        _mm512_maskz_mov_pd(keep, x)
    };
    // SAFETY (every load and store): the lanes from `j` lie in the slices, all at least `n`
    // long (`refractory_steps` when it is read).
    let mut step = |j: usize, lanes: __mmask8| {
        let v_old = unsafe { load(v, j, lanes) };
        // `DecayingCurrents::take`.
        let mut x = zero;
        for p in 0..N {
            let c = unsafe { load(currents[p], j, lanes) };
            x = if p == 0 { c } else { _mm512_add_pd(x, c) };
            unsafe { store(currents[p], j, lanes, flush(_mm512_mul_pd(c, decays[p]))) };
        }
        let v_inf = _mm512_add_pd(v_rest, x);
        let mut v_new = _mm512_add_pd(_mm512_mul_pd(v_old, decay), _mm512_mul_pd(v_inf, rise));
        if CHECKED {
            v_new = _mm512_max_pd(v_new, v_floor);
            v_new = select(ge(_mm512_abs_pd(v_new), tiny), v_new, zero);
        }
        let refractory = match REFRACTORY {
            true => unsafe { load(refractory_steps, j, lanes) },
            false => zero,
        };
        if REFRACTORY {
            v_new = select(le(refractory, zero), v_new, v_reset);
        }
        let spike = ge(v_new, v_th) & lanes;
        unsafe { store(v, j, lanes, select(spike, v_reset, v_new)) };
        if REFRACTORY {
            let left = _mm512_sub_pd(refractory, one);
            unsafe { store(refractory_steps, j, lanes, select(spike, n_ref, left)) };
        }
        store_mask_bytes(spiked, j, lanes, spike);
    };
    let full = n - n % LANES;
    for j in (0..full).step_by(LANES) {
        step(j, 0xff);
    }
    if full < n {
        step(full, tail_lanes(n));
    }
    count_ones(spiked)
}
