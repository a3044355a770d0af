//! Error types of `neurotac-sensor`: one enum per concern ([`FormatError`] for files and byte
//! streams, [`DeviceError`] for the camera), chained into [`SensorError`].
//!
//! Every format error names the input (a file path, or a label such as `<memory>` for in-memory
//! data), the byte offset where the problem was found and what was expected there.

use std::path::PathBuf;
use thiserror::Error;

/// An event file or byte stream that cannot be read or written.
#[derive(Debug, Error)]
pub enum FormatError {
    /// The input could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file (or input label).
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The first bytes match no supported event format.
    #[error(
        "{path}: not an event file: at byte {offset} found {found}, expected one of `#!AER-DAT2.0`, `#!AER-DAT3.1`, `#!AER-DAT4.0`, a `t,x,y,on` CSV header or a `t x y p` text line"
    )]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// Byte offset of the first byte that rules every format out.
        offset: u64,
        /// What was found there (escaped text).
        found: String,
    },
    /// An AEDAT file of a version this crate does not read (e.g. 3.0, 1.0).
    #[error("{path}: unsupported AEDAT version `{found}` (supported: 2.0, 3.1, 4.0)")]
    UnsupportedVersion {
        /// The file.
        path: PathBuf,
        /// The version line found.
        found: String,
    },
    /// The output format cannot be inferred from the file name.
    #[error(
        "{path}: cannot tell the event format from the extension (use .aedat, .aedat3, .aedat4, .txt or .csv)"
    )]
    UnknownExtension {
        /// The file.
        path: PathBuf,
    },
    /// The input ends inside a structure.
    #[error("{path}: truncated at byte {offset}: expected {expected}")]
    Truncated {
        /// The input.
        path: PathBuf,
        /// Byte offset where the data ran out.
        offset: u64,
        /// What was being read.
        expected: &'static str,
    },
    /// A field holds a value the format does not allow.
    #[error("{path}: at byte {offset}: {field} is {found}, expected {expected}")]
    Invalid {
        /// The input.
        path: PathBuf,
        /// Byte offset of the field (or of the structure holding it).
        offset: u64,
        /// The field.
        field: &'static str,
        /// What was found.
        found: String,
        /// What the format allows.
        expected: String,
    },
    /// A text line that does not parse.
    #[error("{path}: line {line} (byte {offset}): {field} is `{found}`, expected {expected}")]
    Text {
        /// The input.
        path: PathBuf,
        /// 1-based line number.
        line: u64,
        /// Byte offset of the start of the line.
        offset: u64,
        /// The column being parsed.
        field: &'static str,
        /// The text found.
        found: String,
        /// What was expected.
        expected: &'static str,
    },
    /// An ASCII header that does not end within the allowed size.
    #[error(
        "{path}: header does not end within {limit} bytes (expected its end marker `{expected}`)"
    )]
    HeaderTooLong {
        /// The input.
        path: PathBuf,
        /// The limit that was reached (bytes).
        limit: u64,
        /// The end marker expected.
        expected: &'static str,
    },
    /// A compressed payload that does not decompress.
    #[error("{path}: packet at byte {offset}: corrupt {codec} payload: {message}")]
    Decompress {
        /// The input.
        path: PathBuf,
        /// Byte offset of the packet header.
        offset: u64,
        /// The codec (`LZ4` or `Zstd`).
        codec: &'static str,
        /// The decoder's message.
        message: String,
    },
    /// An event that the output format cannot store.
    #[error("{path}: event {index} cannot be written: {reason}")]
    Unrepresentable {
        /// The output file.
        path: PathBuf,
        /// Index of the event in the written stream.
        index: u64,
        /// Why.
        reason: String,
    },
}

/// A camera that cannot be found, opened, configured or read.
#[derive(Debug, Error)]
pub enum DeviceError {
    /// No DAVIS camera is attached (or none can be opened).
    #[error(
        "no DAVIS camera found (USB VID 0x152A, PID 0x841B FX2 or 0x841A FX3): is it plugged in, and readable by this user (udev rules)?"
    )]
    NotFound,
    /// libusb cannot start on this machine, so no camera can be found.
    #[error(
        "no DAVIS camera found: USB is not usable on this machine (libusb could not start: {message}); is /dev/bus/usb available?"
    )]
    UsbUnavailable {
        /// The library's message.
        message: String,
    },
    /// The USB library or a USB call failed.
    #[error("USB {operation} failed: {message}")]
    Usb {
        /// What was being done (`open`, `control read module 6 param 0`, …).
        operation: String,
        /// The library's message.
        message: String,
    },
    /// The device firmware (low byte of bcdDevice) is not the one this protocol needs.
    #[error("DAVIS firmware version {found}, expected {required}: update the camera's firmware")]
    Firmware {
        /// Version found.
        found: u8,
        /// Version required (4 on FX2, 6 on FX3).
        required: u8,
    },
    /// The FPGA/CPLD logic version (SYSINFO param 0) is not the supported one.
    #[error("DAVIS logic version {found}, expected {required}")]
    LogicVersion {
        /// Version found.
        found: u32,
        /// Version required (18).
        required: u32,
    },
    /// The logic patch level (SYSINFO param 7) is too old.
    #[error("DAVIS logic patch {found}, expected at least {minimum}")]
    LogicPatch {
        /// Patch found.
        found: u32,
        /// Minimum patch (1).
        minimum: u32,
    },
    /// The chip is not a DAVIS240.
    #[error("chip identifier {found} is not a DAVIS240 (expected 0, 1 or 2 for DAVIS240A/B/C)")]
    UnsupportedChip {
        /// Chip identifier read (SYSINFO param 1).
        found: u32,
    },
    /// A register read returned a value outside its documented range.
    #[error("register module {module} param {param} reads {found}, expected {expected}")]
    Register {
        /// Module address.
        module: u16,
        /// Parameter address.
        param: u16,
        /// Value read.
        found: u32,
        /// What was expected.
        expected: &'static str,
    },
    /// The camera disappeared while streaming (unplugged). Events decoded before have been delivered.
    #[error(
        "camera disconnected while streaming after {bytes_received} bytes ({events_decoded} events decoded and kept)"
    )]
    Disconnected {
        /// Bytes received before the disconnection.
        bytes_received: u64,
        /// Events decoded and delivered before the disconnection.
        events_decoded: u64,
    },
    /// The stream was already stopped.
    #[error("the camera stream is stopped")]
    Stopped,
}

/// Any error of this crate.
#[derive(Debug, Error)]
pub enum SensorError {
    /// A file or byte-stream problem.
    #[error(transparent)]
    Format(#[from] FormatError),
    /// A camera problem.
    #[error(transparent)]
    Device(#[from] DeviceError),
}
