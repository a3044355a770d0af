//! The neuron set-ups shared by benchmarks, single-neuron runs and trade-off reports.
//!
//! The benchmark cases are the ones Brian2 is measured on:
//! - LIF `dv/dt = (I − v)/τ`, τ = 10 ms, threshold 1, reset 0, `I = 1.04` constant, `v₀`
//!   uniform in [0, 1) ([`LifParams::benchmark`]);
//! - Izhikevich regular spiking ([`IzhikevichParams::rs`]) with `I = 10`, `v₀ = −65 mV`.

use crate::menu::Menu;
use neurotac_core::{ModelError, SpikeBuffer};
use neurotac_neurons::{
    InitialPotential, Integrator, Izhikevich, IzhikevichParams, Lif, LifParams, Population,
};

/// A neuron model family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NeuronKind {
    /// Leaky integrate-and-fire.
    Lif,
    /// Izhikevich (2003).
    Izhikevich,
}

impl Menu for NeuronKind {
    const WHAT: &'static str = "neuron model";
    const ALL: &'static [NeuronKind] = &[NeuronKind::Lif, NeuronKind::Izhikevich];
    fn key(self) -> &'static str {
        match self {
            NeuronKind::Lif => "lif",
            NeuronKind::Izhikevich => "izhikevich",
        }
    }
}
crate::menu_text!(NeuronKind);

impl NeuronKind {
    /// Lower-case name (its [`Menu::key`]).
    pub fn name(self) -> &'static str {
        self.key()
    }

    /// The model's default integrator (exact for LIF, Izhikevich's 2003 scheme).
    pub fn default_integrator(self) -> Integrator {
        match self {
            NeuronKind::Lif => Integrator::Exact,
            NeuronKind::Izhikevich => Integrator::Izhikevich2003,
        }
    }

    /// The integrators the model supports, in report order.
    pub fn integrators(self) -> &'static [Integrator] {
        match self {
            NeuronKind::Lif => &[
                Integrator::Exact,
                Integrator::Euler,
                Integrator::Rk2,
                Integrator::Rk4,
            ],
            NeuronKind::Izhikevich => &[
                Integrator::Izhikevich2003,
                Integrator::Euler,
                Integrator::ExponentialEuler,
                Integrator::Rk2,
                Integrator::Rk4,
            ],
        }
    }

    /// The benchmark input current (LIF 1.04, Izhikevich 10).
    pub fn benchmark_current(self) -> f64 {
        match self {
            NeuronKind::Lif => 1.04,
            NeuronKind::Izhikevich => 10.0,
        }
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

/// Everything that defines one neuron population set-up.
#[derive(Debug, Clone, PartialEq)]
pub struct NeuronSetup {
    /// Model family.
    pub kind: NeuronKind,
    /// Izhikevich preset (ignored for LIF).
    pub preset: IzhikevichParams,
    /// Integrator.
    pub integrator: Integrator,
    /// Precision.
    pub precision: Precision,
    /// Interpolate spike times inside the step.
    pub interpolate: bool,
    /// Initial potentials.
    pub initial: InitialPotential,
}

impl NeuronSetup {
    /// The benchmark set-up of `kind` (see the module docs), default integrator, grid times.
    pub fn benchmark(kind: NeuronKind, precision: Precision) -> Self {
        let initial = match kind {
            NeuronKind::Lif => InitialPotential::Uniform {
                low: 0.0,
                high: 1.0,
                seed: 2020,
            },
            NeuronKind::Izhikevich => InitialPotential::Constant(-65.0),
        };
        Self {
            kind,
            preset: IzhikevichParams::rs(),
            integrator: kind.default_integrator(),
            precision,
            interpolate: false,
            initial,
        }
    }

    /// One neuron starting at rest (LIF `v = 0`, Izhikevich `v = −65 mV`): the single-neuron
    /// runs whose truths are known (LIF closed form, fine-step RK4).
    pub fn single(kind: NeuronKind, precision: Precision) -> Self {
        let initial = match kind {
            NeuronKind::Lif => InitialPotential::Constant(0.0),
            NeuronKind::Izhikevich => InitialPotential::Constant(-65.0),
        };
        Self {
            initial,
            ..Self::benchmark(kind, precision)
        }
    }

    /// A population of `n` neurons of this set-up, as a network node.
    pub fn population(&self, n: usize) -> Box<dyn Population> {
        macro_rules! build {
            ($model:ident, $float:ty, $params:expr) => {
                Box::new(
                    $model::<$float>::new(n, $params)
                        .with_integrator(self.integrator)
                        .with_interpolation(self.interpolate)
                        .with_initial_potential(self.initial.clone()),
                )
            };
        }
        match (self.kind, self.precision) {
            (NeuronKind::Lif, Precision::F32) => build!(Lif, f32, LifParams::benchmark()),
            (NeuronKind::Lif, Precision::F64) => build!(Lif, f64, LifParams::benchmark()),
            (NeuronKind::Izhikevich, Precision::F32) => build!(Izhikevich, f32, self.preset),
            (NeuronKind::Izhikevich, Precision::F64) => build!(Izhikevich, f64, self.preset),
        }
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
