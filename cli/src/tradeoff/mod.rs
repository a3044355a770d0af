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
//! To add a trade: a module with a config, a measuring function, its rows' `COLUMNS` and one
//! `cells(row)` building one [`Table`] for `to_csv`, `to_markdown` and `pareto_table` (a
//! [`Column`] or a [`Cell`] where the CSV and the Markdown table differ), `to_svg` built on
//! [`error_series`], a `report` that measures and writes, and a section in [`summary`].

mod error;
pub mod neurons;
pub mod pareto;
pub mod simulator;
pub mod summary;
mod table;
pub mod vr;

pub use error::TradeoffError;
pub use table::{
    Cell, Column, Table, error_series, mark_front, trade_files, write_files, write_trade,
};

use neurotac_core::io::AtomicFileSet;
use neurotac_experiments::progress::Progress;
use std::path::Path;

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

/// Runs every trade (`data`: the Van Rossum trade's spike dataset) and adds to `files` each
/// one's files in its sub-folder of `out` and the summary `out/tradeoff.md`, committed by the
/// caller; `progress` gets one stage and one note (`neurons: 1.2 s`) per trade.
pub fn run_all(
    config: &TradeoffAllConfig,
    data: &neurotac_core::SpikeDataset,
    out: &Path,
    files: &mut AtomicFileSet,
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
    let neuron_rows = neurons::report(&config.neurons, &out.join(summary::NEURONS_DIR), files)?;
    let neurons_s = timed_stage("neurons", t);
    let t = std::time::Instant::now();
    progress.stage("vr", 0);
    let sweep = vr::report(data, &config.vr, &out.join(summary::VR_DIR), files)?;
    let vr_s = timed_stage("vr", t);
    let t = std::time::Instant::now();
    progress.stage("simulator", 0);
    let sim_rows = simulator::report(&config.simulator, &out.join(summary::SIMULATOR_DIR), files)?;
    let simulator_s = timed_stage("simulator", t);
    let header = format!(
        "Made by `neurotac tradeoff{}` in {:.0} s on {} threads (speeds: one thread unless stated).",
        if config.quick { " --quick" } else { "" },
        start.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    let summary =
        summary::summary_markdown(&header, &neuron_rows, &sweep, &sim_rows, &config.simulator);
    write_files(files, out, &[("tradeoff.md", &summary)])?;
    Ok(TradeoffAll {
        neurons: neuron_rows,
        vr: sweep,
        simulator: sim_rows,
        summary,
        seconds: [neurons_s, vr_s, simulator_s],
    })
}
