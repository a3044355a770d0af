//! The AVX-512 synaptic loop against the portable one.

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
        let got = unsafe { step_block_exact_synaptic_avx512(&mut wide, &k, drive) };
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
