//! [`ReportError`]: why a report folder could not be written; shared by the folder writer
//! ([`super::folder`]) and the report itself ([`super::write_report`]).

use super::png::PngError;
use std::path::PathBuf;

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The destination exists and replacing it was not asked for.
    #[error("{0} already exists (use --force to replace it)")]
    Exists(PathBuf),
    /// A figure could not be rasterised.
    #[error("cannot draw {path}")]
    Png {
        /// The PNG's path.
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
