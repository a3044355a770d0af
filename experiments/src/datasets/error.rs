//! Why a dataset could not be simulated, read or written ([`DatasetsError`]).

use crate::threads::ThreadPoolError;
use neurotac_core::{DatasetError, RanksError};
use neurotac_sensor::sim::SimulationError;
use std::path::PathBuf;

/// Dataset generation that cannot proceed.
#[derive(Debug, thiserror::Error)]
pub enum DatasetsError {
    /// The simulator rejected its set-up.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// Pixel events could not be transduced or filtered.
    #[error(transparent)]
    Transduction(#[from] neurotac_sensor::error::TransductionError),
    /// A dataset could not be built, read or written.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// An event file could not be written.
    #[error(transparent)]
    Format(#[from] neurotac_sensor::FormatError),
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The thread pool could not start.
    #[error(transparent)]
    Threads(#[from] ThreadPoolError),
    /// The ranks sharing the simulation could not exchange their trials.
    #[error(transparent)]
    Ranks(#[from] RanksError),
}
