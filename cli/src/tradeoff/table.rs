//! What every trade shares: its [`Table`] (CSV and Markdown), the Pareto front marked on its
//! rows ([`mark_front`]), the series of its error-against-speed plot ([`error_series`]) and the
//! writer of its files ([`write_trade`], [`write_files`]).

use super::error::TradeoffError;
use super::pareto::pareto_front;
use crate::report::png::PngRenderer;
use crate::report::svg::{Marker, PALETTE, Series};
use std::fmt::Write as _;
use std::path::Path;

/// A table of a trade: column names and rows of formatted cells, written as CSV or Markdown.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows of cells, each as long as `columns`.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// An empty table with these columns.
    pub fn new(columns: &[&str]) -> Self {
        Self {
            columns: columns.iter().map(|c| (*c).to_owned()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn push(&mut self, cells: Vec<String>) {
        debug_assert_eq!(cells.len(), self.columns.len());
        self.rows.push(cells);
    }

    /// CSV: the column names, then one line per row (cells are written as given).
    pub fn to_csv(&self) -> String {
        let mut out = self.columns.join(",") + "\n";
        for row in &self.rows {
            out += &(row.join(",") + "\n");
        }
        out
    }

    /// A Markdown table.
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "| {} |", self.columns.join(" | "));
        let _ = writeln!(out, "|{}", "---|".repeat(self.columns.len()));
        for row in &self.rows {
            let _ = writeln!(out, "| {} |", row.join(" | "));
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
    }
}

/// Creates `dir` and writes a trade's `<stem>.csv`, `<stem>.md`, `<stem>.svg` and `<stem>.png`
/// (the figure rasterised as the report's figures are).
pub fn write_trade(
    dir: &Path,
    stem: &str,
    csv: &str,
    markdown: &str,
    svg: &str,
) -> Result<(), TradeoffError> {
    write_files(
        dir,
        &[
            (&format!("{stem}.csv"), csv),
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
    neurotac_core::io::write(&path, png).map_err(|source| TradeoffError::Io { path, source })
}

/// Creates `dir` and writes each `(file name, text)` into it.
pub fn write_files(dir: &Path, files: &[(&str, &str)]) -> Result<(), TradeoffError> {
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| TradeoffError::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    for (name, text) in files {
        let path = dir.join(name);
        neurotac_core::io::write(&path, text).map_err(io(&path))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_writes_csv_and_markdown() {
        let mut t = Table::new(&["a", "b"]);
        t.push(vec!["1".into(), "x".into()]);
        t.push(vec!["2".into(), "".into()]);
        assert_eq!(t.to_csv(), "a,b\n1,x\n2,\n");
        assert_eq!(
            t.to_markdown(),
            "| a | b |\n|---|---|\n| 1 | x |\n| 2 |  |\n"
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
        write_trade(&sub, "x", "c", "m", "<svg/>").unwrap();
        for (f, text) in [("x.csv", "c"), ("x.md", "m"), ("x.svg", "<svg/>")] {
            assert_eq!(std::fs::read_to_string(sub.join(f)).unwrap(), text);
        }
    }
}
