//! Stability at the extremes: time steps, huge currents, long silences, blow-ups, bad values,
//! empty populations, and determinism across block layouts and thread counts.

use neurotac_core::{ModelError, NeuronModel, SpikeBuffer};
use neurotac_neurons::{
    InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Population,
};

const LIF_INTEGRATORS: [Integrator; 5] = [
    Integrator::Exact,
    Integrator::ExponentialEuler,
    Integrator::Euler,
    Integrator::Rk2,
    Integrator::Rk4,
];
const IZH_INTEGRATORS: [Integrator; 5] = [
    Integrator::Izhikevich2003,
    Integrator::ExponentialEuler,
    Integrator::Euler,
    Integrator::Rk2,
    Integrator::Rk4,
];

fn lif(integrator: Integrator) -> Lif<f32> {
    Lif::new(4, LifParams::default()).with_integrator(integrator)
}

fn izh(integrator: Integrator) -> Izhikevich<f32> {
    Izhikevich::new(4, IzhikevichParams::rs()).with_integrator(integrator)
}

fn all_finite(model: &dyn NeuronModel) -> bool {
    let mut values = Vec::new();
    for var in 0..model.variables().len() {
        model.read_variable(var, &[0, 1, 2, 3], &mut values);
    }
    values.iter().all(|x| x.is_finite())
}

/// Runs `steps` steps of `current` through `model`, checking the state after every step.
fn run_checked(model: &mut dyn NeuronModel, current: f64, dt_s: f64, steps: u64) -> usize {
    model.prepare(dt_s).unwrap();
    let input = vec![current; model.len()];
    let mut spikes = SpikeBuffer::new();
    let mut total = 0;
    for k in 0..steps {
        spikes.clear();
        model.step(&input, &mut spikes);
        total += spikes.len();
        assert!(
            all_finite(model),
            "{} non-finite after step {k} (dt {dt_s}, I {current})",
            model.model_name()
        );
    }
    total
}

#[test]
fn every_integrator_is_finite_for_dt_from_a_microsecond_to_ten_milliseconds() {
    for dt in [1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
        let steps = ((0.05 / dt) as u64).clamp(5, 20_000);
        for i in LIF_INTEGRATORS {
            run_checked(&mut lif(i), 1.5, dt, steps);
        }
        for i in IZH_INTEGRATORS {
            run_checked(&mut izh(i), 10.0, dt, steps);
        }
    }
    // Exact LIF stays exact at any dt: period ⌈τ·ln 3 / dt⌉ steps (11 ms → 2 steps at 10 ms).
    let mut exact = Lif::<f64>::new(1, LifParams::default());
    assert_eq!(exact.run_constant(1.5, 1e-2, 100).unwrap(), 50);
}

#[test]
fn currents_of_a_million_either_way_stay_finite() {
    for i in LIF_INTEGRATORS {
        // +10⁶: v∞ far above threshold, a spike every step; −10⁶: never.
        assert_eq!(run_checked(&mut lif(i), 1e6, 1e-4, 200), 4 * 200, "{i}");
        assert_eq!(run_checked(&mut lif(i), -1e6, 1e-4, 200), 0, "{i}");
    }
    for i in IZH_INTEGRATORS {
        assert!(run_checked(&mut izh(i), 1e6, 1e-4, 200) >= 4 * 100, "{i}");
        // −10⁶ makes the model stiff (∂v'/∂v = 0.08·v + 5 ≈ −400/ms near v ≈ −5 000 mV): at 0.1 ms
        // explicit steps oscillate (finite, spurious spikes); at 1 µs they are stable and right.
        run_checked(&mut izh(i), -1e6, 1e-4, 200);
        let mut stable = izh(i);
        assert_eq!(run_checked(&mut stable, -1e6, 1e-6, 5_000), 0, "{i}");
        assert!(
            stable.state_of(0).0 < -1_000.0,
            "{i}: {:?}",
            stable.state_of(0)
        );
    }
}

#[test]
fn a_long_silence_never_leaves_subnormal_potentials() {
    for i in LIF_INTEGRATORS {
        let mut n = Lif::<f32>::new(1, LifParams::default())
            .with_integrator(i)
            .with_initial_potential(InitialPotential::Constant(0.9));
        n.prepare(1e-4).unwrap();
        let mut spikes = SpikeBuffer::new();
        // v decays by e^(−0.01) per step: through the subnormal range after ~9 000 steps.
        for step in 0..40_000 {
            n.step(&[0.0], &mut spikes);
            let v = n.potential(0) as f32;
            assert!(
                v == 0.0 || v.is_normal(),
                "{i}: subnormal {v:e} at step {step}"
            );
        }
        assert_eq!(n.potential(0), 0.0, "{i}");
    }
}

#[test]
fn izhikevich_euler_blow_up_is_clamped_at_the_peak() {
    // dt = 10 ms under Euler overshoots wildly: v is clamped at the peak (a spike), never ∞/NaN.
    let mut n =
        Izhikevich::<f32>::new(1, IzhikevichParams::rs()).with_integrator(Integrator::Euler);
    n.prepare(1e-2).unwrap();
    let mut spikes = SpikeBuffer::new();
    let mut total = 0;
    for _ in 0..1000 {
        spikes.clear();
        n.step(&[40.0], &mut spikes);
        total += spikes.len();
        let (v, u) = n.state_of(0);
        assert!(v.is_finite() && u.is_finite() && v <= 30.0, "v {v}, u {u}");
    }
    assert!(total > 0);
    // A NaN produced inside a step (∞ − ∞ in a stage) becomes a clamped spike, not a NaN state.
    let mut huge = Izhikevich::<f32>::new(1, IzhikevichParams::rs())
        .with_integrator(Integrator::Rk4)
        .with_initial_potential(InitialPotential::Constant(-1e18));
    huge.prepare(1e-2).unwrap();
    for _ in 0..10 {
        huge.step(&[-1e6], &mut spikes);
        let (v, u) = huge.state_of(0);
        assert!(v.is_finite() && u.is_finite(), "v {v}, u {u}");
    }
}

#[test]
fn non_finite_parameters_and_inputs_are_typed_errors() {
    let bad_lif = [
        LifParams {
            tau_m_s: f64::NAN,
            ..LifParams::default()
        },
        LifParams {
            tau_m_s: 0.0,
            ..LifParams::default()
        },
        LifParams {
            v_th: f64::INFINITY,
            ..LifParams::default()
        },
        LifParams {
            v_reset: 1.0,
            ..LifParams::default()
        },
        LifParams {
            t_ref_s: -1e-3,
            ..LifParams::default()
        },
        LifParams {
            v_min: f64::NAN,
            ..LifParams::default()
        },
    ];
    for p in bad_lif {
        let e = Lif::<f64>::new(1, p).prepare(1e-4).unwrap_err();
        assert!(
            matches!(e, ModelError::InvalidParameter { model: "lif", .. }),
            "{e}"
        );
    }
    let bad_izh = [
        IzhikevichParams {
            a: f64::NAN,
            ..IzhikevichParams::rs()
        },
        IzhikevichParams {
            d: f64::NEG_INFINITY,
            ..IzhikevichParams::rs()
        },
        IzhikevichParams {
            c: 40.0,
            ..IzhikevichParams::rs()
        },
    ];
    for p in bad_izh {
        let e = Izhikevich::<f64>::new(1, p).prepare(1e-4).unwrap_err();
        assert!(
            matches!(
                e,
                ModelError::InvalidParameter {
                    model: "izhikevich",
                    ..
                }
            ),
            "{e}"
        );
    }
    for dt in [0.0, -1e-4, f64::NAN, f64::INFINITY] {
        assert!(
            Lif::<f64>::new(1, LifParams::default())
                .prepare(dt)
                .is_err()
        );
        assert!(
            Izhikevich::<f64>::new(1, IzhikevichParams::rs())
                .prepare(dt)
                .is_err()
        );
    }
    let init = InitialPotential::Values(vec![0.0, f64::NAN]);
    assert!(
        Lif::<f64>::new(2, LifParams::default())
            .with_initial_potential(init)
            .prepare(1e-4)
            .is_err()
    );
    let short = InitialPotential::Values(vec![0.0]);
    assert!(
        Lif::<f64>::new(2, LifParams::default())
            .with_initial_potential(short)
            .prepare(1e-4)
            .is_err()
    );

    let mut n = Lif::<f64>::new(3, LifParams::default());
    n.prepare(1e-4).unwrap();
    let mut spikes = SpikeBuffer::new();
    let e = n
        .step_checked(&[0.0, f64::NAN, 0.0], &mut spikes)
        .unwrap_err();
    assert!(
        matches!(e, ModelError::NonFiniteInput { model: "lif", neuron: 1, value } if value.is_nan()),
        "{e}"
    );
    assert!(n.step_checked(&[0.0; 2], &mut spikes).is_err());
    assert!(n.run_constant(f64::INFINITY, 1e-4, 10).is_err());
    let mut z = Izhikevich::<f64>::new(1, IzhikevichParams::rs());
    z.prepare(1e-4).unwrap();
    assert!(z.step_checked(&[f64::NEG_INFINITY], &mut spikes).is_err());
    assert!(
        all_finite_lif(&n),
        "a rejected input must leave the state untouched"
    );
}

fn all_finite_lif(n: &Lif<f64>) -> bool {
    (0..3).all(|i| n.potential(i).is_finite())
}

#[test]
fn unsupported_integrators_are_build_time_errors_naming_model_and_integrator() {
    let e = Lif::<f32>::new(1, LifParams::default())
        .with_integrator(Integrator::Izhikevich2003)
        .prepare(1e-4)
        .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("lif does not support the izhikevich2003 integrator"),
        "{e}"
    );
    let e = Izhikevich::<f32>::new(1, IzhikevichParams::rs())
        .with_integrator(Integrator::Exact)
        .prepare(1e-4)
        .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("izhikevich does not support the exact integrator"),
        "{e}"
    );
}

#[test]
fn empty_populations_run() {
    let mut l = Lif::<f32>::new(0, LifParams::default());
    assert_eq!(l.run_constant(2.0, 1e-4, 100).unwrap(), 0);
    let mut z = Izhikevich::<f64>::new(0, IzhikevichParams::rs());
    z.prepare(1e-4).unwrap();
    let mut spikes = SpikeBuffer::new();
    z.step(&[], &mut spikes);
    assert!(spikes.is_empty() && z.is_empty());
}

/// Per-neuron currents and initial potentials, different for every neuron.
fn inputs(n: usize) -> (Vec<f64>, Vec<f64>) {
    (
        (0..n).map(|i| 0.5 + (i % 97) as f64 / 40.0).collect(),
        (0..n).map(|i| (i % 13) as f64 / 13.0).collect(),
    )
}

fn lif_trace(n: usize, steps: usize, threads: usize) -> (Vec<(u32, f64)>, Vec<f64>) {
    let (current, v0) = inputs(n);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut pop = Lif::<f32>::new(n, LifParams::default())
            .with_integrator(Integrator::Rk2)
            .with_interpolation(true)
            .with_initial_potential(InitialPotential::Values(v0));
        pop.prepare(1e-4).unwrap();
        let mut spikes = SpikeBuffer::new();
        let mut all = Vec::new();
        for k in 0..steps {
            spikes.clear();
            pop.step(&current, &mut spikes);
            all.extend(
                spikes
                    .indices()
                    .iter()
                    .zip(spikes.fractions())
                    .map(|(&i, &f)| (i, k as f64 + f)),
            );
        }
        (all, (0..n).map(|i| pop.potential(i)).collect())
    })
}

#[test]
fn results_are_bit_identical_at_any_thread_count() {
    // 100 000 neurons: above the parallel threshold, so blocks really run on several threads.
    let one = lif_trace(100_000, 30, 1);
    let two = lif_trace(100_000, 30, 2);
    let three = lif_trace(100_000, 30, 3);
    assert!(!one.0.is_empty());
    assert!(one == two && two == three);
}

#[test]
fn the_block_step_equals_the_single_neuron_step() {
    // 5 000 neurons span two blocks; each must evolve exactly as a population of one.
    let n = 5_000;
    let (all_spikes, all_v) = lif_trace(n, 40, 1);
    let (current, v0) = inputs(n);
    for i in (0..n).step_by(331) {
        let mut single = Lif::<f32>::new(1, LifParams::default())
            .with_integrator(Integrator::Rk2)
            .with_interpolation(true)
            .with_initial_potential(InitialPotential::Values(vec![v0[i]]));
        single.prepare(1e-4).unwrap();
        let mut spikes = SpikeBuffer::new();
        let mut mine = Vec::new();
        for k in 0..40 {
            spikes.clear();
            single.step(&[current[i]], &mut spikes);
            mine.extend(spikes.fractions().iter().map(|f| (i as u32, k as f64 + f)));
        }
        let theirs: Vec<(u32, f64)> = all_spikes
            .iter()
            .filter(|s| s.0 == i as u32)
            .copied()
            .collect();
        assert_eq!(mine, theirs, "neuron {i}");
        assert_eq!(single.potential(0), all_v[i], "neuron {i}");
    }
}
