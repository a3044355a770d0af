//! Event files: streaming readers and writers for every format a DAVIS240 user meets
//! (davis240.md §2).
//!
//! | format | module | reader / writer | magic / extension |
//! |---|---|---|---|
//! | AEDAT 2.0 (jAER, DAVIS layout: DAVIS240, DAVIS346) | [`aedat2`] | [`Aedat2Reader`] / [`Aedat2Writer`] | `#!AER-DAT2.0` / `.aedat`, `.aedat2` |
//! | AEDAT 3.1 (polarity packets) | [`aedat3`] | [`Aedat3Reader`] / [`Aedat3Writer`] | `#!AER-DAT3.1` / `.aedat3` |
//! | AEDAT 4.0 (LZ4 / Zstd / none) | [`aedat4`] | [`Aedat4Reader`] / [`Aedat4Writer`] | `#!AER-DAT4.0` / `.aedat4` |
//! | Event Camera Dataset text (`t x y p`, t in s) | [`text`] | [`EcdTextReader`] / [`EcdTextWriter`] | a `t x y p` line / `.txt` |
//! | CSV (`t,x,y,on`, t in µs; the `csv` crate) | [`csv_events`] | [`CsvReader`] / [`CsvWriter`] | a `t,x,y,on` header / `.csv` |
//!
//! Readers pull fixed-size blocks from any [`Read`] and hand out events chunk by chunk into a
//! caller's [`EventBuffer`] ([`EventReader::read_chunk`]): a 10 GB file is never loaded whole, and
//! no allocation is sized by a field read from the file (payloads are read incrementally, capped,
//! and checked against the bytes actually present). [`open_reader`] detects the format from the
//! first bytes; [`create_writer`] picks it from the extension.
//!
//! The sensor size travels with the events: every format states it in its own way ([`camera`]:
//! AEDAT 4.0 `sizeX`/`sizeY`, the camera named by AEDAT 2.0 and 3.1 headers, a first line
//! `# sensor 346x260` in ECD text and CSV); readers report it ([`EventReader::sensor_size`]) and
//! writers are created with it, refusing a size their format cannot state
//! ([`FormatError::UnsupportedSensorSize`]) and events outside it
//! ([`FormatError::Unrepresentable`]). A file that states no size is read as 240 × 180, or as
//! the size given to [`open_reader_assuming`].
//!
//! What readers skip, they count in [`ReadStats`]: events with coordinates outside the sensor,
//! non-polarity records (APS, IMU, special events, frames and other AEDAT 4 streams, empty
//! packets). Timestamps going backwards are kept in file order and reported
//! ([`ReadStats::timestamps_backwards`], [`ReadStats::first_backwards`]), never reordered.
//!
//! ```no_run
//! use neurotac_core::EventBuffer;
//! use neurotac_sensor::format::open_reader;
//! let mut reader = open_reader("recording.aedat4".as_ref())?;
//! let mut chunk = EventBuffer::new();
//! while reader.read_chunk(&mut chunk)? > 0 {
//!     // … use the events, then reuse the buffer
//!     chunk.clear();
//! }
//! println!("{:?}", reader.stats());
//! # Ok::<(), neurotac_sensor::FormatError>(())
//! ```

pub mod aedat2;
pub mod aedat3;
pub mod aedat4;
pub mod camera;
mod contract;
pub mod csv_events;
mod escape;
mod flatbuffer;
mod header;
mod input;
pub mod text;

pub use aedat2::{Aedat2Reader, Aedat2Writer};
pub use aedat3::{Aedat3Reader, Aedat3Writer};
pub use aedat4::{Aedat4Reader, Aedat4Writer, Compression};
pub use camera::{CAMERAS, Camera, parse_sensor_size};
pub use contract::{Backwards, DAVIS240_SIZE, EventReader, EventWriter, ReadStats};
pub use csv_events::{CsvReader, CsvWriter};
pub use text::{EcdTextReader, EcdTextWriter};

use crate::error::FormatError;
use camera::parse_sensor_line;
use contract::{READ_BLOCK, read_error, write_error};
use escape::escape;
use neurotac_core::EventBuffer;
use neurotac_core::io::AtomicFile;
pub use neurotac_core::io::Replace;
use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The event-file formats (davis240.md §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// AEDAT 2.0, jAER DAVIS layout (davis240.md §2.1; DAVIS240 and DAVIS346).
    Aedat2,
    /// AEDAT 3.1 polarity packets (davis240.md §2.2).
    Aedat3,
    /// AEDAT 4.0 with the given compression for writing (davis240.md §2.3); readers take it from
    /// the file.
    Aedat4(Compression),
    /// Event Camera Dataset text: `t x y p`, t in seconds (davis240.md §2.4).
    EcdText,
    /// CSV with header `t,x,y,on`, t in µs (davis240.md §2.4).
    Csv,
}

impl Format {
    /// Every format, AEDAT 4.0 once per compression.
    pub const ALL: [Format; 7] = [
        Format::Aedat2,
        Format::Aedat3,
        Format::Aedat4(Compression::None),
        Format::Aedat4(Compression::Lz4),
        Format::Aedat4(Compression::Zstd),
        Format::EcdText,
        Format::Csv,
    ];

    /// The format named by a file's extension: `.aedat`/`.aedat2` → AEDAT 2.0, `.aedat3` → AEDAT
    /// 3.1, `.aedat4` → AEDAT 4.0 with LZ4, `.txt` → ECD text, `.csv` → CSV (case-insensitive).
    pub fn from_extension(path: &Path) -> Result<Self, FormatError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("aedat") | Some("aedat2") => Ok(Self::Aedat2),
            Some("aedat3") => Ok(Self::Aedat3),
            Some("aedat4") => Ok(Self::Aedat4(Compression::Lz4)),
            Some("txt") => Ok(Self::EcdText),
            Some("csv") => Ok(Self::Csv),
            _ => Err(FormatError::UnknownExtension {
                path: path.to_path_buf(),
            }),
        }
    }

    /// Detects the format from the first bytes of an input (davis240.md §2: the AEDAT version
    /// line; for text, a `t,x,y,on` header or a first line of numbers, after a `# sensor` line
    /// if there is one — that line alone is an ECD text file of no events). On failure returns
    /// the byte offset that ruled every format out and what was found there.
    pub fn detect(head: &[u8]) -> Result<Self, (u64, String)> {
        if let Some(skip) = sensor_line_end(head) {
            let rest = &head[skip..];
            return match rest.first() {
                None => Ok(Self::EcdText),
                Some(b'#') => Err((skip as u64, escape(&rest[..rest.len().min(16)]))),
                Some(_) => Self::detect(rest).map_err(|(at, found)| (at + skip as u64, found)),
            };
        }
        if head.starts_with(b"#!AER-DAT") {
            let line_end = head.iter().position(|&b| b == b'\r' || b == b'\n');
            let version = &head[9..line_end.unwrap_or(head.len()).min(9 + 8)];
            return match version {
                b"2.0" => Ok(Self::Aedat2),
                b"3.1" => Ok(Self::Aedat3),
                b"4.0" => Ok(Self::Aedat4(Compression::None)),
                other => Err((9, escape(other))),
            };
        }
        let line_end = head.iter().position(|&b| b == b'\n').unwrap_or(head.len());
        let line = head[..line_end]
            .strip_suffix(b"\r")
            .unwrap_or(&head[..line_end]);
        // The header as the CSV reader reads it (quoted or not, any letter case).
        let first_record = neurotac_core::io::csv::reader_builder()
            .has_headers(false)
            .flexible(true)
            .from_reader(line)
            .into_byte_records()
            .next();
        if let Some(Ok(record)) = first_record
            && csv_events::csv_header_fields(&record).is_some()
        {
            return Ok(Self::Csv);
        }
        // A first line of numbers: commas make it CSV (no header), blanks ECD text.
        let allowed = |b: u8| b.is_ascii_digit() || b"+-.eE \t,".contains(&b);
        match line.iter().position(|&b| !allowed(b)) {
            None if !line.is_empty() && line.iter().any(u8::is_ascii_digit) => {
                if line.contains(&b',') {
                    Ok(Self::Csv)
                } else {
                    Ok(Self::EcdText)
                }
            }
            None => Err((0, escape(&head[..head.len().min(16)]))),
            Some(i) => Err((i as u64, escape(&line[i..line.len().min(i + 16)]))),
        }
    }

    /// A short name (`AEDAT 2.0`, `AEDAT 4.0 (LZ4)`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::Aedat2 => "AEDAT 2.0",
            Self::Aedat3 => "AEDAT 3.1",
            Self::Aedat4(Compression::None) => "AEDAT 4.0",
            Self::Aedat4(Compression::Lz4) => "AEDAT 4.0 (LZ4)",
            Self::Aedat4(Compression::Zstd) => "AEDAT 4.0 (Zstd)",
            Self::EcdText => "ECD text",
            Self::Csv => "CSV",
        }
    }
}

/// The end (after its line feed) of a `# sensor WIDTHxHEIGHT` first line of `head`, if it starts
/// with one.
fn sensor_line_end(head: &[u8]) -> Option<usize> {
    if head.first() != Some(&b'#') {
        return None;
    }
    let end = head.iter().position(|&b| b == b'\n');
    let line = &head[..end.unwrap_or(head.len())];
    parse_sensor_line(line.strip_suffix(b"\r").unwrap_or(line))?;
    Some(end.map_or(head.len(), |e| e + 1))
}

/// Opens an event file, detecting its format from its first bytes; a file that states no sensor
/// size is read as 240 × 180 ([`open_reader_assuming`]).
pub fn open_reader(path: &Path) -> Result<Box<dyn EventReader>, FormatError> {
    open_reader_assuming(path, DAVIS240_SIZE)
}

/// Opens an event file, detecting its format from its first bytes; a file that states no sensor
/// size ([`EventReader::sensor_size`] is `None`) is read as a `sensor` (width, height) one: its
/// events outside it are skipped, and AEDAT 2.0 addresses are mirrored by it.
pub fn open_reader_assuming(
    path: &Path,
    sensor: (u16, u16),
) -> Result<Box<dyn EventReader>, FormatError> {
    let file = File::open(path).map_err(read_error(path))?;
    let len = file.metadata().ok().map(|m| m.len());
    let mut buffered = BufReader::with_capacity(READ_BLOCK, file);
    let head = buffered.fill_buf().map_err(read_error(path))?;
    let format = match Format::from_extension(path) {
        // An empty ECD text file is a recording of no events (the text formats have no header
        // to detect; an empty CSV lacks its header and stays an error).
        Ok(Format::EcdText) if len == Some(0) => Format::EcdText,
        _ => detect_or_error(head, path, len == Some(head.len() as u64))?,
    };
    open_detected(format, buffered, path.to_path_buf(), len, sensor)
}

/// The version lines of the AEDAT versions read.
const AEDAT_MAGICS: [&[u8]; 3] = [b"#!AER-DAT2.0", b"#!AER-DAT3.1", b"#!AER-DAT4.0"];

/// [`Format::detect`] with the error naming the file. `whole` says that `head` is the entire
/// input, so that one cut inside an AEDAT version line is reported as truncated.
fn detect_or_error(head: &[u8], path: &Path, whole: bool) -> Result<Format, FormatError> {
    Format::detect(&head[..head.len().min(4096)]).map_err(|(offset, found)| {
        let cut_magic = whole
            && !head.is_empty()
            && AEDAT_MAGICS
                .iter()
                .any(|m| m.len() > head.len() && m.starts_with(head));
        if cut_magic {
            FormatError::TruncatedHeader {
                path: path.to_path_buf(),
                offset: head.len() as u64,
                expected: "the rest of the version line (`#!AER-DAT2.0`, `#!AER-DAT3.1` or `#!AER-DAT4.0`)",
            }
        } else if head.starts_with(b"#!AER-DAT") {
            FormatError::UnsupportedVersion {
                path: path.to_path_buf(),
                found,
            }
        } else {
            FormatError::UnknownFormat {
                path: path.to_path_buf(),
                offset,
                found,
            }
        }
    })
}

fn open_detected<'a, R: Read + 'a>(
    format: Format,
    reader: R,
    path: PathBuf,
    len: Option<u64>,
    sensor: (u16, u16),
) -> Result<Box<dyn EventReader + 'a>, FormatError> {
    Ok(match format {
        Format::Aedat2 => Box::new(Aedat2Reader::with_name(reader, path)?.assuming(sensor)),
        Format::Aedat3 => Box::new(Aedat3Reader::with_name(reader, path)?.assuming(sensor)),
        Format::Aedat4(_) => Box::new(Aedat4Reader::with_name(reader, path, len)?.assuming(sensor)),
        Format::EcdText => Box::new(EcdTextReader::with_name(reader, path)?.assuming(sensor)),
        Format::Csv => Box::new(CsvReader::with_name(reader, path)?.assuming(sensor)),
    })
}

/// Opens an in-memory event file (any format, detected from the bytes), labelled `<memory>` in
/// errors; one that states no sensor size is read as 240 × 180.
pub fn reader_from_bytes(bytes: &[u8]) -> Result<Box<dyn EventReader + '_>, FormatError> {
    let path = PathBuf::from("<memory>");
    let format = detect_or_error(bytes, &path, true)?;
    open_detected(format, bytes, path, Some(bytes.len() as u64), DAVIS240_SIZE)
}

/// A writer of `format` for a `sensor` (width, height) recording to any seekable output (a
/// file, a `Cursor<Vec<u8>>`), named `name` in errors. Only AEDAT 4.0 seeks (to patch the
/// data-table position when finishing). A size the format cannot state is refused
/// ([`FormatError::UnsupportedSensorSize`]; module [`camera`]).
pub fn writer_to<'a, W: Write + Seek + 'a>(
    out: W,
    format: Format,
    sensor: (u16, u16),
    name: PathBuf,
) -> Result<Box<dyn EventWriter + 'a>, FormatError> {
    Ok(match format {
        Format::Aedat2 => Box::new(Aedat2Writer::with_name(out, name, sensor)?),
        Format::Aedat3 => Box::new(Aedat3Writer::with_name(out, name, sensor)?),
        Format::Aedat4(c) => Box::new(Aedat4Writer::with_name(out, name, c, sensor)?),
        Format::EcdText => Box::new(EcdTextWriter::with_name(out, name, sensor)?),
        Format::Csv => Box::new(CsvWriter::with_name(out, name, sensor)?),
    })
}

/// Encodes `events` of a `sensor` (width, height) recording in `format` in memory (the bytes a
/// file of that format would hold).
pub fn to_bytes(
    events: &EventBuffer,
    format: Format,
    sensor: (u16, u16),
) -> Result<Vec<u8>, FormatError> {
    let mut cursor = std::io::Cursor::new(Vec::new());
    let mut writer = writer_to(&mut cursor, format, sensor, PathBuf::from("<memory>"))?;
    writer.write(events)?;
    writer.finish()?;
    drop(writer);
    Ok(cursor.into_inner())
}

/// Creates an event file in `format` for a `sensor` (width, height) recording, atomically: the
/// events go to a hidden temporary file beside `path` ([`AtomicFile`]), and only a successful
/// [`EventWriter::finish`] renames it onto `path`. A writer dropped before that (a reader or
/// writer error, an early return) removes the temporary file, so `path` keeps its old content or
/// stays absent (so does a size the format cannot state, refused here). `replace` decides
/// whether `finish` may replace a file that exists by then ([`Replace`]).
pub fn create_writer_as(
    path: &Path,
    format: Format,
    sensor: (u16, u16),
    replace: Replace,
) -> Result<Box<dyn EventWriter>, FormatError> {
    let file = AtomicFile::create(path, replace).map_err(write_error(path))?;
    let handle = file.try_clone_file().map_err(write_error(path))?;
    let inner = writer_to(
        BufWriter::with_capacity(READ_BLOCK, handle),
        format,
        sensor,
        path.to_path_buf(),
    )?;
    Ok(Box::new(AtomicEventWriter {
        inner,
        file: Some(file),
    }))
}

/// An event writer into an [`AtomicFile`]: `finish` completes the file, then commits it.
struct AtomicEventWriter {
    /// Declared first: dropped (and its buffer flushed) before the temporary file is removed.
    inner: Box<dyn EventWriter>,
    /// `None` once committed.
    file: Option<AtomicFile>,
}

impl EventWriter for AtomicEventWriter {
    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
        self.inner.write(events)
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        self.inner.finish()?;
        match self.file.take() {
            Some(file) => {
                let path = file.target().to_path_buf();
                file.commit().map_err(write_error(&path))
            }
            None => Ok(()),
        }
    }
}

/// Creates an event file for a `sensor` (width, height) recording whose format is given by its
/// extension ([`Format::from_extension`]); `replace` as in [`create_writer_as`].
pub fn create_writer(
    path: &Path,
    sensor: (u16, u16),
    replace: Replace,
) -> Result<Box<dyn EventWriter>, FormatError> {
    create_writer_as(path, Format::from_extension(path)?, sensor, replace)
}

/// Reads a whole event file into memory (for small files and tests; stream large ones with
/// [`open_reader`]).
pub fn read_file(path: &Path) -> Result<(EventBuffer, ReadStats), FormatError> {
    let mut reader = open_reader(path)?;
    let mut out = EventBuffer::new();
    reader.read_to_end(&mut out)?;
    Ok((out, reader.stats()))
}

/// Writes `events` of a `sensor` (width, height) recording to a file whose format is given by
/// its extension, atomically (see [`create_writer_as`]), replacing an existing file.
pub fn write_file(
    path: &Path,
    events: &EventBuffer,
    sensor: (u16, u16),
) -> Result<(), FormatError> {
    let mut writer = create_writer(path, sensor, Replace::Yes)?;
    writer.write(events)?;
    writer.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_core::testing::folder_names;

    #[test]
    fn an_empty_recording_reads_back_empty_in_every_format_but_a_headerless_csv_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        for ext in ["aedat", "aedat3", "aedat4", "txt", "csv"] {
            let path = dir.path().join(format!("empty.{ext}"));
            write_file(&path, &EventBuffer::new(), DAVIS240_SIZE).unwrap();
            let (events, _) = read_file(&path).unwrap_or_else(|e| panic!("{ext}: {e}"));
            assert!(events.is_empty(), "{ext}");
        }
        let bare = dir.path().join("bare.csv");
        std::fs::write(&bare, b"").unwrap();
        assert!(matches!(
            read_file(&bare),
            Err(FormatError::UnknownFormat { .. })
        ));
    }

    #[test]
    fn detection_by_magic_and_first_line() {
        assert_eq!(Format::detect(b"#!AER-DAT2.0\r\n#"), Ok(Format::Aedat2));
        assert_eq!(Format::detect(b"#!AER-DAT3.1\r\n"), Ok(Format::Aedat3));
        assert!(matches!(
            Format::detect(b"#!AER-DAT4.0\r\n"),
            Ok(Format::Aedat4(_))
        ));
        assert_eq!(Format::detect(b"t,x,y,on\n0,1,2,1\n"), Ok(Format::Csv));
        assert_eq!(
            Format::detect(b"0.000003000 102 28 1\n"),
            Ok(Format::EcdText)
        );
        assert_eq!(Format::detect(b"3,102,28,1\n"), Ok(Format::Csv));
        assert_eq!(
            Format::detect(b"#!AER-DAT3.0\r\n"),
            Err((9, "`3.0`".into()))
        );
        assert_eq!(
            Format::detect(b"\x89PNG\r\n"),
            Err((0, "`\\x89PNG`".into()))
        );
        assert_eq!(Format::detect(b"0.5 1 2 x\n"), Err((8, "`x`".into())));
        assert_eq!(Format::detect(b""), Err((0, "end of file".into())));
    }

    #[test]
    fn sensor_size_is_stated_by_aedat_and_absent_from_text() {
        let mut events = EventBuffer::new();
        events.push(neurotac_core::Event {
            t: neurotac_core::Timestamp(5),
            x: 239,
            y: 179,
            polarity: true,
        });
        for format in Format::ALL {
            let bytes = to_bytes(&events, format, DAVIS240_SIZE).unwrap();
            let reader = reader_from_bytes(&bytes).unwrap();
            let expected = match format {
                Format::EcdText | Format::Csv => None,
                _ => Some(DAVIS240_SIZE),
            };
            assert_eq!(reader.sensor_size(), expected, "{}", format.name());
        }
        // An AEDAT 4.0 header naming another sensor (same byte length: 240 → 346, 180 → 260).
        let bytes = to_bytes(&events, Format::Aedat4(Compression::None), DAVIS240_SIZE).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let from = "<attr key=\"sizeX\" type=\"int\">240</attr>";
        assert!(text.contains(from));
        let mut patched = bytes.clone();
        for (old, new) in [(">240<", ">346<"), (">180<", ">260<")] {
            let at = patched
                .windows(old.len())
                .position(|w| w == old.as_bytes())
                .unwrap();
            patched[at..at + old.len()].copy_from_slice(new.as_bytes());
        }
        let reader = reader_from_bytes(&patched).unwrap();
        assert_eq!(reader.sensor_size(), Some((346, 260)));
    }

    #[test]
    fn a_failed_or_unfinished_write_leaves_the_old_file_or_none() {
        let dir = tempfile::tempdir().unwrap();
        let mut events = EventBuffer::new();
        for (i, t) in [10, 20, 1 << 40].into_iter().enumerate() {
            events.push(neurotac_core::Event {
                t: neurotac_core::Timestamp(t),
                x: i as u16,
                y: 3,
                polarity: true,
            });
        }
        // A time AEDAT 2.0 cannot hold: the write fails and no file appears.
        let aedat = dir.path().join("o.aedat");
        assert!(matches!(
            write_file(&aedat, &events, DAVIS240_SIZE),
            Err(FormatError::Unrepresentable { .. })
        ));
        assert_eq!(folder_names(dir.path()), Vec::<String>::new());
        // An existing file keeps its content.
        std::fs::write(&aedat, b"old").unwrap();
        assert!(write_file(&aedat, &events, DAVIS240_SIZE).is_err());
        assert_eq!(std::fs::read(&aedat).unwrap(), b"old");
        assert_eq!(folder_names(dir.path()), ["o.aedat"]);
        // Every format: nothing visible until `finish`, nothing left when dropped before it.
        for format in Format::ALL {
            let path = dir.path().join("x.out");
            let mut writer = create_writer_as(&path, format, DAVIS240_SIZE, Replace::No).unwrap();
            let _ = writer.write(&events);
            assert!(!path.exists(), "{format:?}");
            drop(writer);
            assert_eq!(folder_names(dir.path()), ["o.aedat"], "{format:?}");
        }
        let csv = dir.path().join("o.csv");
        write_file(&csv, &events, DAVIS240_SIZE).unwrap();
        assert_eq!(read_file(&csv).unwrap().0, events);
        assert_eq!(folder_names(dir.path()), ["o.aedat", "o.csv"]);
    }

    #[test]
    fn wrong_magic_names_file_and_offset() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("picture.aedat");
        std::fs::write(&path, b"GIF89a....").unwrap();
        let err = open_reader(&path).err().unwrap();
        let msg = err.to_string();
        assert!(
            matches!(err, FormatError::UnknownFormat { offset: 0, .. }),
            "{msg}"
        );
        assert!(
            msg.contains("picture.aedat") && msg.contains("byte 0"),
            "{msg}"
        );
        let path = dir.path().join("old.aedat");
        std::fs::write(&path, b"#!AER-DAT3.0\r\n").unwrap();
        assert!(matches!(
            open_reader(&path),
            Err(FormatError::UnsupportedVersion { .. })
        ));
        assert!(matches!(
            open_reader(&dir.path().join("missing.aedat")),
            Err(FormatError::Io { .. })
        ));
    }

    #[test]
    fn extension_names_the_output_format() {
        assert_eq!(
            Format::from_extension("a.AEDAT".as_ref()).unwrap(),
            Format::Aedat2
        );
        assert_eq!(
            Format::from_extension("a.aedat3".as_ref()).unwrap(),
            Format::Aedat3
        );
        assert_eq!(
            Format::from_extension("a.aedat4".as_ref()).unwrap(),
            Format::Aedat4(Compression::Lz4)
        );
        assert_eq!(
            Format::from_extension("a.txt".as_ref()).unwrap(),
            Format::EcdText
        );
        assert_eq!(
            Format::from_extension("a.csv".as_ref()).unwrap(),
            Format::Csv
        );
        assert!(matches!(
            Format::from_extension("a.bin".as_ref()),
            Err(FormatError::UnknownExtension { .. })
        ));
    }
}
