//! [`Aedat4Writer`]: an event-only AEDAT 4.0 file as dv-processing's `MonoCameraWriter` writes
//! it, with the data table at the end.

use super::framing::lz4_frame_encode;
use super::{Compression, EVENT_BYTES, MAGIC, PACKET_EVENTS};
use crate::error::FormatError;
use crate::format::camera::camera_of_size;
use crate::format::contract::{EventWriter, check_inside, unsupported_size, write_error};
use neurotac_core::EventBuffer;
use std::io::{Seek, SeekFrom, Write};
use std::path::PathBuf;

/// One entry of the file data table.
struct TableEntry {
    payload_offset: i64,
    size: i32,
    events: i64,
    t_start: i64,
    t_end: i64,
}

/// Writer of AEDAT 4.0 files with one event stream (id 0, stating its sensor size; davis240.md
/// §2.3).
pub struct Aedat4Writer<W: Write + Seek> {
    out: W,
    path: PathBuf,
    compression: Compression,
    size: (u16, u16),
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

/// Largest sensor width or height an AEDAT 4.0 file can state: its coordinates are `i16`.
const MAX_SIZE: u16 = i16::MAX as u16;

impl<W: Write + Seek> Aedat4Writer<W> {
    /// Writes the magic and IOHeader of a `sensor` (width, height) recording to `out`, labelled
    /// `<output>` in errors.
    pub fn new(out: W, compression: Compression, sensor: (u16, u16)) -> Result<Self, FormatError> {
        Self::with_name(out, PathBuf::from("<output>"), compression, sensor)
    }

    /// Writes the magic and IOHeader of a `sensor` (width, height) recording to `out`, named
    /// `path` in errors. The description states the size as the stream's `sizeX`/`sizeY` and
    /// its `source` as the camera of that size (`DAVIS240C`, `DAVIS346`; `neurotac` for others);
    /// a width or height of 0 or above 32767 is refused ([`FormatError::UnsupportedSensorSize`]).
    pub fn with_name(
        out: W,
        path: PathBuf,
        compression: Compression,
        sensor: (u16, u16),
    ) -> Result<Self, FormatError> {
        if !(1..=MAX_SIZE).contains(&sensor.0) || !(1..=MAX_SIZE).contains(&sensor.1) {
            let supported = "1 … 32767 pixels each way";
            return Err(unsupported_size(&path, "AEDAT 4.0", sensor, supported));
        }
        let source = camera_of_size(sensor).map_or("neurotac", |c| c.name);
        let description = format!(
            "<dv version=\"2.0\">\n    <node name=\"outInfo\" path=\"/outInfo/\">\n        <node name=\"0\" path=\"/outInfo/0/\">\n            <attr key=\"compression\" type=\"string\">{}</attr>\n            <attr key=\"originalModuleName\" type=\"string\">neurotac</attr>\n            <attr key=\"originalOutputName\" type=\"string\">events</attr>\n            <attr key=\"typeDescription\" type=\"string\">Array of events (polarity ON/OFF).</attr>\n            <attr key=\"typeIdentifier\" type=\"string\">EVTS</attr>\n            <node name=\"info\" path=\"/outInfo/0/info/\">\n                <attr key=\"sizeX\" type=\"int\">{}</attr>\n                <attr key=\"sizeY\" type=\"int\">{}</attr>\n                <attr key=\"source\" type=\"string\">{source}</attr>\n            </node>\n        </node>\n    </node>\n</dv>\n",
            compression.name(),
            sensor.0,
            sensor.1
        );
        let header = io_header(compression, &description);
        let mut w = Self {
            out,
            path,
            compression,
            size: sensor,
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
        self.out.write_all(bytes).map_err(write_error(&self.path))?;
        self.offset += bytes.len() as u64;
        Ok(())
    }

    /// Compresses `self.plain` into `self.compressed` with the file's codec.
    fn compress(&mut self) -> Result<(), FormatError> {
        self.compressed.clear();
        match self.compression {
            Compression::None => self.compressed.extend_from_slice(&self.plain),
            Compression::Lz4 => lz4_frame_encode(&self.plain, &mut self.compressed)
                .map_err(|e| write_error(&self.path)(std::io::Error::other(e.to_string())))?,
            Compression::Zstd => {
                let compressor = match &mut self.zstd {
                    Some(c) => c,
                    None => self.zstd.insert(
                        zstd::bulk::Compressor::new(zstd::DEFAULT_COMPRESSION_LEVEL)
                            .map_err(write_error(&self.path))?,
                    ),
                };
                self.compressed
                    .reserve(zstd::compress_bound(self.plain.len()));
                compressor
                    .compress_to_buffer(&self.plain, &mut self.compressed)
                    .map_err(write_error(&self.path))?;
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
            // Inside a size of at most 32767, x and y fit AEDAT 4.0's 16-bit signed fields.
            check_inside(&self.path, self.written + i as u64, (x, y), self.size)?;
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
            .map_err(write_error(&self.path))?;
        self.finished = true;
        Ok(())
    }
}
