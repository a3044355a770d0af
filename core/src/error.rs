//! Error types of `neurotac-core`, one enum per concern, chained into [`CoreError`].
//!
//! Following the Rust API guidelines, an error's message describes its own layer only; the
//! cause is its [`source`](std::error::Error::source). Print the whole chain (e.g. anyhow's
//! `{:#}`, or [`error_chain`]) to see every layer on one line.
//!
//! Build-time problems (a wrong shape, a dangling id) are [`GraphError`]s returned by
//! [`NetworkBuilder`](crate::NetworkBuilder) methods and `build()`; nothing in a built network's
//! run loop can fail on shapes.

use thiserror::Error;

mod data;
pub use data::{
    DatasetError, ExistsError, FilePosition, IoAction, NestedError, Nesting, SameFileError,
    SpikeError, SpikeLocation,
};

/// A network that cannot be built as described.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GraphError {
    /// A node id that this builder did not hand out.
    #[error("unknown node id {0}")]
    UnknownNode(usize),
    /// A projection id that this builder did not hand out.
    #[error("unknown projection id {0}")]
    UnknownProjection(usize),
    /// An id handed out by another [`NetworkBuilder`](crate::NetworkBuilder), used with this
    /// builder or with the [`Network`](crate::Network) built from it. Each builder brands the
    /// ids it hands out with a number of its own (kept by its network), so an id is never taken
    /// for whatever has the same index in another network.
    #[error(
        "{kind} id of network builder #{id_brand} used with builder #{builder_brand} (or its network): an id works only with the builder that handed it out and the network built from it"
    )]
    ForeignId {
        /// What the id names: "population", "spike input", "current input", "node",
        /// "projection" or "readout".
        kind: &'static str,
        /// The brand of the builder that handed the id out.
        id_brand: u64,
        /// The brand of the builder (or of the network built from it) it was used with.
        builder_brand: u64,
    },
    /// The node cannot play the role asked of it (e.g. a current source as a spike source).
    #[error("node '{node}' is a {kind}, which cannot be {role}")]
    WrongRole {
        /// Node name.
        node: String,
        /// What the node is.
        kind: &'static str,
        /// What was asked of it.
        role: &'static str,
    },
    /// Sizes that do not match (e.g. a one-to-one projection between 49 and 48 neurons).
    #[error("{what}: expected {expected}, got {got}")]
    SizeMismatch {
        /// What was being connected.
        what: String,
        /// Expected size.
        expected: usize,
        /// Given size.
        got: usize,
    },
    /// An explicit synapse names a neuron outside its population.
    #[error("{what}: synapse {index} names neuron {neuron}, but the population has {size}")]
    IndexOutOfRange {
        /// Which side and projection.
        what: String,
        /// Position in the synapse list.
        index: usize,
        /// The neuron named.
        neuron: usize,
        /// The population size.
        size: usize,
    },
    /// A parameter outside its domain (non-finite weight, τ ≤ 0, dt ≤ 0, rate < 0 …).
    #[error("{what} = {}: {expected}", crate::Compact(*value))]
    InvalidParameter {
        /// Parameter name, with its owner.
        what: String,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A neuron model refused its parameters or the time step.
    #[error("population '{population}'")]
    Model {
        /// Population name.
        population: String,
        /// The model's error.
        source: ModelError,
    },
    /// Two nodes with the same name.
    #[error("duplicate node name '{0}'")]
    DuplicateName(String),
    /// A rank outside its group, or a group of no rank
    /// ([`NetworkBuilder::build_partitioned`](crate::NetworkBuilder::build_partitioned)).
    #[error("rank {rank} of {size} ranks: expected at least one rank and rank < size")]
    InvalidPartition {
        /// The rank given.
        rank: usize,
        /// The number of ranks given.
        size: usize,
    },
    /// A population whose model cannot be split over ranks
    /// ([`NeuronModel::restrict`](crate::NeuronModel::restrict) returned `None`).
    #[error(
        "population '{population}' cannot be partitioned over ranks: its model ({model}) does not restrict to a block of neurons"
    )]
    ModelNotPartitionable {
        /// Population name.
        population: String,
        /// Model name.
        model: &'static str,
    },
    /// A readout that needs what only one rank holds (a population's state, a projection's
    /// synaptic currents) in a network partitioned over several ranks.
    #[error("the readout of {node} cannot run partitioned over {ranks} ranks: {reason}")]
    ReadoutNotPartitionable {
        /// The readout's source (a node or a projection).
        node: String,
        /// The number of ranks.
        ranks: usize,
        /// Why.
        reason: &'static str,
    },
    /// A network run on a group of ranks other than the one it was built for (a partitioned
    /// network run with [`Network::run`](crate::Network::run) counts as rank 0 of 1).
    #[error(
        "network built for rank {built_rank} of {built_size} ranks, run as rank {rank} of {size}"
    )]
    RanksMismatch {
        /// The rank the network was built for.
        built_rank: usize,
        /// The number of ranks it was built for.
        built_size: usize,
        /// The rank of the group it was run on.
        rank: usize,
        /// The size of that group.
        size: usize,
    },
    /// The spike exchange between ranks failed (communication error or a malformed message).
    #[error("spike exchange of the steps before step {step} failed: {reason}")]
    Exchange {
        /// The first step after the exchanged epoch.
        step: u64,
        /// What went wrong.
        reason: String,
    },
    /// Another rank's population diverged (that rank's own error names the population); every
    /// rank stops at the same exchange.
    #[error("rank {rank} reported a numerical divergence before step {step}")]
    PeerDiverged {
        /// The first rank that reported one.
        rank: usize,
        /// The first step after the exchanged epoch.
        step: u64,
    },
    /// A node or projection dropped at build because no readout depends on it (see
    /// [`Network::pruned_nodes`](crate::Network::pruned_nodes)): it has no weights or state.
    #[error("{what} was dropped at build (no readout depends on it)")]
    Pruned {
        /// What was asked for.
        what: String,
    },
    /// No node has this name.
    #[error("no node is named '{0}'")]
    UnknownName(String),
    /// A node, model or source that cannot be saved or described (see
    /// [`Network::save`](crate::Network::save)).
    #[error("{node} cannot be saved or described: {reason}")]
    NotSaveable {
        /// The node.
        node: String,
        /// Why.
        reason: String,
    },
    /// A network description (or saved network) that does not describe a network this
    /// version builds: another format or version, a reference to a node that does not exist.
    #[error("network description: {0}")]
    Description(String),
    /// A part of a network whose memory the machine cannot give (see
    /// [`limits`](crate::graph::limits)).
    #[error("{what} needs {} bytes, more than can be allocated", crate::Compact(*bytes))]
    TooLarge {
        /// The part.
        what: String,
        /// The bytes it needs (∞ when the count overflows).
        bytes: f64,
    },
    /// A plastic projection's weight (initial, or set) outside its STDP bounds.
    #[error("{what}: {kind} weight {} of synapse {synapse} is outside the STDP bounds [{}, {}]", crate::Compact(*weight), crate::Compact(*w_min), crate::Compact(*w_max))]
    WeightOutsideBounds {
        /// The projection.
        what: String,
        /// `initial` (at connect) or `new` (set).
        kind: &'static str,
        /// The synapse (0 for a connectivity with one weight).
        synapse: usize,
        /// Its weight.
        weight: f64,
        /// The lower bound.
        w_min: f64,
        /// The upper bound.
        w_max: f64,
    },
    /// The saved network `path` does not fit the network built from it.
    #[error("saved network {}", path.display())]
    Saved {
        /// The file.
        path: std::path::PathBuf,
        /// What does not fit.
        source: Box<GraphError>,
    },
    /// A projection that is not plastic, asked for something only plastic ones have.
    #[error("projection {projection} is not plastic (connect it with connect_plastic)")]
    NotPlastic {
        /// The projection's builder index.
        projection: usize,
    },
}

/// A neuron model that rejects its parameters, integrator or time step.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A parameter outside its domain.
    #[error("{model}: parameter {field} = {}: {expected}", crate::Compact(*value))]
    InvalidParameter {
        /// Model name.
        model: &'static str,
        /// Parameter name.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// The model has no implementation of this integrator.
    #[error("{model} does not support the {integrator} integrator (supported: {supported})")]
    UnsupportedIntegrator {
        /// Model name.
        model: &'static str,
        /// Integrator asked for.
        integrator: &'static str,
        /// Integrators it supports.
        supported: &'static str,
    },
    /// An input value that is NaN or infinite.
    #[error("{model}: input to neuron {neuron} is {value}, not finite")]
    NonFiniteInput {
        /// Model name.
        model: &'static str,
        /// Neuron index.
        neuron: usize,
        /// The value.
        value: f64,
    },
    /// A finite input value that the population's precision cannot hold (e.g. `1e39` in `f32`).
    #[error(
        "{model}: input to neuron {neuron} is {value}, beyond the {precision} range (|x| ≤ {max:e})"
    )]
    InputOutOfRange {
        /// Model name.
        model: &'static str,
        /// Neuron index.
        neuron: usize,
        /// The value.
        value: f64,
        /// The population's precision (`"f32"`).
        precision: &'static str,
        /// The largest magnitude it holds.
        max: f64,
    },
    /// The numerical solution left the model's dynamics (see the model's divergence criterion):
    /// what it would report as spikes are artefacts of the time step or the integrator.
    #[error(
        "{model} diverged in step {step} (t = {t_s} s, dt = {dt_s} s, {integrator} integrator): {what}; use a smaller dt or another integrator"
    )]
    Diverged {
        /// Model name.
        model: &'static str,
        /// The first step (0-based, from `step·dt` to `(step + 1)·dt`) the criterion flagged.
        step: u64,
        /// Start time of that step (s).
        t_s: f64,
        /// The time step (s).
        dt_s: f64,
        /// The integrator.
        integrator: &'static str,
        /// What the criterion detected.
        what: &'static str,
    },
    /// A state variable name the model does not have.
    #[error("{model} has no state variable '{name}' (has: {available})")]
    UnknownVariable {
        /// Model name.
        model: &'static str,
        /// Variable asked for.
        name: String,
        /// Variables it has.
        available: String,
    },
    /// A saved model state that does not fit the model
    /// ([`NeuronModel::restore_state`](crate::NeuronModel::restore_state)).
    #[error("{model}: cannot restore the saved state: {reason}")]
    State {
        /// Model name.
        model: &'static str,
        /// What does not fit.
        reason: String,
    },
    /// A model that cannot be saved or described (it does not implement
    /// [`NeuronModel::describe`](crate::NeuronModel::describe)).
    #[error("{model}: this model cannot be saved or exported (it has no description)")]
    NotSaveable {
        /// Model name.
        model: &'static str,
    },
    /// A description of a model the factory does not make, or with settings it refuses.
    #[error("cannot make model '{model}': {reason}")]
    UnknownModel {
        /// The model name in the description.
        model: String,
        /// Why (not a model this factory makes, or which setting is wrong).
        reason: String,
    },
}

/// A coding (intensive, spatial, temporal, spatiotemporal) that cannot be computed as asked.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CodingError {
    /// A parameter outside its domain (window or duration ≤ 0, not finite, …).
    #[error("{what} = {}: {expected}", crate::Compact(*value))]
    InvalidParameter {
        /// Parameter name, with its owner.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A feature matrix larger than the budget ([`MAX_FEATURE_VALUES`](crate::coding::MAX_FEATURE_VALUES)).
    #[error(
        "{samples} samples × {features} features: more than the limit of {limit} feature values"
    )]
    TooManyFeatures {
        /// Rows (samples).
        samples: usize,
        /// Columns (features per sample).
        features: usize,
        /// The limit.
        limit: usize,
    },
    /// The temporal window is longer than the sample duration, so there is no window at all.
    #[error(
        "temporal window of {window_ms} ms is longer than the sample duration of {duration_ms} ms"
    )]
    WindowLongerThanSample {
        /// Window width Δt (ms).
        window_ms: u32,
        /// Sample duration T (ms).
        duration_ms: u32,
    },
    /// A spike before time 0, which no sample window covers.
    #[error(
        "sample {sample}, channel {channel}: spike at {time_s} s, before the sample start (0 s)"
    )]
    SpikeBeforeZero {
        /// Index of the sample.
        sample: usize,
        /// The channel of the spike.
        channel: usize,
        /// The spike time (s).
        time_s: f64,
    },
    /// An observation with a different channel count than the coding was set up for.
    #[error("sample {sample} has {got} channels, expected {expected}")]
    ChannelCount {
        /// Index of the sample.
        sample: usize,
        /// Channels expected.
        expected: usize,
        /// Channels of this sample.
        got: usize,
    },
}

/// A distance that cannot be computed as asked.
#[derive(Debug, Error)]
pub enum DistanceError {
    /// A parameter outside its domain (τ ≤ 0 or not finite, cos θ outside [0, 1], dt ≤ 0 …).
    #[error("{what} = {}: {expected}", crate::Compact(*value))]
    InvalidParameter {
        /// Parameter name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// Samples with different channel (unit) counts.
    #[error("sample {sample} has {got} channels, sample 0 has {expected}")]
    ChannelCount {
        /// Index of the sample.
        sample: usize,
        /// Channels of sample 0.
        expected: usize,
        /// Channels of this sample.
        got: usize,
    },
    /// Feature rows of different lengths.
    #[error("feature row {row} has {got} values, row 0 has {expected}")]
    FeatureLength {
        /// Index of the row.
        row: usize,
        /// Length of row 0.
        expected: usize,
        /// Length of this row.
        got: usize,
    },
    /// A feature value that is NaN or infinite.
    #[error("feature row {row}, column {column}: value {value} is not finite")]
    NonFiniteFeature {
        /// Row (sample).
        row: usize,
        /// Column (feature).
        column: usize,
        /// The value.
        value: f64,
    },
    /// A spike time that is NaN or infinite.
    #[error("sample {sample}")]
    Spikes {
        /// Index of the sample.
        sample: usize,
        /// The spike error.
        source: SpikeError,
    },
    /// A sample whose trace record cannot be made (a spike before 0, or a step that is not a
    /// whole number of µs).
    #[error("sample {sample}: trace record")]
    TraceRecord {
        /// Index of the sample.
        sample: usize,
        /// Why.
        source: CodingError,
    },
    /// Two matrices that must have the same shape (e.g. LL² and SP²) do not.
    #[error("{what}: shape {got:?}, expected {expected:?}")]
    Shape {
        /// What was combined.
        what: &'static str,
        /// Expected shape.
        expected: (usize, usize),
        /// Given shape.
        got: (usize, usize),
    },
    /// The ranks sharing a matrix could not exchange their rows (the `…_on` functions of
    /// [`distance`](crate::distance)).
    #[error("exchanging distance-matrix rows between ranks")]
    Ranks(#[from] crate::ranks::RanksError),
}

/// A KNN classification or protocol that cannot run as asked.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KnnError {
    /// k = 0.
    #[error("k must be at least 1")]
    ZeroK,
    /// More neighbours asked for than there are training samples.
    #[error("k = {k} but the training set has only {n_train} samples")]
    KTooLarge {
        /// Neighbours asked for.
        k: usize,
        /// Training samples available.
        n_train: usize,
    },
    /// A distance matrix that is not square or does not match the labels.
    #[error("distance matrix is {rows}×{cols} but there are {labels} labels")]
    Shape {
        /// Rows of the matrix.
        rows: usize,
        /// Columns of the matrix.
        cols: usize,
        /// Number of labels.
        labels: usize,
    },
    /// A distance that is NaN (or negative), which no ranking can use.
    #[error("distance between samples {row} and {col} is {value}, not a number ≥ 0")]
    InvalidDistance {
        /// Row (query sample).
        row: usize,
        /// Column (training sample).
        col: usize,
        /// The value.
        value: f64,
    },
    /// A sample index outside the matrix (in a train or test index list).
    #[error("{what}: sample index {index} out of range for {n} samples")]
    IndexOutOfRange {
        /// Which list.
        what: &'static str,
        /// The index.
        index: usize,
        /// Number of samples.
        n: usize,
    },
    /// A protocol parameter outside its domain (folds < 2, test fraction outside (0, 1) …).
    #[error("{what} = {}: {expected}", crate::Compact(*value))]
    InvalidParameter {
        /// Parameter name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A protocol that needs labels got an unlabelled dataset.
    #[error("the dataset has no labels; classification needs one label per sample")]
    Unlabelled,
}

/// Any error of `neurotac-core`.
#[derive(Debug, Error)]
pub enum CoreError {
    /// See [`SpikeError`].
    #[error(transparent)]
    Spike(#[from] SpikeError),
    /// See [`DatasetError`].
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// See [`GraphError`].
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// See [`ModelError`].
    #[error(transparent)]
    Model(#[from] ModelError),
    /// See [`CodingError`].
    #[error(transparent)]
    Coding(#[from] CodingError),
    /// See [`DistanceError`].
    #[error(transparent)]
    Distance(#[from] DistanceError),
    /// See [`KnnError`].
    #[error(transparent)]
    Knn(#[from] KnnError),
    /// See [`SameFileError`].
    #[error(transparent)]
    SameFile(#[from] SameFileError),
    /// See [`NestedError`].
    #[error(transparent)]
    Nested(#[from] NestedError),
}

/// Formats an error and its chain of sources on one line, `outer: inner: innermost`.
pub fn error_chain(error: &dyn std::error::Error) -> String {
    let mut out = error.to_string();
    let mut next = error.source();
    while let Some(e) = next {
        out.push_str(": ");
        out.push_str(&e.to_string());
        next = e.source();
    }
    out
}
