//! Error types of `neurotac-sensor`.

use std::path::PathBuf;
use thiserror::Error;

/// Transduction (filters, receptive fields, pooling, layouts) that cannot proceed.
#[derive(Debug, Error)]
pub enum TransductionError {
    /// An event outside the sensor's pixel array.
    #[error("event {index}: pixel ({x}, {y}) is outside the {width} × {height} sensor")]
    OutOfRange {
        /// Position of the event in the stream.
        index: u64,
        /// Column.
        x: u16,
        /// Row.
        y: u16,
        /// Sensor width.
        width: u16,
        /// Sensor height.
        height: u16,
    },
    /// An event earlier than the one before it.
    #[error(
        "event {index}: timestamp {got_us} µs is earlier than the previous {previous_us} µs (streams must not go back in time)"
    )]
    Backwards {
        /// Position of the event in the stream.
        index: u64,
        /// The previous timestamp.
        previous_us: i64,
        /// The offending timestamp.
        got_us: i64,
    },
    /// An event before the recording origin the pooling windows are aligned to.
    #[error("event {index}: timestamp {got_us} µs is before the recording origin {origin_us} µs")]
    BeforeOrigin {
        /// Position of the event in the stream.
        index: u64,
        /// The origin.
        origin_us: i64,
        /// The offending timestamp.
        got_us: i64,
    },
    /// A parameter outside its domain.
    #[error("{what} = {value}: {expected}")]
    InvalidParameter {
        /// Parameter name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A layout with the wrong number of taxels.
    #[error("layout has {got} taxels, {expected} required")]
    LayoutCount {
        /// Taxels required.
        expected: usize,
        /// Taxels given.
        got: usize,
    },
    /// A taxel centre outside the image or not finite.
    #[error("taxel {taxel} centre ({x}, {y}) is outside the {width} × {height} image")]
    LayoutOutOfImage {
        /// Taxel index.
        taxel: usize,
        /// Centre x (px).
        x: f64,
        /// Centre y (px).
        y: f64,
        /// Image width.
        width: u16,
        /// Image height.
        height: u16,
    },
    /// Two receptive fields that overlap.
    #[error(
        "taxels {a} and {b} are {distance_px:.2} px apart: receptive fields of radius {radius_px} px overlap (need ≥ {min_px} px)"
    )]
    LayoutOverlap {
        /// First taxel.
        a: usize,
        /// Second taxel.
        b: usize,
        /// Their distance (px).
        distance_px: f64,
        /// The receptive-field radius (px).
        radius_px: f64,
        /// The smallest allowed distance (px).
        min_px: f64,
    },
    /// A layout file that cannot be read.
    #[error("cannot read layout file {path}")]
    LayoutIo {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A layout file that is not a JSON list of `[x, y]` centres.
    #[error("{path}: not a taxel layout (expected a JSON list of [x, y] centres in px)")]
    LayoutJson {
        /// The file.
        path: PathBuf,
        /// The parser's error.
        source: serde_json::Error,
    },
}

/// `Ok` when pixel `(x, y)` lies on a `width × height` sensor, else
/// [`TransductionError::OutOfRange`] naming event `index`.
#[inline]
pub(crate) fn check_in_sensor(
    index: u64,
    x: u16,
    y: u16,
    width: u16,
    height: u16,
) -> Result<(), TransductionError> {
    if x >= width || y >= height {
        return Err(TransductionError::OutOfRange {
            index,
            x,
            y,
            width,
            height,
        });
    }
    Ok(())
}
