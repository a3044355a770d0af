//! What every trade shares: its [`Table`] (CSV and Markdown written from the same rows, a
//! [`Column`] or a [`Cell`] telling where the two formats differ), the Pareto front marked on its
//! rows ([`mark_front`]), the series of its error-against-speed plot ([`error_series`]) and the
//! writer of its files ([`write_trade`], [`write_files`]).

use super::error::TradeoffError;
use super::pareto::pareto_front;
use crate::report::png::PngRenderer;
use crate::report::svg::{Marker, PALETTE, Series};
use crate::report::tables::markdown_cell;
use neurotac_core::io::{AtomicFileSet, csv};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A column of a [`Table`]: its name in the CSV and in the Markdown table, or `None` where the
/// column is left out of that format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Column {
    /// Name in the CSV header; `None` for a Markdown-only column.
    pub csv: Option<&'static str>,
    /// Name in the Markdown header; `None` for a CSV-only column.
    pub markdown: Option<&'static str>,
}

impl Column {
    /// A column of both formats, named `name` in both.
    pub const fn both(name: &'static str) -> Self {
        Self::named(name, name)
    }

    /// A column of both formats, named `csv` in the CSV and `markdown` in the Markdown table.
    pub const fn named(csv: &'static str, markdown: &'static str) -> Self {
        Self {
            csv: Some(csv),
            markdown: Some(markdown),
        }
    }

    /// A column of the CSV only.
    pub const fn csv_only(name: &'static str) -> Self {
        Self {
            csv: Some(name),
            markdown: None,
        }
    }

    /// A column of the Markdown table only.
    pub const fn markdown_only(name: &'static str) -> Self {
        Self {
            csv: None,
            markdown: Some(name),
        }
    }

    fn name(&self, format: Format) -> Option<&'static str> {
        match format {
            Format::Csv => self.csv,
            Format::Markdown => self.markdown,
        }
    }
}

impl From<&'static str> for Column {
    fn from(name: &'static str) -> Self {
        Self::both(name)
    }
}

/// A cell of a [`Table`]: one text for both formats, or one for each where they differ (e.g.
/// every digit in the CSV, three in the Markdown table).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Cell {
    /// The same text in both formats.
    Same(String),
    /// A text for each format.
    Split {
        /// Text in the CSV.
        csv: String,
        /// Text in the Markdown table.
        markdown: String,
    },
}

impl Cell {
    /// A cell written as `csv` in the CSV and as `markdown` in the Markdown table.
    pub fn split(csv: impl Into<String>, markdown: impl Into<String>) -> Self {
        Self::Split {
            csv: csv.into(),
            markdown: markdown.into(),
        }
    }

    fn text(&self, format: Format) -> &str {
        match (self, format) {
            (Self::Same(text), _) => text,
            (Self::Split { csv, .. }, Format::Csv) => csv,
            (Self::Split { markdown, .. }, Format::Markdown) => markdown,
        }
    }
}

impl From<String> for Cell {
    fn from(text: String) -> Self {
        Self::Same(text)
    }
}

impl From<&str> for Cell {
    fn from(text: &str) -> Self {
        Self::Same(text.to_owned())
    }
}

#[derive(Debug, Clone, Copy)]
enum Format {
    Csv,
    Markdown,
}

/// A table of a trade: columns and rows of cells, written as CSV or Markdown. A column or a cell
/// can differ between the two formats ([`Column`], [`Cell`]); every row is built once for both.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// The columns.
    pub columns: Vec<Column>,
    /// Rows of cells, each as long as `columns`.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table with these columns (a plain name is a column of both formats).
    pub fn new<C: Into<Column>>(columns: impl IntoIterator<Item = C>) -> Self {
        Self {
            columns: columns.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row (a plain text is the same cell in both formats).
    pub fn push<C: Into<Cell>>(&mut self, cells: impl IntoIterator<Item = C>) {
        let cells: Vec<Cell> = cells.into_iter().map(Into::into).collect();
        debug_assert_eq!(cells.len(), self.columns.len());
        self.rows.push(cells);
    }

    /// The header, then each row, as the texts of the columns `format` writes.
    fn lines(&self, format: Format) -> impl Iterator<Item = Vec<&str>> {
        let header = self.columns.iter().filter_map(|c| c.name(format)).collect();
        let rows = self.rows.iter().map(move |row| {
            self.columns
                .iter()
                .zip(row)
                .filter(|(c, _)| c.name(format).is_some())
                .map(|(_, cell)| cell.text(format))
                .collect()
        });
        std::iter::once(header).chain(rows)
    }

    /// CSV ([`neurotac_core::io::csv`]): the column names, then one record per row (a cell
    /// holding a comma, a quote or a line break is quoted). Fails when a row has not as many
    /// cells as there are columns.
    pub fn to_csv(&self) -> Result<String, csv::Error> {
        let mut lines = self.lines(Format::Csv);
        let header = lines.next().unwrap_or_default();
        csv::table(header, lines)
    }

    /// A Markdown table (a `|` in a cell escaped, [`markdown_cell`]).
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        for (i, line) in self.lines(Format::Markdown).enumerate() {
            let cells: Vec<_> = line.into_iter().map(markdown_cell).collect();
            let _ = writeln!(out, "| {} |", cells.join(" | "));
            if i == 0 {
                let _ = writeln!(out, "|{}", "---|".repeat(cells.len()));
            }
        }
        out
    }
}

/// Marks the Pareto front of `rows` ([`pareto_front`] of each row's `(speed, error)`,
/// `None` for a row that takes no part) with `mark`.
pub fn mark_front<R>(
    rows: &mut [R],
    point: impl Fn(&R) -> Option<(f64, f64)>,
    mark: impl Fn(&mut R, bool),
) {
    let points: Vec<_> = rows.iter().map(&point).collect();
    for (row, on_front) in rows.iter_mut().zip(pareto_front(&points)) {
        mark(row, on_front);
    }
}

/// One series of an error-against-speed plot: palette colour `color`, filled markers joined by
/// a line.
pub fn error_series(label: &str, color: usize, marker: Marker, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: label.to_owned(),
        points,
        color: PALETTE[color % PALETTE.len()].to_owned(),
        marker,
        filled: true,
        line: true,
        y_ranges: Vec::new(),
    }
}

/// A trade's files in `dir`: `<stem>.csv`, `<stem>.md`, `<stem>.svg` and `<stem>.png`.
pub fn trade_files(dir: &Path, stem: &str) -> [PathBuf; 4] {
    ["csv", "md", "svg", "png"].map(|ext| dir.join(format!("{stem}.{ext}")))
}

/// Creates `dir` and adds a trade's files ([`trade_files`]) to `files`, committed by the
/// caller with the command's other outputs (the figure rasterised as the report's figures are);
/// a CSV table that could not be made is an I/O error of its file.
pub fn write_trade(
    files: &mut AtomicFileSet,
    dir: &Path,
    stem: &str,
    csv: Result<String, csv::Error>,
    markdown: &str,
    svg: &str,
) -> Result<(), TradeoffError> {
    let csv_name = format!("{stem}.csv");
    let csv = csv.map_err(|e| TradeoffError::Io {
        path: dir.join(&csv_name),
        source: e.into(),
    })?;
    write_files(
        files,
        dir,
        &[
            (&csv_name, &csv),
            (&format!("{stem}.md"), markdown),
            (&format!("{stem}.svg"), svg),
        ],
    )?;
    let path = dir.join(format!("{stem}.png"));
    let png = PngRenderer::new()
        .render(svg, 1.5)
        .map_err(|source| TradeoffError::Png {
            path: path.clone(),
            source,
        })?;
    files
        .write(&path, png)
        .map_err(|source| TradeoffError::Io { path, source })
}

/// Creates `dir` and adds each `(file name, text)` in it to `files`.
pub fn write_files(
    files: &mut AtomicFileSet,
    dir: &Path,
    texts: &[(&str, &str)],
) -> Result<(), TradeoffError> {
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| TradeoffError::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    for (name, text) in texts {
        let path = dir.join(name);
        files.write(&path, text).map_err(io(&path))?;
    }
    Ok(())
}

/// The columns of both formats (by CSV name) whose texts differ, in some row, between a written
/// CSV and the first table of a written Markdown text; panics unless both have the columns
/// and as many rows.
#[cfg(test)]
pub(crate) fn columns_written_differently(
    columns: &[Column],
    csv: &str,
    markdown: &str,
) -> Vec<&'static str> {
    let (header, rows) = csv::read_table(csv).expect("a CSV table");
    let csv: Vec<Vec<String>> = std::iter::once(header).chain(rows).collect();
    let markdown: Vec<Vec<&str>> = markdown
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .filter(|l| !l.starts_with("|---"))
        .map(|l| {
            let inner = l.strip_prefix("| ").and_then(|l| l.strip_suffix(" |"));
            inner.expect("a Markdown row").split(" | ").collect()
        })
        .collect();
    assert_eq!(csv.len(), markdown.len(), "as many rows");
    let position = |header: &[&str], name| header.iter().position(|h| *h == name).expect(name);
    columns
        .iter()
        .filter_map(|c| Some((c.csv?, c.markdown?)))
        .filter(|&(csv_name, markdown_name)| {
            let names: Vec<&str> = csv[0].iter().map(String::as_str).collect();
            let i = position(&names, csv_name);
            let j = position(&markdown[0], markdown_name);
            csv.iter().zip(&markdown).skip(1).any(|(a, b)| a[i] != b[j])
        })
        .map(|(csv_name, _)| csv_name)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_writes_csv_and_markdown() {
        let mut t = Table::new(["a", "b"]);
        t.push(["1", "x"]);
        t.push(["2", ""]);
        t.push(["3", "pool 20 ms, BA 5 ms"]);
        assert_eq!(
            t.to_csv().unwrap(),
            "a,b\n1,x\n2,\n3,\"pool 20 ms, BA 5 ms\"\n"
        );
        assert_eq!(
            t.to_markdown(),
            "| a | b |\n|---|---|\n| 1 | x |\n| 2 |  |\n| 3 | pool 20 ms, BA 5 ms |\n"
        );
    }

    #[test]
    fn a_column_or_a_cell_can_differ_between_the_formats() {
        let mut t = Table::new([
            Column::named("x_s", "x (s)"),
            Column::csv_only("n"),
            Column::markdown_only("note"),
        ]);
        t.push([Cell::split("1.25e-3", "1.3e-3"), "4".into(), "four".into()]);
        assert_eq!(t.to_csv().unwrap(), "x_s,n\n1.25e-3,4\n");
        assert_eq!(
            t.to_markdown(),
            "| x (s) | note |\n|---|---|\n| 1.3e-3 | four |\n"
        );
    }

    #[test]
    fn the_front_is_marked_on_the_rows() {
        let mut rows = vec![(10.0, 1.0, false), (5.0, 2.0, false), (1.0, 0.1, false)];
        mark_front(&mut rows, |r| Some((r.0, r.1)), |r, on| r.2 = on);
        assert_eq!(
            rows.iter().map(|r| r.2).collect::<Vec<_>>(),
            [true, false, true]
        );
    }

    #[test]
    fn a_trade_writes_its_three_files() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("t");
        let mut files = AtomicFileSet::new(neurotac_core::io::Replace::No);
        write_trade(&mut files, &sub, "x", Ok("c".into()), "m", "<svg/>").unwrap();
        assert_eq!(
            neurotac_core::testing::folder_names(&sub).len(),
            4,
            "hidden until committed"
        );
        files.commit().unwrap();
        for (f, text) in [("x.csv", "c"), ("x.md", "m"), ("x.svg", "<svg/>")] {
            assert_eq!(std::fs::read_to_string(sub.join(f)).unwrap(), text);
        }
    }
}
