//! The network graph: defined in Rust code with a [`NetworkBuilder`], run by a [`Network`].
//!
//! Nodes are populations ([`NeuronModel`](crate::NeuronModel)s), spike sources ([`SpikeSource`]s:
//! recorded arrays, Poisson) and current sources ([`CurrentInput`]). Projections connect a
//! spike-emitting node to a population through exponential current synapses ([`ExpSynapse`],
//! [`Connectivity`]). Readouts ([`Readout`]) watch a node or projection.
//!
//! # Only what a readout needs is modelled
//! [`NetworkBuilder::build`] walks back from every readout: a readout needs its source; a
//! population needs every projection and current that feeds it; a projection needs its
//! presynaptic node. Everything else is dropped before it is prepared: an unreferenced
//! population is never allocated, validated against `dt` or stepped, and random connectivity
//! is drawn only for needed projections. [`Network::pruned_nodes`] lists what was dropped.
//!
//! # Phase order of one step
//! Step `k` advances time from `t_k = k·dt` to `t_k + dt`:
//! 0. **stepping**: a population stepped automatically ([`Stepping::Auto`]) whose measured
//!    activity calls for it switches between clock- and event-driven stepping (see
//!    [`Stepping`]);
//! 1. **inputs**: every spike source emits the spikes that fall in `[t_k, t_k + dt)`;
//! 2. **synapses**: every projection adds the weights of the presynaptic spikes emitted `delay`
//!    steps ago (this step's, for delay 0 from an input) to its currents, giving `I(t_k)`;
//! 3. **integration**: every population sums its projections' currents `I(t_k)` and direct
//!    currents (evaluated at `t_k`) and advances one step, holding that input constant; in the
//!    same pass each projection's currents decay exactly to `I(t_k + dt) = I(t_k)·e^(−dt/τ)`.
//!    A clock-driven population fed by one or two projections and nothing else gets them as a
//!    [`SynapticDrive`] ([`NeuronModel::step_synaptic`](crate::NeuronModel::step_synaptic)), so
//!    the model can sum and decay the currents inside its own update loop (LIF does);
//! 4. **threshold/reset**: inside the model's step, which pushes this step's spikes;
//! 5. **readouts**: each sees this step's spikes of its source, the population state at
//!    `t_k + dt`, or the projection currents at `t_k + dt` (decayed, before the next delivery).
//!    In a run over several ranks, the readouts see an epoch's steps after its spike exchange
//!    (spikes only; see [`Network::run_steps`]).
//!
//! # Partitioned over ranks
//! [`NetworkBuilder::build_partitioned`] builds one rank's share of a network that several
//! ranks ([`Ranks`](crate::Ranks): MPI processes, or threads in tests) compute together: each
//! population is split into contiguous blocks of neurons, one per rank, inputs are replicated,
//! and each rank keeps the synapses onto its own neurons. [`Network::run`] steps the local
//! neurons and exchanges spikes once per epoch (the smallest population → population delay),
//! so readouts see, and end with, exactly the spikes of one process.
//!
//! ```
//! use neurotac_core::{ExpSynapse, Connectivity, MultiSpikeTrain, NetworkBuilder, NetworkConfig, SpikeArrayInput};
//! # use neurotac_core::{NeuronModel, SpikeBuffer, ModelError};
//! # struct Relay(usize);
//! # impl NeuronModel for Relay {
//! #   fn model_name(&self) -> &'static str { "relay" }
//! #   fn len(&self) -> usize { self.0 }
//! #   fn variables(&self) -> &'static [&'static str] { &[] }
//! #   fn prepare(&mut self, _: f64) -> Result<(), ModelError> { Ok(()) }
//! #   fn reset(&mut self) {}
//! #   fn step(&mut self, i: &[f64], s: &mut SpikeBuffer) { for (k, &x) in i.iter().enumerate() { if x > 0.5 { s.push(k as u32) } } }
//! #   fn read_variable(&self, _: usize, _: &[u32], _: &mut Vec<f64>) {}
//! # }
//! let taxels = MultiSpikeTrain::from_channels(vec![vec![0.0105], vec![]])?;
//! let mut b = NetworkBuilder::new();
//! let input = b.add_spike_input("taxels", SpikeArrayInput::new(taxels))?;
//! let relay = b.add_population("relay", Relay(2))?;
//! b.connect(input, relay, Connectivity::OneToOne { weight: 1.0 }, ExpSynapse::new(5e-3).with_delay(0))?;
//! let spikes = b.record_spikes(relay)?;
//! let mut net = b.build(NetworkConfig { dt_s: 1e-3 })?;
//! net.run(0.02, &neurotac_core::OneProcess)?;
//! // The current is e^(−k·dt/τ) in the k-th step after the spike: above 0.5 for k = 0..=3.
//! assert_eq!(net.readout(spikes)?.counts(), vec![4, 0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod builder;
mod description;
mod exchange;
mod ids;
mod input;
mod inspect;
pub mod limits;
mod names;
mod network;
mod partitioned;
mod readout;
mod running;
mod saved;
mod snapshot;
mod stepping;
mod synapse;
mod weight;

pub use crate::currents::{DecayingCurrents, FLUSH_TO_ZERO, SynapticDrive};
pub use builder::NetworkBuilder;
pub use description::{
    NETWORK_FORMAT, NETWORK_VERSION, NetworkDescription, NodeDescription, ProjectionDescription,
    WiringDescription,
};
pub use ids::{
    CurrentId, InputId, NetworkConfig, NodeId, PopulationId, ProjectionId, ReadoutId,
    ReadoutSource, SpikingNode,
};
pub use input::{CurrentInput, PoissonInput, SourceDescription, SpikeArrayInput, SpikeSource};
pub use network::{DEFAULT_EPOCH_STEPS, Network, RunSummary};
pub use readout::{
    Readout, ReadoutContext, SpikeRecorder, StateRecorder, StateSampler, StepView,
    SynapticCurrentSampler, SynapticTraceRecorder, TraceRecorder, TraceSampler,
};
pub use saved::{NETWORK_FILE_MAGIC, NETWORK_FILE_VERSION, NetworkFileError};
pub use stepping::{
    CLOCK_SAMPLE_STEPS, CROSSOVER_FILE_NAME, Crossovers, DECISION_WINDOW_STEPS, EVENT_CHECK_STEPS,
    HYSTERESIS, MAX_CROSSOVER_FILE_BYTES, PopulationStepping, Stepping, SteppingFileError,
    SteppingMode,
};
pub use synapse::{
    Connectivity, ExpSynapse, Stdp, Synapse, TraceInteraction, WeightDependence, Weights,
};
pub use weight::one_spike_weight;

#[cfg(test)]
mod tests;
