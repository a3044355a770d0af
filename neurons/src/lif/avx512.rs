//! The exact step of an f64 block under its synaptic currents in AVX-512 ([`crate::avx512`]):
//! the portable fused loop (`step_block_synaptic` with the exact update) on 8 neurons at a
//! time — the currents summed in projection order, decayed and flushed
//! ([`DecayingCurrents::take`]), the update `v·e^(−h) + v∞·(1 − e^(−h))`, the optional floor
//! and flush, refractory hold, threshold and reset — in the same order, so the same states,
//! currents and spikes bit for bit.

use super::{LifConstants, LifState, floor_and_flush_are_no_ops};
use crate::avx512::{LANES, ge, le, load, select, store, store_mask_bytes, tail_lanes};
use crate::integrate::Integrator;
use crate::population::{BlockStep, count_ones};
use neurotac_core::DecayingCurrents;
use neurotac_core::graph::FLUSH_TO_ZERO;
use std::arch::x86_64::*;

/// One exact step of the block `s` under `currents`, as the portable fused loop computes it.
///
/// # Safety
/// The CPU must have what [`crate::avx512::available`] checks.
pub(super) unsafe fn step_block_exact_synaptic<const N: usize>(
    s: &mut LifState<f64>,
    k: &LifConstants<f64>,
    currents: DecayingCurrents<'_, N>,
) -> BlockStep {
    let checked = !floor_and_flush_are_no_ops(k, Integrator::Exact, currents.bound());
    // SAFETY (each arm): the caller checked the CPU.
    let spikes = unsafe {
        match (k.refractory_steps > 0, checked) {
            (false, false) => exact_synaptic::<N, false, false>(s, k, currents),
            (true, false) => exact_synaptic::<N, true, false>(s, k, currents),
            (false, true) => exact_synaptic::<N, false, true>(s, k, currents),
            (true, true) => exact_synaptic::<N, true, true>(s, k, currents),
        }
    };
    BlockStep {
        spikes,
        diverged: 0,
    }
}

/// The fused loop; `CHECKED` keeps the floor and the subnormal flush. Returns the spikes.
#[target_feature(enable = "avx512f,avx512bw,avx512vl")]
fn exact_synaptic<const N: usize, const REFRACTORY: bool, const CHECKED: bool>(
    s: &mut LifState<f64>,
    k: &LifConstants<f64>,
    mut currents: DecayingCurrents<'_, N>,
) -> u64 {
    let n = s.v.len();
    let (currents, decays) = currents.parts_mut();
    assert!(currents.iter().all(|c| c.len() >= n) && s.spiked.len() == n);
    assert!(!REFRACTORY || s.refractory_steps.len() == n);
    let LifState {
        v,
        refractory_steps,
        spiked,
        ..
    } = s;
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

#[cfg(test)]
mod tests {
    use super::super::{LifModel, LifParams, advance_potential, step_block_synaptic};
    use super::*;
    use crate::population::BlockModel;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    type Model = LifModel<f64>;

    /// Random potentials around threshold (with some far off it) and currents that range from
    /// flushable to large, of both signs.
    fn random_block(k: &LifConstants<f64>, len: usize, rng: &mut ChaCha8Rng) -> LifState<f64> {
        let v0: Vec<f64> = (0..len)
            .map(|_| match rng.random_range(0..8) {
                0 => rng.random_range(-1e6..1e6),
                _ => k.v_th + rng.random_range(-20.0..2.0),
            })
            .collect();
        let mut s = Model::new_block(&LifParams::default(), k, &v0, false);
        for r in &mut s.refractory_steps {
            *r = f64::from(rng.random_range(-3..4));
        }
        s
    }

    fn random_currents(len: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
        (0..len)
            .map(|_| match rng.random_range(0..6) {
                0 => 0.0,
                1 => rng.random_range(-2e-30..2e-30),
                2 => rng.random_range(-1e3..1e3),
                _ => rng.random_range(-3.0..3.0),
            })
            .collect()
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|x| x.to_bits()).collect()
    }

    /// Steps two copies of a block, one by the portable fused loop and one by the AVX-512 loop,
    /// and asserts the same potentials, refractory counts, currents and spike masks after
    /// every step.
    fn assert_same_steps(params: LifParams, len: usize, bound: f64, seed: u64) {
        let k = Model::constants(&params, 1e-4);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut portable = random_block(&k, len, &mut rng);
        let mut wide = portable.clone();
        let mut currents = [
            random_currents(len, &mut rng),
            random_currents(len, &mut rng),
        ];
        let mut wide_currents = currents.clone();
        let decays = [0.9512, 0.9048];
        let update = |v, v_inf| advance_potential(Integrator::Exact, v, v_inf, k.h, k.decay);
        for step in 0..40 {
            let [a, b] = &mut currents;
            let drive = DecayingCurrents::new([a, b], decays, bound).unwrap();
            let expected = step_block_synaptic::<f64, 2, true>(&mut portable, &k, &update, drive);
            let [a, b] = &mut wide_currents;
            let drive = DecayingCurrents::new([a, b], decays, bound).unwrap();
            // SAFETY: the caller checked the CPU.
            let got = unsafe { step_block_exact_synaptic(&mut wide, &k, drive) };
            let at = format!("{params:?}, {len} neurons, step {step}");
            assert_eq!(got.spikes, expected.spikes, "{at}");
            assert_eq!(bits(&wide.v), bits(&portable.v), "{at}");
            assert_eq!(wide.refractory_steps, portable.refractory_steps, "{at}");
            assert_eq!(wide.spiked, portable.spiked, "{at}");
            assert_eq!(bits(&wide_currents[0]), bits(&currents[0]), "{at}");
            assert_eq!(bits(&wide_currents[1]), bits(&currents[1]), "{at}");
            // New input arrives between steps, as a projection delivers it.
            for c in currents.iter_mut().chain(wide_currents.iter_mut()) {
                c[step % len] += 1.5;
            }
        }
    }

    #[test]
    fn the_avx512_synaptic_step_is_the_portable_step_bit_for_bit() {
        if !crate::avx512::available() {
            eprintln!("skipped: this CPU has no AVX-512F and BMI2");
            return;
        }
        let floored = LifParams {
            v_min: -5.0,
            ..LifParams::default()
        };
        let refractory = LifParams {
            t_ref_s: 2e-4,
            ..LifParams::default()
        };
        for len in [1, 7, 8, 9, 64, 203] {
            // CUBA: no floor or flush (finite bound), and refractoriness.
            assert_same_steps(LifParams::cuba(), len, 1e4, len as u64);
            // The same neurons with the floor and flush kept (no bound known).
            assert_same_steps(LifParams::cuba(), len, f64::INFINITY, len as u64);
            assert_same_steps(LifParams::default(), len, f64::INFINITY, len as u64);
            assert_same_steps(floored, len, f64::INFINITY, len as u64);
            assert_same_steps(refractory, len, 1e4, len as u64);
        }
    }
}
