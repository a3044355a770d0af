//! AEDAT 2.0, the jAER format, in the DAVIS240 layout (davis240.md §2.1).
//!
//! Header: ASCII lines starting with `#` (CRLF), the first one `#!AER-DAT2.0`. Data starts right
//! after a `#End Of ASCII Header` sentinel line (matched case-insensitively, ignoring `#` and
//! blanks) when there is one, else at the first line that does not start with `#` (older files).
//! A data record may itself start with byte `#`, which is why the sentinel wins. An input that
//! ends before either (inside a header line, or after whole `#` lines) is truncated inside the
//! header ([`FormatError::TruncatedHeader`]); a header with its sentinel and no records is an
//! empty recording.
//!
//! Body: 8-byte big-endian records, `u32 address` then `i32 timestamp` (µs). A DVS polarity event
//! has bit 31 = 0 and bits 11–10 ≠ `01`: raw y = bits 30–22, raw x = bits 21–12, polarity = bit
//! 11 (1 = ON). For a DAVIS240, top-left coordinates are **x = 239 − raw x, y = 179 − raw y**.
//! Other records (external input, APS samples, IMU) are skipped and counted. Timestamps are
//! 32-bit: each one is unwrapped to the time closest to the one before with the same low 32
//! bits, so a drop of more than 2³¹ µs is a wrap (counted), and a step back of less than 2³¹ µs
//! is a timestamp going backwards — across a wrap too — reported in [`ReadStats`] and kept in
//! file order. A header whose `AEChip`
//! line names another chip than a DAVIS240 is refused (its layout differs); a header without one
//! is read as DAVIS240.

use super::contract::{EventReader, EventWriter, READ_BLOCK, ReadStats, ReaderEnd, io_error};
use super::header::{HeaderSpec, read_header};
use super::input::Input;
use crate::error::FormatError;
use neurotac_core::EventBuffer;
use std::io::{Read, Write};
use std::path::PathBuf;

/// Largest header accepted (jAER may embed its XML preferences, some 100 KB; davis240.md §2.1).
pub const MAX_HEADER_BYTES: u64 = 16 << 20;

const SIZE_X: u32 = crate::geometry::DAVIS240_WIDTH as u32;
const SIZE_Y: u32 = crate::geometry::DAVIS240_HEIGHT as u32;
const RECORD: usize = 8;

/// The header lines this crate writes (a minimal jAER-style header for a DAVIS240C).
const HEADER: &[u8] = b"#!AER-DAT2.0\r\n\
# This is a raw AE data file - do not edit\r\n\
# Data format is int32 address, int32 timestamp (8 bytes total), repeated for each event\r\n\
# Timestamps tick is 1 us\r\n\
# AEChip: eu.seebetter.ini.chips.davis.DAVIS240C\r\n\
# End of ASCII Header\r\n";

/// The AEDAT 2.0 header (module docs): ends at the sentinel, or at the first data byte in files
/// without one.
const HEADER_SPEC: HeaderSpec = HeaderSpec {
    version: "#!AER-DAT2.0",
    end_marker: "# End of ASCII Header",
    expected_end: "the rest of the header: its end line `# End of ASCII Header` or the first record",
    is_end: is_sentinel,
    limit: MAX_HEADER_BYTES,
    data_ends_header: true,
};

/// The chip class of an ` AEChip: …` header line (after its `#`).
fn aechip(line: &[u8]) -> Option<String> {
    let text = std::str::from_utf8(line).ok()?.trim();
    Some(text.strip_prefix("AEChip:")?.trim().to_owned())
}

/// `true` for the header sentinel `#End Of ASCII Header` in any case and spacing.
fn is_sentinel(line: &[u8]) -> bool {
    let letters = line
        .iter()
        .filter(|b| !matches!(b, b'#' | b' ' | b'\t' | b'\r' | b'\n'))
        .map(u8::to_ascii_lowercase);
    letters.eq(b"endofasciiheader".iter().copied())
}

/// Streaming reader of AEDAT 2.0 DAVIS240 files (davis240.md §2.1; §7 pitfalls 5 and 6).
pub struct Aedat2Reader<R> {
    input: Input<R>,
    /// The header lines, including the version line and the sentinel (if any).
    header: Vec<u8>,
    /// Raw block; `block[..filled]` holds unread bytes starting at a record boundary.
    block: Vec<u8>,
    filled: usize,
    /// Offset of `block[0]` in the input.
    block_offset: u64,
    previous: i64,
    stats: ReadStats,
    end: ReaderEnd,
}

impl<R: Read> Aedat2Reader<R> {
    /// Reads the header of an AEDAT 2.0 input, labelled `<input>` in errors.
    pub fn new(reader: R) -> Result<Self, FormatError> {
        Self::with_name(reader, PathBuf::from("<input>"))
    }

    /// Reads the header of an AEDAT 2.0 input named `path` in errors.
    pub fn with_name(reader: R, path: PathBuf) -> Result<Self, FormatError> {
        let mut input = Input::new(reader, path);
        let header = read_header(&mut input, &HEADER_SPEC)?;
        for (at, line) in header.lines() {
            if let Some(chip) = aechip(&line[1..]) {
                if !chip.to_ascii_lowercase().contains("davis240") {
                    let expected = "a DAVIS240 chip class (the x/y mirroring of this reader is DAVIS240-specific)";
                    return Err(input.invalid(at, "AEChip", format!("`{chip}`"), expected));
                }
            }
        }
        // The first byte of the data when a line that does not start with `#` ended the header.
        let data_start: Vec<u8> = header.data_start.into_iter().collect();
        let header = header.bytes;
        let block_offset = input.offset() - data_start.len() as u64;
        let filled = data_start.len();
        let mut block = data_start;
        block.resize(filled + READ_BLOCK, 0);
        Ok(Self {
            input,
            header,
            block,
            filled,
            block_offset,
            previous: i64::MIN,
            stats: ReadStats::default(),
            end: ReaderEnd::default(),
        })
    }

    /// The header lines as read (version line through the sentinel).
    pub fn header(&self) -> &[u8] {
        &self.header
    }

    /// Decodes the whole records of `block[..filled]`, appending events; returns the bytes used.
    fn decode_block(&mut self, out: &mut EventBuffer) -> usize {
        let whole = self.filled - self.filled % RECORD;
        let mut stats = self.stats;
        let mut previous = self.previous;
        out.t.reserve(whole / RECORD);
        out.x.reserve(whole / RECORD);
        out.y.reserve(whole / RECORD);
        out.polarity.reserve(whole / RECORD);
        for (i, rec) in self.block[..whole].chunks_exact(RECORD).enumerate() {
            let addr = u32::from_be_bytes([rec[0], rec[1], rec[2], rec[3]]);
            let ts = i32::from_be_bytes([rec[4], rec[5], rec[6], rec[7]]);
            if addr & 0x8000_0000 != 0 || (addr >> 10) & 3 == 1 {
                stats.skipped += 1; // APS, IMU or external-input record
                continue;
            }
            let raw_x = (addr >> 12) & 0x3FF;
            let raw_y = (addr >> 22) & 0x1FF;
            if raw_x >= SIZE_X || raw_y >= SIZE_Y {
                stats.out_of_range += 1;
                continue;
            }
            let t = match previous {
                i64::MIN => i64::from(ts),
                _ => {
                    // The time closest to the previous one with these low 32 bits.
                    let low = previous as i32;
                    let step = ts.wrapping_sub(low);
                    if step > 0 && ts < low {
                        stats.timestamp_wraps += 1;
                    }
                    let t = previous + i64::from(step);
                    let offset = self.block_offset + (i * RECORD) as u64;
                    stats.check_order(offset, previous, t);
                    t
                }
            };
            previous = t;
            out.t.push(t);
            out.x.push((SIZE_X - 1 - raw_x) as u16);
            out.y.push((SIZE_Y - 1 - raw_y) as u16);
            out.polarity.push(addr & 0x800 != 0);
        }
        self.stats = stats;
        self.previous = previous;
        whole
    }
}

impl<R: Read> Aedat2Reader<R> {
    /// Reads blocks until one yields events or the input ends.
    fn fill(&mut self, out: &mut EventBuffer) -> Result<(), FormatError> {
        let before = out.len();
        while out.len() == before {
            let n = self.input.read_full(&mut self.block[self.filled..])?;
            self.filled += n;
            if n == 0 && self.filled < RECORD {
                if self.filled > 0 {
                    let expected = "an 8-byte AEDAT 2.0 record";
                    return Err(self.input.truncated_at(self.block_offset, expected));
                }
                return Ok(());
            }
            let used = self.decode_block(out);
            self.block.copy_within(used..self.filled, 0);
            self.filled -= used;
            self.block_offset += used as u64;
        }
        self.stats.events += (out.len() - before) as u64;
        Ok(())
    }
}

impl<R: Read> EventReader for Aedat2Reader<R> {
    fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
        ReaderEnd::chunk(self, |r| &mut r.end, out, Self::fill)
    }

    fn stats(&self) -> ReadStats {
        self.stats
    }

    fn sensor_size(&self) -> Option<(u16, u16)> {
        Some((SIZE_X as u16, SIZE_Y as u16))
    }
}

/// Writer of AEDAT 2.0 DAVIS240 files (the header of `pick.aedat`, records as in
/// davis240.md §2.1).
///
/// Times are stored as 32-bit timestamps; the first event must lie in `i32` range and
/// consecutive events less than 2³¹ µs apart, so that the reader's unwrapping restores them.
pub struct Aedat2Writer<W: Write> {
    out: W,
    path: PathBuf,
    previous: Option<i64>,
    written: u64,
    block: Vec<u8>,
}

impl<W: Write> Aedat2Writer<W> {
    /// Writes the header to `out`, labelled `<output>` in errors.
    pub fn new(out: W) -> Result<Self, FormatError> {
        Self::with_name(out, PathBuf::from("<output>"))
    }

    /// Writes the header to `out`, named `path` in errors.
    pub fn with_name(mut out: W, path: PathBuf) -> Result<Self, FormatError> {
        out.write_all(HEADER).map_err(io_error(&path))?;
        Ok(Self {
            out,
            path,
            previous: None,
            written: 0,
            block: Vec::with_capacity(READ_BLOCK),
        })
    }

    fn unrepresentable(&self, index: u64, reason: String) -> FormatError {
        FormatError::Unrepresentable {
            path: self.path.clone(),
            index,
            reason,
        }
    }
}

impl<W: Write> EventWriter for Aedat2Writer<W> {
    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
        for chunk_start in (0..events.len()).step_by(READ_BLOCK / RECORD) {
            let end = (chunk_start + READ_BLOCK / RECORD).min(events.len());
            self.block.clear();
            for i in chunk_start..end {
                let index = self.written + i as u64;
                let (t, x, y) = (events.t[i], events.x[i], events.y[i]);
                if u32::from(x) >= SIZE_X || u32::from(y) >= SIZE_Y {
                    let reason = format!("pixel ({x}, {y}) is outside the DAVIS240's 240 × 180");
                    return Err(self.unrepresentable(index, reason));
                }
                let step_ok = match self.previous {
                    None => i32::try_from(t).is_ok(),
                    Some(p) => t.abs_diff(p) < 1 << 31,
                };
                if !step_ok {
                    let reason = format!(
                        "time {t} µs cannot be stored as a 32-bit AEDAT 2.0 timestamp (first event must be within ±2^31 µs, steps below 2^31 µs)"
                    );
                    return Err(self.unrepresentable(index, reason));
                }
                self.previous = Some(t);
                let raw_x = SIZE_X - 1 - u32::from(x);
                let raw_y = SIZE_Y - 1 - u32::from(y);
                let addr = raw_y << 22 | raw_x << 12 | u32::from(events.polarity[i]) << 11;
                self.block.extend_from_slice(&addr.to_be_bytes());
                self.block.extend_from_slice(&(t as i32).to_be_bytes());
            }
            self.out
                .write_all(&self.block)
                .map_err(io_error(&self.path))?;
        }
        self.written += events.len() as u64;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        self.out.flush().map_err(io_error(&self.path))
    }
}
