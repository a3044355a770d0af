//! # neurotac-core
//!
//! The core of neurotac, a spiking-neural-network framework for neuromorphic touch: the types
//! every other crate speaks and the network graph that runs spiking models.
//!
//! | concept | types |
//! |---|---|
//! | time (µs events, s spikes, one conversion) | [`Timestamp`], [`us_to_s`], [`s_to_us`] |
//! | pixel events | [`Event`], [`EventBuffer`] |
//! | spike trains | [`SpikeTrain`], [`MultiSpikeTrain`] (CSR, N channels) |
//! | labelled spike data | [`SpikeDataset`] (JSON and binary) |
//! | neuron-model interface | [`NeuronModel`], [`SpikeBuffer`] |
//! | the network graph | [`NetworkBuilder`] → [`Network`], [`ExpSynapse`], [`Connectivity`], [`SpikeArrayInput`], [`PoissonInput`], [`CurrentInput`] |
//! | readouts (monitors) | [`Readout`], [`SpikeRecorder`], [`StateRecorder`], [`SynapticTraceRecorder`] (both a [`TraceRecorder`]) |
//! | the paper's four codings (readouts, or direct on trains) | [`coding`]: [`IntensiveCoding`], [`SpatialCoding`], [`TemporalCoding`], [`SpatiotemporalCoding`] |
//! | distances and N×N matrices | [`distance`]: Euclidean, exact multi-unit [`VanRossum`], trace-sampled |
//! | the KNN head | [`knn`]: [`Knn`] (leave-one-out in one pass, documented tie rules) |
//! | several processes (MPI ranks, or threads in tests) | [`ranks`]: [`Ranks`], [`OneProcess`], [`ranks::balanced_blocks`] |
//! | special functions | [`special`]: `erfc` |
//! | seed hashes (names and parameters → seeds, seed mixing) | [`seed_hash`]: FNV-1a [`seed_hash::fnv1a`], SplitMix64 [`seed_hash::splitmix64`] |
//! | outputs never half-written | [`io`]: [`AtomicFile`], [`AtomicDir`], [`AtomicFileSet`] (committed together), [`Replace`], [`io::check_distinct`] and [`io::check_not_nested`] (outputs apart from inputs) |
//! | errors | [`SpikeError`], [`DatasetError`], [`GraphError`], [`ModelError`], [`CodingError`], [`DistanceError`], [`KnnError`], [`SameFileError`], [`NestedError`], [`ExistsError`], [`CoreError`] |
//!
//! Data flows one way through neurotac: sensor → core graph → readouts → experiments. Neuron
//! models (LIF, Izhikevich) live in `neurotac-neurons`; the DAVIS240 and the sensor simulator in
//! `neurotac-sensor`.
//!
//! ```
//! use neurotac_core::{MultiSpikeTrain, SpikeDataset};
//! let slide = MultiSpikeTrain::from_channels(vec![vec![0.010, 0.030], vec![0.020]])?;
//! let data = SpikeDataset::new(vec![slide], vec![0], vec!["5 mm".into()], Default::default())?;
//! assert_eq!(data.n_channels(), 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod coding;
mod compact;
mod currents;
pub mod dataset;
pub mod distance;
pub mod error;
pub mod event;
pub mod graph;
pub mod io;
pub mod knn;
pub mod model;
pub mod model_state;
pub mod ranks;
pub mod seed_hash;
pub mod special;
pub mod spikes;
#[doc(hidden)]
pub mod testing;
pub mod time;

pub use coding::{IntensiveCoding, SpatialCoding, SpatiotemporalCoding, TemporalCoding};
pub use compact::Compact;
pub use dataset::SpikeDataset;
pub use distance::VanRossum;
pub use error::{
    CodingError, CoreError, DatasetError, DistanceError, ExistsError, FilePosition, GraphError,
    IoAction, KnnError, ModelError, NestedError, Nesting, SameFileError, SpikeError, SpikeLocation,
    error_chain,
};
pub use event::{Event, EventBuffer};
pub use graph::{
    Connectivity, Crossovers, CurrentId, CurrentInput, DecayingCurrents, ExpSynapse, InputId,
    NETWORK_FILE_MAGIC, NETWORK_FILE_VERSION, NETWORK_FORMAT, NETWORK_VERSION, Network,
    NetworkBuilder, NetworkConfig, NetworkDescription, NetworkFileError, NodeDescription, NodeId,
    PoissonInput, PopulationId, PopulationStepping, ProjectionDescription, ProjectionId, Readout,
    ReadoutContext, ReadoutId, ReadoutSource, RunSummary, SourceDescription, SpikeArrayInput,
    SpikeRecorder, SpikeSource, StateRecorder, StateSampler, Stdp, StepView, Stepping,
    SteppingFileError, SteppingMode, Synapse, SynapticCurrentSampler, SynapticDrive,
    SynapticTraceRecorder, TraceInteraction, TraceRecorder, TraceSampler, WeightDependence,
    Weights, WiringDescription, one_spike_weight,
};
pub use io::{AtomicDir, AtomicFile, AtomicFileSet, Replace};
pub use knn::{Decision, FittedKnn, Knn};
pub use model::{ModelFactory, NeuronModel, SpikeBuffer};
pub use model_state::{ModelDescription, ModelState};
/// The `ndarray` version neurotac's matrices use (feature matrices, distance matrices), so user
/// code needs no matching dependency of its own.
pub use ndarray;
pub use ranks::{OneProcess, Ranks, RanksError};
pub use spikes::{MultiSpikeTrain, SpikeTrain};
pub use time::{Timestamp, s_to_us, us_to_s};
