//! The error type of `neurotac-experiments`.

use neurotac_core::{CodingError, DatasetError, DistanceError, GraphError, KnnError, RanksError};
use neurotac_sensor::{DeviceError, FormatError, TransductionError};
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
    /// See [`GraphError`] (a network such as the afferent one could not be built or run).
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// See [`KnnError`].
    #[error(transparent)]
    Knn(#[from] KnnError),
    /// See [`RanksError`] (the ranks sharing a computation could not exchange their parts).
    #[error(transparent)]
    Ranks(#[from] RanksError),
    /// A stratified split would leave a class out of the training or the test set.
    #[error(
        "class {class} has {samples} sample(s): the {percent}/{rest} split needs every class in both the training and the test set (use leave-one-out, which is defined for any class size)",
        percent = 100.0 - 100.0 * test_fraction,
        rest = 100.0 * test_fraction
    )]
    ClassTooSmallToSplit {
        /// The class label.
        class: usize,
        /// Its samples.
        samples: usize,
        /// The test fraction asked for.
        test_fraction: f64,
    },
    /// A search or protocol parameter outside its domain.
    #[error("{what} = {}: {expected}", neurotac_core::Compact(*value))]
    InvalidParameter {
        /// Parameter name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A coding was asked for without one of its parameters.
    #[error("the {coding} coding needs {what}")]
    MissingParameter {
        /// The coding (`temporal`, `spatiotemporal`).
        coding: &'static str,
        /// The missing parameter.
        what: &'static str,
    },
    /// See [`TransductionError`] (pixel events out of order or off the sensor, bad settings).
    #[error(transparent)]
    Transduction(#[from] TransductionError),
    /// See [`FormatError`] (an event file that cannot be read, naming file and offset).
    #[error(transparent)]
    Format(#[from] FormatError),
    /// See [`DeviceError`] (the camera failed or was unplugged).
    #[error(transparent)]
    Device(#[from] DeviceError),
    /// See [`DatasetsError`](crate::datasets::DatasetsError) (simulating or loading a texture set).
    #[error(transparent)]
    Datasets(#[from] Box<crate::datasets::DatasetsError>),
    /// A stream ended before its first event: nothing to decide.
    #[error("the event stream is empty: no event arrived, so there is nothing to recognise")]
    EmptyStream,
    /// A stated sample duration is shorter than the data it should hold.
    #[error(
        "sample duration {stated_ms} ms is shorter than the data, whose latest spike needs {needed_ms} ms"
    )]
    DurationShorterThanData {
        /// The duration given or stated by the dataset (ms).
        stated_ms: u32,
        /// One ms past the latest spike (ms).
        needed_ms: u32,
    },
}
