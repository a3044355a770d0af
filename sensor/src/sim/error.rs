//! Errors of the NeuroTac simulator ([`SimulationError`]).

use std::path::PathBuf;
use thiserror::Error;

/// A simulation that cannot be set up or run.
#[derive(Debug, Error)]
pub enum SimulationError {
    /// A parameter outside its physical domain (negative size, threshold, NaN, …).
    #[error("parameter `{field}` = {}: {expected}", neurotac_core::Compact(*value))]
    InvalidParameter {
        /// The parameter, as spelled in the parameter file (`group.field`).
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A texture name that is neither a bump grid nor one of the 20 natural textures.
    #[error("unknown texture `{name}` (expected `grid <d> mm` with d in 0…5 or one of: {known})")]
    UnknownTexture {
        /// The name given.
        name: String,
        /// The names that exist.
        known: String,
    },
    /// A request for zero trials.
    #[error("`trials` = 0: at least one trial per texture is needed")]
    ZeroTrials,
    /// More trials than a run may simulate.
    #[error(
        "`trials` = {trials} slides of each of {textures} textures: more than the limit of \
         {limit} simulated trials per run"
    )]
    TooManyTrials {
        /// Slides per texture asked for.
        trials: usize,
        /// Textures slid over.
        textures: usize,
        /// The limit (the simulator's `MAX_TRIALS`).
        limit: usize,
    },
    /// A parameter file that cannot be read.
    #[error("cannot read parameter file {path}")]
    ParamsIo {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A parameter file that is not a complete JSON parameter set (serde names the missing or
    /// unknown field).
    #[error("{path}: not a simulator parameter set")]
    ParamsJson {
        /// The file.
        path: PathBuf,
        /// The parser's error (names the field).
        source: serde_json::Error,
    },
    /// The simulated events could not be transduced to taxel spikes.
    #[error("transducing the simulated events")]
    Transduction(#[from] crate::error::TransductionError),
    /// The pin geometry does not fit the simulator (no pins, or more than 254).
    #[error("pin geometry with {pins} pins: 1 to 254 pins are supported")]
    Geometry {
        /// Pins in the geometry.
        pins: usize,
    },
}
