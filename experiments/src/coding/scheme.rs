//! What a coding of the menu is ([`CodingScheme`]): its readout in a network and offline, its
//! distance matrix, its run through the pipeline (with its parameter search, if it has one)
//! and its online scorer. Each coding implements it in its own file; the registration list in
//! [`crate::coding`] makes the menu of them.

use crate::coding::encoded::{EncodedSet, Readout, SetReadout, VrFrom};
use crate::error::ExperimentError;
use crate::scoring::{PipelineRun, Scored};
use ndarray::Array2;
use neurotac_core::{MultiSpikeTrain, Network, NetworkBuilder, Ranks, ReadoutSource};

/// The parameters of a coding; each coding reads only its own.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CodingParameters {
    /// Temporal: the window Δt (ms).
    pub window_ms: Option<u32>,
    /// Temporal: the sample duration (ms), e.g. from
    /// [`sample_duration_ms`](crate::coding::sample_duration_ms); default one ms past the
    /// latest spike.
    pub duration_ms: Option<u32>,
    /// Spatiotemporal: the Van Rossum kernel time constant τ (s).
    pub tau_s: Option<f64>,
    /// Spatiotemporal: cos θ in [0, 1].
    pub cos: Option<f64>,
}

/// The error naming `what` as missing for the coding `key`.
pub fn missing(key: &'static str, what: &'static str) -> ExperimentError {
    ExperimentError::MissingParameter { coding: key, what }
}

/// What a readout is built for: the set's channels and sample duration, and where the Van
/// Rossum distance comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReadoutContext {
    /// Channels per sample.
    pub n_channels: usize,
    /// Sample duration the readouts cover (ms).
    pub duration_ms: u32,
    /// Exact Van Rossum, or from traces (the spatiotemporal readout records them).
    pub vr_from: VrFrom,
}

/// Reads one sample's readout from a network that has run it: a set of one sample.
pub type SampleReader =
    Box<dyn Fn(&Network) -> Result<Box<dyn SetReadout>, ExperimentError> + Send>;

/// A [`SampleReader`] from `read`, which gives the sample's readout.
pub fn sample_reader<T: Readout>(
    read: impl Fn(&Network) -> Result<T, ExperimentError> + Send + 'static,
) -> SampleReader {
    Box::new(move |network| Ok(Box::new(vec![read(network)?])))
}

/// The readout `key` wrote into `set`, or the error saying it is missing (a set encoded
/// without that coding).
pub fn readout_of<'a, T: Readout>(
    set: &'a EncodedSet,
    key: &'static str,
) -> Result<&'a [T], ExperimentError> {
    set.readout(key)
        .ok_or_else(|| missing(key, "its readout in the encoded set"))
}

/// One coding of the menu. Implemented by a unit struct in the coding's own file
/// (`experiments/src/coding/<key>.rs`), registered once in [`crate::coding`]'s `codings!`
/// list.
pub trait CodingScheme: Sync {
    /// The menu key (CLI value, file names): `intensive`.
    fn key(&self) -> &'static str;

    /// The name in prose and table headers: `Intensive`.
    fn label(&self) -> &'static str;

    /// Its parameters as a report prints them (`Δt = 159 ms`); empty without parameters or
    /// when they are not set.
    fn describe(&self, parameters: &CodingParameters) -> String;

    /// Adds its readout of `source` to a readout network and returns the reader of one
    /// sample's readout.
    fn add_readout(
        &self,
        builder: &mut NetworkBuilder,
        source: ReadoutSource,
        context: &ReadoutContext,
    ) -> Result<SampleReader, ExperimentError>;

    /// The same readouts, sample by sample, from finished spike trains (no network).
    fn encode(
        &self,
        trains: &[MultiSpikeTrain],
        context: &ReadoutContext,
    ) -> Result<Box<dyn SetReadout>, ExperimentError>;

    /// The N × N distance matrix of `set`'s samples at `parameters`, split over `ranks`
    /// (every rank returns the whole one-process matrix; collective).
    fn distances(
        &self,
        set: &EncodedSet,
        parameters: &CodingParameters,
        ranks: &dyn Ranks,
    ) -> Result<Array2<f64>, ExperimentError>;

    /// Its run through the pipeline: its parameter search, if it has one, then the scoring
    /// at the chosen parameters ([`PipelineRun::score`]).
    fn pipeline(&self, set: &EncodedSet, run: &PipelineRun<'_>) -> Result<Scored, ExperimentError>;

    /// Its training side for online recognition, prepared once from `training` at
    /// `parameters`.
    fn online<'a>(
        &self,
        training: &'a EncodedSet,
        parameters: &CodingParameters,
    ) -> Result<Box<dyn OnlineScorer + 'a>, ExperimentError>;
}

/// A coding's training side for online recognition, prepared once and shared by every live
/// stream.
pub trait OnlineScorer: Send + Sync {
    /// A live side for one stream.
    fn live(&self) -> Box<dyn LiveScorer + '_>;
}

/// A coding's live side, grown window by window.
pub trait LiveScorer {
    /// The distances from the live sample's prefix `[0, t_end_s)` to the same prefix of every
    /// training sample, in training order; `t_end_s = +∞` compares whole samples exactly as
    /// the offline classifier does. Called with increasing `t_end_s`.
    fn distances(
        &mut self,
        live: &MultiSpikeTrain,
        t_end_s: f64,
    ) -> Result<Vec<f64>, ExperimentError>;
}

/// The spikes of `train` before `t_end_s`.
pub fn before(train: &[f64], t_end_s: f64) -> &[f64] {
    &train[..train.partition_point(|&t| t < t_end_s)]
}
