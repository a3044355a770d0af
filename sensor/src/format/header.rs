//! The ASCII headers of AEDAT 2.0 and AEDAT 3.1 (davis240.md §2.1–2.2), read by one function.
//!
//! Both are lines starting with `#` and ending in a line feed (CRLF in practice), the first one
//! the version line. They differ only in how the header ends:
//!
//! | format | end | a line not starting with `#` |
//! |---|---|---|
//! | AEDAT 2.0 | the sentinel `#End Of ASCII Header` (any case and spacing) | the first data byte (older files have no sentinel) |
//! | AEDAT 3.1 | the line `#!END-HEADER` | an error |
//!
//! An input that ends before the header does (inside a line, or after whole lines but before
//! the end a header needs) is [`FormatError::TruncatedHeader`] at the byte where it ends; an
//! AEDAT 2.0 header therefore needs its sentinel or at least one data byte.

use super::escape::escape;
use super::input::Input;
use crate::error::FormatError;
use std::io::Read;

/// How one format's ASCII header starts and ends.
pub(crate) struct HeaderSpec {
    /// The start of the first line (`#!AER-DAT2.0`).
    pub version: &'static str,
    /// The end line, as errors name it.
    pub end_marker: &'static str,
    /// What a cut header was missing, for [`FormatError::TruncatedHeader`].
    pub expected_end: &'static str,
    /// `true` for the end line (given the whole line, line end included).
    pub is_end: fn(&[u8]) -> bool,
    /// Largest header accepted (bytes).
    pub limit: u64,
    /// Whether a line that does not start with `#` is the first data byte (AEDAT 2.0 without
    /// sentinel) rather than an error.
    pub data_ends_header: bool,
}

/// A header as read.
pub(crate) struct AsciiHeader {
    /// The header lines, version line through end line, line ends included.
    pub bytes: Vec<u8>,
    /// The first data byte, already consumed, when a line not starting with `#` ended the header.
    pub data_start: Option<u8>,
}

impl AsciiHeader {
    /// The header lines with the byte offset of each (the header starts at byte 0).
    pub fn lines(&self) -> impl Iterator<Item = (u64, &[u8])> {
        let mut offset = 0u64;
        self.bytes
            .split_inclusive(|&b| b == b'\n')
            .map(move |line| {
                let at = offset;
                offset += line.len() as u64;
                (at, line)
            })
    }
}

/// A typed error for an input that ends inside its header.
fn truncated<R: Read>(input: &Input<R>, expected: &'static str) -> FormatError {
    FormatError::TruncatedHeader {
        path: input.path().to_path_buf(),
        offset: input.offset(),
        expected,
    }
}

/// Reads the header described by `spec` from the start of `input`.
pub(crate) fn read_header<R: Read>(
    input: &mut Input<R>,
    spec: &HeaderSpec,
) -> Result<AsciiHeader, FormatError> {
    let mut bytes = Vec::new();
    let mut line = Vec::new();
    input.read_line(&mut line, 0, spec.limit, spec.end_marker)?;
    let version = spec.version.as_bytes();
    if !line.starts_with(version) {
        if !line.is_empty() && !line.ends_with(b"\n") && version.starts_with(&line) {
            return Err(truncated(input, "the rest of the version line"));
        }
        let found = escape(&line[..line.len().min(16)]);
        return Err(input.invalid(0, "version line", found, format!("`{}`", spec.version)));
    }
    if !line.ends_with(b"\n") {
        return Err(truncated(input, spec.expected_end));
    }
    bytes.extend_from_slice(&line);
    let mut first = [0u8; 1];
    loop {
        let at = input.offset();
        if input.read_full(&mut first)? == 0 {
            return Err(truncated(input, spec.expected_end));
        }
        if first[0] != b'#' && spec.data_ends_header {
            return Ok(AsciiHeader {
                bytes,
                data_start: Some(first[0]),
            });
        }
        let used = bytes.len() as u64 + 1;
        input.read_line(&mut line, used, spec.limit, spec.end_marker)?;
        line.insert(0, first[0]);
        if !line.ends_with(b"\n") {
            return Err(truncated(input, spec.expected_end));
        }
        if first[0] != b'#' {
            let found = escape(&line[..line.len().min(16)]);
            return Err(input.invalid(at, "header line", found, "a line starting with `#`"));
        }
        bytes.extend_from_slice(&line);
        if (spec.is_end)(&line) {
            return Ok(AsciiHeader {
                bytes,
                data_start: None,
            });
        }
    }
}
