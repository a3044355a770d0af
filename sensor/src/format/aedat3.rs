//! AEDAT 3.1, the cAER/libcaer format (davis240.md §2.2).
//!
//! Header: ASCII lines (CRLF) from `#!AER-DAT3.1` to `#!END-HEADER`. Then event packets, all
//! little-endian: a 28-byte header (`i16 eventType, i16 eventSource, i32 eventSize,
//! i32 eventTSOffset, i32 eventTSOverflow, i32 eventCapacity, i32 eventNumber, i32 eventValid`)
//! followed by `eventCapacity × eventSize` bytes. Polarity packets (type 1, 8-byte events):
//! `u32 data` (bit 0 valid, bit 1 polarity, bits 16–2 y, bits 31–17 x) then `i32 timestamp`;
//! time = `(eventTSOverflow << 31) | timestamp`. Other packet types are skipped (counted), as are
//! invalid events (valid bit 0) and the unused capacity past `eventNumber`.
//!
//! Sensor size: cAER names the camera on a header line `#Source <id>: <name>` (`DAVIS240C`,
//! `DAVIS346`, `DAVIS346B`, …); a name of [`CAMERAS`](super::camera::CAMERAS) states its size.
//! A header without one, or naming another camera, states none and is read with the assumed
//! size (240 × 180 by default). The writer names the camera of its size and refuses any other
//! size: AEDAT 3.1 cannot state one.

use super::camera::{CAMERA_SIZES, camera_named, camera_of_size};
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

/// Largest header accepted.
pub const MAX_HEADER_BYTES: u64 = 1 << 20;
/// Events per packet written.
pub const PACKET_EVENTS: usize = 4096;

const PACKET_HEADER: usize = 28;
const POLARITY_TYPE: i16 = 1;
const EVENT_SIZE: usize = 8;
const END_HEADER: &str = "#!END-HEADER";

/// The AEDAT 3.1 header: `#` lines from the version line to `#!END-HEADER`.
const HEADER_SPEC: HeaderSpec = HeaderSpec {
    version: "#!AER-DAT3.1",
    end_marker: END_HEADER,
    expected_end: "the rest of the header through its end line `#!END-HEADER`",
    is_end: |line| line.trim_ascii_end() == END_HEADER.as_bytes(),
    limit: MAX_HEADER_BYTES,
    data_ends_header: false,
};

/// The camera of a `#Source <id>: <name>` header line, if it names one of the known cameras.
fn source_camera(line: &[u8]) -> Option<&'static super::camera::Camera> {
    let text = std::str::from_utf8(line).ok()?;
    let (_, name) = text.strip_prefix("#Source ")?.split_once(':')?;
    camera_named(name)
}

/// The packet being read.
#[derive(Debug, Clone, Copy)]
struct Packet {
    /// `eventTSOverflow << 31`.
    overflow: i64,
    /// Events still to decode.
    events_left: u64,
    /// Bytes of unused capacity after them.
    tail_bytes: u64,
}

/// Streaming reader of AEDAT 3.1 files (polarity events; davis240.md §2.2).
pub struct Aedat3Reader<R> {
    input: Input<R>,
    header: Vec<u8>,
    sensor: ReaderSensor,
    packet: Option<Packet>,
    block: Vec<u8>,
    previous: i64,
    stats: ReadStats,
    end: ReaderEnd,
}

impl<R: Read> Aedat3Reader<R> {
    /// Reads the header of an AEDAT 3.1 input, labelled `<input>` in errors.
    pub fn new(reader: R) -> Result<Self, FormatError> {
        Self::with_name(reader, PathBuf::from("<input>"))
    }

    /// Reads the header of an AEDAT 3.1 input named `path` in errors. Events outside the
    /// sensor its `#Source` line names (module docs) are skipped.
    pub fn with_name(reader: R, path: PathBuf) -> Result<Self, FormatError> {
        let mut input = Input::new(reader, path);
        let header = read_header(&mut input, &HEADER_SPEC)?;
        let stated = header
            .lines()
            .filter_map(|(_, line)| source_camera(line))
            .map(|c| c.size)
            .next();
        Ok(Self {
            input,
            header: header.bytes,
            sensor: ReaderSensor::new(stated),
            packet: None,
            block: vec![0; READ_BLOCK],
            previous: i64::MIN,
            stats: ReadStats::default(),
            end: ReaderEnd::default(),
        })
    }

    /// Reads a file whose header names no known camera as a `size` sensor (instead of
    /// 240 × 180).
    pub fn assuming(mut self, size: (u16, u16)) -> Self {
        self.sensor.assumed = size;
        self
    }

    /// The header lines as read.
    pub fn header(&self) -> &[u8] {
        &self.header
    }

    /// Reads the next packet header; `None` at a clean end of the input.
    fn next_packet(&mut self) -> Result<Option<Packet>, FormatError> {
        let at = self.input.offset();
        let mut h = [0u8; PACKET_HEADER];
        let n = self.input.read_full(&mut h)?;
        if n == 0 {
            return Ok(None);
        }
        if n < PACKET_HEADER {
            return Err(self
                .input
                .truncated_at(at, "a 28-byte AEDAT 3.1 packet header"));
        }
        let i32_at = |i: usize| i32::from_le_bytes([h[i], h[i + 1], h[i + 2], h[i + 3]]);
        let event_type = i16::from_le_bytes([h[0], h[1]]);
        let (size, ts_offset, overflow) = (i32_at(4), i32_at(8), i32_at(12));
        let (capacity, number) = (i32_at(16), i32_at(20));
        for (field, v) in [
            ("eventSize", size),
            ("eventCapacity", capacity),
            ("eventNumber", number),
            ("eventTSOverflow", overflow),
        ] {
            if v < 0 {
                return Err(self.input.invalid(at, field, v, "a non-negative value"));
            }
        }
        if number > capacity {
            let expected = format!("at most eventCapacity = {capacity}");
            return Err(self.input.invalid(at, "eventNumber", number, expected));
        }
        let payload = capacity as u64 * size as u64;
        if event_type != POLARITY_TYPE {
            self.stats.skipped += 1;
            self.input
                .skip(payload, "the events of an AEDAT 3.1 packet")?;
            return Ok(Some(Packet {
                overflow: 0,
                events_left: 0,
                tail_bytes: 0,
            }));
        }
        if size as usize != EVENT_SIZE || ts_offset != 4 {
            let found = format!("{size} (eventTSOffset {ts_offset})");
            return Err(self.input.invalid(
                at,
                "eventSize",
                found,
                "8 (eventTSOffset 4) for polarity events",
            ));
        }
        if capacity == 0 {
            self.stats.skipped += 1; // an empty packet
        }
        Ok(Some(Packet {
            overflow: i64::from(overflow) << 31,
            events_left: number as u64,
            tail_bytes: (capacity - number) as u64 * EVENT_SIZE as u64,
        }))
    }

    /// Decodes up to one block of the current packet's events.
    fn decode_some(
        &mut self,
        packet: &mut Packet,
        out: &mut EventBuffer,
    ) -> Result<(), FormatError> {
        let wanted = (packet.events_left as usize).min(READ_BLOCK / EVENT_SIZE);
        let start = self.input.offset();
        let got = self
            .input
            .read_full(&mut self.block[..wanted * EVENT_SIZE])?;
        // Whole events that arrived are decoded even when the packet is cut short.
        let n = got / EVENT_SIZE;
        let (size_x, size_y) = self.sensor.bounds();
        let (size_x, size_y) = (u32::from(size_x), u32::from(size_y));
        let mut delivered = 0u64;
        for (i, e) in self.block[..n * EVENT_SIZE]
            .chunks_exact(EVENT_SIZE)
            .enumerate()
        {
            let data = u32::from_le_bytes([e[0], e[1], e[2], e[3]]);
            let ts = i32::from_le_bytes([e[4], e[5], e[6], e[7]]);
            if data & 1 == 0 {
                self.stats.skipped += 1;
                continue;
            }
            let (x, y) = (data >> 17, (data >> 2) & 0x7FFF);
            if x >= size_x || y >= size_y {
                self.stats.out_of_range += 1;
                continue;
            }
            let t = packet.overflow | i64::from(ts);
            self.stats
                .check_order(start + (i * EVENT_SIZE) as u64, self.previous, t);
            self.previous = t;
            out.t.push(t);
            out.x.push(x as u16);
            out.y.push(y as u16);
            out.polarity.push(data & 2 != 0);
            delivered += 1;
        }
        self.stats.events += delivered;
        if n < wanted {
            return Err(self.input.truncated_at(
                start + got as u64,
                "the events of an AEDAT 3.1 polarity packet",
            ));
        }
        packet.events_left -= n as u64;
        if packet.events_left == 0 && packet.tail_bytes > 0 {
            self.input.skip(
                packet.tail_bytes,
                "the unused capacity of an AEDAT 3.1 packet",
            )?;
            packet.tail_bytes = 0;
        }
        Ok(())
    }

    fn fill(&mut self, out: &mut EventBuffer) -> Result<(), FormatError> {
        let before = out.len();
        while out.len() == before {
            let mut packet = match self.packet.take() {
                Some(p) => p,
                None => match self.next_packet()? {
                    Some(p) => p,
                    None => return Ok(()),
                },
            };
            if packet.events_left > 0 {
                self.decode_some(&mut packet, out)?;
            }
            if packet.events_left > 0 {
                self.packet = Some(packet);
            }
        }
        Ok(())
    }
}

impl<R: Read> EventReader for Aedat3Reader<R> {
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

/// Writer of AEDAT 3.1 files (davis240.md §2.2): a header naming the camera, then polarity
/// packets of up to [`PACKET_EVENTS`] events (capacity = number = valid), a new packet whenever
/// `t >> 31` changes. The sensor must be one of [`CAMERAS`](super::camera::CAMERAS); times must
/// be non-negative.
pub struct Aedat3Writer<W: Write> {
    out: W,
    path: PathBuf,
    size: (u16, u16),
    written: u64,
    packet: Vec<u8>,
    count: usize,
    overflow: i64,
}

impl<W: Write> Aedat3Writer<W> {
    /// Writes the header of a `sensor` (width, height) recording to `out`, labelled `<output>`
    /// in errors.
    pub fn new(out: W, sensor: (u16, u16)) -> Result<Self, FormatError> {
        Self::with_name(out, PathBuf::from("<output>"), sensor)
    }

    /// Writes the header of a `sensor` (width, height) recording to `out`, named `path` in
    /// errors; a sensor that no camera of [`CAMERAS`](super::camera::CAMERAS) has is refused
    /// ([`FormatError::UnsupportedSensorSize`]).
    pub fn with_name(mut out: W, path: PathBuf, sensor: (u16, u16)) -> Result<Self, FormatError> {
        let camera = camera_of_size(sensor)
            .ok_or_else(|| unsupported_size(&path, "AEDAT 3.1", sensor, CAMERA_SIZES))?;
        let header = format!(
            "#!AER-DAT3.1\r\n#Format: RAW\r\n#Source 1: {}\r\n#!END-HEADER\r\n",
            camera.name
        );
        out.write_all(header.as_bytes())
            .map_err(write_error(&path))?;
        Ok(Self {
            out,
            path,
            size: sensor,
            written: 0,
            packet: Vec::with_capacity(PACKET_HEADER + PACKET_EVENTS * EVENT_SIZE),
            count: 0,
            overflow: 0,
        })
    }

    fn flush_packet(&mut self) -> Result<(), FormatError> {
        if self.count == 0 {
            return Ok(());
        }
        let n = self.count as i32;
        let mut h = [0u8; PACKET_HEADER];
        h[0..2].copy_from_slice(&POLARITY_TYPE.to_le_bytes());
        h[2..4].copy_from_slice(&1i16.to_le_bytes());
        let fields = [EVENT_SIZE as i32, 4, self.overflow as i32, n, n, n];
        for (k, v) in fields.iter().enumerate() {
            h[4 + 4 * k..8 + 4 * k].copy_from_slice(&v.to_le_bytes());
        }
        self.out.write_all(&h).map_err(write_error(&self.path))?;
        self.out
            .write_all(&self.packet)
            .map_err(write_error(&self.path))?;
        self.packet.clear();
        self.count = 0;
        Ok(())
    }
}

impl<W: Write> EventWriter for Aedat3Writer<W> {
    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
        for (i, e) in events.iter().enumerate() {
            let t = e.t.0;
            if t < 0 || t >> 31 > i64::from(i32::MAX) {
                return Err(FormatError::Unrepresentable {
                    path: self.path.clone(),
                    index: self.written + i as u64,
                    reason: format!("time {t} µs is negative or beyond AEDAT 3.1's range"),
                });
            }
            if self.count == PACKET_EVENTS || (self.count > 0 && t >> 31 != self.overflow) {
                self.flush_packet()?;
            }
            check_inside(&self.path, self.written + i as u64, (e.x, e.y), self.size)?;
            self.overflow = t >> 31;
            // The sensor is a known camera, so x and y fit the 15-bit fields.
            let data = u32::from(e.x) << 17 | u32::from(e.y) << 2 | u32::from(e.polarity) << 1 | 1;
            self.packet.extend_from_slice(&data.to_le_bytes());
            self.packet
                .extend_from_slice(&((t & 0x7FFF_FFFF) as i32).to_le_bytes());
            self.count += 1;
        }
        self.written += events.len() as u64;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        self.flush_packet()?;
        self.out.flush().map_err(write_error(&self.path))
    }
}
