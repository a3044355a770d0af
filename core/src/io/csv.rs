//! CSV, written and read by one crate (`csv`) in one dialect: every table neurotac writes (the
//! report's, the trade-offs', the online evaluation's) and the event files of the `t,x,y,on`
//! layout.
//!
//! The dialect is RFC 4180 with `\n` line ends: fields separated by `,`; a field holding a
//! comma, a `"` or a line break is enclosed in `"` with its quotes doubled, every other field is
//! written as it is (so a number is never quoted); every record has as many fields as the header
//! (a writer refuses a record of another length). pandas' `read_csv`, Python's `csv` module and
//! spreadsheets read it as written. The reader accepts `\n`, `\r\n` and `\r` line ends and skips
//! empty lines.
//!
//! - [`table`]: a header and rows of texts (the columns known at run time);
//! - [`records`]: a list of serde records, the header named by the record's fields;
//! - [`writer`]: a streaming writer whose header is given (an interchange layout), rows by
//!   `write_record` or `serialize` (a tuple or a record, values only);
//! - [`reader`]: the strict reader (a header, then records as long as it), [`read_table`] a
//!   whole text through it, and [`reader_builder`] for a reader of the same dialect with other
//!   rules.
//!
//! ```
//! use neurotac_core::io::csv;
//! let text = csv::table(["setting", "pct"], [["pool 20 ms, BA 5 ms", "97.5"]])?;
//! assert_eq!(text, "setting,pct\n\"pool 20 ms, BA 5 ms\",97.5\n");
//! let mut read = csv::reader(text.as_bytes());
//! assert_eq!(read.headers()?, vec!["setting", "pct"]);
//! let row = read.records().next().unwrap()?;
//! assert_eq!(&row[0], "pool 20 ms, BA 5 ms");
//! # Ok::<(), ::csv::Error>(())
//! ```

use serde::Serialize;
use std::io::{Read, Write};

pub use ::csv::Error;

/// The writer's dialect (module docs); no serde header unless asked for.
fn writer_builder() -> ::csv::WriterBuilder {
    let mut b = ::csv::WriterBuilder::new();
    b.terminator(::csv::Terminator::Any(b'\n'))
        .has_headers(false);
    b
}

/// A writer of the dialect to `out` whose first record is `header`; every later record must
/// have as many fields. Rows are written by `write_record` or `serialize` (values only: the
/// header is this one); `flush` (or dropping the writer) writes what it buffers.
pub fn writer<W, H>(out: W, header: H) -> Result<::csv::Writer<W>, Error>
where
    W: Write,
    H: IntoIterator,
    H::Item: AsRef<[u8]>,
{
    let mut w = writer_builder().from_writer(out);
    w.write_record(header)?;
    Ok(w)
}

/// The text a writer wrote into memory.
fn into_text(w: ::csv::Writer<Vec<u8>>) -> Result<String, Error> {
    let bytes = w.into_inner().map_err(|e| Error::from(e.into_error()))?;
    // Every field was a `str` or a number, so the bytes are UTF-8.
    String::from_utf8(bytes).map_err(|e| Error::from(std::io::Error::other(e)))
}

/// A table as CSV text: `header`, then each row. Fails when a row has not as many fields as
/// the header.
pub fn table<H, R>(header: H, rows: impl IntoIterator<Item = R>) -> Result<String, Error>
where
    H: IntoIterator,
    H::Item: AsRef<[u8]>,
    R: IntoIterator,
    R::Item: AsRef<[u8]>,
{
    let mut w = writer(Vec::new(), header)?;
    for row in rows {
        w.write_record(row)?;
    }
    into_text(w)
}

/// A list of records as CSV text: the header names the record's fields (serde's names), then
/// one row per record (`None` is an empty field). Without records, the header alone (the
/// fields of `T::default()`). Fails on a record serde cannot write as one row (a field that is
/// itself a list or a record).
pub fn records<T: Serialize + Default>(rows: impl IntoIterator<Item = T>) -> Result<String, Error> {
    let mut w = writer_builder().has_headers(true).from_writer(Vec::new());
    let mut any = false;
    for row in rows {
        w.serialize(row)?;
        any = true;
    }
    if any {
        return into_text(w);
    }
    w.serialize(T::default())?;
    let text = into_text(w)?;
    // Field names hold no line break: the header is the first line.
    let header_end = text.find('\n').map_or(text.len(), |i| i + 1);
    Ok(text[..header_end].to_owned())
}

/// A reader builder of the dialect (module docs), strict: a header, then records as long as it.
/// Change what a reader of another layout needs (`has_headers(false)`, `flexible(true)`).
pub fn reader_builder() -> ::csv::ReaderBuilder {
    ::csv::ReaderBuilder::new()
}

/// The strict reader of `input`: its first record is the header, every later one must have as
/// many fields (else [`csv::ErrorKind::UnequalLengths`]).
pub fn reader<R: Read>(input: R) -> ::csv::Reader<R> {
    reader_builder().from_reader(input)
}

/// A whole CSV text read by the strict [`reader`]: the header's names and every record's
/// fields (unquoted).
pub fn read_table(text: &str) -> Result<(Vec<String>, Vec<Vec<String>>), Error> {
    let mut r = reader(text.as_bytes());
    let header = r.headers()?.iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|row| Ok(row?.iter().map(String::from).collect()))
        .collect::<Result<_, Error>>()?;
    Ok((header, rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_with_commas_quotes_or_line_breaks_are_quoted_and_read_back() {
        let cells = ["plain", "a, b", "say \"hi\"", "two\nlines", "", "1.5e-3"];
        let text = table(["a", "b", "c", "d", "e", "f"], [cells]).unwrap();
        assert_eq!(
            text,
            "a,b,c,d,e,f\nplain,\"a, b\",\"say \"\"hi\"\"\",\"two\nlines\",,1.5e-3\n"
        );
        let (header, rows) = read_table(&text).unwrap();
        assert_eq!(header, ["a", "b", "c", "d", "e", "f"]);
        assert_eq!(rows, [cells.map(String::from)]);
    }

    #[test]
    fn a_row_of_another_length_is_refused_by_the_writer_and_the_reader() {
        let e = table(["a", "b"], [vec!["1", "2"], vec!["1", "2", "3"]]).unwrap_err();
        assert!(
            matches!(e.kind(), ::csv::ErrorKind::UnequalLengths { .. }),
            "{e}"
        );
        let e = read_table("a,b\n1,2\n1,2,3\n").unwrap_err();
        assert!(
            matches!(e.kind(), ::csv::ErrorKind::UnequalLengths { .. }),
            "{e}"
        );
    }

    #[derive(Serialize, Default)]
    struct Row {
        name: String,
        value: f64,
        paper: Option<f64>,
    }

    #[test]
    fn records_are_named_by_their_fields_and_an_empty_list_is_its_header() {
        let rows = [
            Row {
                name: "grid 0.5 mm, pins".into(),
                value: 0.25,
                paper: None,
            },
            Row {
                name: "x".into(),
                value: 3.0,
                paper: Some(0.928),
            },
        ];
        assert_eq!(
            records(rows).unwrap(),
            "name,value,paper\n\"grid 0.5 mm, pins\",0.25,\nx,3.0,0.928\n"
        );
        assert_eq!(records(Vec::<Row>::new()).unwrap(), "name,value,paper\n");
    }

    #[test]
    fn a_streaming_writer_writes_its_header_and_tuples() {
        let mut w = writer(Vec::new(), ["t", "x", "y", "on"]).unwrap();
        w.serialize((-5i64, 3u16, 4u16, 1u8)).unwrap();
        w.serialize((7i64, 0u16, 179u16, 0u8)).unwrap();
        assert_eq!(into_text(w).unwrap(), "t,x,y,on\n-5,3,4,1\n7,0,179,0\n");
    }

    #[test]
    fn the_reader_takes_crlf_and_skips_empty_lines() {
        let (header, rows) = read_table("a,b\r\n\r\n1,\"2\"\r\n\n3,4").unwrap();
        assert_eq!(header, ["a", "b"]);
        assert_eq!(rows, [["1", "2"], ["3", "4"]]);
    }
}
