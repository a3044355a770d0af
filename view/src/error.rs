//! [`ViewError`]: what can go wrong between a stream and the page.

use neurotac_sensor::TransductionError;

/// Errors of the live view.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// A setting outside its range.
    #[error("invalid {what}: {value} (must be finite and positive)")]
    InvalidParameter {
        /// The setting.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// The stream could not be transduced (an out-of-order or off-sensor event, named).
    #[error(transparent)]
    Transduction(#[from] TransductionError),
    /// The server could not listen on its address.
    #[error("cannot listen on {address}: {source}")]
    Listen {
        /// `host:port`.
        address: String,
        /// The system's reason.
        source: std::io::Error,
    },
    /// The source failed (a read error names the file and offset; a camera, what happened).
    #[error(transparent)]
    Source(crate::source::SourceError),
    /// A snapshot time after the stream's last event.
    #[error("--at {at_s} s is after the stream's end ({end_s:.3} s)")]
    PastTheEnd {
        /// The time asked for (s).
        at_s: f64,
        /// The stream's last event (s from its first).
        end_s: f64,
    },
}
