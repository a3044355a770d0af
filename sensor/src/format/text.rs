//! Text event files (davis240.md §2.4): the Event Camera Dataset's `events.txt` and the CSV that
//! faery writes. This module reads and writes ECD text and holds what both readers share (the
//! sensor line, the checks of a pixel and of the time order); CSV is read and written by the
//! `csv` crate (`neurotac_core::io::csv`) in [`super::csv_events`].
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
use std::path::{Path, PathBuf};

/// Longest line accepted (bytes).
pub const MAX_LINE_BYTES: usize = 4096;

/// Most bytes of a line quoted in an error.
pub(super) const FOUND_MAX_BYTES: usize = 64;

/// A parse failure inside a line: the column, what was expected and the bytes found.
pub(super) type FieldError<'a> = (&'static str, &'static str, &'a [u8]);

/// Parses a decimal integer (optional sign) in `s`.
pub(super) fn parse_int(s: &[u8]) -> Option<i64> {
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

/// Parses the x, y and polarity fields of an event line: `(x, y, on)`.
pub(super) fn parse_pixel<'a>(
    x: &'a [u8],
    y: &'a [u8],
    polarity: &'a [u8],
) -> Result<(i64, i64, bool), FieldError<'a>> {
    let coord = |field: &'a [u8], name| {
        parse_int(field)
            .filter(|v| (0..=i64::from(u16::MAX)).contains(v))
            .ok_or((name, "an integer 0–65535", field))
    };
    let (x, y) = (coord(x, "x")?, coord(y, "y")?);
    let on = match polarity {
        b"1" => true,
        b"0" | b"-1" => false,
        _ => return Err(("polarity", "1 or 0", polarity)),
    };
    Ok((x, y, on))
}

/// Parses one non-empty ECD line (`t x y p`, blanks between) into `(t, x, y, on)`.
fn parse_line(line: &[u8]) -> Result<(i64, i64, i64, bool), FieldError<'_>> {
    let mut fields = line
        .split(|&b| b == b' ' || b == b'\t')
        .filter(|f| !f.is_empty());
    let mut next = || fields.next().ok_or(("line", "4 fields: t x y p", line));
    let (t, x, y, p) = (next()?, next()?, next()?, next()?);
    if fields.next().is_some() {
        return Err(("line", "exactly 4 fields", line));
    }
    let t = parse_seconds_us(t).ok_or(("t", "decimal seconds", t))?;
    let (x, y, on) = parse_pixel(x, y, p)?;
    Ok((t, x, y, on))
}

/// What both text readers keep of the events read so far: the sensor size (stated or
/// assumed), the last time and the counters.
pub(super) struct TextEvents {
    pub(super) sensor: ReaderSensor,
    pub(super) stats: ReadStats,
    previous: i64,
}

impl TextEvents {
    /// A file that states `stated` (or nothing).
    pub(super) fn new(stated: Option<(u16, u16)>) -> Self {
        Self {
            sensor: ReaderSensor::new(stated),
            stats: ReadStats::default(),
            previous: i64::MIN,
        }
    }

    /// Appends the event of the line at `offset` to `out`, or counts it as outside the sensor.
    #[inline]
    pub(super) fn push(
        &mut self,
        offset: u64,
        (t, x, y, on): (i64, i64, i64, bool),
        out: &mut EventBuffer,
    ) {
        let (size_x, size_y) = self.sensor.bounds();
        if x >= i64::from(size_x) || y >= i64::from(size_y) {
            self.stats.out_of_range += 1;
            return;
        }
        self.stats.check_order(offset, self.previous, t);
        self.previous = t;
        out.t.push(t);
        out.x.push(x as u16);
        out.y.push(y as u16);
        out.polarity.push(on);
        self.stats.events += 1;
    }
}

/// The error of a text line: `line` (1-based) at `offset`, and what was wrong in it.
pub(super) fn text_error(path: &Path, line: u64, offset: u64, e: FieldError<'_>) -> FormatError {
    let (field, expected, found) = e;
    FormatError::Text {
        path: path.to_path_buf(),
        line,
        offset,
        field,
        found: escape_text(found, FOUND_MAX_BYTES),
        expected,
    }
}

/// The start of a text input, as [`read_sensor_line`] read it.
pub(super) struct TextStart {
    /// The size the `# sensor` line states, if the input starts with one.
    pub(super) stated: Option<(u16, u16)>,
    /// The bytes read past the start without such a line (its first byte, to be read again).
    pub(super) ahead: Vec<u8>,
}

/// Reads the optional first line `# sensor WIDTHxHEIGHT` of a text input. A first line that
/// starts with `#` and is not a sensor line is an error naming line 1.
pub(super) fn read_sensor_line<R: Read>(input: &mut Input<R>) -> Result<TextStart, FormatError> {
    let mut byte = [0u8; 1];
    let without = |ahead: &[u8]| TextStart {
        stated: None,
        ahead: ahead.to_vec(),
    };
    if input.read_full(&mut byte)? == 0 {
        return Ok(without(&[]));
    }
    if byte[0] != b'#' {
        return Ok(without(&byte));
    }
    // Byte by byte: the line is short, and what follows is the line reader's.
    let mut line = vec![b'#'];
    while line.len() <= MAX_LINE_BYTES && input.read_full(&mut byte)? == 1 {
        if byte[0] == b'\n' {
            break;
        }
        line.push(byte[0]);
    }
    let line = line.strip_suffix(b"\r").unwrap_or(&line);
    let expected = "`# sensor WIDTHxHEIGHT` (the one `#` line read, first in the file)";
    let size = parse_sensor_line(line)
        .ok_or_else(|| text_error(input.path(), 1, 0, ("sensor line", expected, line)))?;
    Ok(TextStart {
        stated: Some(size),
        ahead: Vec::new(),
    })
}

/// The line engine of the ECD text reader.
struct TextReader<R> {
    input: Input<R>,
    events: TextEvents,
    block: Vec<u8>,
    start: usize,
    filled: usize,
    /// Offset of `block[0]`.
    block_offset: u64,
    line: u64,
    eof: bool,
    end: ReaderEnd,
}

impl<R: Read> TextReader<R> {
    /// A reader of `reader`; reads the `# sensor` line if the input starts with `#`.
    fn new(reader: R, path: PathBuf) -> Result<Self, FormatError> {
        let mut input = Input::new(reader, path);
        let TextStart { stated, ahead } = read_sensor_line(&mut input)?;
        let mut block = vec![0; READ_BLOCK];
        block[..ahead.len()].copy_from_slice(&ahead);
        Ok(Self {
            block_offset: input.offset() - ahead.len() as u64,
            input,
            events: TextEvents::new(stated),
            block,
            start: 0,
            filled: ahead.len(),
            line: u64::from(stated.is_some()),
            eof: false,
            end: ReaderEnd::default(),
        })
    }

    /// Handles one line (without its line end).
    fn line(&mut self, offset: u64, line: &[u8], out: &mut EventBuffer) -> Result<(), FormatError> {
        self.line += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.is_empty() {
            return Ok(());
        }
        let event =
            parse_line(line).map_err(|e| text_error(self.input.path(), self.line, offset, e))?;
        self.events.push(offset, event, out);
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
                        let e = ("line", "a line shorter than 4096 bytes", rest);
                        return Err(text_error(self.input.path(), self.line + 1, offset, e));
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

/// The public type `$name` of a text reader over its engine `$engine` (with `new(reader,
/// path)`, `read_chunk` and its [`TextEvents`] in `events`).
macro_rules! text_reader {
    ($name:ident, $engine:ident, $doc:literal) => {
        #[doc = $doc]
        pub struct $name<R>($engine<R>);

        impl<R: Read> $name<R> {
            /// A reader of `reader`, labelled `<input>` in errors; reads its `# sensor` line,
            /// if it has one.
            pub fn new(reader: R) -> Result<Self, FormatError> {
                Self::with_name(reader, PathBuf::from("<input>"))
            }

            /// A reader of `reader`, named `path` in errors; reads its `# sensor` line, if it
            /// has one (another `#` first line is an error).
            pub fn with_name(reader: R, path: PathBuf) -> Result<Self, FormatError> {
                Ok(Self($engine::new(reader, path)?))
            }

            /// Reads a file without a `# sensor` line as a `size` sensor (instead of
            /// 240 × 180).
            pub fn assuming(mut self, size: (u16, u16)) -> Self {
                self.0.events.sensor.assumed = size;
                self
            }
        }

        impl<R: Read> EventReader for $name<R> {
            fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
                self.0.read_chunk(out)
            }

            fn stats(&self) -> ReadStats {
                self.0.events.stats
            }

            fn sensor_size(&self) -> Option<(u16, u16)> {
                self.0.events.sensor.stated
            }
        }
    };
}
pub(super) use text_reader;

text_reader!(
    EcdTextReader,
    TextReader,
    "Streaming reader of Event Camera Dataset text (`t x y p`, t in seconds; davis240.md §2.4)."
);

/// The first lines of a text file for a `sensor` (width, height) recording: `# sensor
/// WIDTHxHEIGHT` for any size but 240 × 180 (module docs); a width or height of 0 is refused
/// ([`FormatError::UnsupportedSensorSize`]) naming `format`.
pub(super) fn sensor_head(
    path: &Path,
    format: &'static str,
    sensor: (u16, u16),
) -> Result<String, FormatError> {
    if sensor.0 == 0 || sensor.1 == 0 {
        let supported = "1 … 65535 pixels each way";
        return Err(unsupported_size(path, format, sensor, supported));
    }
    Ok(match sensor == DAVIS240_SIZE {
        true => String::new(),
        false => sensor_line(sensor),
    })
}

/// The line engine of the ECD text writer.
struct TextWriter<W: Write> {
    out: W,
    path: PathBuf,
    size: (u16, u16),
    written: u64,
    line: Vec<u8>,
}

impl<W: Write> TextWriter<W> {
    fn new(mut out: W, path: PathBuf, sensor: (u16, u16)) -> Result<Self, FormatError> {
        let head = sensor_head(&path, "ECD text", sensor)?;
        out.write_all(head.as_bytes()).map_err(write_error(&path))?;
        Ok(Self {
            out,
            path,
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
            let sign = if t < 0 { "-" } else { "" };
            let abs = t.unsigned_abs();
            // Writing into a Vec cannot fail.
            let _ = writeln!(
                self.line,
                "{sign}{}.{:06}000 {} {} {}",
                abs / 1_000_000,
                abs % 1_000_000,
                e.x,
                e.y,
                u8::from(e.polarity)
            );
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

/// The public type `$name` of a text writer over its engine `$engine` (with `new(out, path,
/// sensor)`, `write` and `finish`).
macro_rules! text_writer {
    ($name:ident, $engine:ident, $doc:literal) => {
        #[doc = $doc]
        pub struct $name<W: Write>($engine<W>);

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
                Ok(Self($engine::new(out, path, sensor)?))
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
pub(super) use text_writer;

text_writer!(
    EcdTextWriter,
    TextWriter,
    "Writer of Event Camera Dataset text: `t x y p` with t in seconds and 9 decimals (davis240.md §2.4)."
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
            parse_line(b"0.000011001 158 145 1"),
            Ok((11, 158, 145, true))
        );
        assert_eq!(
            parse_line(b" 0.000011\t158  145 0 "),
            Ok((11, 158, 145, false))
        );
        assert_eq!(parse_line(b"0.1 2 3 7").unwrap_err().0, "polarity");
        assert_eq!(
            parse_line(b"0.1 -2 3 1").unwrap_err(),
            ("x", "an integer 0–65535", &b"-2"[..])
        );
        assert_eq!(parse_line(b"0.1 2 3").unwrap_err().0, "line");
        assert_eq!(parse_line(b"0.1 2 3 1 5").unwrap_err().0, "line");
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
    }
}
