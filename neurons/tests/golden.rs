//! Golden tests: neuron models against truths derived independently of the code under test.

use neurotac_core::{NeuronModel, SpikeBuffer};
use neurotac_neurons::{
    InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Population, Real,
};

/// Spike times of a one-neuron population under constant input.
fn spike_times(model: &mut dyn NeuronModel, current: f64, dt_s: f64, duration_s: f64) -> Vec<f64> {
    model.prepare(dt_s).unwrap();
    let input = vec![current; model.len()];
    let mut times = Vec::new();
    let mut spikes = SpikeBuffer::new();
    let steps = (duration_s / dt_s).round() as u64;
    for k in 0..steps {
        spikes.clear();
        model.step(&input, &mut spikes);
        times.extend(spikes.fractions().iter().map(|phi| (k as f64 + phi) * dt_s));
    }
    times
}

/// LIF from v = 0 under I > 1 (τ = 10 ms, threshold 1, reset 0): t_k = k·τ·ln(I/(I − 1)).
fn lif_period(current: f64) -> f64 {
    LifParams::default().closed_form_period_s(current).unwrap()
}

#[test]
fn lif_exact_on_the_grid_spikes_at_the_end_of_the_crossing_step() {
    let (current, dt) = (1.04, 1e-4);
    let mut lif = Lif::<f64>::new(1, LifParams::default());
    let times = spike_times(&mut lif, current, dt, 1.0);
    // Exact integration: v crosses 1 in step ⌈T/dt⌉ − 1 and is stamped at its end, ⌈T/dt⌉·dt;
    // the reset then happens on the grid, so every period is ⌈T/dt⌉ steps.
    let steps_per_period = (lif_period(current) / dt).ceil();
    assert_eq!(
        times.len(),
        (1.0 / (steps_per_period * dt)).floor() as usize
    );
    for (k, t) in times.iter().enumerate() {
        let expected = (k + 1) as f64 * steps_per_period * dt;
        assert!((t - expected).abs() < 1e-12, "spike {k}: {t} vs {expected}");
        // The stamp never precedes the true crossing and lags it by less than one step.
        let truth = (k + 1) as f64 * lif_period(current);
        assert!(*t >= truth - 1e-12 || k > 0);
    }
    assert!(times[0] >= lif_period(current) && times[0] < lif_period(current) + dt);
}

#[test]
fn lif_interpolated_spike_times_match_the_closed_form_at_second_order() {
    let current = 1.04;
    let max_error = |dt: f64| {
        let mut lif = Lif::<f64>::new(1, LifParams::default()).with_interpolation(true);
        let times = spike_times(&mut lif, current, dt, 1.0);
        assert_eq!(times.len(), 30, "closed form: ⌊1 s / 32.58 ms⌋ = 30 spikes");
        times
            .iter()
            .enumerate()
            .map(|(k, t)| (t - (k + 1) as f64 * lif_period(current)).abs())
            .fold(0.0, f64::max)
    };
    let (coarse, fine) = (max_error(2e-4), max_error(1e-4));
    // Each linear crossing is late by ≈ |v''|·dt²/(8·v') = 400·dt²/32 (5·10⁻⁷ s at 0.2 ms), and
    // the reset inherits it, so over 30 spikes the error grows to ≈ 30× that — still O(dt²).
    assert!(
        coarse < 30.0 * 400.0 * 2e-4f64.powi(2) / 32.0 * 1.2,
        "{coarse}"
    );
    let order = (coarse / fine).log2();
    assert!(
        (1.7..2.3).contains(&order),
        "interpolation order {order} ({coarse} → {fine})"
    );
}

#[test]
fn lif_trajectory_errors_shrink_at_each_integrators_order() {
    // Sub-threshold (I = 0.9 never reaches 1): v(t) = I·(1 − e^(−t/τ)) from v = 0.
    let v_at = |integrator: Integrator, dt: f64| {
        let mut lif = Lif::<f64>::new(1, LifParams::default()).with_integrator(integrator);
        lif.run_constant(0.9, dt, (0.02 / dt).round() as u64)
            .unwrap();
        (lif.potential(0) - 0.9 * (1.0 - (-2.0f64).exp())).abs()
    };
    for (integrator, order) in [
        (Integrator::Euler, 1.0),
        (Integrator::Rk2, 2.0),
        (Integrator::Rk4, 4.0),
    ] {
        let measured = (v_at(integrator, 1e-3) / v_at(integrator, 5e-4)).log2();
        assert!(
            (measured - order).abs() < 0.15,
            "{integrator}: order {measured}"
        );
    }
    assert!(v_at(Integrator::Exact, 1e-3) < 1e-15);
    assert!(v_at(Integrator::ExponentialEuler, 1e-3) < 1e-15);
}

fn izhikevich_reference() -> Vec<f64> {
    let mut rs = Izhikevich::<f64>::new(1, IzhikevichParams::rs())
        .with_integrator(Integrator::Rk4)
        .with_interpolation(true);
    spike_times(&mut rs, 10.0, 1e-6, 0.5)
}

#[test]
fn izhikevich_converges_to_a_fine_rk4_run() {
    let truth = izhikevich_reference();
    assert!(
        truth.len() >= 10,
        "RS at I = 10 fires tonically: {} spikes",
        truth.len()
    );
    for integrator in [
        Integrator::Izhikevich2003,
        Integrator::Euler,
        Integrator::Rk2,
        Integrator::Rk4,
        Integrator::ExponentialEuler,
    ] {
        let mean_error = |dt: f64| {
            let mut rs = Izhikevich::<f64>::new(1, IzhikevichParams::rs())
                .with_integrator(integrator)
                .with_interpolation(true);
            let times = spike_times(&mut rs, 10.0, dt, 0.5);
            assert_eq!(times.len(), truth.len(), "{integrator} at dt = {dt}");
            times
                .iter()
                .zip(&truth)
                .map(|(a, b)| (a - b).abs())
                .sum::<f64>()
                / truth.len() as f64
        };
        let errors: Vec<f64> = [1e-4, 5e-5, 2.5e-5]
            .iter()
            .map(|&dt| mean_error(dt))
            .collect();
        // The reset happens at the end of the step, so spike times converge at first order
        // whatever the integrator: a 4× finer step must give ≥ 3× smaller errors.
        assert!(errors[0] < 5e-3, "{integrator}: {errors:?}");
        assert!(
            errors[1] < errors[0] && errors[2] < errors[1],
            "{integrator}: {errors:?}"
        );
        assert!(errors[2] < errors[0] / 3.0, "{integrator}: {errors:?}");
    }
}

#[test]
fn izhikevich_trajectory_errors_shrink_at_each_integrators_order() {
    // Sub-threshold relaxation from v = −60 mV, I = 0 (−70 mV would already be RS's fixed
    // point), against a 1 µs RK4 run.
    let state_after = |integrator: Integrator, dt: f64| {
        let mut rs = Izhikevich::<f64>::new(1, IzhikevichParams::rs())
            .with_integrator(integrator)
            .with_initial_potential(InitialPotential::Constant(-60.0));
        rs.run_constant(0.0, dt, (0.02 / dt).round() as u64)
            .unwrap();
        rs.state_of(0).0
    };
    let truth = state_after(Integrator::Rk4, 1e-6);
    for (integrator, order) in [
        (Integrator::Euler, 1.0),
        (Integrator::Rk2, 2.0),
        (Integrator::Rk4, 4.0),
        (Integrator::Izhikevich2003, 1.0),
    ] {
        let e1 = (state_after(integrator, 4e-4) - truth).abs();
        let e2 = (state_after(integrator, 2e-4) - truth).abs();
        let measured = (e1 / e2).log2();
        assert!(
            (measured - order).abs() < 0.3,
            "{integrator}: order {measured} ({e1} → {e2})"
        );
    }
}

#[test]
fn izhikevich_presets_have_their_published_parameters_and_behaviour() {
    let p = IzhikevichParams::named("FS").unwrap();
    assert_eq!((p.a, p.b, p.c, p.d), (0.1, 0.2, -65.0, 2.0));
    assert_eq!(IzhikevichParams::named("tc").unwrap().d, 0.05);
    assert!(IzhikevichParams::named("xx").is_none());
    // Fast spiking fires faster than regular spiking under the same drive (Izhikevich 2003, Fig. 2).
    let rate = |p: IzhikevichParams| {
        let mut n = Izhikevich::<f64>::new(1, p);
        n.run_constant(10.0, 1e-4, 10_000).unwrap()
    };
    assert!(rate(IzhikevichParams::fs()) > 2 * rate(IzhikevichParams::rs()));
}

fn f32_and_f64_agree<M: NeuronModel>(
    make32: impl Fn() -> M,
    make64: impl Fn() -> Box<dyn NeuronModel>,
    current: f64,
) {
    let dt = 1e-4;
    let a = spike_times(&mut make32(), current, dt, 0.5);
    let b = spike_times(make64().as_mut(), current, dt, 0.5);
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= dt * 1.000001, "{x} vs {y}");
    }
}

#[test]
fn single_and_double_precision_agree_within_a_step() {
    f32_and_f64_agree(
        || Lif::<f32>::new(1, LifParams::default()),
        || Box::new(Lif::<f64>::new(1, LifParams::default())),
        1.04,
    );
    f32_and_f64_agree(
        || Izhikevich::<f32>::new(1, IzhikevichParams::rs()),
        || Box::new(Izhikevich::<f64>::new(1, IzhikevichParams::rs())),
        10.0,
    );
    assert_eq!((f32::NAME, f64::NAME), ("f32", "f64"));
}

#[test]
fn refractory_period_holds_the_reset_potential() {
    let params = LifParams {
        t_ref_s: 5e-3,
        ..LifParams::default()
    };
    let mut lif = Lif::<f64>::new(1, params);
    let times = spike_times(&mut lif, 1.04, 1e-4, 1.0);
    let steps_per_period = (lif_period(1.04) / 1e-4).ceil() + 50.0;
    for w in times.windows(2) {
        assert!(
            ((w[1] - w[0]) / 1e-4 - steps_per_period).abs() < 1e-6,
            "{:?}",
            w
        );
    }
}
