//! AEDAT 4.0, the DV / dv-processing format (davis240.md §2.3).
//!
//! Layout: `#!AER-DAT4.0\r\n`, a `u32` IOHeader size N, the IOHeader flatbuffer (identifier
//! `IOHE`; fields 0 compression — 0 none, 1 LZ4, 2 LZ4 high, 3 Zstd, 4 Zstd high —, 1 data-table
//! position (−1: none), 2 XML description of the streams). Then packets until the end of the file
//! or the data-table position: `i32 streamId, i32 size`, then `size` bytes: one LZ4 or Zstd frame
//! (or the raw bytes) holding a size-prefixed flatbuffer. Event packets (identifier `EVTS`) hold
//! a vector of 16-byte events `i64 t, i16 x, i16 y, u8 on, 3 bytes padding`.
//!
//! The reader takes the first stream whose `typeIdentifier` is `EVTS` (with its `sizeX`/`sizeY`)
//! from the description; packets of other streams (frames, IMU, triggers, a second camera) and
//! zero-length packets are skipped without decompressing them and counted in
//! [`ReadStats::skipped`]. It ignores the file data table and stops where it starts.
//!
//! The writer produces what dv-processing's `MonoCameraWriter` does for an event-only stream: one
//! stream 0 `EVTS`, packets of [`PACKET_EVENTS`] events, and the `FTAB` data table at the end,
//! its position patched into the IOHeader.

use super::flatbuffer::{Buffer, u32_at};
use super::input::Input;
use super::{DAVIS240_SIZE, EventReader, EventWriter, ReadStats, ReaderEnd, io_error};
use crate::error::FormatError;
use neurotac_core::EventBuffer;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::PathBuf;
use zstd::stream::raw::Operation;

/// The magic line.
const MAGIC: &[u8; 14] = b"#!AER-DAT4.0\r\n";
/// Largest IOHeader accepted.
pub const MAX_HEADER_BYTES: u32 = 1 << 20;
/// Largest packet payload accepted (bytes in the file).
pub const MAX_PACKET_BYTES: u64 = 256 << 20;
/// Largest decompressed packet accepted.
pub const MAX_DECOMPRESSED_BYTES: usize = 512 << 20;
/// Events per packet written (as dv-processing).
pub const PACKET_EVENTS: usize = 10_000;
const EVENT_BYTES: usize = 16;
const LZ4_MAGIC: u32 = 0x184D_2204;
const LZ4_BLOCK: usize = 64 << 10;

/// Packet compression of an AEDAT 4.0 file (IOHeader field 0; davis240.md §2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Compression {
    /// Raw flatbuffers (IOHeader value 0).
    None,
    /// One LZ4 frame per packet (values 1 and 2, "LZ4 high" differs only when writing).
    Lz4,
    /// One Zstd frame per packet (values 3 and 4).
    Zstd,
}

impl Compression {
    fn from_header(v: i32) -> Option<Self> {
        match v {
            0 => Some(Self::None),
            1 | 2 => Some(Self::Lz4),
            3 | 4 => Some(Self::Zstd),
            _ => None,
        }
    }

    fn header_value(self) -> i32 {
        match self {
            Self::None => 0,
            Self::Lz4 => 1,
            Self::Zstd => 3,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::None => "NONE",
            Self::Lz4 => "LZ4",
            Self::Zstd => "ZSTD",
        }
    }
}

/// An event stream found in the IOHeader description (davis240.md §2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EventStream {
    /// The packets' `streamId`.
    pub id: i32,
    /// Pixel-array size from the stream's `info` node (240 × 180 when absent).
    pub size: (u16, u16),
}

/// Text of an `<attr key="KEY" …>VALUE</attr>` inside `xml`.
fn attr<'a>(xml: &'a str, key: &str) -> Option<&'a str> {
    let at = xml.find(&format!("key=\"{key}\""))?;
    let rest = &xml[at..];
    let start = rest.find('>')? + 1;
    let end = rest[start..].find('<')?;
    Some(rest[start..start + end].trim())
}

/// The first `EVTS` stream of a DV description (`outInfo` → one node per stream id, each with a
/// `typeIdentifier` attribute and an `info` child holding `sizeX`/`sizeY`).
fn event_stream(description: &str) -> Option<EventStream> {
    let mut found: Option<EventStream> = None;
    let mut current: Option<i32> = None;
    for node in description.split("<node name=\"").skip(1) {
        let name = &node[..node.find('"').unwrap_or(0)];
        if let Ok(id) = name.parse::<i32>() {
            current = Some(id);
            if found.is_none() && attr(node, "typeIdentifier") == Some("EVTS") {
                found = Some(EventStream {
                    id,
                    size: DAVIS240_SIZE,
                });
            }
        } else if name == "info" {
            if let (Some(f), Some(id)) = (found.as_mut(), current) {
                if f.id == id {
                    let size = |k| attr(node, k).and_then(|v| v.parse::<u16>().ok());
                    if let (Some(x), Some(y)) = (size("sizeX"), size("sizeY")) {
                        f.size = (x, y);
                    }
                }
            }
        }
    }
    found
}

/// xxHash32 (seed 0) of an input shorter than 16 bytes: the LZ4 frame header checksum.
fn xxh32_short(input: &[u8]) -> u32 {
    const P1: u32 = 0x9E37_79B1;
    const P2: u32 = 0x85EB_CA77;
    const P3: u32 = 0xC2B2_AE3D;
    const P4: u32 = 0x27D4_EB2F;
    const P5: u32 = 0x1656_67B1;
    debug_assert!(input.len() < 16);
    let mut h = P5.wrapping_add(input.len() as u32);
    let mut chunks = input.chunks_exact(4);
    for c in &mut chunks {
        let v = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        h = h
            .wrapping_add(v.wrapping_mul(P3))
            .rotate_left(17)
            .wrapping_mul(P4);
    }
    for &b in chunks.remainder() {
        h = h
            .wrapping_add(u32::from(b).wrapping_mul(P5))
            .rotate_left(11)
            .wrapping_mul(P1);
    }
    h ^= h >> 15;
    h = h.wrapping_mul(P2);
    h ^= h >> 13;
    h = h.wrapping_mul(P3);
    h ^ (h >> 16)
}

/// Decodes one LZ4 frame (the LZ4 frame format: magic, FLG, BD, optional content size and
/// dictionary id, header checksum, then blocks ending with a zero size) into `dst[..n]`; `dst`
/// only grows. Blocks may be linked (each may refer to the 64 KiB before it).
fn lz4_frame_decode(src: &[u8], dst: &mut Vec<u8>, cap: usize) -> Result<usize, String> {
    let err = |m: &str| m.to_owned();
    if u32_at(src, 0) != Some(LZ4_MAGIC) || src.len() < 7 {
        return Err(err("missing LZ4 frame magic 04 22 4D 18"));
    }
    let (flg, bd) = (src[4], src[5]);
    if flg >> 6 != 1 || flg & 0x02 != 0 || bd & 0x8F != 0 {
        return Err(format!(
            "unsupported LZ4 frame descriptor FLG {flg:#04x} BD {bd:#04x}"
        ));
    }
    let block_max = match (bd >> 4) & 7 {
        4 => 64 << 10,
        5 => 256 << 10,
        6 => 1 << 20,
        7 => 4 << 20,
        other => return Err(format!("invalid LZ4 block size code {other}")),
    };
    let independent = flg & 0x20 != 0;
    let block_checksum = if flg & 0x10 != 0 { 4 } else { 0 };
    let descriptor_end =
        6 + if flg & 0x08 != 0 { 8 } else { 0 } + if flg & 0x01 != 0 { 4 } else { 0 };
    let hc = *src
        .get(descriptor_end)
        .ok_or_else(|| err("truncated LZ4 frame header"))?;
    if hc != (xxh32_short(&src[4..descriptor_end]) >> 8) as u8 {
        return Err(err("LZ4 frame header checksum mismatch"));
    }
    let mut pos = descriptor_end + 1;
    let mut len = 0usize;
    loop {
        let word = u32_at(src, pos).ok_or_else(|| err("truncated LZ4 frame (no end mark)"))?;
        pos += 4;
        if word == 0 {
            break;
        }
        let size = (word & 0x7FFF_FFFF) as usize;
        if size > block_max {
            return Err(format!(
                "LZ4 block of {size} bytes exceeds the frame's {block_max}"
            ));
        }
        let block = src
            .get(pos..pos + size)
            .ok_or_else(|| err("truncated LZ4 block"))?;
        pos += size + block_checksum;
        if len + block_max > cap {
            return Err(format!("LZ4 frame decompresses to more than {cap} bytes"));
        }
        if dst.len() < len + block_max {
            dst.resize(len + block_max, 0);
        }
        let n = if word & 0x8000_0000 != 0 {
            dst[len..len + size].copy_from_slice(block);
            size
        } else if independent || len == 0 {
            lz4_flex::block::decompress_into(block, &mut dst[len..len + block_max])
                .map_err(|e| e.to_string())?
        } else {
            let (dict, out) = dst.split_at_mut(len);
            let dict = &dict[len.saturating_sub(LZ4_BLOCK)..];
            lz4_flex::block::decompress_into_with_dict(block, &mut out[..block_max], dict)
                .map_err(|e| e.to_string())?
        };
        len += n;
    }
    if flg & 0x04 != 0 && src.len() < pos + 4 {
        return Err(err("truncated LZ4 content checksum"));
    }
    Ok(len)
}

/// Decodes the Zstd frame(s) of `src` into `dst[..n]` with a reused decoder; `dst` only grows.
fn zstd_decode(
    decoder: &mut zstd::stream::raw::Decoder<'static>,
    src: &[u8],
    dst: &mut Vec<u8>,
    cap: usize,
) -> Result<usize, String> {
    decoder.reinit().map_err(|e| e.to_string())?;
    let (mut read, mut len) = (0usize, 0usize);
    loop {
        if dst.len() - len < LZ4_BLOCK {
            let grown = (dst.len() * 2).max(1 << 20).min(cap);
            if grown <= dst.len() {
                return Err(format!("Zstd frame decompresses to more than {cap} bytes"));
            }
            dst.resize(grown, 0);
        }
        let status = decoder
            .run_on_buffers(&src[read..], &mut dst[len..])
            .map_err(|e| e.to_string())?;
        read += status.bytes_read;
        len += status.bytes_written;
        if status.remaining == 0 && read == src.len() {
            return Ok(len);
        }
        if status.bytes_read == 0 && status.bytes_written == 0 {
            return Err("truncated Zstd frame".to_owned());
        }
    }
}

/// Streaming reader of AEDAT 4.0 files (the first event stream; davis240.md §2.3).
pub struct Aedat4Reader<R> {
    input: Input<R>,
    compression: Compression,
    data_table: Option<u64>,
    file_len: Option<u64>,
    description: String,
    stream: Option<EventStream>,
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
            return Err(input.invalid(0, "magic", super::escape(&magic), "`#!AER-DAT4.0\\r\\n`"));
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
            let found = super::escape(buf.identifier().unwrap_or(&[]));
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
            payload: Vec::new(),
            plain: Vec::new(),
            zstd: None,
            previous: i64::MIN,
            stats: ReadStats::default(),
            end: ReaderEnd::default(),
        })
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
            let found = super::escape(fb.identifier().unwrap_or(&[]));
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
        let (size_x, size_y) = self.stream.map_or(DAVIS240_SIZE, |s| s.size);
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
        Some(self.stream.map_or(DAVIS240_SIZE, |s| s.size))
    }
}

/// One entry of the file data table.
struct TableEntry {
    payload_offset: i64,
    size: i32,
    events: i64,
    t_start: i64,
    t_end: i64,
}

/// Writer of AEDAT 4.0 files with one event stream (id 0, 240 × 180; davis240.md §2.3).
pub struct Aedat4Writer<W: Write + Seek> {
    out: W,
    path: PathBuf,
    compression: Compression,
    /// Offset of the next byte in the file.
    offset: u64,
    /// Events of the packet being filled (16 bytes each).
    events: Vec<u8>,
    count: usize,
    range: (i64, i64),
    plain: Vec<u8>,
    compressed: Vec<u8>,
    zstd: Option<zstd::bulk::Compressor<'static>>,
    table: Vec<TableEntry>,
    written: u64,
    finished: bool,
}

/// Byte offset of the data-table position inside the IOHeader written by [`Aedat4Writer`].
const TABLE_POSITION_AT: u64 = 18 + 36;

/// The IOHeader flatbuffer (the layout dv-processing writes): root at 24, vtable at 14, table at
/// 24 with compression at +4, description offset at +8, data-table position at +12, then the
/// NUL-terminated description string.
fn io_header(compression: Compression, description: &str) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&24u32.to_le_bytes());
    b.extend_from_slice(b"IOHE");
    b.extend_from_slice(&[0; 6]);
    for v in [10u16, 20, 4, 12, 8] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&10i32.to_le_bytes());
    b.extend_from_slice(&compression.header_value().to_le_bytes());
    b.extend_from_slice(&12u32.to_le_bytes()); // string at 32 + 12 = 44
    b.extend_from_slice(&(-1i64).to_le_bytes());
    b.extend_from_slice(&(description.len() as u32).to_le_bytes());
    b.extend_from_slice(description.as_bytes());
    b.push(0);
    while b.len() % 4 != 0 {
        b.push(0);
    }
    b
}

impl<W: Write + Seek> Aedat4Writer<W> {
    /// Writes the magic and IOHeader to `out`, labelled `<output>` in errors.
    pub fn new(out: W, compression: Compression) -> Result<Self, FormatError> {
        Self::with_name(out, PathBuf::from("<output>"), compression)
    }

    /// Writes the magic and IOHeader to `out`, named `path` in errors.
    pub fn with_name(out: W, path: PathBuf, compression: Compression) -> Result<Self, FormatError> {
        let description = format!(
            "<dv version=\"2.0\">\n    <node name=\"outInfo\" path=\"/outInfo/\">\n        <node name=\"0\" path=\"/outInfo/0/\">\n            <attr key=\"compression\" type=\"string\">{}</attr>\n            <attr key=\"originalModuleName\" type=\"string\">neurotac</attr>\n            <attr key=\"originalOutputName\" type=\"string\">events</attr>\n            <attr key=\"typeDescription\" type=\"string\">Array of events (polarity ON/OFF).</attr>\n            <attr key=\"typeIdentifier\" type=\"string\">EVTS</attr>\n            <node name=\"info\" path=\"/outInfo/0/info/\">\n                <attr key=\"sizeX\" type=\"int\">{}</attr>\n                <attr key=\"sizeY\" type=\"int\">{}</attr>\n                <attr key=\"source\" type=\"string\">DAVIS240C</attr>\n            </node>\n        </node>\n    </node>\n</dv>\n",
            compression.name(),
            DAVIS240_SIZE.0,
            DAVIS240_SIZE.1
        );
        let header = io_header(compression, &description);
        let mut w = Self {
            out,
            path,
            compression,
            offset: 0,
            events: Vec::with_capacity(PACKET_EVENTS * EVENT_BYTES),
            count: 0,
            range: (0, 0),
            plain: Vec::new(),
            compressed: Vec::new(),
            zstd: None,
            table: Vec::new(),
            written: 0,
            finished: false,
        };
        w.put(MAGIC)?;
        w.put(&(header.len() as u32).to_le_bytes())?;
        w.put(&header)?;
        Ok(w)
    }

    fn put(&mut self, bytes: &[u8]) -> Result<(), FormatError> {
        self.out.write_all(bytes).map_err(io_error(&self.path))?;
        self.offset += bytes.len() as u64;
        Ok(())
    }

    /// Compresses `self.plain` into `self.compressed` with the file's codec.
    fn compress(&mut self) -> Result<(), FormatError> {
        self.compressed.clear();
        match self.compression {
            Compression::None => self.compressed.extend_from_slice(&self.plain),
            Compression::Lz4 => {
                // Frame header: FLG = version 01 | independent blocks, BD = 64 KiB blocks.
                let descriptor = [0x60u8, 0x40];
                self.compressed.extend_from_slice(&LZ4_MAGIC.to_le_bytes());
                self.compressed.extend_from_slice(&descriptor);
                self.compressed.push((xxh32_short(&descriptor) >> 8) as u8);
                for block in self.plain.chunks(LZ4_BLOCK) {
                    let at = self.compressed.len();
                    let bound = lz4_flex::block::get_maximum_output_size(block.len());
                    self.compressed.resize(at + 4 + bound, 0);
                    let n = lz4_flex::block::compress_into(block, &mut self.compressed[at + 4..])
                        .map_err(|e| {
                        io_error(&self.path)(std::io::Error::other(e.to_string()))
                    })?;
                    let word = if n < block.len() {
                        n as u32
                    } else {
                        // Incompressible: store the block raw (high bit set).
                        self.compressed[at + 4..at + 4 + block.len()].copy_from_slice(block);
                        block.len() as u32 | 0x8000_0000
                    };
                    self.compressed[at..at + 4].copy_from_slice(&word.to_le_bytes());
                    self.compressed
                        .truncate(at + 4 + (word & 0x7FFF_FFFF) as usize);
                }
                self.compressed.extend_from_slice(&0u32.to_le_bytes());
            }
            Compression::Zstd => {
                let compressor = match &mut self.zstd {
                    Some(c) => c,
                    None => self.zstd.insert(
                        zstd::bulk::Compressor::new(zstd::DEFAULT_COMPRESSION_LEVEL)
                            .map_err(io_error(&self.path))?,
                    ),
                };
                self.compressed
                    .reserve(zstd::compress_bound(self.plain.len()));
                compressor
                    .compress_to_buffer(&self.plain, &mut self.compressed)
                    .map_err(io_error(&self.path))?;
            }
        }
        Ok(())
    }

    /// Writes the events collected so far as one packet.
    fn flush_packet(&mut self) -> Result<(), FormatError> {
        if self.count == 0 {
            return Ok(());
        }
        // Size-prefixed EVTS flatbuffer, laid out as dv-processing does: root table at 16
        // (after the prefix), vtable at 10, event vector at 24, events 8-aligned at 28.
        self.plain.clear();
        let total = 28 + self.events.len();
        self.plain.extend_from_slice(&(total as u32).to_le_bytes());
        self.plain.extend_from_slice(&16u32.to_le_bytes());
        self.plain.extend_from_slice(b"EVTS");
        self.plain.extend_from_slice(&[0, 0]);
        for v in [6u16, 8, 4] {
            self.plain.extend_from_slice(&v.to_le_bytes());
        }
        self.plain.extend_from_slice(&6i32.to_le_bytes());
        self.plain.extend_from_slice(&4u32.to_le_bytes());
        self.plain
            .extend_from_slice(&(self.count as u32).to_le_bytes());
        self.plain.extend_from_slice(&self.events);
        self.compress()?;
        let size = self.compressed.len() as i32;
        let payload_offset = self.offset as i64 + 8;
        let mut h = [0u8; 8];
        h[4..].copy_from_slice(&size.to_le_bytes());
        self.put(&h)?;
        let compressed = std::mem::take(&mut self.compressed);
        let result = self.put(&compressed);
        self.compressed = compressed;
        result?;
        self.table.push(TableEntry {
            payload_offset,
            size,
            events: self.count as i64,
            t_start: self.range.0,
            t_end: self.range.1,
        });
        self.events.clear();
        self.count = 0;
        Ok(())
    }

    /// The FTAB flatbuffer (size-prefixed): a root table whose field 0 is a vector of entry
    /// tables {0 byteOffset i64, 1 struct {i32 streamId, i32 size}, 2 numElements i64,
    /// 3 timestampStart i64, 4 timestampEnd i64}, all entries sharing one vtable.
    fn data_table(&self) -> Vec<u8> {
        let n = self.table.len();
        let mut b = Vec::new();
        b.extend_from_slice(&0u32.to_le_bytes()); // size prefix, patched below
        b.extend_from_slice(&16u32.to_le_bytes()); // root table at 4 + 16 = 20
        b.extend_from_slice(b"FTAB");
        for v in [6u16, 8, 4] {
            b.extend_from_slice(&v.to_le_bytes()); // root vtable at 12
        }
        b.extend_from_slice(&[0, 0]);
        b.extend_from_slice(&8i32.to_le_bytes()); // root table at 20
        b.extend_from_slice(&4u32.to_le_bytes()); // vector at 28
        b.extend_from_slice(&(n as u32).to_le_bytes());
        let offsets_at = b.len();
        b.resize(offsets_at + 4 * n, 0);
        let vtable_at = b.len();
        for v in [14u16, 48, 8, 16, 24, 32, 40] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        while b.len() % 8 != 0 {
            b.push(0);
        }
        for (k, e) in self.table.iter().enumerate() {
            let at = b.len();
            let slot = offsets_at + 4 * k;
            b[slot..slot + 4].copy_from_slice(&((at - slot) as u32).to_le_bytes());
            b.extend_from_slice(&((at - vtable_at) as i32).to_le_bytes());
            b.extend_from_slice(&[0; 4]);
            b.extend_from_slice(&e.payload_offset.to_le_bytes());
            b.extend_from_slice(&0i32.to_le_bytes());
            b.extend_from_slice(&e.size.to_le_bytes());
            for v in [e.events, e.t_start, e.t_end] {
                b.extend_from_slice(&v.to_le_bytes());
            }
        }
        let size = (b.len() - 4) as u32;
        b[..4].copy_from_slice(&size.to_le_bytes());
        b
    }
}

impl<W: Write + Seek> EventWriter for Aedat4Writer<W> {
    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
        for i in 0..events.len() {
            let (x, y) = (events.x[i], events.y[i]);
            if x > i16::MAX as u16 || y > i16::MAX as u16 {
                return Err(FormatError::Unrepresentable {
                    path: self.path.clone(),
                    index: self.written + i as u64,
                    reason: format!("pixel ({x}, {y}) exceeds AEDAT 4.0's 16-bit signed addresses"),
                });
            }
            let t = events.t[i];
            if self.count == 0 {
                self.range = (t, t);
            }
            self.range = (self.range.0.min(t), self.range.1.max(t));
            let mut e = [0u8; EVENT_BYTES];
            e[..8].copy_from_slice(&t.to_le_bytes());
            e[8..10].copy_from_slice(&x.to_le_bytes());
            e[10..12].copy_from_slice(&y.to_le_bytes());
            e[12] = u8::from(events.polarity[i]);
            self.events.extend_from_slice(&e);
            self.count += 1;
            if self.count == PACKET_EVENTS {
                self.flush_packet()?;
            }
        }
        self.written += events.len() as u64;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        if self.finished {
            return Ok(());
        }
        self.flush_packet()?;
        let position = self.offset;
        self.plain = self.data_table();
        self.compress()?;
        let table = std::mem::take(&mut self.compressed);
        self.put(&table)?;
        self.out
            .seek(SeekFrom::Start(TABLE_POSITION_AT))
            .and_then(|_| self.out.write_all(&(position as i64).to_le_bytes()))
            .and_then(|_| self.out.seek(SeekFrom::End(0)))
            .and_then(|_| self.out.flush())
            .map_err(io_error(&self.path))?;
        self.finished = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lz4_header_checksum_matches_dv_processing() {
        // dv-processing's LZ4 packets start 04 22 4D 18 40 40 C0.
        assert_eq!((xxh32_short(&[0x40, 0x40]) >> 8) as u8, 0xC0);
        assert_eq!(xxh32_short(&[]), 0x02CC_5D05); // the xxHash32 test vector for "" and seed 0
    }

    #[test]
    fn description_names_the_event_stream_and_size() {
        let xml = "<dv><node name=\"outInfo\"><node name=\"0\"><attr key=\"typeIdentifier\" type=\"string\">FRME</attr><node name=\"info\"><attr key=\"sizeX\" type=\"int\">346</attr></node></node><node name=\"3\"><attr key=\"typeIdentifier\" type=\"string\">EVTS</attr><node name=\"info\"><attr key=\"sizeX\" type=\"int\">346</attr><attr key=\"sizeY\" type=\"int\">260</attr></node></node></node></dv>";
        assert_eq!(
            event_stream(xml),
            Some(EventStream {
                id: 3,
                size: (346, 260)
            })
        );
        assert_eq!(event_stream("<dv></dv>"), None);
    }
}
