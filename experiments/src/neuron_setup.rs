//! The menu of neuron models, [`NeuronKind`], and the neuron set-ups shared by benchmarks,
//! single-neuron runs and trade-off reports, [`NeuronSetup`].
//!
//! The menu is one registration list, the `neuron_models!` invocation in this file: each line
//! names a variant and the model's [`ModelFamily`], and the enum, its keys and
//! [`NeuronKind::visit`] are generated from it. Whatever depends on the model — its benchmark
//! case (Brian2's: LIF `I = 1.04` from `v₀` uniform in [0, 1), [`LifFamily`]; Izhikevich RS
//! `I = 10` from −65 mV, [`IzhikevichFamily`]), its integrators, presets and afferent set-up —
//! comes from the family, through code generic over [`ModelFamily`] that [`NeuronKind::visit`]
//! runs for the choice. A new model is its file in `neurotac-neurons` plus one line here.

use crate::menu::Menu;
use neurotac_core::{ModelError, SpikeBuffer};
use neurotac_neurons::{
    BlockModel, BlockPopulation, FamilyVisitor, InitialPotential, Integrator, ModelFamily,
    Population, UpdateCost,
};
#[cfg(doc)]
use neurotac_neurons::{IzhikevichFamily, LifFamily};
use std::fmt;
use std::str::FromStr;

/// Generates [`NeuronKind`] from the registration list: the enum (one variant per line, in
/// menu order), its [`Menu`] keys (each family's [`ModelFamily::KEY`]) and [`NeuronKind::visit`].
macro_rules! neuron_models {
    ($($(#[$doc:meta])* $variant:ident => $family:ty),+ $(,)?) => {
        /// A neuron model family: one choice of the menu, registered with its [`ModelFamily`].
        /// Serialised as its key (`"lif"`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum NeuronKind {
            $($(#[$doc])* $variant,)+
        }

        impl Menu for NeuronKind {
            const WHAT: &'static str = "neuron model";
            const ALL: &'static [NeuronKind] = &[$(NeuronKind::$variant),+];
            fn key(self) -> &'static str {
                match self {
                    $(NeuronKind::$variant => <$family as ModelFamily>::KEY,)+
                }
            }
        }

        impl NeuronKind {
            /// Runs `visitor` for this choice's [`ModelFamily`].
            pub fn visit<V: FamilyVisitor>(self, visitor: V) -> V::Output {
                match self {
                    $(NeuronKind::$variant => visitor.visit::<$family>(),)+
                }
            }
        }
    };
}

neuron_models! {
    /// Leaky integrate-and-fire.
    Lif => neurotac_neurons::LifFamily,
    /// Izhikevich (2003).
    Izhikevich => neurotac_neurons::IzhikevichFamily,
}

crate::menu_text!(NeuronKind);

impl serde::Serialize for NeuronKind {
    /// As its key, a unit variant (what `#[serde(rename_all = "lowercase")]` derives).
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_unit_variant("NeuronKind", *self as u32, self.key())
    }
}

/// What the menu shows of a family ([`ReadFacts`]).
struct Facts {
    label: &'static str,
    default_integrator: Integrator,
    integrators: &'static [Integrator],
    benchmark_current: f64,
}

/// Reads a family's [`Facts`].
struct ReadFacts;

impl FamilyVisitor for ReadFacts {
    type Output = Facts;
    fn visit<Fam: ModelFamily>(self) -> Facts {
        Facts {
            label: Fam::LABEL,
            default_integrator: Fam::default_integrator(),
            integrators: Fam::INTEGRATORS,
            benchmark_current: Fam::benchmark().current,
        }
    }
}

/// The closed-form spike times of the single-neuron benchmark ([`NeuronKind::exact_spike_times`]).
struct ExactSpikeTimes {
    duration_s: f64,
}

impl FamilyVisitor for ExactSpikeTimes {
    type Output = Option<Vec<f64>>;
    fn visit<Fam: ModelFamily>(self) -> Option<Vec<f64>> {
        let b = Fam::benchmark();
        Fam::exact_spike_times(&b.params, b.current, self.duration_s)
    }
}

impl NeuronKind {
    fn facts(self) -> Facts {
        self.visit(ReadFacts)
    }

    /// Lower-case name (its [`Menu::key`]).
    pub fn name(self) -> &'static str {
        self.key()
    }

    /// The name in prose ([`ModelFamily::LABEL`]: `"LIF"`, `"Izhikevich"`).
    pub fn label(self) -> &'static str {
        self.facts().label
    }

    /// The model's default integrator (exact for LIF, Izhikevich's 2003 scheme).
    pub fn default_integrator(self) -> Integrator {
        self.facts().default_integrator
    }

    /// The integrators a report compares, the default first ([`ModelFamily::INTEGRATORS`]).
    pub fn integrators(self) -> &'static [Integrator] {
        self.facts().integrators
    }

    /// The names of the model's parameter presets ([`ModelFamily::PRESETS`]; LIF has none).
    pub fn presets(self) -> Vec<&'static str> {
        self.visit(Presets).1
    }

    /// The benchmark input current (LIF 1.04, Izhikevich 10).
    pub fn benchmark_current(self) -> f64 {
        self.facts().benchmark_current
    }

    /// The spike times (s) up to `duration_s` of one benchmark neuron starting at rest
    /// ([`NeuronSetup::single`]) under the benchmark current, in closed form
    /// ([`ModelFamily::exact_spike_times`]: LIF's `t_k = k·τ·ln(I/(I − 1))`); `None` when the
    /// model has none.
    pub fn exact_spike_times(self, duration_s: f64) -> Option<Vec<f64>> {
        self.visit(ExactSpikeTimes { duration_s })
    }
}

/// Floating-point precision of a population.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    /// 32-bit floats.
    F32,
    /// 64-bit floats.
    F64,
}

impl Menu for Precision {
    const WHAT: &'static str = "precision";
    const ALL: &'static [Precision] = &[Precision::F32, Precision::F64];
    fn key(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}
crate::menu_text!(Precision);

impl Precision {
    /// `"f32"` or `"f64"` (its [`Menu::key`]).
    pub fn name(self) -> &'static str {
        self.key()
    }
}

/// The name of a parameter preset of a model of the menu ([`ModelFamily::PRESETS`]:
/// Izhikevich's rs, ib, ch, fs, lts, tc, rz), checked when parsed (case-insensitively) and
/// held in lower case. A model without a preset of that name (LIF has none) ignores it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PresetName(&'static str);

impl PresetName {
    /// The lower-case name.
    pub fn as_str(self) -> &'static str {
        self.0
    }
}

impl fmt::Display for PresetName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

/// A preset name that no model of the menu has.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {models} preset '{given}' (expected {expected})")]
pub struct UnknownPreset {
    /// The name given.
    pub given: String,
    /// The models that have presets, in prose (`"Izhikevich"`).
    pub models: String,
    /// Every preset name, as a list ending in "or".
    pub expected: String,
}

/// A family's label and preset names.
struct Presets;

impl FamilyVisitor for Presets {
    type Output = (&'static str, Vec<&'static str>);
    fn visit<Fam: ModelFamily>(self) -> Self::Output {
        (
            Fam::LABEL,
            Fam::PRESETS.iter().map(|&(name, _)| name).collect(),
        )
    }
}

impl FromStr for PresetName {
    type Err = UnknownPreset;
    fn from_str(given: &str) -> Result<Self, UnknownPreset> {
        let mut models = Vec::new();
        let mut names: Vec<&'static str> = Vec::new();
        for kind in NeuronKind::ALL {
            let (label, presets) = kind.visit(Presets);
            if !presets.is_empty() {
                models.push(label);
            }
            for name in presets {
                if !names.contains(&name) {
                    names.push(name);
                }
            }
        }
        if let Some(name) = names.iter().find(|n| n.eq_ignore_ascii_case(given)) {
            return Ok(PresetName(name));
        }
        let expected = match names.split_last() {
            None => "none".to_owned(),
            Some((last, [])) => (*last).to_owned(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        };
        Err(UnknownPreset {
            given: given.to_owned(),
            models: if models.is_empty() {
                NeuronKind::WHAT.to_owned()
            } else {
                models.join(" or ")
            },
            expected,
        })
    }
}

/// Everything that defines one neuron population set-up.
#[derive(Debug, Clone, PartialEq)]
pub struct NeuronSetup {
    /// Model family.
    pub kind: NeuronKind,
    /// Named parameter preset; `None`, or a preset the model does not have, runs the model's
    /// benchmark parameters ([`ModelFamily::benchmark`]). Default `None`.
    pub preset: Option<PresetName>,
    /// Integrator.
    pub integrator: Integrator,
    /// Precision.
    pub precision: Precision,
    /// Interpolate spike times inside the step.
    pub interpolate: bool,
    /// Initial potentials.
    pub initial: InitialPotential,
}

/// The initial potentials of a benchmark population, or of one neuron at rest.
struct Initial {
    single: bool,
}

impl FamilyVisitor for Initial {
    type Output = InitialPotential;
    fn visit<Fam: ModelFamily>(self) -> InitialPotential {
        let b = Fam::benchmark();
        if self.single {
            Fam::at_rest(&b.params)
        } else {
            b.initial
        }
    }
}

/// The update cost of a set-up ([`NeuronSetup::update_cost`]).
struct Cost {
    integrator: Integrator,
    precision: Precision,
}

impl FamilyVisitor for Cost {
    type Output = UpdateCost;
    fn visit<Fam: ModelFamily>(self) -> UpdateCost {
        match self.precision {
            Precision::F32 => Fam::update_cost::<f32>(self.integrator),
            Precision::F64 => Fam::update_cost::<f64>(self.integrator),
        }
        .unwrap_or_default()
    }
}

/// Builds the population of a set-up ([`NeuronSetup::population`]).
struct Build<'a> {
    setup: &'a NeuronSetup,
    n: usize,
}

impl FamilyVisitor for Build<'_> {
    type Output = Box<dyn Population>;
    fn visit<Fam: ModelFamily>(self) -> Box<dyn Population> {
        let params = self
            .setup
            .preset
            .and_then(|p| Fam::preset(p.as_str()))
            .unwrap_or_else(|| Fam::benchmark().params);
        match self.setup.precision {
            Precision::F32 => self.setup.build::<Fam::Model<f32>>(self.n, params),
            Precision::F64 => self.setup.build::<Fam::Model<f64>>(self.n, params),
        }
    }
}

impl NeuronSetup {
    /// The benchmark set-up of `kind` ([`ModelFamily::benchmark`]: parameters and initial
    /// potentials), default integrator, grid times.
    pub fn benchmark(kind: NeuronKind, precision: Precision) -> Self {
        Self {
            kind,
            preset: None,
            integrator: kind.default_integrator(),
            precision,
            interpolate: false,
            initial: kind.visit(Initial { single: false }),
        }
    }

    /// One neuron starting at rest ([`ModelFamily::at_rest`]: LIF `v = 0`, Izhikevich
    /// `v = −65 mV`): the single-neuron runs whose truths are known (closed forms, fine-step
    /// RK4).
    pub fn single(kind: NeuronKind, precision: Precision) -> Self {
        Self {
            initial: kind.visit(Initial { single: true }),
            ..Self::benchmark(kind, precision)
        }
    }

    /// The cost of one neuron update of this set-up's model, integrator and precision on the
    /// model's benchmark case ([`ModelFamily::update_cost`]: floating-point operations and
    /// bytes of state memory per update, with the conventions of [`UpdateCost`] and each
    /// model's derivation from its equations). An integrator the model does not support (its
    /// population refuses to prepare) costs nothing: [`UpdateCost::default`].
    pub fn update_cost(&self) -> UpdateCost {
        self.kind.visit(Cost {
            integrator: self.integrator,
            precision: self.precision,
        })
    }

    /// A population of `n` neurons of this set-up, as a network node.
    pub fn population(&self, n: usize) -> Box<dyn Population> {
        self.kind.visit(Build { setup: self, n })
    }

    fn build<M: BlockModel>(&self, n: usize, params: M::Params) -> Box<dyn Population> {
        Box::new(
            BlockPopulation::<M>::new(n, params)
                .with_integrator(self.integrator)
                .with_interpolation(self.interpolate)
                .with_initial_potential(self.initial.clone()),
        )
    }

    /// Runs `n` neurons for `steps` steps of `dt_s` under the constant `current`, without
    /// recording spike indices, and returns `(spikes, stepping wall time in s)`. Preparation
    /// (allocation, initial state) is not timed; the kernels are statically dispatched inside
    /// each step, so the one dynamic call per step costs nothing measurable.
    pub fn run_constant(
        &self,
        n: usize,
        current: f64,
        dt_s: f64,
        steps: u64,
    ) -> Result<(u64, f64), ModelError> {
        let mut pop = self.population(n);
        pop.prepare(dt_s)?;
        let start = std::time::Instant::now();
        let spikes = pop.run_constant(current, dt_s, steps)?;
        Ok((spikes, start.elapsed().as_secs_f64()))
    }

    /// Spike times (s) of one neuron of this set-up under the constant `current`.
    pub fn spike_times(
        &self,
        current: f64,
        dt_s: f64,
        duration_s: f64,
    ) -> Result<Vec<f64>, ModelError> {
        if !current.is_finite() {
            return Err(ModelError::NonFiniteInput {
                model: self.kind.name(),
                neuron: 0,
                value: current,
            });
        }
        let mut pop = self.population(1);
        pop.prepare(dt_s)?;
        let steps = (duration_s / dt_s).round() as u64;
        let mut spikes = SpikeBuffer::new();
        let mut times = Vec::new();
        for k in 0..steps {
            spikes.clear();
            pop.step(&[current], &mut spikes);
            times.extend(spikes.fractions().iter().map(|phi| (k as f64 + phi) * dt_s));
        }
        Ok(times)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_neurons::{Izhikevich, IzhikevichParams, check_family};

    /// Runs [`check_family`] for a family.
    struct Check;

    impl FamilyVisitor for Check {
        type Output = Result<(), String>;
        fn visit<Fam: ModelFamily>(self) -> Self::Output {
            check_family::<Fam>()
        }
    }

    #[test]
    fn every_registered_model_is_consistent_and_named_by_its_key() {
        for &kind in NeuronKind::ALL {
            kind.visit(Check).unwrap();
            assert_eq!(kind.key().parse::<NeuronKind>(), Ok(kind));
            let json = serde_json::to_string(&kind).unwrap();
            assert_eq!(json, format!("\"{}\"", kind.key()));
            assert_eq!(kind.integrators()[0], kind.default_integrator());
        }
        assert_eq!(
            NeuronKind::ALL[..2],
            [NeuronKind::Lif, NeuronKind::Izhikevich]
        );
        assert_eq!(
            (NeuronKind::Lif.label(), NeuronKind::Izhikevich.label()),
            ("LIF", "Izhikevich")
        );
    }

    #[test]
    fn the_benchmark_and_single_set_ups_are_brian2s_cases() {
        let lif = NeuronSetup::benchmark(NeuronKind::Lif, Precision::F32);
        assert_eq!(lif.integrator, Integrator::Exact);
        assert_eq!(
            lif.initial,
            InitialPotential::Uniform {
                low: 0.0,
                high: 1.0,
                seed: 2020
            }
        );
        assert_eq!(NeuronKind::Lif.benchmark_current(), 1.04);
        let single = NeuronSetup::single(NeuronKind::Lif, Precision::F64);
        assert_eq!(single.initial, InitialPotential::Constant(0.0));
        let rs = NeuronSetup::benchmark(NeuronKind::Izhikevich, Precision::F64);
        assert_eq!(rs.integrator, Integrator::Izhikevich2003);
        assert_eq!(rs.initial, InitialPotential::Constant(-65.0));
        assert_eq!(NeuronKind::Izhikevich.benchmark_current(), 10.0);
        let single = NeuronSetup::single(NeuronKind::Izhikevich, Precision::F64);
        assert_eq!(single.initial, InitialPotential::Constant(-65.0));
    }

    #[test]
    fn the_update_cost_counts_the_equations_operations_and_the_state_bytes() {
        // Izhikevich by Euler: dv = 0.04·v·v + 5·v + 140 − u + I is 3 mul + 4 add/sub,
        // du = a·(b·v − u) 2 mul + 1 sub, v + h·dv and u + h·du 2 each, the reset value u + d
        // 1: 7 + 3 + 4 + 1 = 15 flops. v and u read and written in f64 (4 × 8 bytes) and the
        // spike byte: 33 bytes.
        let izhikevich = NeuronSetup {
            integrator: Integrator::Euler,
            ..NeuronSetup::benchmark(NeuronKind::Izhikevich, Precision::F64)
        };
        assert_eq!(
            izhikevich.update_cost(),
            UpdateCost {
                flops: 15,
                bytes: 33
            }
        );
        // LIF's exact step under a constant input: v·e^(−h) + (a per-step constant), 2 flops;
        // v read and written in f32 and the spike byte, 9 bytes.
        let lif = NeuronSetup::benchmark(NeuronKind::Lif, Precision::F32);
        assert_eq!(lif.update_cost(), UpdateCost { flops: 2, bytes: 9 });
        let unsupported = NeuronSetup {
            integrator: Integrator::Izhikevich2003,
            ..lif
        };
        assert_eq!(unsupported.update_cost(), UpdateCost::default());
    }

    #[test]
    fn a_preset_is_any_models_and_is_ignored_by_a_model_without_it() {
        let fs: PresetName = "FS".parse().unwrap();
        assert_eq!(fs.as_str(), "fs");
        let e = "xyz".parse::<PresetName>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown Izhikevich preset 'xyz' (expected rs, ib, ch, fs, lts, tc or rz)"
        );
        let run = |kind, preset| {
            let setup = NeuronSetup {
                preset,
                ..NeuronSetup::single(kind, Precision::F64)
            };
            setup
                .spike_times(kind.benchmark_current(), 1e-4, 0.3)
                .unwrap()
        };
        let mut direct = Izhikevich::<f64>::new(1, IzhikevichParams::fs());
        let direct_spikes = direct.run_constant(10.0, 1e-4, 3000).unwrap();
        let with_fs = run(NeuronKind::Izhikevich, Some(fs));
        assert_eq!(with_fs.len() as u64, direct_spikes);
        assert_ne!(with_fs, run(NeuronKind::Izhikevich, None));
        // LIF has no presets: `fs` leaves it at its benchmark parameters.
        assert_eq!(run(NeuronKind::Lif, Some(fs)), run(NeuronKind::Lif, None));
        assert_eq!(
            NeuronKind::Lif.exact_spike_times(0.1).map(|t| t.len()),
            Some(3)
        );
        assert_eq!(NeuronKind::Izhikevich.exact_spike_times(0.1), None);
    }
}
