//! CSV event files (davis240.md §2.4, the layout faery writes): a header `t,x,y,on`, then one
//! event per record, t in integer µs, x and y top-left, `on` 1 = ON / 0 = OFF (−1 is also read
//! as OFF). Read and written by the `csv` crate in the dialect of [`neurotac_core::io::csv`]:
//! what the writer writes is byte for byte the faery layout (numbers are never quoted, lines end
//! with LF), and the reader reads any valid CSV of that layout — quoted fields, CRLF line ends,
//! empty lines, no header (as the first line of a file says, see [`super::text`] for the
//! `# sensor` line). A fifth column `pin` (the source pin of every event, as `neurotac simulate
//! --pixel-events --labels` writes it) is read past when the header names it.
//!
//! A line is at most [`MAX_LINE_BYTES`] long: the reader stops at a longer one with an error
//! naming it, so a line that never ends is never held whole.

use super::contract::{
    EventReader, EventWriter, READ_BLOCK, ReadStats, ReaderEnd, check_inside, write_error,
};
use super::input::Input;
use super::text::{
    FOUND_MAX_BYTES, MAX_LINE_BYTES, TextEvents, TextStart, parse_int, parse_pixel,
    read_sensor_line, sensor_head, text_error, text_reader, text_writer,
};
use crate::error::FormatError;
use neurotac_core::EventBuffer;
use std::io::{self, Read, Write};
use std::path::PathBuf;

/// The header of the layout, written as it is and read in any letter case (or `p` for `on`).
pub const CSV_HEADER: [&str; 4] = ["t", "x", "y", "on"];

/// The number of fields of the layout's records when a record is its header: 4 for
/// `t,x,y,on`, 5 for the labelled layout `t,x,y,on,pin`; `None` for any other record.
pub(super) fn csv_header_fields(fields: &csv::ByteRecord) -> Option<usize> {
    let names: [&[&[u8]]; 5] = [&[b"t"], &[b"x"], &[b"y"], &[b"on", b"p"], &[b"pin"]];
    let named = |n: usize| {
        fields
            .iter()
            .zip(&names[..n])
            .all(|(f, allowed)| allowed.iter().any(|a| f.eq_ignore_ascii_case(a)))
    };
    match fields.len() {
        n @ (4 | 5) if named(n) => Some(n),
        _ => None,
    }
}

/// Most events appended per chunk (one per shortest line, `0,0,0,1\n`, of a block).
const CHUNK_EVENTS: usize = READ_BLOCK / 8;

/// A line longer than [`MAX_LINE_BYTES`], as the reader's input stops at it.
#[derive(Debug, Clone)]
struct LineTooLong {
    /// 1-based line number.
    line: u64,
    /// Offset of the line's first byte.
    offset: u64,
    /// Its first bytes (a few more than an error quotes).
    head: Vec<u8>,
}

impl std::fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {} is longer than {MAX_LINE_BYTES} bytes",
            self.line
        )
    }
}

impl std::error::Error for LineTooLong {}

/// The CSV reader's input: the bytes of the file, counted (offset, line) so that a line longer
/// than [`MAX_LINE_BYTES`] is stopped at, before the `csv` crate holds it whole.
struct LineLimit<R> {
    inner: R,
    /// Offset of the next byte.
    offset: u64,
    /// Line ends (`\n`) before the next byte.
    lines: u64,
    /// Offset of the first byte of the current line.
    line_start: u64,
    /// The first bytes of the current line.
    head: Vec<u8>,
    /// Set once a line was too long: every later read fails with it.
    too_long: Option<LineTooLong>,
}

impl<R: Read> Read for LineLimit<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if let Some(long) = &self.too_long {
            return Err(io::Error::new(io::ErrorKind::InvalidData, long.clone()));
        }
        let n = self.inner.read(buf)?;
        let mut i = 0;
        // Line by line: the part of the current line in `buf`, then its end, if there.
        while i < n {
            let rest = &buf[i..n];
            let end = memchr::memchr2(b'\n', b'\r', rest);
            let part = &rest[..end.unwrap_or(rest.len())];
            let room = (FOUND_MAX_BYTES + 1).saturating_sub(self.head.len());
            self.head.extend_from_slice(&part[..part.len().min(room)]);
            let limit = self.line_start + MAX_LINE_BYTES as u64;
            if self.offset + (i + part.len()) as u64 > limit {
                self.too_long = Some(LineTooLong {
                    line: self.lines + 1,
                    offset: self.line_start,
                    head: std::mem::take(&mut self.head),
                });
                // The bytes before the first one past the limit are delivered; the next read
                // fails.
                let delivered = (limit - self.offset) as usize;
                self.offset = limit;
                return match delivered {
                    0 => self.read(buf),
                    _ => Ok(delivered),
                };
            }
            let Some(end) = end else { break };
            self.lines += u64::from(rest[end] == b'\n');
            i += end + 1;
            self.line_start = self.offset + i as u64;
            self.head.clear();
        }
        self.offset += n as u64;
        Ok(n)
    }
}

/// The engine of [`CsvReader`].
struct CsvLines<R> {
    path: PathBuf,
    records: csv::Reader<LineLimit<io::Chain<io::Cursor<Vec<u8>>, R>>>,
    record: csv::ByteRecord,
    /// Offset and line number of the first byte the `csv` reader reads (after a sensor line).
    base_offset: u64,
    base_line: u64,
    /// Whether a record was read (the first one may be the header).
    started: bool,
    /// Fields per record: 4, or 5 after a `t,x,y,on,pin` header (the pin is not read).
    fields: usize,
    events: TextEvents,
    end: ReaderEnd,
}

impl<R: Read> CsvLines<R> {
    /// A reader of `reader`; reads the `# sensor` line if the input starts with `#`.
    fn new(reader: R, path: PathBuf) -> Result<Self, FormatError> {
        let mut input = Input::new(reader, path);
        let TextStart { stated, ahead } = read_sensor_line(&mut input)?;
        let base_offset = input.offset() - ahead.len() as u64;
        let base_line = u64::from(stated.is_some());
        let (inner, path) = input.into_parts();
        let limited = LineLimit {
            inner: io::Cursor::new(ahead).chain(inner),
            offset: base_offset,
            lines: base_line,
            line_start: base_offset,
            head: Vec::new(),
            too_long: None,
        };
        let records = neurotac_core::io::csv::reader_builder()
            .has_headers(false)
            .flexible(true)
            .from_reader(limited);
        Ok(Self {
            path,
            records,
            record: csv::ByteRecord::new(),
            base_offset,
            base_line,
            started: false,
            fields: 4,
            events: TextEvents::new(stated),
            end: ReaderEnd::default(),
        })
    }

    /// The error of a read that failed: a line too long, or the input's I/O error.
    fn read_failed(&self, e: csv::Error) -> FormatError {
        let e = match e.into_kind() {
            csv::ErrorKind::Io(e) => e,
            // Byte records of any length: nothing but reading fails.
            other => io::Error::other(format!("{other:?}")),
        };
        match e
            .get_ref()
            .and_then(|inner| inner.downcast_ref::<LineTooLong>())
        {
            Some(long) => {
                let expected = "a line shorter than 4096 bytes";
                text_error(
                    &self.path,
                    long.line,
                    long.offset,
                    ("line", expected, &long.head),
                )
            }
            None => FormatError::Io {
                path: self.path.clone(),
                action: neurotac_core::IoAction::Read,
                source: e,
            },
        }
    }

    /// Handles the record just read.
    fn record(&mut self, out: &mut EventBuffer) -> Result<(), FormatError> {
        let r = &self.record;
        let (line, offset) = r.position().map_or((0, 0), |p| (p.line(), p.byte()));
        let (line, offset) = (self.base_line + line, self.base_offset + offset);
        let first = !std::mem::replace(&mut self.started, true);
        let error = |e| text_error(&self.path, line, offset, e);
        let whole = || {
            let mut text = Vec::new();
            for (i, f) in r.iter().enumerate() {
                if text.len() > FOUND_MAX_BYTES {
                    break;
                }
                if i > 0 {
                    text.push(b',');
                }
                text.extend_from_slice(f);
            }
            text
        };
        if first
            && r.get(0)
                .and_then(|f| f.first())
                .is_some_and(u8::is_ascii_alphabetic)
        {
            return match csv_header_fields(r) {
                Some(fields) => {
                    self.fields = fields;
                    Ok(())
                }
                None => Err(error((
                    "header",
                    "`t,x,y,on` (or `t,x,y,on,pin`)",
                    &whole(),
                ))),
            };
        }
        if r.len() != self.fields {
            let expected = match (self.fields, r.len() < self.fields) {
                (4, true) => "4 fields: t,x,y,on",
                (4, false) => "exactly 4 fields",
                (_, true) => "5 fields: t,x,y,on,pin",
                (_, false) => "exactly 5 fields",
            };
            return Err(error(("line", expected, &whole())));
        }
        let t = parse_int(&r[0]).ok_or_else(|| error(("t", "integer microseconds", &r[0])))?;
        let (x, y, on) = parse_pixel(&r[1], &r[2], &r[3]).map_err(error)?;
        self.events.push(offset, (t, x, y, on), out);
        Ok(())
    }

    fn fill(&mut self, out: &mut EventBuffer) -> Result<(), FormatError> {
        let before = out.len();
        while out.len() - before < CHUNK_EVENTS {
            match self.records.read_byte_record(&mut self.record) {
                Ok(true) => self.record(out)?,
                Ok(false) => break,
                Err(e) => return Err(self.read_failed(e)),
            }
        }
        Ok(())
    }

    fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
        ReaderEnd::chunk(self, |r| &mut r.end, out, Self::fill)
    }
}

text_reader!(
    CsvReader,
    CsvLines,
    "Streaming reader of CSV events (`t,x,y,on`, t in µs; the header line is optional; davis240.md §2.4), through the `csv` crate."
);

/// The engine of [`CsvWriter`].
struct CsvEvents<W: Write> {
    out: csv::Writer<W>,
    path: PathBuf,
    size: (u16, u16),
    written: u64,
}

impl<W: Write> CsvEvents<W> {
    fn new(mut out: W, path: PathBuf, sensor: (u16, u16)) -> Result<Self, FormatError> {
        let head = sensor_head(&path, "CSV", sensor)?;
        out.write_all(head.as_bytes()).map_err(write_error(&path))?;
        let out = neurotac_core::io::csv::writer(out, CSV_HEADER)
            .map_err(|e| write_error(&path)(e.into()))?;
        Ok(Self {
            out,
            path,
            size: sensor,
            written: 0,
        })
    }

    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
        for (i, e) in events.iter().enumerate() {
            check_inside(&self.path, self.written + i as u64, (e.x, e.y), self.size)?;
            let record = (e.t.0, e.x, e.y, u8::from(e.polarity));
            self.out
                .serialize(record)
                .map_err(|e| write_error(&self.path)(e.into()))?;
        }
        self.written += events.len() as u64;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        self.out.flush().map_err(write_error(&self.path))
    }
}

text_writer!(
    CsvWriter,
    CsvEvents,
    "Writer of CSV events: header `t,x,y,on`, t in integer µs (davis240.md §2.4), through the `csv` crate."
);

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> (EventBuffer, Result<u64, FormatError>) {
        let mut out = EventBuffer::new();
        let result = CsvReader::new(bytes).and_then(|mut r| r.read_to_end(&mut out));
        (out, result)
    }

    #[test]
    fn records_parse_or_name_the_bad_field_line_and_offset() {
        let (out, result) = read(b"t,x,y,on\n11,158,145,0\n12,-2,3,1\n");
        assert_eq!((out.t, out.x), (vec![11], vec![158]));
        assert!(
            matches!(
                result,
                Err(FormatError::Text { line: 3, offset: 22, field: "x", ref found, .. }) if found == "-2"
            ),
            "{result:?}"
        );
        for (bytes, field) in [
            (&b"0,2,3\n"[..], "line"),
            (b"0,2,3,1,5\n", "line"),
            (b"0.5,2,3,1\n", "t"),
            (b"0,2,3,7\n", "polarity"),
            (b"time,x,y,on\n", "header"),
        ] {
            let (_, result) = read(bytes);
            assert!(
                matches!(result, Err(FormatError::Text { line: 1, offset: 0, field: f, .. }) if f == field),
                "{result:?}"
            );
        }
    }

    #[test]
    fn any_valid_csv_of_the_layout_is_read() {
        let quoted = b"\"T\",\"x\",\"y\",\"p\"\r\n\r\n\"7\",1,2,\"1\"\r\n8,3,4,-1";
        let (out, result) = read(quoted);
        result.unwrap();
        assert_eq!(
            (out.t, out.x, out.polarity),
            (vec![7, 8], vec![1, 3], vec![true, false])
        );
        let (out, result) = read(b"7,1,2,1\n8,3,4,0");
        result.unwrap();
        assert_eq!(out.t, vec![7, 8], "a CSV without header");
        let (out, result) = read(b"# sensor 346x260\nt,x,y,on\n5,300,250,1\n");
        result.unwrap();
        assert_eq!(out.x, vec![300], "inside the stated sensor");
    }

    #[test]
    fn the_labelled_layout_of_the_simulator_is_read_past_its_pin_column() {
        let labelled = b"t,x,y,on,pin\n5,10,20,1,3\n6,11,21,0,-1\n";
        assert_eq!(
            super::super::Format::detect(labelled),
            Ok(super::super::Format::Csv)
        );
        let (out, result) = read(labelled);
        result.unwrap();
        assert_eq!(
            (out.t, out.x, out.y, out.polarity),
            (vec![5, 6], vec![10, 11], vec![20, 21], vec![true, false])
        );
        let (_, result) = read(b"t,x,y,on,pin\n5,10,20,1\n");
        assert!(
            matches!(
                result,
                Err(FormatError::Text {
                    line: 2,
                    field: "line",
                    expected: "5 fields: t,x,y,on,pin",
                    ..
                })
            ),
            "{result:?}"
        );
        let (_, result) = read(b"t,x,y,on,label\n5,10,20,1,3\n");
        assert!(
            matches!(
                result,
                Err(FormatError::Text {
                    line: 1,
                    field: "header",
                    ..
                })
            ),
            "{result:?}"
        );
    }

    #[test]
    fn a_line_longer_than_the_limit_is_named_after_the_lines_before() {
        let mut bytes = b"t,x,y,on\n1,2,3,1\n".to_vec();
        bytes.extend(std::iter::repeat_n(b'7', 10 * MAX_LINE_BYTES));
        let (out, result) = read(&bytes);
        assert_eq!(out.t, vec![1]);
        assert!(
            matches!(
                result,
                Err(FormatError::Text { line: 3, offset: 17, field: "line", ref found, .. }) if found.starts_with("7777") && found.ends_with('…')
            ),
            "{result:?}"
        );
    }

    #[test]
    fn a_line_of_the_limit_is_read_and_one_byte_more_is_not() {
        let fields = "4 fields: t,x,y,on";
        for (extra, expected) in [(0, fields), (1, "a line shorter than 4096 bytes")] {
            let mut bytes = b"t,x,y,on\n".to_vec();
            bytes.extend(std::iter::repeat_n(b'7', MAX_LINE_BYTES + extra));
            bytes.push(b'\n');
            let (_, result) = read(&bytes);
            assert!(
                matches!(result, Err(FormatError::Text { line: 2, offset: 9, field: "line", expected: e, .. }) if e == expected),
                "{result:?}"
            );
        }
    }

    #[test]
    fn the_writer_writes_the_faery_layout() {
        let mut events = EventBuffer::new();
        for (t, x, y, on) in [(-5, 3, 4, true), (7, 239, 179, false)] {
            events.t.push(t);
            events.x.push(x);
            events.y.push(y);
            events.polarity.push(on);
        }
        let mut w = CsvWriter::new(Vec::new(), super::super::DAVIS240_SIZE).unwrap();
        w.write(&events).unwrap();
        w.finish().unwrap();
        let bytes = w.0.out.into_inner().unwrap();
        assert_eq!(bytes, b"t,x,y,on\n-5,3,4,1\n7,239,179,0\n");
    }
}
