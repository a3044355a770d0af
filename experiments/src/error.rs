//! The error type of `neurotac-experiments`.

use neurotac_core::{CodingError, DatasetError, DistanceError, KnnError};
use thiserror::Error;

/// Anything that stops an experiment, protocol or search.
#[derive(Debug, Error)]
pub enum ExperimentError {
    /// See [`DatasetError`].
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// See [`CodingError`].
    #[error(transparent)]
    Coding(#[from] CodingError),
    /// See [`DistanceError`].
    #[error(transparent)]
    Distance(#[from] DistanceError),
    /// See [`KnnError`].
    #[error(transparent)]
    Knn(#[from] KnnError),
    /// A search or protocol parameter outside its domain.
    #[error("{what} = {value}: {expected}")]
    InvalidParameter {
        /// Parameter name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
}
