//! Spikes and states pinned bit for bit: every model, integrator, precision and spike-time mode
//! on a heterogeneous population of two blocks (a whole one and a partial one, so that every
//! split of the fused loops is crossed), through both entry points — `step` (one input per
//! neuron, the network's path) and `run_constant` (the benchmark's path). A change to a fused
//! loop must leave each fingerprint as it is: a faster kernel computes the same numbers.

use neurotac_core::seed_hash::Fnv1a;
use neurotac_core::{NeuronModel, SpikeBuffer};
use neurotac_neurons::population::BLOCK;
use neurotac_neurons::{
    BlockModel, BlockPopulation, InitialPotential, Integrator, IzhikevichFamily, IzhikevichParams,
    LifFamily, LifParams, ModelFamily, Population,
};

const N: usize = BLOCK + 300;
const STEPS: u64 = 1500;
const DT_S: f64 = 1e-4;

/// FNV-1a over 64-bit words (little-endian).
fn add(fp: &mut Fnv1a, word: u64) {
    fp.write(&word.to_le_bytes());
}

/// The population's state, every variable of every neuron, bit for bit.
fn add_state(model: &dyn NeuronModel, fp: &mut Fnv1a) {
    let all: Vec<u32> = (0..N as u32).collect();
    let mut values = Vec::new();
    for var in 0..model.variables().len() {
        model.read_variable(var, &all, &mut values);
    }
    values.iter().for_each(|x| add(fp, x.to_bits()));
}

/// `(step path, constant path)` fingerprints: spikes (step, neuron, fraction bits) and final
/// states of `STEPS` steps of per-neuron `input`, and the spike count and final states of
/// `run_constant(constant)`.
fn fingerprints<M: BlockModel>(
    params: M::Params,
    integrator: Integrator,
    interpolate: bool,
    initial: InitialPotential,
    input: &[f64],
    constant: f64,
) -> (u64, u64) {
    let build = || {
        BlockPopulation::<M>::new(N, params)
            .with_integrator(integrator)
            .with_interpolation(interpolate)
            .with_initial_potential(initial.clone())
    };
    let mut pop = build();
    pop.prepare(DT_S).unwrap();
    let mut fp = Fnv1a::new();
    let mut spikes = SpikeBuffer::new();
    for step in 0..STEPS {
        pop.step_checked(input, &mut spikes).unwrap();
        add(&mut fp, step);
        spikes
            .indices()
            .iter()
            .for_each(|&i| add(&mut fp, u64::from(i)));
        spikes
            .fractions()
            .iter()
            .for_each(|f| add(&mut fp, f.to_bits()));
    }
    add_state(&pop, &mut fp);
    let mut pop = build();
    let mut constant_fp = Fnv1a::new();
    add(
        &mut constant_fp,
        pop.run_constant(constant, DT_S, STEPS).unwrap(),
    );
    add_state(&pop, &mut constant_fp);
    (fp.finish(), constant_fp.finish())
}

/// One case of a family's model, run in f32 and in f64.
struct Case<'a, P> {
    name: &'a str,
    params: P,
    integrator: Integrator,
    interpolate: bool,
    initial: &'a InitialPotential,
    input: &'a [f64],
    constant: f64,
}

/// The lines of `case` at both precisions.
fn both_precisions<Fam: ModelFamily>(case: Case<'_, Fam::Params>, lines: &mut Vec<String>) {
    let Case {
        name,
        params,
        integrator,
        interpolate,
        initial,
        input,
        constant,
    } = case;
    type Run<P> = fn(P, Integrator, bool, InitialPotential, &[f64], f64) -> (u64, u64);
    let runs: [(&str, Run<Fam::Params>); 2] = [
        ("f32", fingerprints::<Fam::Model<f32>>),
        ("f64", fingerprints::<Fam::Model<f64>>),
    ];
    for (precision, run) in runs {
        let (a, b) = run(
            params,
            integrator,
            interpolate,
            initial.clone(),
            input,
            constant,
        );
        lines.push(format!(
            "{name} {integrator} {precision} {interpolate} {a:016x} {b:016x}"
        ));
    }
}

/// One line per case: `model integrator precision interpolate step-fingerprint constant-fingerprint`.
fn all_cases() -> Vec<String> {
    let mut lines = Vec::new();
    let lif_input: Vec<f64> = (0..N).map(|i| 0.8 + 0.5 * (i % 17) as f64 / 17.0).collect();
    let lif_initial = InitialPotential::Uniform {
        low: -0.2,
        high: 1.0,
        seed: 11,
    };
    let lif_params = LifParams {
        t_ref_s: 2e-3,
        ..LifParams::default()
    };
    let izh_input: Vec<f64> = (0..N)
        .map(|i| 15.0 * ((i * 7) % 13) as f64 / 13.0)
        .collect();
    let izh_initial = InitialPotential::Uniform {
        low: -75.0,
        high: -45.0,
        seed: 12,
    };
    for interpolate in [false, true] {
        for integrator in [
            Integrator::Exact,
            Integrator::Euler,
            Integrator::Rk2,
            Integrator::Rk4,
        ] {
            for (params, name) in [(LifParams::default(), "lif"), (lif_params, "lif-ref")] {
                let case = Case {
                    name,
                    params,
                    integrator,
                    interpolate,
                    initial: &lif_initial,
                    input: &lif_input,
                    constant: 1.04,
                };
                both_precisions::<LifFamily>(case, &mut lines);
            }
        }
        for integrator in [
            Integrator::Izhikevich2003,
            Integrator::Euler,
            Integrator::ExponentialEuler,
            Integrator::Rk2,
            Integrator::Rk4,
        ] {
            let case = Case {
                name: "izhikevich",
                params: IzhikevichParams::rs(),
                integrator,
                interpolate,
                initial: &izh_initial,
                input: &izh_input,
                constant: 10.0,
            };
            both_precisions::<IzhikevichFamily>(case, &mut lines);
        }
    }
    lines
}

/// The fingerprints of the kernels as they were before the in-place Izhikevich loop (and
/// every kernel change since must reproduce them).
const EXPECTED: &str = include_str!("spike_identity.txt");

#[test]
fn spikes_and_states_are_bit_identical_to_the_pinned_kernels() {
    let got = all_cases();
    let expected: Vec<&str> = EXPECTED.lines().collect();
    let mismatches: Vec<String> = got
        .iter()
        .zip(&expected)
        .filter(|(g, e)| g != e)
        .map(|(g, e)| format!("got      {g}\nexpected {e}"))
        .collect();
    assert_eq!(got.len(), expected.len(), "{}", got.join("\n"));
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}
