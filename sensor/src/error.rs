//! Error types of `neurotac-sensor`: one enum per concern ([`FormatError`] for files and byte
//! streams, [`DeviceError`] for the camera, [`TransductionError`] for filters, taxels and
//! layouts, [`ReaderTransductionError`] for a whole input read and transduced), chained into
//! [`SensorError`].
//!
//! Every format error names the input (a file path, or a label such as `<memory>` for in-memory
//! data), the byte offset where the problem was found and what was expected there. As in
//! `neurotac-core`, a message describes its own layer; its cause is its `source()`.

use std::path::PathBuf;
use thiserror::Error;

/// An event file or byte stream that cannot be read or written.
#[derive(Debug, Error)]
pub enum FormatError {
    /// The input could not be opened or read, or the output created or written; the message
    /// says which, and the cause (`source`) the system's reason.
    #[error("cannot {action} {path}")]
    Io {
        /// The file (or input label).
        path: PathBuf,
        /// What was being done to it.
        action: neurotac_core::IoAction,
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
    #[error("{path}: unsupported AEDAT version {found} (supported: 2.0, 3.1, 4.0)")]
    UnsupportedVersion {
        /// The file.
        path: PathBuf,
        /// The version found after `#!AER-DAT`, escaped and quoted (`` `3.0` ``).
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
    /// The input ends inside its header: an AEDAT 2.0 or 3.1 ASCII header, or the version line
    /// (magic) of any AEDAT version.
    #[error("{path}: truncated inside the header at byte {offset}: expected {expected}")]
    TruncatedHeader {
        /// The input.
        path: PathBuf,
        /// Byte offset where the data ran out (the input's length).
        offset: u64,
        /// What the header still needed.
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
    /// A sensor size that the output format cannot state (AEDAT 2.0 and 3.1 name a camera, not
    /// a size; AEDAT 4.0 coordinates are 16-bit signed), refused before any event is written.
    #[error("{path}: {format} cannot state a {width} × {height} sensor (it can state {supported})")]
    UnsupportedSensorSize {
        /// The output file.
        path: PathBuf,
        /// The output format (`AEDAT 2.0`, …).
        format: &'static str,
        /// Sensor width (pixels).
        width: u16,
        /// Sensor height (pixels).
        height: u16,
        /// The sizes the format can state.
        supported: &'static str,
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
    /// A transduction problem.
    #[error(transparent)]
    Transduction(#[from] TransductionError),
    /// An input that cannot be read or transduced.
    #[error(transparent)]
    ReaderTransduction(#[from] ReaderTransductionError),
}

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
    #[error("{what} = {}: {expected}", neurotac_core::Compact(*value))]
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

/// An event file or stream that cannot be transduced
/// ([`Transducer::transduce_reader`](crate::taxel::Transducer::transduce_reader)).
#[derive(Debug, Error)]
pub enum ReaderTransductionError {
    /// Reading failed; the reader's error names the input and the byte offset.
    #[error(transparent)]
    Read(#[from] FormatError),
    /// The events read are not a stream the transducer accepts (an event outside the sensor,
    /// time going back); the cause names the event by its index in the input.
    #[error("{path}: cannot transduce the events read")]
    Transduction {
        /// The input (a file path, or the label given for in-memory data).
        path: PathBuf,
        /// What the transducer found.
        source: TransductionError,
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
