//! The fused synaptic step (`NeuronModel::step_synaptic`: the currents summed and decayed
//! inside the model's loop, and for CUBA-like LIF without the floor and flush it proves to be
//! no-ops) gives bit for bit what draining the currents and stepping gives.

use neurotac_core::graph::FLUSH_TO_ZERO;
use neurotac_core::{DecayingCurrents, NeuronModel, SpikeBuffer, SynapticDrive};
use neurotac_neurons::{
    InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Real,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Steps `fused` with `step_synaptic` and `plain` with drain + `step` under the same currents
/// (kicked at random every step), and checks spikes, states and currents agree bit for bit.
/// `two` feeds two projections; with `bounded` the drive declares the bound the kicks obey
/// (each current gets at most one kick per step, so `|I_p| ≤ |kick_p|/(1 − d_p)`), else none.
fn assert_fused_equals_plain(
    fused: &mut dyn NeuronModel,
    plain: &mut dyn NeuronModel,
    kicks: [f64; 2],
    two: bool,
    bounded: bool,
    steps: usize,
) {
    let n = fused.len();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (da, db) = ((-1e-4f64 / 5e-3).exp(), (-1e-4f64 / 10e-3).exp());
    let bound = if bounded {
        4.0 * (kicks[0].abs() / (1.0 - da) + kicks[1].abs() / (1.0 - db))
    } else {
        f64::INFINITY
    };
    let mut currents = [[vec![0.0; n], vec![0.0; n]], [vec![0.0; n], vec![0.0; n]]];
    let (mut input, mut scratch) = (vec![0.0; n], vec![0.0; n]);
    let (mut s_fused, mut s_plain) = (SpikeBuffer::new(), SpikeBuffer::new());
    let everyone: Vec<u32> = (0..n as u32).collect();
    let mut total = 0;
    for step in 0..steps {
        let [fused_currents, plain_currents] = &mut currents;
        for ((f, p), kick) in fused_currents.iter_mut().zip(plain_currents).zip(kicks) {
            for (f, p) in f.iter_mut().zip(p.iter_mut()) {
                if rng.random::<f64>() < 0.05 {
                    let w = kick * rng.random::<f64>();
                    *f += w;
                    *p += w;
                }
            }
        }
        let [[fa, fb], [pa, pb]] = &mut currents;
        s_fused.clear();
        s_plain.clear();
        if two {
            let d = DecayingCurrents::new([&mut fa[..], &mut fb[..]], [da, db], bound).unwrap();
            fused.step_synaptic(SynapticDrive::Two(d), &mut scratch, &mut s_fused);
        } else {
            let d = DecayingCurrents::new([&mut fa[..]], [da], bound).unwrap();
            fused.step_synaptic(SynapticDrive::One(d), &mut scratch, &mut s_fused);
        }
        // The network's unfused drain: the sum, then each current decayed and flushed.
        let decay = |c: f64, d: f64| {
            let c = c * d;
            if c.abs() < FLUSH_TO_ZERO { 0.0 } else { c }
        };
        for i in 0..n {
            input[i] = if two { pa[i] + pb[i] } else { pa[i] };
            pa[i] = decay(pa[i], da);
            if two {
                pb[i] = decay(pb[i], db);
            }
        }
        plain.step(&input, &mut s_plain);
        assert_eq!(s_fused, s_plain, "spikes of step {step}");
        total += s_fused.len();
        let (mut vf, mut vp) = (Vec::new(), Vec::new());
        fused.read_variable(0, &everyone, &mut vf);
        plain.read_variable(0, &everyone, &mut vp);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&vf), bits(&vp), "states after step {step}");
        let [f, p] = &currents;
        assert_eq!((bits(&f[0]), bits(&f[1])), (bits(&p[0]), bits(&p[1])));
    }
    assert_eq!(
        fused.check_divergence().is_ok(),
        plain.check_divergence().is_ok()
    );
    assert!(total > 0, "the case must spike to test anything");
}

/// CUBA's neurons (mV; threshold below 0: the fused loop may leave out floor and flush).
fn cuba_params() -> LifParams {
    LifParams::cuba()
}

fn lif<F: Real>(
    n: usize,
    params: LifParams,
    integrator: Integrator,
    interpolate: bool,
    initial: InitialPotential,
) -> Lif<F> {
    let mut p = Lif::<F>::new(n, params)
        .with_integrator(integrator)
        .with_interpolation(interpolate)
        .with_initial_potential(initial);
    p.prepare(1e-4).unwrap();
    p
}

fn check_lif<F: Real>(n: usize, params: LifParams, kicks: [f64; 2], initial: InitialPotential) {
    for integrator in [
        Integrator::Exact,
        Integrator::Euler,
        Integrator::Rk2,
        Integrator::Rk4,
    ] {
        for interpolate in [false, true] {
            for two in [false, true] {
                for bounded in [false, true] {
                    let make = || lif::<F>(n, params, integrator, interpolate, initial.clone());
                    let (mut fused, mut plain) = (make(), make());
                    assert_fused_equals_plain(&mut fused, &mut plain, kicks, two, bounded, 300);
                }
            }
        }
    }
}

#[test]
fn lif_fused_steps_equal_drain_and_step_in_f64_and_f32() {
    let spread = InitialPotential::Uniform {
        low: -60.0,
        high: -50.0,
        seed: 2,
    };
    check_lif::<f64>(97, cuba_params(), [40.0, -60.0], spread.clone());
    check_lif::<f32>(97, cuba_params(), [40.0, -60.0], spread);
    // The dimensionless convention (threshold 1, rest 0: the flush stays) and no refractory
    // period.
    let unit = LifParams::default();
    let near = InitialPotential::Uniform {
        low: -0.5,
        high: 1.0,
        seed: 3,
    };
    check_lif::<f64>(97, unit, [3.0, -1.0], near.clone());
    check_lif::<f32>(97, unit, [3.0, -1.0], near);
    // A finite floor.
    let floored = LifParams {
        v_min: -62.0,
        ..cuba_params()
    };
    check_lif::<f64>(
        97,
        floored,
        [40.0, -200.0],
        InitialPotential::Constant(-62.0),
    );
}

#[test]
fn lif_fused_steps_equal_drain_and_step_at_the_extremes() {
    // Potentials near the largest finite numbers, and currents that overflow to ±∞ (declared
    // unbounded): the checked loop runs and must agree with the unfused step.
    let huge = InitialPotential::Uniform {
        low: -1e38,
        high: 1e38,
        seed: 4,
    };
    check_lif::<f32>(64, cuba_params(), [1e38, -1e38], huge);
    let huge = InitialPotential::Uniform {
        low: -8e307,
        high: 8e307,
        seed: 5,
    };
    check_lif::<f64>(64, cuba_params(), [1.7e308, -1.7e308], huge.clone());
    // A bounded drive from extreme initial potentials: the loop without floor and flush.
    for integrator in [Integrator::Exact, Integrator::ExponentialEuler] {
        let make = || lif::<f64>(64, cuba_params(), integrator, false, huge.clone());
        let (mut fused, mut plain) = (make(), make());
        assert_fused_equals_plain(&mut fused, &mut plain, [1e3, -1e3], true, true, 300);
    }
}

#[test]
fn lif_fused_steps_split_blocks_as_the_plain_step_at_any_thread_count() {
    // 40 000 neurons: ten blocks, stepped in parallel on a pool of 2.
    let spread = InitialPotential::Uniform {
        low: -60.0,
        high: -50.0,
        seed: 6,
    };
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let make = || {
                lif::<f64>(
                    40_000,
                    cuba_params(),
                    Integrator::Exact,
                    false,
                    spread.clone(),
                )
            };
            let (mut fused, mut plain) = (make(), make());
            assert_fused_equals_plain(&mut fused, &mut plain, [40.0, -60.0], true, true, 20);
        });
    }
}

#[test]
fn izhikevich_takes_the_default_synaptic_step() {
    let make = || {
        let mut p = Izhikevich::<f64>::new(50, IzhikevichParams::rs());
        p.prepare(1e-4).unwrap();
        p
    };
    let (mut fused, mut plain) = (make(), make());
    assert_fused_equals_plain(&mut fused, &mut plain, [400.0, -100.0], true, false, 300);
}

#[test]
fn a_silent_lif_decays_to_exact_zero_under_the_fused_step() {
    // Threshold 1, rest 0: the flush is not a no-op, so the fused loop keeps it, and a
    // potential decaying towards 0 ends at exactly 0 rather than in the subnormal range.
    let mut lif = lif::<f64>(
        4,
        LifParams::default(),
        Integrator::Exact,
        false,
        InitialPotential::Constant(1e-300),
    );
    let mut currents = [vec![0.0; 4], vec![0.0; 4]];
    let (mut input, mut spikes) = (vec![0.0; 4], SpikeBuffer::new());
    for _ in 0..3000 {
        let [a, b] = &mut currents;
        let d = DecayingCurrents::new([&mut a[..], &mut b[..]], [0.9, 0.9], 0.0).unwrap();
        spikes.clear();
        lif.step_synaptic(SynapticDrive::Two(d), &mut input, &mut spikes);
    }
    assert!(spikes.is_empty());
    assert!(
        (0..4).all(|i| lif.potential(i).to_bits() == 0),
        "{}",
        lif.potential(0)
    );
}
