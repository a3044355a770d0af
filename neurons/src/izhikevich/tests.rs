//! The AVX-512 Euler loop against the portable one.

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
        let got = unsafe { step_block_euler_avx512(&mut wide, &k, drive) };
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
