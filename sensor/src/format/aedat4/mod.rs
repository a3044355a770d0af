//! AEDAT 4.0, the DV / dv-processing format (davis240.md §2.3).
//!
//! Layout: `#!AER-DAT4.0\r\n`, a `u32` IOHeader size N, the IOHeader flatbuffer (identifier
//! `IOHE`; fields 0 compression — 0 none, 1 LZ4, 2 LZ4 high, 3 Zstd, 4 Zstd high —, 1 data-table
//! position (−1: none), 2 XML description of the streams). Then packets until the end of the file
//! or the data-table position: `i32 streamId, i32 size`, then `size` bytes: one LZ4 or Zstd frame
//! (or the raw bytes) holding a size-prefixed flatbuffer. Event packets (identifier `EVTS`) hold
//! a vector of 16-byte events `i64 t, i16 x, i16 y, u8 on, 3 bytes padding`.
//!
//! The reader takes the first stream whose `typeIdentifier` is `EVTS` (with its `sizeX`/`sizeY`,
//! the sensor size the file states; without them it assumes 240 × 180 unless told otherwise)
//! from the description; packets of other streams (frames, IMU, triggers, a second camera) and
//! zero-length packets are skipped without decompressing them and counted in
//! [`ReadStats::skipped`](super::ReadStats::skipped). It ignores the file data table and stops
//! where it starts.
//!
//! The writer produces what dv-processing's `MonoCameraWriter` does for an event-only stream: one
//! stream 0 `EVTS` with the sensor's `sizeX`/`sizeY` (each 1 … 32767: coordinates are 16-bit
//! signed), packets of [`PACKET_EVENTS`] events, and the `FTAB` data table at the end, its
//! position patched into the IOHeader.
//!
//! | concern | where |
//! |---|---|
//! | header, description, packets → events | [`Aedat4Reader`] (`reader.rs`) |
//! | events → packets, data table | [`Aedat4Writer`] (`writer.rs`) |
//! | LZ4 frames (xxHash32 header checksum) and Zstd frames | `framing.rs` |

mod framing;
mod reader;
mod writer;

pub use reader::Aedat4Reader;
pub use writer::Aedat4Writer;

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
    /// Pixel-array size from the stream's `info` node (`sizeX`, `sizeY`); `None` when absent.
    pub size: Option<(u16, u16)>,
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
                found = Some(EventStream { id, size: None });
            }
        } else if name == "info"
            && let (Some(f), Some(id)) = (found.as_mut(), current)
            && f.id == id
        {
            let size = |k| attr(node, k).and_then(|v| v.parse::<u16>().ok());
            if let (Some(x), Some(y)) = (size("sizeX"), size("sizeY")) {
                f.size = Some((x, y));
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn description_names_the_event_stream_and_size() {
        let xml = "<dv><node name=\"outInfo\"><node name=\"0\"><attr key=\"typeIdentifier\" type=\"string\">FRME</attr><node name=\"info\"><attr key=\"sizeX\" type=\"int\">346</attr></node></node><node name=\"3\"><attr key=\"typeIdentifier\" type=\"string\">EVTS</attr><node name=\"info\"><attr key=\"sizeX\" type=\"int\">346</attr><attr key=\"sizeY\" type=\"int\">260</attr></node></node></node></dv>";
        assert_eq!(
            event_stream(xml),
            Some(EventStream {
                id: 3,
                size: Some((346, 260))
            })
        );
        assert_eq!(event_stream("<dv></dv>"), None);
    }
}
