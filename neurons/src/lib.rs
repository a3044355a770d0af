//! # neurotac-neurons
//!
//! Spiking neuron models for neurotac networks, each a [`neurotac_core::NeuronModel`]:
//!
//! | model | population | parameters (presets) | integrators |
//! |---|---|---|---|
//! | leaky integrate-and-fire ([`lif`]) | [`Lif`] | [`LifParams`] | exact, exp-euler, euler, rk2, rk4 |
//! | Izhikevich 2003 ([`izhikevich`]) | [`Izhikevich`] | [`IzhikevichParams`] (rs, ib, ch, fs, lts, tc, rz) | izhikevich2003, euler, exp-euler, rk2, rk4 |
//! | integrate-and-fire, no leak ([`integrate_and_fire`]; NIR's `IF`) | [`IntegrateAndFire`] | [`IfParams`] | exact, euler |
//!
//! Every population computes in `f32` or `f64` ([`Real`]), picks its [`Integrator`] and
//! optionally interpolates spike times inside the step. The integrators are written once in
//! [`integrate`]; state is structure-of-arrays in blocks ([`population`]), stepped by one fused,
//! branch-free update–threshold–reset loop that the compiler vectorises, on rayon's pool for
//! large populations. On CPUs with AVX-512 the two f64 loops that matter most, Izhikevich's
//! Euler step and LIF's exact step under synaptic currents (CUBA), run as 512-bit loops written
//! with intrinsics, which LLVM's 256-bit tuning would not emit; states and spikes are the
//! portable loops' bit for bit. A model file holds only its maths ([`BlockModel`]: parameters, block
//! state, the fused step); the builder, block allocation and `prepare`/`reset`/`step` are
//! [`BlockPopulation`]'s. Each model flags steps whose result left its dynamics (divergence;
//! see the models' docs), reported by [`neurotac_core::NeuronModel::check_divergence`].
//!
//! Populations can be saved with their network: [`NeuronModel::describe`] gives what a
//! population is (model, size, settings as JSON), [`NeuronModel::save_state`] where it is
//! (every number its next step depends on, event-driven bookkeeping included), and
//! [`BuiltinModels`] makes LIF and Izhikevich populations anew from their descriptions, which
//! [`NeuronModel::restore_state`] then puts where the saved one was, to continue bit for bit.
//!
//! [`NeuronModel::describe`]: neurotac_core::NeuronModel::describe
//! [`NeuronModel::save_state`]: neurotac_core::NeuronModel::save_state
//! [`NeuronModel::restore_state`]: neurotac_core::NeuronModel::restore_state
//!
//! Each model is also a [`ModelFamily`] ([`LifFamily`], [`IzhikevichFamily`]): the model at
//! every precision with the set-ups the applications run it in — its benchmark case, named
//! presets, afferent set-up and closed-form spike times if any — declared in the model's file.
//! Applications write generic code over a family and reach the one chosen at run time through a
//! [`FamilyVisitor`] ([`family`]), so a new model is its own file plus one registration.
//!
//! ```
//! use neurotac_neurons::{Integrator, Lif, LifParams};
//! use neurotac_core::{CurrentInput, NetworkBuilder, NetworkConfig};
//! let mut b = NetworkBuilder::new();
//! let lif = b.add_population("lif", Lif::<f32>::new(10, LifParams::default()).with_integrator(Integrator::Rk2))?;
//! let drive = b.add_current_input("drive", CurrentInput::constant(1.5))?;
//! b.inject(drive, lif)?;
//! let spikes = b.record_spikes(lif)?;
//! let mut net = b.build(NetworkConfig { dt_s: 1e-4 })?;
//! net.run(0.1, &neurotac_core::OneProcess)?;
//! assert!(net.readout(spikes)?.counts().iter().all(|&c| c == 9)); // period τ·ln 3 = 11 ms
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

#[cfg(target_arch = "x86_64")]
mod avx512;
mod builtin;
pub mod family;
pub mod integrate;
pub mod integrate_and_fire;
pub mod izhikevich;
pub mod lif;
pub mod population;
pub mod real;
pub mod run;
pub mod testing;

pub use builtin::BuiltinModels;
pub use family::{AfferentPreset, Benchmark, FamilyVisitor, ModelFamily, UpdateCost, check_family};
pub use integrate::{Integrator, UnknownIntegrator};
pub use integrate_and_fire::{IfModel, IfParams, IfState, IntegrateAndFire};
pub use izhikevich::{
    Izhikevich, IzhikevichFamily, IzhikevichModel, IzhikevichParams, IzhikevichState,
};
pub use lif::{Lif, LifFamily, LifModel, LifParams, LifState};
pub use population::{
    ActiveNeurons, ActiveStep, BlockModel, BlockPopulation, BlockStep, DIVERGENCE_CHECK_STEPS,
    Drive, InitialPotential, Population,
};
pub use real::Real;
pub use run::{DEFAULT_MAX_STEPS, RunError, stream_spike_times, whole_steps};
