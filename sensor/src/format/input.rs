//! A byte input that knows its name and offset, so every error says where it happened.

use crate::error::FormatError;
use std::io::{self, ErrorKind, Read};
use std::path::{Path, PathBuf};

/// A reader with its label and the offset of the next byte.
pub(crate) struct Input<R> {
    inner: R,
    path: PathBuf,
    offset: u64,
}

impl<R: Read> Input<R> {
    pub(crate) fn new(inner: R, path: PathBuf) -> Self {
        Self {
            inner,
            path,
            offset: 0,
        }
    }

    /// The reader and the label, for a reader that takes over the input.
    pub(crate) fn into_parts(self) -> (R, PathBuf) {
        (self.inner, self.path)
    }

    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Offset of the next byte to be read.
    pub(crate) fn offset(&self) -> u64 {
        self.offset
    }

    pub(crate) fn io(&self, source: io::Error) -> FormatError {
        FormatError::Io {
            path: self.path.clone(),
            action: neurotac_core::IoAction::Read,
            source,
        }
    }

    pub(crate) fn truncated_at(&self, offset: u64, expected: &'static str) -> FormatError {
        FormatError::Truncated {
            path: self.path.clone(),
            offset,
            expected,
        }
    }

    pub(crate) fn invalid(
        &self,
        offset: u64,
        field: &'static str,
        found: impl ToString,
        expected: impl ToString,
    ) -> FormatError {
        FormatError::Invalid {
            path: self.path.clone(),
            offset,
            field,
            found: found.to_string(),
            expected: expected.to_string(),
        }
    }

    /// Reads until `buf` is full or the input ends; returns the number of bytes read.
    pub(crate) fn read_full(&mut self, buf: &mut [u8]) -> Result<usize, FormatError> {
        let mut n = 0;
        while n < buf.len() {
            match self.inner.read(&mut buf[n..]) {
                Ok(0) => break,
                Ok(k) => n += k,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(self.io(e)),
            }
        }
        self.offset += n as u64;
        Ok(n)
    }

    /// Fills `buf` exactly, or fails with [`FormatError::Truncated`] naming `expected`.
    pub(crate) fn read_exact(
        &mut self,
        buf: &mut [u8],
        expected: &'static str,
    ) -> Result<(), FormatError> {
        let start = self.offset;
        if self.read_full(buf)? < buf.len() {
            return Err(self.truncated_at(start, expected));
        }
        Ok(())
    }

    /// Reads exactly `n` bytes into `buf` (replacing its content). `buf` grows only as bytes
    /// actually arrive, so a corrupt size field cannot drive a large allocation.
    pub(crate) fn read_vec(
        &mut self,
        n: u64,
        buf: &mut Vec<u8>,
        expected: &'static str,
    ) -> Result<(), FormatError> {
        let start = self.offset;
        buf.clear();
        let got = (&mut self.inner)
            .take(n)
            .read_to_end(buf)
            .map_err(|e| self.io(e))?;
        self.offset += got as u64;
        if (got as u64) < n {
            return Err(self.truncated_at(start, expected));
        }
        Ok(())
    }

    /// Skips exactly `n` bytes without storing them.
    pub(crate) fn skip(&mut self, n: u64, expected: &'static str) -> Result<(), FormatError> {
        let start = self.offset;
        let got =
            io::copy(&mut (&mut self.inner).take(n), &mut io::sink()).map_err(|e| self.io(e))?;
        self.offset += got;
        if got < n {
            return Err(self.truncated_at(start, expected));
        }
        Ok(())
    }

    /// Reads one header line (through `\n`) into `line` (replacing its content), given that
    /// `used` bytes of a header limited to `limit` bytes were read before. Returns `false` at the
    /// end of the input. Passing the limit fails with [`FormatError::HeaderTooLong`] naming
    /// `end_marker`.
    pub(crate) fn read_line(
        &mut self,
        line: &mut Vec<u8>,
        used: u64,
        limit: u64,
        end_marker: &'static str,
    ) -> Result<bool, FormatError> {
        line.clear();
        let mut byte = [0u8; 1];
        // Byte by byte on purpose: only headers are read this way, and reading ahead would eat
        // the binary data that follows.
        loop {
            if used + line.len() as u64 >= limit {
                return Err(FormatError::HeaderTooLong {
                    path: self.path.clone(),
                    limit,
                    expected: end_marker,
                });
            }
            if self.read_full(&mut byte)? == 0 {
                return Ok(!line.is_empty());
            }
            line.push(byte[0]);
            if byte[0] == b'\n' {
                return Ok(true);
            }
        }
    }
}
