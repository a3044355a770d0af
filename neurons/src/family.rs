//! [`ModelFamily`]: a neuron model at every precision, with what the applications need to know
//! about it besides its step — the case it is benchmarked on, its named presets, its afferent
//! set-up and its closed-form spike times, if it has them.
//!
//! A model file implements the family next to its [`BlockModel`] (`LifFamily` in [`lif`](crate::lif),
//! `IzhikevichFamily` in [`izhikevich`](crate::izhikevich)); an application lists the families
//! once, in its menu of models, and reaches the one chosen at run time through a
//! [`FamilyVisitor`], whose [`visit`](FamilyVisitor::visit) is generic over the family. Code
//! written that way serves every model, so a new model is its own file plus one line in the menu.
//!
//! What [`BlockModel`] already says is not repeated: the menu key is the model's
//! [`NAME`](BlockModel::NAME), the default integrator its
//! [`DEFAULT_INTEGRATOR`](BlockModel::DEFAULT_INTEGRATOR), and a neuron "at rest" starts at
//! its [`default_initial`](BlockModel::default_initial) potential.
//!
//! ```
//! use neurotac_neurons::{FamilyVisitor, Integrator, IzhikevichFamily, LifFamily, ModelFamily};
//! /// The default integrator and the benchmark current of a family.
//! struct Defaults;
//! impl FamilyVisitor for Defaults {
//!     type Output = (&'static str, Integrator, f64);
//!     fn visit<Fam: ModelFamily>(self) -> Self::Output {
//!         (Fam::KEY, Fam::default_integrator(), Fam::benchmark().current)
//!     }
//! }
//! assert_eq!(Defaults.visit::<LifFamily>(), ("lif", Integrator::Exact, 1.04));
//! assert_eq!(Defaults.visit::<IzhikevichFamily>().1, Integrator::Izhikevich2003);
//! ```

use crate::integrate::Integrator;
use crate::population::{BlockModel, InitialPotential};
use crate::real::Real;
use std::fmt;

/// A neuron model at every precision: its [`BlockModel`] for `f32` and `f64` and the set-ups
/// the applications run it in. Implemented in the model's own file.
pub trait ModelFamily: 'static {
    /// The parameter record, shared by every precision.
    type Params: Copy + PartialEq + fmt::Debug + Send + Sync + 'static;
    /// The model in precision `F`; its population is
    /// [`BlockPopulation<Self::Model<F>>`](crate::BlockPopulation).
    type Model<F: Real>: BlockModel<Real = F, Params = Self::Params>;

    /// The menu key: lower case, what a user types (`"lif"`); the model's
    /// [`BlockModel::NAME`].
    const KEY: &'static str = <Self::Model<f64> as BlockModel>::NAME;
    /// The name in prose (`"LIF"`, `"Izhikevich"`).
    const LABEL: &'static str;
    /// The integrators a report compares, the default first (a subset of the supported ones:
    /// one of two integrators that are the same for the model is left out).
    const INTEGRATORS: &'static [Integrator];
    /// Named parameter sets, the name lower case (Izhikevich's `rs`, `fs`, …). Default none.
    const PRESETS: &'static [(&'static str, Self::Params)] = &[];

    /// The benchmark case: parameters, constant input and initial potentials.
    fn benchmark() -> Benchmark<Self::Params>;

    /// The model as a mechanoreceptor afferent, fed by exponential synapses from taxels.
    fn afferent() -> AfferentPreset<Self::Params>;

    /// The spike times (s) up to `duration_s` of one neuron starting
    /// [`at_rest`](Self::at_rest) under the constant `current`, in closed form; `None` when the
    /// model has none (then a fine-step RK4 run is the reference, so such a model supports
    /// [`Integrator::Rk4`]). Default `None`.
    fn exact_spike_times(params: &Self::Params, current: f64, duration_s: f64) -> Option<Vec<f64>> {
        let _ = (params, current, duration_s);
        None
    }

    /// The cost of one neuron update of the [`benchmark`](Self::benchmark) case with
    /// `integrator` in precision `F` ([`UpdateCost`]: its conventions); `None` when the model
    /// does not support `integrator`. Each model derives its counts from its equations in its
    /// implementation's docs.
    fn update_cost<F: Real>(integrator: Integrator) -> Option<UpdateCost>;

    /// The integrator a population starts with ([`BlockModel::DEFAULT_INTEGRATOR`]).
    fn default_integrator() -> Integrator {
        <Self::Model<f64> as BlockModel>::DEFAULT_INTEGRATOR
    }

    /// The initial potential of one neuron "at rest", the start of single-neuron runs
    /// ([`BlockModel::default_initial`]).
    fn at_rest(params: &Self::Params) -> InitialPotential {
        <Self::Model<f64> as BlockModel>::default_initial(params)
    }

    /// The preset called `name` (case-insensitive) of [`PRESETS`](Self::PRESETS).
    fn preset(name: &str) -> Option<Self::Params> {
        Self::PRESETS
            .iter()
            .find(|(key, _)| key.eq_ignore_ascii_case(name))
            .map(|&(_, params)| params)
    }
}

/// The cost of one neuron update of a model's benchmark case ([`ModelFamily::update_cost`]),
/// as its fused loop computes it: one neuron, one step, constant input.
///
/// Conventions:
/// - `flops`: floating-point additions, subtractions, multiplications and divisions on the
///   neuron's values, one each (an FMA would count 2; the loops issue none, Rust does not
///   contract `a·b + c`). Compares, selects, minimum/maximum, clamps and absolute values count
///   0; so do terms of the per-step constants alone (`v∞·(1 − e^(−h))` under a constant input),
///   which the loop computes once per step, not per neuron.
/// - `bytes`: state memory read plus written per update: each state variable read once and
///   written once, in place (`v` for LIF, `v` and `u` for Izhikevich; 4 bytes each in `f32`,
///   8 in `f64`), plus the one-byte spike mask written. The constant input is not in memory;
///   the benchmark case has no refractory counters and no interpolation buffers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct UpdateCost {
    /// Floating-point operations per update.
    pub flops: u32,
    /// Bytes of state memory read plus written per update.
    pub bytes: u32,
}

impl UpdateCost {
    /// The cost of `flops` operations on `variables` state variables of precision `F`, each
    /// read and written once, plus the spike mask byte.
    pub(crate) fn of<F: Real>(flops: u32, variables: u32) -> UpdateCost {
        UpdateCost {
            flops,
            bytes: 2 * variables * std::mem::size_of::<F>() as u32 + 1,
        }
    }
}

/// The case a model is benchmarked on (Brian2's, where it has one): `n` neurons under one
/// constant input.
#[derive(Debug, Clone, PartialEq)]
pub struct Benchmark<P> {
    /// Parameters.
    pub params: P,
    /// The constant input, in the model's input units.
    pub current: f64,
    /// The initial potentials of a benchmark population.
    pub initial: InitialPotential,
}

/// A model as a mechanoreceptor afferent: taxel spikes → exponential synapses → one afferent
/// per taxel, integrated with the model's default integrator in `f64`.
#[derive(Debug, Clone, PartialEq)]
pub struct AfferentPreset<P> {
    /// Parameters.
    pub params: P,
    /// Initial potential (an afferent without input is at rest).
    pub initial: InitialPotential,
    /// Synaptic weight: the jump of the synaptic current per taxel spike, in the model's input
    /// units, chosen so that a lone taxel event makes exactly one afferent spike.
    pub weight: f64,
    /// The afferents as the description of a pipeline names them (`"LIF afferents
    /// (event-driven)"`).
    pub description: &'static str,
    /// The afferents with their integrator, precision and start, as the afferent activity
    /// bench reports them (`"LIF afferents (exact, f64)"`).
    pub bench_description: &'static str,
}

/// Code generic over a [`ModelFamily`], run for a family chosen at run time (a menu of models
/// calls [`visit`](Self::visit) with the family of the choice).
pub trait FamilyVisitor {
    /// What the visit returns.
    type Output;
    /// Runs for the family `Fam`.
    fn visit<Fam: ModelFamily>(self) -> Self::Output;
}

/// Checks a family's declarations against its [`BlockModel`]: its report integrators are
/// supported, distinct and start with the default; its presets have distinct lower-case
/// names; its benchmark and afferent parameters are valid in both precisions. `Err` names the
/// first inconsistency. Every family's tests run it.
pub fn check_family<Fam: ModelFamily>() -> Result<(), String> {
    let model = Fam::KEY;
    let integrators = Fam::INTEGRATORS;
    if integrators.first() != Some(&Fam::default_integrator()) {
        return Err(format!(
            "{model}: the report integrators must start with the default"
        ));
    }
    for (i, &integrator) in integrators.iter().enumerate() {
        if !<Fam::Model<f64> as BlockModel>::supports(integrator) {
            return Err(format!(
                "{model}: report integrator {integrator} is not supported"
            ));
        }
        if integrators[..i].contains(&integrator) {
            return Err(format!(
                "{model}: report integrator {integrator} is listed twice"
            ));
        }
    }
    for (i, (name, _)) in Fam::PRESETS.iter().enumerate() {
        let taken = Fam::PRESETS[..i]
            .iter()
            .any(|(n, _)| n.eq_ignore_ascii_case(name));
        if taken || name.to_ascii_lowercase() != *name {
            return Err(format!(
                "{model}: preset name '{name}' is repeated or not lower case"
            ));
        }
    }
    for params in [Fam::benchmark().params, Fam::afferent().params] {
        <Fam::Model<f32> as BlockModel>::validate(&params).map_err(|e| e.to_string())?;
        <Fam::Model<f64> as BlockModel>::validate(&params).map_err(|e| e.to_string())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{IzhikevichFamily, IzhikevichParams, LifFamily, LifParams};

    #[test]
    fn each_family_agrees_with_its_block_model() {
        check_family::<LifFamily>().unwrap();
        check_family::<IzhikevichFamily>().unwrap();
        assert_eq!(
            (LifFamily::KEY, IzhikevichFamily::KEY),
            ("lif", "izhikevich")
        );
        assert_eq!(
            LifFamily::at_rest(&LifParams::benchmark()),
            InitialPotential::Constant(0.0)
        );
    }

    #[test]
    fn presets_are_found_by_name_and_lif_has_none() {
        assert_eq!(IzhikevichFamily::preset("FS"), Some(IzhikevichParams::fs()));
        assert_eq!(IzhikevichFamily::preset("xyz"), None);
        assert_eq!(LifFamily::preset("rs"), None);
        let names: Vec<_> = IzhikevichFamily::PRESETS.iter().map(|(n, _)| *n).collect();
        assert_eq!(names, ["rs", "ib", "ch", "fs", "lts", "tc", "rz"]);
    }

    #[test]
    fn only_lif_has_closed_form_spike_times() {
        let lif = LifFamily::benchmark();
        assert_eq!(
            LifFamily::exact_spike_times(&lif.params, lif.current, 1.0),
            Some(lif.params.closed_form_spike_times(lif.current, 1.0))
        );
        let shifted = LifParams {
            v_reset: -0.5,
            ..lif.params
        };
        assert_eq!(LifFamily::exact_spike_times(&shifted, 1.04, 1.0), None);
        let rs = IzhikevichFamily::benchmark();
        assert_eq!(
            IzhikevichFamily::exact_spike_times(&rs.params, rs.current, 1.0),
            None
        );
    }
}
