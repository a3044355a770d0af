//! [`TradeoffError`]: why a trade could not be measured or written, shared by every trade,
//! the table writers ([`super::table`]) and the study ([`super::study`]).

use crate::bench::BenchError;
use crate::report::png::PngError;
use neurotac_experiments::datasets::DatasetsError;
use neurotac_experiments::error::ExperimentError;
use std::path::PathBuf;

/// Why a trade could not be measured or written.
#[derive(Debug, thiserror::Error)]
pub enum TradeoffError {
    /// A neuron benchmark failed.
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// A distance or parameter was refused.
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// The simulator failed.
    #[error(transparent)]
    Simulation(#[from] DatasetsError),
    /// A parameter outside its domain.
    #[error("{what} = {}: {expected}", neurotac_core::Compact(*value))]
    InvalidParameter {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A family that re-simulates the set was asked of a recorded set.
    #[error("the {family} family re-simulates its set: it needs a simulated set, not --dataset")]
    NeedsSimulation {
        /// The family.
        family: String,
    },
    /// A figure could not be rasterised to PNG.
    #[error("cannot draw {path}")]
    Png {
        /// The PNG file.
        path: PathBuf,
        /// Why.
        source: PngError,
    },
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}
