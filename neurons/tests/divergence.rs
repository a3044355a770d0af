//! Divergence: a numerical blow-up is a typed error naming the step, never firing.

use neurotac_core::{CurrentInput, GraphError, ModelError, NetworkBuilder, NetworkConfig};
use neurotac_neurons::{
    Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Population, Real,
};

fn izhikevich<F: Real>(integrator: Integrator) -> Izhikevich<F> {
    Izhikevich::new(1, IzhikevichParams::rs()).with_integrator(integrator)
}

/// The first diverged step of a one-second run, or `None` for a healthy run.
fn diverged_step(pop: &mut dyn Population, current: f64, dt_s: f64) -> Option<u64> {
    match pop.run_constant(current, dt_s, (1.0 / dt_s).round() as u64) {
        Ok(_) => None,
        Err(ModelError::Diverged { step, dt_s: dt, .. }) => {
            assert_eq!(dt, dt_s);
            Some(step)
        }
        Err(e) => panic!("unexpected error {e}"),
    }
}

#[test]
fn izhikevich_blow_ups_are_divergence_errors_not_spikes() {
    // `neurotac neuron --model izhikevich --current=-1e5`: one "spike" per step before.
    assert_eq!(
        diverged_step(
            &mut izhikevich::<f64>(Integrator::Izhikevich2003),
            -1e5,
            1e-4
        ),
        Some(0)
    );
    // Euler and RK4 at −10⁴.
    for integrator in [Integrator::Euler, Integrator::Rk4] {
        assert!(
            diverged_step(&mut izhikevich::<f64>(integrator), -1e4, 1e-4).is_some(),
            "{integrator}"
        );
    }
    // `--current 0 --dt 1e-2`: 99 spikes from a resting neuron before.
    for integrator in [
        Integrator::Izhikevich2003,
        Integrator::Euler,
        Integrator::ExponentialEuler,
    ] {
        assert!(
            diverged_step(&mut izhikevich::<f32>(integrator), 0.0, 1e-2).is_some(),
            "{integrator}"
        );
    }
    let e = izhikevich::<f64>(Integrator::Izhikevich2003)
        .run_constant(-1e5, 1e-4, 100)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("izhikevich diverged in step 0 (t = 0 s, dt = 0.0001 s, izhikevich2003")
            && e.contains("smaller dt or another integrator"),
        "{e}"
    );
}

#[test]
fn lif_overshoot_below_threshold_is_a_divergence() {
    // Euler at dt = 3τ under v∞ = 0.9 < v_th jumps from 0 to 2.7: a spike the model cannot fire.
    let mut lif = Lif::<f64>::new(1, LifParams::default()).with_integrator(Integrator::Euler);
    assert_eq!(diverged_step(&mut lif, 0.9, 3e-2), Some(0));
    // The exact step at the same dt is right: it never fires.
    let mut exact = Lif::<f64>::new(1, LifParams::default());
    assert_eq!(exact.run_constant(0.9, 3e-2, 100).unwrap(), 0);
    // Just past Euler's monotone range (dt = 1.5τ, still stable): 0 → 1.35 overshoots v∞ and
    // the threshold, and is caught; the checks are compiled out only where a step cannot do so.
    for precision_f32 in [false, true] {
        let pop: &mut dyn neurotac_neurons::Population = if precision_f32 {
            &mut Lif::<f32>::new(1, LifParams::default()).with_integrator(Integrator::Euler)
        } else {
            &mut Lif::<f64>::new(1, LifParams::default()).with_integrator(Integrator::Euler)
        };
        assert_eq!(diverged_step(pop, 0.9, 1.5e-2), Some(0));
    }
    // RK2 at 1.5τ moves monotonically (R = 1 − h + h²/2 = 0.625): healthy, never fires.
    let mut rk2 = Lif::<f64>::new(1, LifParams::default()).with_integrator(Integrator::Rk2);
    assert_eq!(rk2.run_constant(0.9, 1.5e-2, 100).unwrap(), 0);
}

#[test]
fn healthy_runs_are_never_flagged() {
    // The whole `tradeoff neurons` sweep: both models, every integrator, both precisions,
    // grid and interpolated times, 10 µs … 1 ms, at the benchmark currents.
    for dt in [1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3] {
        for interpolate in [false, true] {
            for integrator in [
                Integrator::Exact,
                Integrator::Euler,
                Integrator::Rk2,
                Integrator::Rk4,
            ] {
                let mut lif = Lif::<f32>::new(1, LifParams::default())
                    .with_integrator(integrator)
                    .with_interpolation(interpolate);
                assert_eq!(diverged_step(&mut lif, 1.04, dt), None, "{integrator} {dt}");
            }
            for integrator in [
                Integrator::Izhikevich2003,
                Integrator::Euler,
                Integrator::ExponentialEuler,
                Integrator::Rk2,
                Integrator::Rk4,
            ] {
                // Every preset at the usual steps; RS (the sweep's model) at every step. (FS under
                // RK4 at 1 ms in f32 does diverge: one overshooting step turns u from −8.6 into 210.)
                for preset in ["rs", "ib", "ch", "fs", "lts", "tc", "rz"] {
                    if preset != "rs" && dt > 1e-4 {
                        continue;
                    }
                    let params = IzhikevichParams::named(preset).unwrap();
                    for current in [0.0, 10.0] {
                        let what = format!("{preset} {integrator} {dt} {current}");
                        let mut z32 = Izhikevich::<f32>::new(1, params)
                            .with_integrator(integrator)
                            .with_interpolation(interpolate);
                        let mut z64 = Izhikevich::<f64>::new(1, params)
                            .with_integrator(integrator)
                            .with_interpolation(interpolate);
                        assert_eq!(diverged_step(&mut z32, current, dt), None, "{what}");
                        assert_eq!(diverged_step(&mut z64, current, dt), None, "{what}");
                    }
                }
            }
        }
    }
    // A drive strong enough to fire every step is firing, not divergence (Euler: u grows by d
    // per spike, as it should); −10⁶ at 1 µs is stable and silent.
    let mut strong = izhikevich::<f64>(Integrator::Euler);
    assert_eq!(strong.run_constant(1e6, 1e-4, 1000).unwrap(), 1000);
    for integrator in [
        Integrator::Izhikevich2003,
        Integrator::Euler,
        Integrator::Rk4,
    ] {
        let mut stable = izhikevich::<f64>(integrator);
        assert_eq!(stable.run_constant(-1e6, 1e-6, 5000).unwrap(), 0);
    }
    // RK4 integrates through the spike's singularity at +10⁶: u grows 6.8·10⁶, 7.5·10⁹, 2·10²²,
    // 10⁷² in four steps — flagged from the first step that fires from the reset against it.
    assert_eq!(
        diverged_step(&mut izhikevich::<f64>(Integrator::Rk4), 1e6, 1e-4),
        Some(1)
    );
}

#[test]
fn networks_report_divergence_as_a_model_error() {
    let mut b = NetworkBuilder::new();
    let pop = b
        .add_population("izh", Izhikevich::<f32>::new(3, IzhikevichParams::rs()))
        .unwrap();
    let drive = b
        .add_current_input("drive", CurrentInput::constant(-1e5))
        .unwrap();
    b.inject(drive, pop).unwrap();
    let _spikes = b.record_spikes(pop).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: 1e-4 }).unwrap();
    match net.run(1.0, &neurotac_core::OneProcess) {
        Err(GraphError::Model {
            population,
            source: ModelError::Diverged { step: 0, .. },
        }) => assert_eq!(population, "izh"),
        other => panic!("expected a divergence, got {other:?}"),
    }
    // The check runs once per 256 steps: the run stopped at the first check, not at 1 s.
    assert_eq!(net.steps_done(), 256);
}
