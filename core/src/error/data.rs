//! Errors of spike data and files: invalid spike trains ([`SpikeError`]), datasets that cannot
//! be read or written ([`DatasetError`], with where in the file), and outputs that would
//! overwrite or lie inside their inputs.

use std::path::PathBuf;
use thiserror::Error;

/// Invalid spike times or spike-train layout.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpikeError {
    /// A time is NaN or infinite.
    #[error("channel {channel}, spike {index}: time {value} is not finite")]
    NonFinite {
        /// Channel (0 for a single train).
        channel: usize,
        /// Position within the channel (or within the input list).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A time is smaller than the one before it in the same channel.
    #[error("channel {channel}, spike {index}: times not sorted ({value} s after {previous} s)")]
    Unsorted {
        /// Channel (0 for a single train).
        channel: usize,
        /// Position within the channel.
        index: usize,
        /// The time before it.
        previous: f64,
        /// The offending time.
        value: f64,
    },
    /// More channels than a spike train may have ([`MAX_CHANNELS`](crate::spikes::MAX_CHANNELS)).
    #[error("{n_channels} channels: more than the limit of {limit} channels per sample")]
    TooManyChannels {
        /// Channels asked for.
        n_channels: usize,
        /// The limit.
        limit: usize,
    },
    /// A spike names a channel that does not exist.
    #[error("spike on channel {channel}, but there are only {n_channels} channels")]
    ChannelOutOfRange {
        /// The channel named.
        channel: usize,
        /// Number of channels.
        n_channels: usize,
    },
    /// CSR offsets that do not describe the time buffer.
    #[error(
        "invalid CSR offsets for {n_times} times: must start at 0, never decrease and end at {n_times}"
    )]
    InvalidOffsets {
        /// Length of the time buffer.
        n_times: usize,
    },
    /// A time window with NaN bounds or start after end.
    #[error("invalid time window [{start_s}, {end_s}) s")]
    InvalidWindow {
        /// Window start (s).
        start_s: f64,
        /// Window end (s).
        end_s: f64,
    },
}

/// What was being done to a file when an I/O error happened: the verb of an I/O error's message
/// (`cannot read x.json`, `cannot write y.bin`), so the message says what failed and its
/// `source` why.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IoAction {
    /// Opening or reading an input.
    Read,
    /// Creating, writing or committing an output.
    Write,
}

impl std::fmt::Display for IoAction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            IoAction::Read => "read",
            IoAction::Write => "write",
        })
    }
}

/// A spike dataset that cannot be read, written or is inconsistent.
#[derive(Debug, Error)]
pub enum DatasetError {
    /// The file could not be opened, read or written; the message says which, and the cause
    /// (`source`) the system's reason (`No such file or directory (os error 2)`).
    #[error("cannot {action} {path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done to it.
        action: IoAction,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The JSON text is malformed or does not have the dataset's shape.
    #[error("{path}: invalid spike-dataset JSON{}", in_observations(*at))]
    Json {
        /// The file.
        path: PathBuf,
        /// Where in `observations` the parser stopped, when it was inside them.
        at: Option<SpikeLocation>,
        /// The parser's error, with line and column.
        source: serde_json::Error,
    },
    /// The compact binary form is corrupt or truncated.
    #[error("{path}: byte {offset}: {what}")]
    Binary {
        /// The file.
        path: PathBuf,
        /// Byte offset where decoding failed.
        offset: usize,
        /// What was wrong there.
        what: String,
    },
    /// An observation's spike trains are invalid (a time that is not finite or out of order);
    /// the [`SpikeError`] names the channel, the spike and the value.
    #[error("observation {observation}{}", at_position(*position))]
    Spikes {
        /// Index of the observation.
        observation: usize,
        /// Where the offending time is in the file, when it was read from one.
        position: Option<FilePosition>,
        /// The spike error.
        source: SpikeError,
    },
    /// `labels` and `observations` differ in length.
    #[error("{labels} labels for {observations} observations")]
    LabelCount {
        /// Number of labels.
        labels: usize,
        /// Number of observations.
        observations: usize,
    },
    /// A label has no class name.
    #[error("observation {observation}: label {label} but only {n_classes} class names")]
    LabelOutOfRange {
        /// Index of the observation.
        observation: usize,
        /// The label.
        label: usize,
        /// Number of class names.
        n_classes: usize,
    },
    /// A label at or beyond [`MAX_CLASSES`](crate::dataset::MAX_CLASSES): per-class tables
    /// (class means, confusion matrices) are sized by the number of classes, so a corrupt label
    /// must not size them.
    #[error(
        "observation {observation}: label {label}, but a dataset has at most {max} classes (labels 0 to {})",
        max - 1
    )]
    LabelBeyondLimit {
        /// Index of the observation.
        observation: usize,
        /// The label.
        label: usize,
        /// The most classes a dataset may have.
        max: usize,
    },
    /// More class names than [`MAX_CLASSES`](crate::dataset::MAX_CLASSES).
    #[error("{names} class names, but a dataset has at most {max} classes")]
    TooManyClassNames {
        /// Number of class names.
        names: usize,
        /// The most classes a dataset may have.
        max: usize,
    },
    /// Observations with different channel counts.
    #[error("observation {observation} has {got} channels, observation 0 has {expected}")]
    ChannelCount {
        /// Index of the observation.
        observation: usize,
        /// Channels of observation 0.
        expected: usize,
        /// Channels of this observation.
        got: usize,
    },
    /// The binary form's CRC-32 does not match its bytes: the file is corrupt or truncated.
    #[error(
        "{path}: checksum mismatch (stored CRC-32 {stored:08x}, computed {computed:08x}): the file is corrupt or truncated"
    )]
    Checksum {
        /// The file.
        path: PathBuf,
        /// The CRC-32 stored in the file's last 4 bytes.
        stored: u32,
        /// The CRC-32 of the bytes before it.
        computed: u32,
    },
    /// A typed metadata field (such as `duration_s`) holds a value it cannot take.
    #[error("meta.{field} = {value}: {expected}")]
    Meta {
        /// The field.
        field: &'static str,
        /// The value found (JSON text).
        value: String,
        /// What it must be.
        expected: &'static str,
    },
}

impl DatasetError {
    /// The file this error names in its message, if it names one: the I/O, JSON, binary-layout
    /// and checksum errors do; errors about the content (a spike, a label, a channel count,
    /// metadata) do not, so a caller reading a file can name it once.
    pub fn path(&self) -> Option<&std::path::Path> {
        match self {
            Self::Io { path, .. }
            | Self::Json { path, .. }
            | Self::Binary { path, .. }
            | Self::Checksum { path, .. } => Some(path),
            Self::Spikes { .. }
            | Self::LabelCount { .. }
            | Self::LabelOutOfRange { .. }
            | Self::LabelBeyondLimit { .. }
            | Self::TooManyClassNames { .. }
            | Self::ChannelCount { .. }
            | Self::Meta { .. } => None,
        }
    }
}

/// Where a problem lies in a spike dataset's `observations`: the observation, and when known
/// the channel and the spike (all 0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpikeLocation {
    /// Index of the observation.
    pub observation: usize,
    /// Channel within the observation, when the problem is inside one.
    pub channel: Option<usize>,
    /// Position of the spike within the channel, when the problem is at a spike time.
    pub spike: Option<usize>,
}

impl std::fmt::Display for SpikeLocation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "observation {}", self.observation)?;
        if let Some(channel) = self.channel {
            write!(f, ", channel {channel}")?;
        }
        if let Some(spike) = self.spike {
            write!(f, ", spike {spike}")?;
        }
        Ok(())
    }
}

/// A place in a dataset file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilePosition {
    /// Line and column of the JSON form, 1-based, as serde_json counts them: the column counts
    /// bytes and is where the parser stopped, on the offending value or just after it.
    Text {
        /// Line (1-based).
        line: usize,
        /// Column (1-based, in bytes).
        column: usize,
    },
    /// Byte offset in the binary form, from the start of the file.
    Byte {
        /// Offset (0-based).
        offset: usize,
    },
}

impl std::fmt::Display for FilePosition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Text { line, column } => write!(f, "line {line}, column {column}"),
            Self::Byte { offset } => write!(f, "byte {offset}"),
        }
    }
}

/// `" in observation 1, channel 2, spike 3"`, or nothing.
fn in_observations(at: Option<SpikeLocation>) -> String {
    at.map(|at| format!(" in {at}")).unwrap_or_default()
}

/// `" (line 1, column 7)"`, `" (byte 301)"`, or nothing.
fn at_position(position: Option<FilePosition>) -> String {
    position.map(|p| format!(" ({p})")).unwrap_or_default()
}

/// An output that is the same file as an input: writing it would destroy the input.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error(
    "the output {output} is the input {input} (the same file): refusing to overwrite the input; choose another output"
)]
pub struct SameFileError {
    /// The input path as given.
    pub input: PathBuf,
    /// The output path as given.
    pub output: PathBuf,
}

/// An output whose commit was not allowed to replace an existing target (no `--force`), found
/// at commit time: the target appeared after the run checked it (another run wrote it), or
/// was there all along. It travels inside an [`std::io::Error`] of kind `AlreadyExists`;
/// [`crate::io::existing_output`] finds it in an error chain.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{} already exists", path.display())]
pub struct ExistsError {
    /// The target that exists.
    pub path: PathBuf,
}

/// How an output and an input overlap ([`NestedError`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Nesting {
    /// The output is the input.
    Same,
    /// The output is a folder that holds the input.
    Holds,
    /// The output lies inside the input folder.
    Inside,
}

impl std::fmt::Display for Nesting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Nesting::Same => "is",
            Nesting::Holds => "holds",
            Nesting::Inside => "lies inside",
        })
    }
}

/// An output path that is, holds or lies inside an input path (compared as canonical paths):
/// writing or replacing it could delete or change the input.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error(
    "the output {output} {nesting} the input {input}: refusing to write there; choose an output apart from the inputs",
    output = output.display(),
    input = input.display()
)]
pub struct NestedError {
    /// The input path as given.
    pub input: PathBuf,
    /// The output path as given.
    pub output: PathBuf,
    /// How they overlap.
    pub nesting: Nesting,
}
