//! The Euler step of an f64 block in AVX-512 ([`crate::avx512`]): the portable fused loop's
//! operations (`derivative`, `integrate::euler`, `clamp_and_reset`) on 8 neurons at a time,
//! in the same order, so the same states and spikes bit for bit. Only the start states of the
//! neurons that spike are kept for the divergence check, which then runs as in the portable
//! loop.

use super::{CHUNK, IzhikevichConstants, IzhikevichState, advance_state, diverged_spikes};
use crate::avx512::{LANES, ge, load, select, store, store_mask_bytes, tail_lanes};
use crate::integrate::Integrator;
use crate::population::{BlockStep, Drive, count_ones};
use std::arch::x86_64::*;

/// One step of the block `s` by Euler under `drive`, as the portable loop computes it.
///
/// # Safety
/// The CPU must have what [`crate::avx512::available`] checks.
pub(super) unsafe fn step_block_euler(
    s: &mut IzhikevichState<f64>,
    k: &IzhikevichConstants<f64>,
    drive: Drive<'_>,
) -> BlockStep {
    let n = s.v.len();
    let update = |v, u, i| advance_state(Integrator::Euler, k, (v, u), i, k.h, k.u_decay);
    let mut start_state = ([0.0; CHUNK], [0.0; CHUNK]);
    let mut out = BlockStep::default();
    for start in (0..n).step_by(CHUNK) {
        let r = start..n.min(start + CHUNK);
        let input = match drive {
            Drive::Constant(c) => Drive::Constant(c),
            Drive::PerNeuron(x) => Drive::PerNeuron(&x[r.clone()]),
        };
        let (v, u, spiked) = (&mut s.v[r.clone()], &mut s.u[r.clone()], &mut s.spiked[r]);
        // SAFETY: the caller checked the CPU.
        let spikes = unsafe { euler_chunk(v, u, spiked, &mut start_state, k, input) };
        let diverged = match spikes {
            0 => 0,
            _ => {
                let len = v.len();
                let (v_start, u_start) = (&start_state.0[..len], &start_state.1[..len]);
                diverged_spikes(k, spiked, v_start, u_start, &update, |j| input.at(j))
            }
        };
        out = out.add(BlockStep { spikes, diverged });
    }
    out
}

/// The fused Euler loop of one chunk of at most [`CHUNK`] neurons, in place: writes the spike
/// mask and, for the neurons that spike, their start state; returns the number of spikes.
#[target_feature(enable = "avx512f,avx512bw,avx512vl")]
fn euler_chunk(
    v: &mut [f64],
    u: &mut [f64],
    spiked: &mut [u8],
    (v_start, u_start): &mut ([f64; CHUNK], [f64; CHUNK]),
    k: &IzhikevichConstants<f64>,
    input: Drive<'_>,
) -> u64 {
    let n = v.len();
    assert!(u.len() == n && spiked.len() == n && n <= CHUNK);
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
    // SAFETY (every load and store): the lanes from `j` lie in the slices, all of length `n`
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

#[cfg(test)]
mod tests {
    use super::super::{IzhikevichModel, IzhikevichParams, step_block};
    use super::*;
    use crate::population::BlockModel;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    type Model = IzhikevichModel<f64>;

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|x| x.to_bits()).collect()
    }

    /// Steps two copies of a random block, by the portable fused loop and by the AVX-512
    /// loop, and asserts the same states, spike masks, spike counts and divergence counts
    /// after every step. The states range from rest to the peak, with a few far outside
    /// (which overflow or diverge), and the input is constant or per neuron.
    fn assert_same_steps(params: IzhikevichParams, len: usize, dt_s: f64, seed: u64) {
        let k = Model::constants(&params, dt_s);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let v0: Vec<f64> = (0..len)
            .map(|_| match rng.random_range(0..10) {
                0 => rng.random_range(-1e160..1e160),
                _ => rng.random_range(-80.0..35.0),
            })
            .collect();
        let mut portable = Model::new_block(&params, &k, &v0, false);
        for u in &mut portable.u {
            *u += rng.random_range(-5.0..5.0);
        }
        let mut wide = portable.clone();
        let input: Vec<f64> = (0..len).map(|_| rng.random_range(-20.0..60.0)).collect();
        let update = |v, u, i| advance_state(Integrator::Euler, &k, (v, u), i, k.h, k.u_decay);
        for step in 0..60 {
            let drive = match step % 3 {
                0 => Drive::Constant(12.0),
                1 => Drive::Constant(-1e200),
                _ => Drive::PerNeuron(&input),
            };
            let expected = step_block::<f64, false>(&mut portable, drive, &k, &update);
            // SAFETY: the caller checked the CPU.
            let got = unsafe { step_block_euler(&mut wide, &k, drive) };
            let at = format!("{len} neurons, dt {dt_s} s, step {step}");
            assert_eq!(got, expected, "{at}");
            assert_eq!(bits(&wide.v), bits(&portable.v), "{at}");
            assert_eq!(bits(&wide.u), bits(&portable.u), "{at}");
            assert_eq!(wide.spiked, portable.spiked, "{at}");
        }
    }

    #[test]
    fn the_avx512_euler_step_is_the_portable_step_bit_for_bit() {
        if !crate::avx512::available() {
            eprintln!("skipped: this CPU has no AVX-512F and BMI2");
            return;
        }
        let floored = IzhikevichParams {
            v_min: -90.0,
            ..IzhikevichParams::rs()
        };
        for len in [1, 7, 8, 9, 255, 256, 257, 700] {
            for dt_s in [1e-4, 1e-3] {
                assert_same_steps(IzhikevichParams::rs(), len, dt_s, len as u64);
                assert_same_steps(IzhikevichParams::fs(), len, dt_s, len as u64);
                assert_same_steps(floored, len, dt_s, len as u64);
            }
        }
    }
}
