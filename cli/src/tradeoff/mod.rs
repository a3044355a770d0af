//! Speed ↔ accuracy trade-offs (`neurotac tradeoff`): each trade measures rows, marks their
//! Pareto front ([`pareto`]) and writes `<stem>.csv`, `<stem>.md` and `<stem>.svg` through the
//! shared [`Table`] and [`write_trade`]; [`summary`] is the one-page summary of all of them and
//! [`run_all`] runs every trade.
//!
//! | module | trade |
//! |---|---|
//! | [`neurons`] | model × integrator × dt × precision × spike stamping: updates/s against spike-time error |
//! | [`vr`] | exact vs synaptic-trace Van Rossum distance (trace dt × f32/f64): matrix time against LOO accuracy |
//! | [`simulator`] | pixel-model step tolerance: trials/s against event-timing error |
//!
//! To add a trade: a module with a config, a measuring function, `to_csv`/`to_markdown`/`to_svg`
//! built on [`Table`] and [`error_series`], a `report` that measures and writes, and a section in
//! [`summary`].

pub mod neurons;
pub mod pareto;
pub mod simulator;
pub mod summary;
pub mod vr;

use crate::bench::BenchError;
use crate::report::svg::{Marker, PALETTE, Series};
use neurotac_experiments::datasets::DatasetsError;
use neurotac_experiments::error::ExperimentError;
use neurotac_experiments::progress::Progress;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Why a trade could not be measured or written.
#[derive(Debug, thiserror::Error)]
pub enum TradeoffError {
    /// A neuron benchmark failed.
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// A distance or parameter was refused.
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// The simulator failed.
    #[error(transparent)]
    Simulation(#[from] DatasetsError),
    /// A parameter outside its domain.
    #[error("{what} = {value}: {expected}")]
    InvalidParameter {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A figure could not be rasterised to PNG.
    #[error("cannot draw {path}")]
    Png {
        /// The PNG file.
        path: PathBuf,
        /// Why.
        source: crate::report::png::PngError,
    },
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

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

/// Marks the Pareto front of `rows` ([`pareto::pareto_front`] of each row's `(speed, error)`,
/// `None` for a row that takes no part) with `mark`.
pub fn mark_front<R>(
    rows: &mut [R],
    point: impl Fn(&R) -> Option<(f64, f64)>,
    mark: impl Fn(&mut R, bool),
) {
    let points: Vec<_> = rows.iter().map(&point).collect();
    for (row, on_front) in rows.iter_mut().zip(pareto::pareto_front(&points)) {
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
    let png = crate::report::png::PngRenderer::new()
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

/// What [`run_all`] runs: every trade's settings and where the Van Rossum trade's samples come
/// from.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffAllConfig {
    /// The neuron trade.
    pub neurons: neurons::NeuronTradeoffConfig,
    /// The Van Rossum trade.
    pub vr: vr::VrTradeoffConfig,
    /// The simulator trade.
    pub simulator: simulator::SimulatorTradeoffConfig,
    /// `true` for the quick settings (named in the summary's header).
    pub quick: bool,
}

impl TradeoffAllConfig {
    /// Every trade's defaults, or its quick settings (a few seconds in all).
    pub fn new(quick: bool) -> Self {
        let (mut n, mut v, mut s) = Default::default();
        if quick {
            neurons::quick(&mut n);
            vr::quick(&mut v);
            simulator::quick(&mut s);
        }
        Self {
            neurons: n,
            vr: v,
            simulator: s,
            quick,
        }
    }
}

/// Every trade measured by [`run_all`], and the summary page.
#[derive(Debug, Clone)]
pub struct TradeoffAll {
    /// The neuron trade's rows.
    pub neurons: Vec<neurons::NeuronTradeoffRow>,
    /// The Van Rossum trade.
    pub vr: vr::VrTradeoff,
    /// The simulator trade's rows.
    pub simulator: Vec<simulator::SimulatorTradeoffRow>,
    /// `tradeoff.md`.
    pub summary: String,
    /// Wall time of each trade (s): neurons, Van Rossum, simulator.
    pub seconds: [f64; 3],
}

/// Runs every trade (`data`: the Van Rossum trade's spike dataset), writes each one's files to
/// its sub-folder of `out` and the summary to `out/tradeoff.md`; `progress` gets one stage and
/// one note (`neurons: 1.2 s`) per trade.
pub fn run_all(
    config: &TradeoffAllConfig,
    data: &neurotac_core::SpikeDataset,
    out: &Path,
    progress: &dyn Progress,
) -> Result<TradeoffAll, TradeoffError> {
    let timed_stage = |name: &str, t: std::time::Instant| {
        progress.finish();
        let seconds = t.elapsed().as_secs_f64();
        progress.note(&format!("{name}: {seconds:.1} s"));
        seconds
    };
    let start = std::time::Instant::now();
    let t = std::time::Instant::now();
    progress.stage("neurons", 0);
    let neuron_rows = neurons::report(&config.neurons, &out.join(summary::NEURONS_DIR))?;
    let neurons_s = timed_stage("neurons", t);
    let t = std::time::Instant::now();
    progress.stage("vr", 0);
    let sweep = vr::report(data, &config.vr, &out.join(summary::VR_DIR))?;
    let vr_s = timed_stage("vr", t);
    let t = std::time::Instant::now();
    progress.stage("simulator", 0);
    let sim_rows = simulator::report(&config.simulator, &out.join(summary::SIMULATOR_DIR))?;
    let simulator_s = timed_stage("simulator", t);
    let header = format!(
        "Made by `neurotac tradeoff{}` in {:.0} s on {} threads (speeds: one thread unless stated).",
        if config.quick { " --quick" } else { "" },
        start.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    let summary =
        summary::summary_markdown(&header, &neuron_rows, &sweep, &sim_rows, &config.simulator);
    write_files(out, &[("tradeoff.md", &summary)])?;
    Ok(TradeoffAll {
        neurons: neuron_rows,
        vr: sweep,
        simulator: sim_rows,
        summary,
        seconds: [neurons_s, vr_s, simulator_s],
    })
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
