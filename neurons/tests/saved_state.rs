//! Saved populations: a population made anew from its description
//! ([`BuiltinModels`]), prepared and given the saved state continues bit for bit as the
//! original — LIF and Izhikevich, f32 and f64, every integrator, clock-driven (with and without
//! interpolation) and event-driven with its bookkeeping mid-run; states that do not fit and
//! descriptions that name no built-in model or carry bad settings are typed errors.

use neurotac_core::{ModelError, ModelFactory, ModelState, NeuronModel, SpikeBuffer};
use neurotac_neurons::{
    BuiltinModels, InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Real,
};
use rand::SeedableRng;
use serde_json::json;

mod common;
use common::push_poisson;

const DT: f64 = 1e-4;
const N: usize = 40;
const LIF_INTEGRATORS: [Integrator; 5] = [
    Integrator::Exact,
    Integrator::ExponentialEuler,
    Integrator::Euler,
    Integrator::Rk2,
    Integrator::Rk4,
];
const IZHIKEVICH_INTEGRATORS: [Integrator; 5] = [
    Integrator::Izhikevich2003,
    Integrator::Euler,
    Integrator::ExponentialEuler,
    Integrator::Rk2,
    Integrator::Rk4,
];

/// The inputs of one step: the neurons with input (ascending) and their inputs.
type StepInput = (Vec<u32>, Vec<f64>);

/// `steps` steps of input: each neuron but every fourth (silent) gets `weight` per spike of
/// its own Poisson train at `rate_hz` (seeded) in the step, nothing otherwise.
fn poisson_inputs(steps: usize, rate_hz: f64, weight: f64, seed: u64) -> Vec<StepInput> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut out = vec![(Vec::new(), Vec::new()); steps];
    for i in (0..N as u32).filter(|i| i % 4 != 0) {
        let mut train = Vec::new();
        push_poisson(&mut train, &mut rng, rate_hz, 0.0, steps as f64 * DT);
        for t in train {
            let (active, inputs): &mut StepInput = &mut out[((t / DT) as usize).min(steps - 1)];
            if active.last() == Some(&i) {
                *inputs.last_mut().unwrap() += weight;
            } else {
                active.push(i);
                inputs.push(weight);
            }
        }
    }
    out
}

fn lif<F: Real>(integrator: Integrator, interpolate: bool) -> Box<dyn NeuronModel> {
    let params = LifParams {
        t_ref_s: 2e-3,
        ..LifParams::default()
    };
    let initial = InitialPotential::Uniform {
        low: 0.0,
        high: 0.9,
        seed: 3,
    };
    Box::new(
        Lif::<F>::new(N, params)
            .with_integrator(integrator)
            .with_interpolation(interpolate)
            .with_initial_potential(initial),
    )
}

/// Regular spiking, held once within 10⁻³ mV of rest (event-driven), half the neurons
/// starting at rest and half above it.
fn izhikevich<F: Real>(integrator: Integrator, interpolate: bool) -> Box<dyn NeuronModel> {
    let params = IzhikevichParams {
        rest_tolerance: 1e-3,
        ..IzhikevichParams::rs()
    };
    let rest = params.resting_potential().unwrap();
    let v0 = (0..N).map(|i| {
        if i % 2 == 0 {
            rest
        } else {
            -72.0 + 0.3 * i as f64
        }
    });
    Box::new(
        Izhikevich::<F>::new(N, params)
            .with_integrator(integrator)
            .with_interpolation(interpolate)
            .with_initial_potential(InitialPotential::Values(v0.collect())),
    )
}

/// Every model set-up of the test, with the input weight that makes it fire.
fn setups(interpolate: bool) -> Vec<(Box<dyn NeuronModel>, f64)> {
    let mut out = Vec::new();
    for integrator in LIF_INTEGRATORS {
        out.push((lif::<f32>(integrator, interpolate), 60.0));
        out.push((lif::<f64>(integrator, interpolate), 60.0));
    }
    for integrator in IZHIKEVICH_INTEGRATORS {
        out.push((izhikevich::<f32>(integrator, interpolate), 150.0));
        out.push((izhikevich::<f64>(integrator, interpolate), 150.0));
    }
    out
}

/// Every variable of every neuron, as bits.
fn state_bits(model: &dyn NeuronModel) -> Vec<u64> {
    let all: Vec<u32> = (0..model.len() as u32).collect();
    let mut values = Vec::new();
    for var in 0..model.variables().len() {
        model.read_variable(var, &all, &mut values);
    }
    values.iter().map(|x| x.to_bits()).collect()
}

/// A saved state with its numbers as bits (so `-0.0 ≠ 0.0`).
fn saved_bits(model: &dyn NeuronModel) -> String {
    let state = model.save_state().expect("a prepared population saves");
    let arrays: Vec<_> = (state.arrays.iter())
        .map(|(name, a)| (name, a.iter().map(|x| x.to_bits()).collect::<Vec<_>>()))
        .collect();
    format!("{:?} {arrays:?} {:?}", state.counters, state.indices)
}

/// One step of `model` under `input`: event-driven (`step_active`) or clock-driven (`step`).
fn step(
    model: &mut dyn NeuronModel,
    input: &StepInput,
    event_driven: bool,
    spikes: &mut SpikeBuffer,
) {
    spikes.clear();
    let (active, inputs) = input;
    if event_driven {
        model.step_active(active, inputs, spikes);
    } else {
        let mut dense = vec![0.0; model.len()];
        active
            .iter()
            .zip(inputs)
            .for_each(|(&i, &x)| dense[i as usize] = x);
        model.step(&dense, spikes);
    }
}

/// Runs `original` for `before` of the `inputs`, saves it, makes it anew from its description,
/// prepares and restores that; then runs both over the rest: their spikes (indices and
/// fractions) at every step, their variables and their saved states must be equal bit for bit.
/// Returns the state saved mid-run.
fn continues_bit_for_bit(
    mut original: Box<dyn NeuronModel>,
    inputs: &[StepInput],
    before: usize,
    event_driven: bool,
) -> ModelState {
    let what = format!("{:?}", original.describe().map(|d| d.settings));
    original.prepare(DT).unwrap();
    assert!(original.event_driven() || !event_driven, "{what}");
    let (mut a, mut b) = (SpikeBuffer::new(), SpikeBuffer::new());
    let mut spikes_before = 0;
    for input in &inputs[..before] {
        step(original.as_mut(), input, event_driven, &mut a);
        spikes_before += a.len();
    }
    let saved = original.save_state().expect("a prepared population saves");
    let mut copy = BuiltinModels
        .make(&original.describe().expect("describable"))
        .unwrap();
    copy.prepare(DT).unwrap();
    copy.restore_state(&saved).unwrap();
    assert_eq!(
        state_bits(copy.as_ref()),
        state_bits(original.as_ref()),
        "{what}"
    );
    assert_eq!(
        saved_bits(copy.as_ref()),
        saved_bits(original.as_ref()),
        "{what}"
    );
    let mut spikes_after = 0;
    for (k, input) in inputs.iter().enumerate().skip(before) {
        step(original.as_mut(), input, event_driven, &mut a);
        step(copy.as_mut(), input, event_driven, &mut b);
        assert_eq!(a.indices(), b.indices(), "step {k}: {what}");
        let fractions = |s: &SpikeBuffer| {
            s.fractions()
                .iter()
                .map(|f| f.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(fractions(&a), fractions(&b), "step {k}: {what}");
        spikes_after += a.len();
    }
    assert!(
        spikes_before > 0 && spikes_after > 0,
        "the run must spike: {what}"
    );
    assert_eq!(
        saved_bits(copy.as_ref()),
        saved_bits(original.as_ref()),
        "{what}"
    );
    original.settle();
    copy.settle();
    assert_eq!(
        state_bits(copy.as_ref()),
        state_bits(original.as_ref()),
        "{what}"
    );
    saved
}

#[test]
fn restored_populations_continue_clock_driven_bit_for_bit() {
    let inputs_for = |weight| poisson_inputs(600, 300.0, weight, 11);
    for interpolate in [false, true] {
        for (model, weight) in setups(interpolate) {
            continues_bit_for_bit(model, &inputs_for(weight), 250, false);
        }
    }
}

#[test]
fn restored_populations_continue_event_driven_bit_for_bit_from_their_bookkeeping() {
    let inputs_for = |weight| poisson_inputs(600, 300.0, weight, 12);
    for (model, weight) in setups(false) {
        let izhikevich = model.model_name() == "izhikevich";
        let saved = continues_bit_for_bit(model, &inputs_for(weight), 250, true);
        // The state was saved mid-run, as it was: neurons left behind by event-driven stepping,
        // and Izhikevich neurons still settling after their input.
        let current_to = saved.index_list("test", "current_to", Some(N)).unwrap();
        assert!(
            current_to.iter().any(|&t| t < 250),
            "none behind: {current_to:?}"
        );
        let restless = saved.index_list("test", "restless", None).unwrap();
        assert_eq!(!restless.is_empty(), izhikevich, "restless {restless:?}");
    }
}

#[test]
fn a_restored_population_reports_the_divergence_of_the_saved_one() {
    // Izhikevich under Euler at 10 ms steps oscillates into spurious spikes at input 0.
    let mut original =
        Izhikevich::<f64>::new(3, IzhikevichParams::rs()).with_integrator(Integrator::Euler);
    original.prepare(1e-2).unwrap();
    let mut spikes = SpikeBuffer::new();
    for _ in 0..50 {
        spikes.clear();
        original.step(&[0.0; 3], &mut spikes);
    }
    let diverged = original.check_divergence().unwrap_err();
    let mut copy = BuiltinModels.make(&original.describe().unwrap()).unwrap();
    copy.prepare(1e-2).unwrap();
    assert!(copy.check_divergence().is_ok());
    copy.restore_state(&original.save_state().unwrap()).unwrap();
    assert_eq!(copy.check_divergence().unwrap_err(), diverged);
}

/// A LIF population (f32, 2 ms refractory period) after 200 event-driven steps.
fn stepped_lif() -> Box<dyn NeuronModel> {
    let mut model = lif::<f32>(Integrator::Exact, false);
    model.prepare(DT).unwrap();
    let mut spikes = SpikeBuffer::new();
    for input in &poisson_inputs(200, 300.0, 60.0, 13) {
        step(model.as_mut(), input, true, &mut spikes);
    }
    model
}

#[test]
fn states_that_do_not_fit_are_refused_and_leave_the_population_as_it_was() {
    let good = stepped_lif().save_state().unwrap();
    let steps = good.counter("test", "steps").unwrap();
    let edit_array = |name: &str, f: &dyn Fn(&mut Vec<f64>)| {
        let mut s = good.clone();
        f(&mut s.arrays.iter_mut().find(|(n, _)| n == name).unwrap().1);
        s
    };
    let edit_index = |name: &str, f: &dyn Fn(&mut Vec<u64>)| {
        let mut s = good.clone();
        f(&mut s.indices.iter_mut().find(|(n, _)| n == name).unwrap().1);
        s
    };
    let without_v = {
        let mut s = good.clone();
        s.arrays.retain(|(n, _)| n != "v");
        s
    };
    let without_steps = {
        let mut s = good.clone();
        s.counters.retain(|(n, _)| n != "steps");
        s
    };
    let late_divergence = {
        let mut s = good.clone();
        s.counters
            .iter_mut()
            .find(|(n, _)| n == "diverged_at")
            .unwrap()
            .1 = steps + 1;
        s
    };
    let far_steps = {
        let mut s = good.clone();
        s.counters.iter_mut().find(|(n, _)| n == "steps").unwrap().1 = u64::MAX;
        s
    };
    let cases: Vec<(&str, ModelState)> = vec![
        ("'steps' is 18446744073709551615, beyond", far_steps),
        ("'v'", without_v),
        ("'steps'", without_steps),
        ("'v' holds 41 values", edit_array("v", &|v| v.push(0.5))),
        (
            "'refractory_steps' holds 39",
            edit_array("refractory_steps", &|v| {
                v.pop();
            }),
        ),
        ("representable", edit_array("v", &|v| v[3] = 0.1)),
        ("'v'[2] = NaN", edit_array("v", &|v| v[2] = f64::NAN)),
        (
            "refractory period",
            edit_array("refractory_steps", &|v| v[0] = 21.0),
        ),
        (
            "refractory period",
            edit_array("refractory_steps", &|v| v[0] = 1.5),
        ),
        ("dt", edit_array("dt_s", &|v| v[0] = 2e-4)),
        ("'diverged_at'", late_divergence),
        (
            "'current_to'[5]",
            edit_index("current_to", &|v| v[5] = steps + 1),
        ),
        (
            "'current_to' holds 39",
            edit_index("current_to", &|v| {
                v.pop();
            }),
        ),
        (
            "'restless'[0] = 40",
            edit_index("restless", &|v| v.push(40)),
        ),
        (
            "'restless'[1] = 3",
            edit_index("restless", &|v| v.extend([3, 3])),
        ),
    ];
    for (needle, state) in cases {
        let mut model = stepped_lif();
        let before = saved_bits(model.as_ref());
        let err = model.restore_state(&state).unwrap_err();
        assert!(
            matches!(err, ModelError::State { model: "lif", .. })
                && err.to_string().contains(needle),
            "{needle}: {err}"
        );
        assert_eq!(saved_bits(model.as_ref()), before, "{needle}");
    }
    // The good state fits, and an unprepared population refuses any.
    stepped_lif().restore_state(&good).unwrap();
    let mut unprepared = lif::<f32>(Integrator::Exact, false);
    let err = unprepared.restore_state(&good).unwrap_err();
    assert!(err.to_string().contains("not prepared"), "{err}");
    assert_eq!(unprepared.save_state(), None);
}

#[test]
fn descriptions_make_the_population_they_describe() {
    let initials = [
        InitialPotential::Constant(0.25),
        InitialPotential::Uniform {
            low: 0.0,
            high: 0.9,
            seed: u64::MAX,
        },
        InitialPotential::Values((0..N).map(|i| 0.1 + i as f64 / 97.0).collect()),
    ];
    let lif_params = [
        LifParams::default(),
        LifParams {
            v_min: -70.0,
            t_ref_s: 1.3e-3,
            tau_m_s: 0.0123456789,
            ..LifParams::cuba()
        },
    ];
    let mut models: Vec<Box<dyn NeuronModel>> = Vec::new();
    for initial in &initials {
        for params in lif_params {
            models.push(Box::new(
                Lif::<f32>::new(N, params).with_initial_potential(initial.clone()),
            ));
        }
        models.push(Box::new(
            Izhikevich::<f64>::new(N, IzhikevichParams::lts())
                .with_initial_potential(initial.clone())
                .with_interpolation(true),
        ));
    }
    models.extend(setups(true).into_iter().map(|(m, _)| m));
    for model in models {
        let description = model.describe().unwrap();
        // Through JSON text, as a saved network holds it.
        let text = serde_json::to_string(&description).unwrap();
        let read = serde_json::from_str(&text).unwrap();
        let mut made = BuiltinModels.make(&read).unwrap();
        assert_eq!(made.describe().as_ref(), Some(&description));
        let mut model = model;
        model.prepare(DT).unwrap();
        made.prepare(DT).unwrap();
        assert_eq!(state_bits(made.as_ref()), state_bits(model.as_ref()));
    }
    let lif = Lif::<f64>::new(2, LifParams::default()).describe().unwrap();
    assert_eq!(
        lif.settings,
        json!({
            "precision": "f64", "integrator": "exact", "interpolate": false,
            "params": {"tau_m_s": 0.01, "v_rest": 0.0, "v_th": 1.0, "v_reset": 0.0, "t_ref_s": 0.0,
                       "v_min": null},
            "initial": {"constant": 0.0},
        })
    );
    let rs = Izhikevich::<f32>::new(2, IzhikevichParams::rs())
        .describe()
        .unwrap();
    assert_eq!(rs.model, "izhikevich");
    assert_eq!(
        rs.settings["params"],
        json!({"a": 0.02, "b": 0.2, "c": -65.0, "d": 8.0, "v_peak": 30.0, "v_min": null,
               "rest_tolerance": 0.0})
    );
}

#[test]
fn a_restricted_population_is_described_with_its_own_initial_potentials() {
    let whole = Lif::<f64>::new(100, LifParams::default()).with_initial_potential(
        InitialPotential::Uniform {
            low: 0.0,
            high: 1.0,
            seed: 9,
        },
    );
    let part = whole.restrict(30..70).unwrap();
    let nested = whole.restrict(20..90).unwrap().restrict(10..50).unwrap();
    let description = part.describe().unwrap();
    assert_eq!(description.size, 40);
    assert_eq!(
        description.settings["initial"]["values"]
            .as_array()
            .map(Vec::len),
        Some(40)
    );
    assert_eq!(nested.describe(), Some(description.clone()));
    let mut made = BuiltinModels.make(&description).unwrap();
    let mut part = part;
    part.prepare(DT).unwrap();
    made.prepare(DT).unwrap();
    assert_eq!(state_bits(made.as_ref()), state_bits(part.as_ref()));
}

#[test]
fn unknown_models_and_bad_settings_are_refused_naming_the_field() {
    let good = Lif::<f32>::new(4, LifParams::default()).describe().unwrap();
    let with = |path: &[&str], value: Option<serde_json::Value>| {
        let mut d = good.clone();
        let (last, parents) = path.split_last().unwrap();
        let mut at = &mut d.settings;
        for p in parents {
            at = &mut at[*p];
        }
        let object = at.as_object_mut().unwrap();
        match value {
            Some(v) => object.insert(last.to_string(), v),
            None => object.remove(*last),
        };
        d
    };
    let mut unknown = good.clone();
    unknown.model = "hodgkin-huxley".into();
    let mut izhikevich_with_lif_params = good.clone();
    izhikevich_with_lif_params.model = "izhikevich".into();
    let cases = [
        (unknown, "not a built-in model"),
        (
            izhikevich_with_lif_params,
            "settings.integrator: izhikevich has no 'exact'",
        ),
        (with(&["precision"], None), "settings.precision: missing"),
        (
            with(&["precision"], Some(json!("f16"))),
            "settings.precision: 'f16'",
        ),
        (
            with(&["integrator"], Some(json!("izhikevich2003"))),
            "settings.integrator",
        ),
        (
            with(&["integrator"], Some(json!("leapfrog"))),
            "settings.integrator",
        ),
        (
            with(&["interpolate"], Some(json!(1))),
            "settings.interpolate",
        ),
        (
            with(&["colour"], Some(json!("red"))),
            "settings.colour: not a field",
        ),
        (
            with(&["params", "tau_m_s"], Some(json!(-1.0))),
            "settings.params.tau_m_s = -1",
        ),
        (
            with(&["params", "v_th"], None),
            "settings.params.v_th: missing",
        ),
        (
            with(&["params", "v_min"], Some(json!("low"))),
            "settings.params.v_min",
        ),
        (
            with(&["params", "v_rest"], Some(json!(null))),
            "settings.params.v_rest",
        ),
        (
            with(&["initial"], Some(json!({"values": [0.0, 0.1]}))),
            "settings.initial.values: 2 values",
        ),
        (
            with(
                &["initial"],
                Some(json!({"uniform": {"low": 1.0, "high": 0.0, "seed": 1}})),
            ),
            "settings.initial.uniform",
        ),
        (
            with(&["initial"], Some(json!({"constant": 0.0, "values": []}))),
            "settings.initial",
        ),
    ];
    for (description, needle) in cases {
        let err = BuiltinModels.make(&description).err().expect(needle);
        assert!(
            matches!(err, ModelError::UnknownModel { .. }) && err.to_string().contains(needle),
            "{needle}: {err}"
        );
    }
}
