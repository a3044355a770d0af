//! [`Aedat4Reader`]: header, description and packets of an AEDAT 4.0 input, chunk by chunk.

use super::framing::{lz4_frame_decode, zstd_decode};
use super::{
    Compression, EVENT_BYTES, EventStream, MAGIC, MAX_DECOMPRESSED_BYTES, MAX_HEADER_BYTES,
    MAX_PACKET_BYTES, event_stream,
};
use crate::error::FormatError;
use crate::format::contract::{EventReader, ReadStats, ReaderEnd, ReaderSensor};
use crate::format::escape::escape;
use crate::format::flatbuffer::{Buffer, u32_at};
use crate::format::input::Input;
use neurotac_core::EventBuffer;
use std::io::Read;
use std::path::PathBuf;

/// Streaming reader of AEDAT 4.0 files (the first event stream; davis240.md §2.3).
pub struct Aedat4Reader<R> {
    input: Input<R>,
    compression: Compression,
    data_table: Option<u64>,
    file_len: Option<u64>,
    description: String,
    stream: Option<EventStream>,
    sensor: ReaderSensor,
    payload: Vec<u8>,
    plain: Vec<u8>,
    zstd: Option<zstd::stream::raw::Decoder<'static>>,
    previous: i64,
    stats: ReadStats,
    end: ReaderEnd,
}

impl<R: Read> Aedat4Reader<R> {
    /// Reads the header of an AEDAT 4.0 input, labelled `<input>` in errors.
    pub fn new(reader: R) -> Result<Self, FormatError> {
        Self::with_name(reader, PathBuf::from("<input>"), None)
    }

    /// Reads the header of an AEDAT 4.0 input named `path` in errors. With the input's length,
    /// packet sizes larger than what remains are reported before anything is read.
    pub fn with_name(reader: R, path: PathBuf, file_len: Option<u64>) -> Result<Self, FormatError> {
        let mut input = Input::new(reader, path);
        let mut magic = [0u8; 14];
        input.read_exact(&mut magic, "the `#!AER-DAT4.0` magic line")?;
        if &magic != MAGIC {
            return Err(input.invalid(0, "magic", escape(&magic), "`#!AER-DAT4.0\\r\\n`"));
        }
        let mut size = [0u8; 4];
        input.read_exact(&mut size, "the IOHeader size")?;
        let size = u32::from_le_bytes(size);
        if size > MAX_HEADER_BYTES {
            return Err(input.invalid(
                14,
                "IOHeader size",
                size,
                format!("at most {MAX_HEADER_BYTES}"),
            ));
        }
        let mut header = Vec::new();
        input.read_vec(u64::from(size), &mut header, "the IOHeader flatbuffer")?;
        let buf = Buffer(&header);
        if buf.identifier() != Some(b"IOHE") {
            let found = escape(buf.identifier().unwrap_or(&[]));
            return Err(input.invalid(18, "IOHeader identifier", found, "`IOHE`"));
        }
        let bad = |input: &Input<R>, field| {
            input.invalid(18, field, "an out-of-bounds offset", "a valid flatbuffer")
        };
        let root = buf
            .root()
            .ok_or_else(|| bad(&input, "IOHeader root table"))?;
        let code = root
            .i32_or(0, 0)
            .ok_or_else(|| bad(&input, "compression"))?;
        let compression = Compression::from_header(code).ok_or_else(|| {
            input.invalid(18, "compression", code, "0 (none), 1/2 (LZ4) or 3/4 (Zstd)")
        })?;
        let table = root
            .i64_or(1, -1)
            .ok_or_else(|| bad(&input, "dataTablePosition"))?;
        let data_start = input.offset();
        let data_table = u64::try_from(table).ok();
        if data_table.is_some_and(|t| t < data_start) {
            let expected = format!("−1 (none) or a position after the header (≥ {data_start})");
            return Err(input.invalid(18, "dataTablePosition", table, expected));
        }
        let description = root.string(2).ok_or_else(|| bad(&input, "description"))?;
        let description = String::from_utf8_lossy(description).into_owned();
        let stream = event_stream(&description);
        Ok(Self {
            input,
            compression,
            data_table,
            file_len,
            description,
            stream,
            sensor: ReaderSensor::new(stream.and_then(|s| s.size)),
            payload: Vec::new(),
            plain: Vec::new(),
            zstd: None,
            previous: i64::MIN,
            stats: ReadStats::default(),
            end: ReaderEnd::default(),
        })
    }

    /// Reads a file whose event stream states no `sizeX`/`sizeY` as a `size` sensor (instead
    /// of 240 × 180).
    pub fn assuming(mut self, size: (u16, u16)) -> Self {
        self.sensor.assumed = size;
        self
    }

    /// The packet compression.
    pub fn compression(&self) -> Compression {
        self.compression
    }

    /// The XML description of the streams.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The event stream read (`None`: the description names none, and every packet whose
    /// flatbuffer identifier is `EVTS` is read).
    pub fn event_stream(&self) -> Option<EventStream> {
        self.stream
    }

    /// Reads packets until one yields events; `Ok(false)` at the end.
    fn next_events(&mut self, out: &mut EventBuffer) -> Result<bool, FormatError> {
        loop {
            let at = self.input.offset();
            if self.data_table.is_some_and(|t| at >= t) {
                return Ok(false);
            }
            let mut h = [0u8; 8];
            match self.input.read_full(&mut h)? {
                0 if self.data_table.is_some_and(|t| at < t) => {
                    let expected = "more packets: the file ends before its data table";
                    return Err(self.input.truncated_at(at, expected));
                }
                0 => return Ok(false),
                8 => {}
                _ => {
                    return Err(self
                        .input
                        .truncated_at(at, "an 8-byte AEDAT 4.0 packet header"));
                }
            }
            let id = i32::from_le_bytes([h[0], h[1], h[2], h[3]]);
            let size = i32::from_le_bytes([h[4], h[5], h[6], h[7]]);
            // Packets end at the data table (when there is one), else at the end of the file.
            let limit = match (self.data_table, self.file_len) {
                (Some(t), Some(l)) => Some(t.min(l)),
                (t, l) => t.or(l),
            };
            let left = limit.map(|l| l.saturating_sub(at + 8));
            if size < 0 || size as u64 > MAX_PACKET_BYTES || left.is_some_and(|l| size as u64 > l) {
                let expected = match left {
                    Some(l) => format!(
                        "0 to {} (the bytes left before the data table or the end of the file)",
                        l.min(MAX_PACKET_BYTES)
                    ),
                    None => format!("0 to {MAX_PACKET_BYTES}"),
                };
                return Err(self.input.invalid(at + 4, "packet size", size, expected));
            }
            let size = size as u64;
            let wanted = self.stream.is_none_or(|s| s.id == id);
            if size == 0 || !wanted {
                self.stats.skipped += 1;
                self.input
                    .skip(size, "the payload of an AEDAT 4.0 packet")?;
                continue;
            }
            self.input.read_vec(
                size,
                &mut self.payload,
                "the payload of an AEDAT 4.0 packet",
            )?;
            if self.decode_packet(at, out)? {
                return Ok(true);
            }
        }
    }

    /// Decompresses and decodes one packet read into `payload`; `Ok(false)` when it held no
    /// event of the stream.
    fn decode_packet(&mut self, at: u64, out: &mut EventBuffer) -> Result<bool, FormatError> {
        let decompress_error = |input: &Input<R>, codec, message| FormatError::Decompress {
            path: input.path().to_path_buf(),
            offset: at,
            codec,
            message,
        };
        let plain: &[u8] = match self.compression {
            Compression::None => &self.payload,
            Compression::Lz4 => {
                let n = lz4_frame_decode(&self.payload, &mut self.plain, MAX_DECOMPRESSED_BYTES)
                    .map_err(|m| decompress_error(&self.input, "LZ4", m))?;
                &self.plain[..n]
            }
            Compression::Zstd => {
                let decoder = match &mut self.zstd {
                    Some(d) => d,
                    None => self.zstd.insert(
                        zstd::stream::raw::Decoder::new()
                            .map_err(|e| decompress_error(&self.input, "Zstd", e.to_string()))?,
                    ),
                };
                let n = zstd_decode(
                    decoder,
                    &self.payload,
                    &mut self.plain,
                    MAX_DECOMPRESSED_BYTES,
                )
                .map_err(|m| decompress_error(&self.input, "Zstd", m))?;
                &self.plain[..n]
            }
        };
        let bad = |field, found: String, expected: &str| FormatError::Invalid {
            path: self.input.path().to_path_buf(),
            offset: at,
            field,
            found,
            expected: expected.to_owned(),
        };
        let prefix = u32_at(plain, 0)
            .ok_or_else(|| bad("flatbuffer size prefix", "missing".into(), "4 bytes"))?;
        let fb = plain
            .get(4..(prefix as usize).saturating_add(4))
            .ok_or_else(|| {
                bad(
                    "flatbuffer size prefix",
                    prefix.to_string(),
                    "at most the payload size",
                )
            })?;
        let fb = Buffer(fb);
        if fb.identifier() != Some(b"EVTS") {
            if self.stream.is_none() {
                self.stats.skipped += 1; // another stream type, no description to tell
                return Ok(false);
            }
            let found = escape(fb.identifier().unwrap_or(&[]));
            return Err(bad(
                "packet identifier",
                found,
                "`EVTS` (the description says so)",
            ));
        }
        let (_, events) = fb
            .root()
            .and_then(|t| t.struct_vector(0, EVENT_BYTES))
            .ok_or_else(|| {
                bad(
                    "event vector",
                    "an out-of-bounds offset".into(),
                    "a valid flatbuffer",
                )
            })?;
        let (size_x, size_y) = self.sensor.bounds();
        let (size_x, size_y) = (
            i16::try_from(size_x).unwrap_or(i16::MAX),
            i16::try_from(size_y).unwrap_or(i16::MAX),
        );
        let before = out.len();
        let n = events.len() / EVENT_BYTES;
        out.t.reserve(n);
        out.x.reserve(n);
        out.y.reserve(n);
        out.polarity.reserve(n);
        let mut previous = self.previous;
        for e in events.chunks_exact(EVENT_BYTES) {
            let t = i64::from_le_bytes([e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7]]);
            let x = i16::from_le_bytes([e[8], e[9]]);
            let y = i16::from_le_bytes([e[10], e[11]]);
            if !(0..size_x).contains(&x) || !(0..size_y).contains(&y) {
                self.stats.out_of_range += 1;
                continue;
            }
            if t < previous {
                self.stats.check_order(at, previous, t);
            }
            previous = t;
            out.t.push(t);
            out.x.push(x as u16);
            out.y.push(y as u16);
            out.polarity.push(e[12] != 0);
        }
        self.previous = previous;
        self.stats.events += (out.len() - before) as u64;
        Ok(out.len() > before)
    }
}

impl<R: Read> EventReader for Aedat4Reader<R> {
    fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
        ReaderEnd::chunk(
            self,
            |r| &mut r.end,
            out,
            |r, out| r.next_events(out).map(|_| ()),
        )
    }

    fn stats(&self) -> ReadStats {
        self.stats
    }

    fn sensor_size(&self) -> Option<(u16, u16)> {
        self.sensor.stated
    }
}
