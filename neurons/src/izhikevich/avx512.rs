//! The Euler step of an f64 chunk in AVX-512 ([`crate::avx512`]): the portable fused loop's
//! operations (`derivative`, `integrate::euler`, `clamp_and_reset`) on 8 neurons at a time,
//! in the same order, so the same states and spikes bit for bit. Only the start states of the
//! neurons that spike are kept, for the divergence check that the caller then runs as the
//! portable loop does.

use crate::avx512::{LANES, ge, load, select, store, store_mask_bytes, tail_lanes};
use crate::population::{Drive, count_ones};
use std::arch::x86_64::*;

/// The constants of the Euler step (`IzhikevichConstants` in f64).
#[derive(Debug, Clone, Copy)]
pub(super) struct EulerConstants {
    pub(super) a: f64,
    pub(super) b: f64,
    pub(super) c: f64,
    pub(super) d: f64,
    pub(super) h: f64,
    pub(super) v_peak: f64,
    pub(super) v_floor: f64,
}

/// The fused Euler loop of one chunk of at most [`CHUNK`] neurons, in place: writes the spike
/// mask and, for the neurons that spike, their start state; returns the number of spikes.
/// The CPU must have what [`crate::avx512::available`] checks (the caller's `unsafe`).
#[target_feature(enable = "avx512f,avx512bw,avx512vl")]
pub(super) fn euler_chunk(
    v: &mut [f64],
    u: &mut [f64],
    spiked: &mut [u8],
    (v_start, u_start): (&mut [f64], &mut [f64]),
    k: &EulerConstants,
    input: Drive<'_>,
) -> u64 {
    let n = v.len();
    assert!(u.len() == n && spiked.len() == n && v_start.len() >= n && u_start.len() >= n);
    let splat = |x| _mm512_set1_pd(x);
    let (quadratic, linear, offset) = (splat(0.04), splat(5.0), splat(140.0));
    let (a, b, c, d, h) = (splat(k.a), splat(k.b), splat(k.c), splat(k.d), splat(k.h));
    let (v_peak, v_floor) = (splat(k.v_peak), splat(k.v_floor));
    let (u_max, u_min) = (splat(f64::MAX), splat(f64::MIN));
    let per_neuron = match input {
        Drive::Constant(_) => &[][..],
        Drive::PerNeuron(x) => &x[..n],
    };
    let constant = splat(match input {
        Drive::Constant(x) => x,
        Drive::PerNeuron(_) => 0.0,
    });
    // SAFETY (every load and store): the lanes from `j` lie in the slices, all at least `n` long
    // (`per_neuron` too when it is read).
    let mut step = |j: usize, lanes: __mmask8| {
        let (v_old, u_old) = unsafe { (load(v, j, lanes), load(u, j, lanes)) };
        let i = match per_neuron.is_empty() {
            true => constant,
            false => unsafe { load(per_neuron, j, lanes) },
        };
        // derivative: 0.04·v·v + 5·v + 140 − u + I and a·(b·v − u), then x + h·f(x).
        let vv = _mm512_mul_pd(_mm512_mul_pd(quadratic, v_old), v_old);
        let dv = _mm512_add_pd(vv, _mm512_mul_pd(linear, v_old));
        let dv = _mm512_add_pd(_mm512_sub_pd(_mm512_add_pd(dv, offset), u_old), i);
        let du = _mm512_mul_pd(a, _mm512_sub_pd(_mm512_mul_pd(b, v_old), u_old));
        let v_raw = _mm512_add_pd(v_old, _mm512_mul_pd(h, dv));
        let u_raw = _mm512_add_pd(u_old, _mm512_mul_pd(h, du));
        // clamp_and_reset: each `if x < hi { x } else { hi }` is vminpd, each
        // `if x > lo { x } else { lo }` vmaxpd (NaN becomes the bound).
        let v_new = _mm512_max_pd(_mm512_min_pd(v_raw, v_peak), v_floor);
        let u_new = _mm512_max_pd(_mm512_min_pd(u_raw, u_max), u_min);
        let spike = ge(v_new, v_peak) & lanes;
        let u_reset = _mm512_min_pd(_mm512_add_pd(u_new, d), u_max);
        unsafe {
            store(v, j, lanes, select(spike, c, v_new));
            store(u, j, lanes, select(spike, u_reset, u_new));
            store(v_start, j, spike, v_old);
            store(u_start, j, spike, u_old);
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
