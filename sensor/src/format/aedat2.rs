//! AEDAT 2.0, the jAER format, in its DAVIS layout (davis240.md §2.1).
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
//! 11 (1 = ON). jAER records every DAVIS with raw x = W − 1 − x and raw y = H − 1 − y
//! (`DAViSFX3HardwareInterface`), so top-left coordinates are **x = W − 1 − raw x, y = H − 1 −
//! raw y** for a W × H sensor (239 − raw x, 179 − raw y on a DAVIS240).
//! Other records (external input, APS samples, IMU) are skipped and counted. Timestamps are
//! 32-bit: each one is unwrapped to the time closest to the one before with the same low 32
//! bits, so a drop of more than 2³¹ µs is a wrap (counted), and a step back of less than 2³¹ µs
//! is a timestamp going backwards — across a wrap too — reported in [`ReadStats`] and kept in
//! file order.
//!
//! Sensor size: the header's `AEChip` line names jAER's chip class, which fixes the size — a
//! DAVIS240 class (`eu.seebetter.ini.chips.davis.DAVIS240C`) 240 × 180, a DAVIS346 class
//! (`eu.seebetter.ini.chips.davis.Davis346B`, `Davis346red`, …) 346 × 260 (see
//! [`CAMERAS`](super::camera::CAMERAS)). A header naming another chip is refused (its layout is
//! not this one; aedat4to2's misspelt `DAVI346`, which also leaves x unmirrored, is among them); a
//! header without one states no size and is read with the assumed one (240 × 180 by default).
//! The writer names the class of its size and refuses any other size: AEDAT 2.0 cannot state one.

use super::camera::{CAMERA_SIZES, Camera, camera_named, camera_of_size};
use super::contract::{
    EventReader, EventWriter, READ_BLOCK, ReadStats, ReaderEnd, ReaderSensor, check_inside,
    unsupported_size, write_error,
};
use super::header::{HeaderSpec, read_header};
use super::input::Input;
use crate::error::FormatError;
use neurotac_core::EventBuffer;
use std::io::{Read, Write};
use std::path::PathBuf;

/// Largest header accepted (jAER may embed its XML preferences, some 100 KB; davis240.md §2.1).
pub const MAX_HEADER_BYTES: u64 = 16 << 20;

const RECORD: usize = 8;

/// The header lines this crate writes: a minimal jAER-style header naming `camera`'s chip class.
fn header(camera: &Camera) -> String {
    format!(
        "#!AER-DAT2.0\r\n\
         # This is a raw AE data file - do not edit\r\n\
         # Data format is int32 address, int32 timestamp (8 bytes total), repeated for each event\r\n\
         # Timestamps tick is 1 us\r\n\
         # AEChip: {}\r\n\
         # End of ASCII Header\r\n",
        camera.jaer_class
    )
}

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

/// Streaming reader of AEDAT 2.0 DAVIS files (davis240.md §2.1; §7 pitfalls 5 and 6).
pub struct Aedat2Reader<R> {
    input: Input<R>,
    sensor: ReaderSensor,
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
        let mut camera = None;
        for (at, line) in header.lines() {
            if let Some(chip) = aechip(&line[1..]) {
                match camera_named(&chip) {
                    Some(c) => camera = Some(c),
                    None => {
                        let expected = "a DAVIS240 or DAVIS346 chip class (the address layout of this reader is jAER's DAVIS one)";
                        return Err(input.invalid(at, "AEChip", format!("`{chip}`"), expected));
                    }
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
            sensor: ReaderSensor::new(camera.map(|c| c.size)),
            header,
            block,
            filled,
            block_offset,
            previous: i64::MIN,
            stats: ReadStats::default(),
            end: ReaderEnd::default(),
        })
    }

    /// Reads a file whose header names no chip as a `size` sensor (instead of 240 × 180).
    pub fn assuming(mut self, size: (u16, u16)) -> Self {
        self.sensor.assumed = size;
        self
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
        let (size_x, size_y) = self.sensor.bounds();
        let (size_x, size_y) = (u32::from(size_x), u32::from(size_y));
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
            if raw_x >= size_x || raw_y >= size_y {
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
            out.x.push((size_x - 1 - raw_x) as u16);
            out.y.push((size_y - 1 - raw_y) as u16);
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
        self.sensor.stated
    }
}

/// Writer of AEDAT 2.0 DAVIS files (the header of `pick.aedat` naming the camera's jAER chip
/// class, records as in davis240.md §2.1).
///
/// The sensor must be one of [`CAMERAS`](super::camera::CAMERAS) (240 × 180 or 346 × 260).
/// Times are stored as 32-bit timestamps; the first event must lie in `i32` range and
/// consecutive events less than 2³¹ µs apart, so that the reader's unwrapping restores them.
pub struct Aedat2Writer<W: Write> {
    out: W,
    path: PathBuf,
    size: (u16, u16),
    previous: Option<i64>,
    written: u64,
    block: Vec<u8>,
}

impl<W: Write> Aedat2Writer<W> {
    /// Writes the header of a `sensor` (width, height) recording to `out`, labelled `<output>`
    /// in errors.
    pub fn new(out: W, sensor: (u16, u16)) -> Result<Self, FormatError> {
        Self::with_name(out, PathBuf::from("<output>"), sensor)
    }

    /// Writes the header of a `sensor` (width, height) recording to `out`, named `path` in
    /// errors; a sensor that no jAER chip class of [`CAMERAS`](super::camera::CAMERAS) has is
    /// refused ([`FormatError::UnsupportedSensorSize`]).
    pub fn with_name(mut out: W, path: PathBuf, sensor: (u16, u16)) -> Result<Self, FormatError> {
        let camera = camera_of_size(sensor)
            .ok_or_else(|| unsupported_size(&path, "AEDAT 2.0", sensor, CAMERA_SIZES))?;
        out.write_all(header(camera).as_bytes())
            .map_err(write_error(&path))?;
        Ok(Self {
            out,
            path,
            size: sensor,
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
                check_inside(&self.path, index, (x, y), self.size)?;
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
                let raw_x = u32::from(self.size.0 - 1 - x);
                let raw_y = u32::from(self.size.1 - 1 - y);
                let addr = raw_y << 22 | raw_x << 12 | u32::from(events.polarity[i]) << 11;
                self.block.extend_from_slice(&addr.to_be_bytes());
                self.block.extend_from_slice(&(t as i32).to_be_bytes());
            }
            self.out
                .write_all(&self.block)
                .map_err(write_error(&self.path))?;
        }
        self.written += events.len() as u64;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        self.out.flush().map_err(write_error(&self.path))
    }
}
