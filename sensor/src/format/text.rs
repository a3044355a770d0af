//! Text event files (davis240.md §2.4): the Event Camera Dataset's `events.txt` and the CSV that
//! faery writes.
//!
//! | format | line | time |
//! |---|---|---|
//! | ECD text | `t x y p`, single spaces, no header, e.g. `0.000011001 158 145 1` | seconds with up to 9 decimals, rounded to the nearest µs |
//! | CSV | header `t,x,y,on`, then `t,x,y,on` | integer µs |
//!
//! Coordinates are top-left; polarity 1 = ON, 0 = OFF (−1 is also read as OFF). Lines end with
//! LF or CRLF; empty lines are skipped.
//!
//! Sensor size: neither format has a header for it, so a file may state it on its first line,
//! `# sensor 346x260` (width × height, each 1 … 65535; before the CSV header). Tools that skip
//! `#` comment lines (numpy's `loadtxt`, pandas with `comment="#"`) read past it; it is the only
//! `#` line these readers accept. Events outside the stated size — or, in a file without the
//! line, outside the assumed one (240 × 180 unless told otherwise) — are skipped and counted.
//! The writers write the line for every size but 240 × 180, so that a DAVIS240 file stays
//! exactly the ECD / faery layout (read back, it gives the same 240 × 180 as the line would).

use super::camera::{parse_sensor_line, sensor_line};
use super::contract::{
    DAVIS240_SIZE, EventReader, EventWriter, READ_BLOCK, ReadStats, ReaderEnd, ReaderSensor,
    check_inside, unsupported_size, write_error,
};
use super::escape::escape_text;
use super::input::Input;
use crate::error::FormatError;
use neurotac_core::EventBuffer;
use std::io::{Read, Write};
use std::path::PathBuf;

/// Longest line accepted (bytes).
pub const MAX_LINE_BYTES: usize = 4096;

/// Most bytes of a line quoted in an error.
const FOUND_MAX_BYTES: usize = 64;

/// Which text dialect a reader parses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Dialect {
    Ecd,
    Csv,
}

/// A parse failure inside a line: column, what was expected, and the byte range found.
type FieldError = (&'static str, &'static str, usize, usize);

/// Parses a decimal integer (optional sign) in `s`.
fn parse_int(s: &[u8]) -> Option<i64> {
    let (neg, digits) = match s.first()? {
        b'-' => (true, &s[1..]),
        b'+' => (false, &s[1..]),
        _ => (false, s),
    };
    // 20 digits cannot overflow i128; the result must fit in i64 (every i64 parses).
    if digits.is_empty() || digits.len() > 20 || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let v = digits
        .iter()
        .fold(0i128, |a, &d| a * 10 + i128::from(d - b'0'));
    i64::try_from(if neg { -v } else { v }).ok()
}

/// Parses decimal seconds (`[-]int[.frac]`) exactly into µs, rounding half away from zero at
/// the 7th decimal; `None` unless the result fits in i64 (every i64 µs, as the writer prints it,
/// parses).
fn parse_seconds_us(s: &[u8]) -> Option<i64> {
    let (neg, body) = match s.first()? {
        b'-' => (true, &s[1..]),
        _ => (false, s),
    };
    let (int, frac) = match body.iter().position(|&b| b == b'.') {
        Some(i) => (&body[..i], &body[i + 1..]),
        None => (body, &[][..]),
    };
    // 20 integer digits cannot overflow i128.
    if int.is_empty() || int.len() > 20 || !int.iter().chain(frac).all(u8::is_ascii_digit) {
        return None;
    }
    let mut us = int
        .iter()
        .fold(0i128, |a, &d| a * 10 + i128::from(d - b'0'))
        * 1_000_000;
    let mut scale = 100_000;
    for &d in frac.iter().take(6) {
        us += i128::from(d - b'0') * scale;
        scale /= 10;
    }
    if frac.get(6).is_some_and(|&d| d >= b'5') {
        us += 1;
    }
    i64::try_from(if neg { -us } else { us }).ok()
}

/// Parses one non-empty line into `(t, x, y, on)`.
fn parse_line(dialect: Dialect, line: &[u8]) -> Result<(i64, i64, i64, bool), FieldError> {
    let sep = match dialect {
        Dialect::Ecd => b' ',
        Dialect::Csv => b',',
    };
    let mut fields = [(0usize, 0usize); 4];
    let mut count = 0;
    let mut start = 0;
    for (i, &b) in line
        .iter()
        .enumerate()
        .chain(std::iter::once((line.len(), &sep)))
    {
        let is_sep = b == sep || (dialect == Dialect::Ecd && b == b'\t');
        if is_sep {
            if dialect == Dialect::Ecd && i == start {
                start = i + 1; // runs of blanks
                continue;
            }
            if count == 4 {
                return Err(("line", "exactly 4 fields", 0, line.len()));
            }
            fields[count] = (start, i);
            count += 1;
            start = i + 1;
        }
    }
    if count < 4 {
        return Err(("line", "4 fields: t x y p", 0, line.len()));
    }
    let field = |k: usize| &line[fields[k].0..fields[k].1];
    let t = match dialect {
        Dialect::Ecd => parse_seconds_us(field(0)),
        Dialect::Csv => parse_int(field(0)),
    }
    .ok_or(match dialect {
        Dialect::Ecd => ("t", "decimal seconds", fields[0].0, fields[0].1),
        Dialect::Csv => ("t", "integer microseconds", fields[0].0, fields[0].1),
    })?;
    let coord = |k: usize, name| {
        parse_int(field(k))
            .filter(|v| (0..=i64::from(u16::MAX)).contains(v))
            .ok_or((name, "an integer 0–65535", fields[k].0, fields[k].1))
    };
    let (x, y) = (coord(1, "x")?, coord(2, "y")?);
    let on = match field(3) {
        b"1" => true,
        b"0" | b"-1" => false,
        _ => return Err(("polarity", "1 or 0", fields[3].0, fields[3].1)),
    };
    Ok((t, x, y, on))
}

/// The line engine shared by both text readers.
struct TextReader<R> {
    input: Input<R>,
    dialect: Dialect,
    sensor: ReaderSensor,
    /// The number of the line that may hold the CSV header (1, or 2 after a sensor line).
    header_line: u64,
    block: Vec<u8>,
    start: usize,
    filled: usize,
    /// Offset of `block[0]`.
    block_offset: u64,
    line: u64,
    previous: i64,
    stats: ReadStats,
    eof: bool,
    end: ReaderEnd,
}

impl<R: Read> TextReader<R> {
    /// A reader of `reader`; reads the `# sensor` line if the input starts with `#`.
    fn new(reader: R, path: PathBuf, dialect: Dialect) -> Result<Self, FormatError> {
        let mut r = Self {
            input: Input::new(reader, path),
            dialect,
            sensor: ReaderSensor::new(None),
            header_line: 1,
            block: vec![0; READ_BLOCK],
            start: 0,
            filled: 0,
            block_offset: 0,
            line: 0,
            previous: i64::MIN,
            stats: ReadStats::default(),
            eof: false,
            end: ReaderEnd::default(),
        };
        let mut byte = [0u8; 1];
        if r.input.read_full(&mut byte)? == 0 {
            return Ok(r);
        }
        if byte[0] != b'#' {
            r.block[0] = byte[0];
            r.filled = 1;
            return Ok(r);
        }
        // Byte by byte: the line is short, and what follows is the line engine's.
        let mut line = vec![b'#'];
        while line.len() <= MAX_LINE_BYTES && r.input.read_full(&mut byte)? == 1 {
            if byte[0] == b'\n' {
                break;
            }
            line.push(byte[0]);
        }
        r.line = 1;
        let line = line.strip_suffix(b"\r").unwrap_or(&line);
        let expected = "`# sensor WIDTHxHEIGHT` (the one `#` line read, first in the file)";
        let size = parse_sensor_line(line)
            .ok_or_else(|| r.text_error(0, line, ("sensor line", expected, 0, line.len())))?;
        r.sensor.stated = Some(size);
        r.header_line = 2;
        r.block_offset = r.input.offset();
        Ok(r)
    }

    fn text_error(&self, offset: u64, line: &[u8], e: FieldError) -> FormatError {
        let (field, expected, a, b) = e;
        FormatError::Text {
            path: self.input.path().to_path_buf(),
            line: self.line,
            offset,
            field,
            found: escape_text(&line[a..b], FOUND_MAX_BYTES),
            expected,
        }
    }

    /// Handles one line (without its line end).
    fn line(&mut self, offset: u64, line: &[u8], out: &mut EventBuffer) -> Result<(), FormatError> {
        self.line += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.is_empty() {
            return Ok(());
        }
        if self.line == self.header_line
            && self.dialect == Dialect::Csv
            && line[0].is_ascii_alphabetic()
        {
            if line.eq_ignore_ascii_case(b"t,x,y,on") || line.eq_ignore_ascii_case(b"t,x,y,p") {
                return Ok(());
            }
            return Err(self.text_error(offset, line, ("header", "`t,x,y,on`", 0, line.len())));
        }
        let (t, x, y, on) =
            parse_line(self.dialect, line).map_err(|e| self.text_error(offset, line, e))?;
        let (size_x, size_y) = self.sensor.bounds();
        if x >= i64::from(size_x) || y >= i64::from(size_y) {
            self.stats.out_of_range += 1;
            return Ok(());
        }
        self.stats.check_order(offset, self.previous, t);
        self.previous = t;
        out.t.push(t);
        out.x.push(x as u16);
        out.y.push(y as u16);
        out.polarity.push(on);
        self.stats.events += 1;
        Ok(())
    }

    fn fill(&mut self, out: &mut EventBuffer) -> Result<(), FormatError> {
        let before = out.len();
        while out.len() == before && !self.eof {
            // Move the partial line to the front, then read more.
            self.block.copy_within(self.start..self.filled, 0);
            self.block_offset += self.start as u64;
            self.filled -= self.start;
            self.start = 0;
            let n = self.input.read_full(&mut self.block[self.filled..])?;
            self.filled += n;
            self.eof = n == 0;
            let block = std::mem::take(&mut self.block);
            let result = self.lines(&block, out);
            self.block = block;
            result?;
        }
        Ok(())
    }

    /// Parses the complete lines of `block[start..filled]` (and the last one at the end).
    fn lines(&mut self, block: &[u8], out: &mut EventBuffer) -> Result<(), FormatError> {
        while self.start < self.filled {
            let rest = &block[self.start..self.filled];
            let (line, next) = match rest.iter().position(|&b| b == b'\n') {
                Some(i) => (&rest[..i], self.start + i + 1),
                None if self.eof => (rest, self.filled),
                None => {
                    if rest.len() > MAX_LINE_BYTES {
                        let offset = self.block_offset + self.start as u64;
                        let e = ("line", "a line shorter than 4096 bytes", 0, rest.len());
                        return Err(self.text_error(offset, rest, e));
                    }
                    return Ok(());
                }
            };
            let offset = self.block_offset + self.start as u64;
            self.start = next;
            self.line(offset, line, out)?;
        }
        Ok(())
    }

    fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
        ReaderEnd::chunk(self, |r| &mut r.end, out, Self::fill)
    }
}

macro_rules! text_reader {
    ($name:ident, $dialect:expr, $doc:literal) => {
        #[doc = $doc]
        pub struct $name<R>(TextReader<R>);

        impl<R: Read> $name<R> {
            /// A reader of `reader`, labelled `<input>` in errors; reads its `# sensor` line,
            /// if it has one.
            pub fn new(reader: R) -> Result<Self, FormatError> {
                Self::with_name(reader, PathBuf::from("<input>"))
            }

            /// A reader of `reader`, named `path` in errors; reads its `# sensor` line, if it
            /// has one (another `#` first line is an error).
            pub fn with_name(reader: R, path: PathBuf) -> Result<Self, FormatError> {
                Ok(Self(TextReader::new(reader, path, $dialect)?))
            }

            /// Reads a file without a `# sensor` line as a `size` sensor (instead of
            /// 240 × 180).
            pub fn assuming(mut self, size: (u16, u16)) -> Self {
                self.0.sensor.assumed = size;
                self
            }
        }

        impl<R: Read> EventReader for $name<R> {
            fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
                self.0.read_chunk(out)
            }

            fn stats(&self) -> ReadStats {
                self.0.stats
            }

            fn sensor_size(&self) -> Option<(u16, u16)> {
                self.0.sensor.stated
            }
        }
    };
}

text_reader!(
    EcdTextReader,
    Dialect::Ecd,
    "Streaming reader of Event Camera Dataset text (`t x y p`, t in seconds; davis240.md §2.4)."
);
text_reader!(
    CsvReader,
    Dialect::Csv,
    "Streaming reader of CSV events (`t,x,y,on`, t in µs; the header line is optional; davis240.md §2.4)."
);

/// The line engine shared by both text writers.
struct TextWriter<W: Write> {
    out: W,
    path: PathBuf,
    dialect: Dialect,
    size: (u16, u16),
    written: u64,
    line: Vec<u8>,
}

impl<W: Write> TextWriter<W> {
    fn new(
        mut out: W,
        path: PathBuf,
        dialect: Dialect,
        sensor: (u16, u16),
    ) -> Result<Self, FormatError> {
        if sensor.0 == 0 || sensor.1 == 0 {
            let format = match dialect {
                Dialect::Ecd => "ECD text",
                Dialect::Csv => "CSV",
            };
            let supported = "1 … 65535 pixels each way";
            return Err(unsupported_size(&path, format, sensor, supported));
        }
        let mut head = match sensor == DAVIS240_SIZE {
            true => String::new(),
            false => sensor_line(sensor),
        };
        if dialect == Dialect::Csv {
            head.push_str("t,x,y,on\n");
        }
        out.write_all(head.as_bytes()).map_err(write_error(&path))?;
        Ok(Self {
            out,
            path,
            dialect,
            size: sensor,
            written: 0,
            line: Vec::with_capacity(READ_BLOCK),
        })
    }

    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
        self.line.clear();
        for (i, e) in events.iter().enumerate() {
            check_inside(&self.path, self.written + i as u64, (e.x, e.y), self.size)?;
            let t = e.t.0;
            let on = u8::from(e.polarity);
            // Writing into a Vec cannot fail.
            let _ = match self.dialect {
                Dialect::Csv => writeln!(self.line, "{t},{},{},{on}", e.x, e.y),
                Dialect::Ecd => {
                    let sign = if t < 0 { "-" } else { "" };
                    let abs = t.unsigned_abs();
                    writeln!(
                        self.line,
                        "{sign}{}.{:06}000 {} {} {on}",
                        abs / 1_000_000,
                        abs % 1_000_000,
                        e.x,
                        e.y
                    )
                }
            };
            if self.line.len() >= READ_BLOCK - 64 {
                self.flush_line()?;
            }
        }
        self.written += events.len() as u64;
        self.flush_line()
    }

    fn flush_line(&mut self) -> Result<(), FormatError> {
        self.out
            .write_all(&self.line)
            .map_err(write_error(&self.path))?;
        self.line.clear();
        Ok(())
    }

    fn finish(&mut self) -> Result<(), FormatError> {
        self.out.flush().map_err(write_error(&self.path))
    }
}

macro_rules! text_writer {
    ($name:ident, $dialect:expr, $doc:literal) => {
        #[doc = $doc]
        pub struct $name<W: Write>(TextWriter<W>);

        impl<W: Write> $name<W> {
            /// A writer of a `sensor` (width, height) recording to `out`, labelled `<output>`
            /// in errors.
            pub fn new(out: W, sensor: (u16, u16)) -> Result<Self, FormatError> {
                Self::with_name(out, PathBuf::from("<output>"), sensor)
            }

            /// A writer of a `sensor` (width, height) recording to `out`, named `path` in
            /// errors: a first line `# sensor WIDTHxHEIGHT` states any size but 240 × 180
            /// (module docs); a width or height of 0 is refused
            /// ([`FormatError::UnsupportedSensorSize`]).
            pub fn with_name(
                out: W,
                path: PathBuf,
                sensor: (u16, u16),
            ) -> Result<Self, FormatError> {
                Ok(Self(TextWriter::new(out, path, $dialect, sensor)?))
            }
        }

        impl<W: Write> EventWriter for $name<W> {
            fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError> {
                self.0.write(events)
            }

            fn finish(&mut self) -> Result<(), FormatError> {
                self.0.finish()
            }
        }
    };
}

text_writer!(
    EcdTextWriter,
    Dialect::Ecd,
    "Writer of Event Camera Dataset text: `t x y p` with t in seconds and 9 decimals (davis240.md §2.4)."
);
text_writer!(
    CsvWriter,
    Dialect::Csv,
    "Writer of CSV events: header `t,x,y,on`, t in integer µs (davis240.md §2.4)."
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seconds_parse_exactly_to_microseconds() {
        assert_eq!(parse_seconds_us(b"0.000003000"), Some(3));
        assert_eq!(parse_seconds_us(b"1.390419000"), Some(1_390_419));
        assert_eq!(parse_seconds_us(b"2"), Some(2_000_000));
        assert_eq!(parse_seconds_us(b"0.0000015"), Some(2));
        assert_eq!(parse_seconds_us(b"-0.5"), Some(-500_000));
        assert_eq!(parse_seconds_us(b"1e-6"), None);
        assert_eq!(parse_seconds_us(b"."), None);
    }

    #[test]
    fn every_i64_time_the_writers_print_parses_back() {
        for t in [
            i64::MAX,
            i64::MIN,
            -1_000_000_000_000_000_000,
            999_999_999_999_999_999,
        ] {
            let abs = t.unsigned_abs();
            let sign = if t < 0 { "-" } else { "" };
            let ecd = format!("{sign}{}.{:06}000", abs / 1_000_000, abs % 1_000_000);
            assert_eq!(parse_seconds_us(ecd.as_bytes()), Some(t), "{ecd}");
            assert_eq!(parse_int(t.to_string().as_bytes()), Some(t));
        }
        assert_eq!(parse_int(b"9223372036854775808"), None);
        assert_eq!(parse_seconds_us(b"9223372036854.775808"), None);
        assert_eq!(parse_seconds_us(b"-9223372036854.7758085"), None);
    }

    #[test]
    fn lines_parse_or_name_the_bad_field() {
        assert_eq!(
            parse_line(Dialect::Ecd, b"0.000011001 158 145 1"),
            Ok((11, 158, 145, true))
        );
        assert_eq!(
            parse_line(Dialect::Csv, b"11,158,145,0"),
            Ok((11, 158, 145, false))
        );
        assert_eq!(
            parse_line(Dialect::Ecd, b"0.1 2 3 7").unwrap_err().0,
            "polarity"
        );
        assert_eq!(parse_line(Dialect::Csv, b"0,-2,3,1").unwrap_err().0, "x");
        assert_eq!(parse_line(Dialect::Csv, b"0,2,3").unwrap_err().0, "line");
        assert_eq!(
            parse_line(Dialect::Csv, b"0,2,3,1,5").unwrap_err().0,
            "line"
        );
    }

    #[test]
    fn crlf_blank_lines_and_a_last_line_without_end_are_read() {
        let mut out = EventBuffer::new();
        let mut r =
            EcdTextReader::new(&b"0.000001 1 2 1\r\n\r\n0.000002  3 4 0\r\n0.000003 5 6 1"[..])
                .unwrap();
        r.read_to_end(&mut out).unwrap();
        assert_eq!(
            (out.t.clone(), out.x.clone()),
            (vec![1, 2, 3], vec![1, 3, 5])
        );
        let mut out = EventBuffer::new();
        CsvReader::new(&b"7,1,2,1\n8,3,4,0"[..])
            .unwrap()
            .read_to_end(&mut out)
            .unwrap();
        assert_eq!(out.t, vec![7, 8], "a CSV without header");
    }
}
