//! `neurotac tradeoff simulator`: writes simulator.csv, simulator.md and simulator.svg.

use super::write_files;
use clap::Args;
use neurotac_experiments::simulator_tradeoff::{
    SimulatorTradeoffConfig, SimulatorTradeoffRow, simulator_tradeoff, to_csv, to_markdown, to_svg,
};
use neurotac_sensor::sim::SimParams;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct SimulatorArgs {
    /// Output folder (created if needed).
    #[arg(long, default_value = "tradeoff")]
    out: PathBuf,
    /// Slides per texture (flat plate and 5 mm grid).
    #[arg(long, default_value_t = 3)]
    trials: usize,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Simulator parameter file (JSON).
    #[arg(long)]
    params: Option<PathBuf>,
    /// One slide per texture and three tolerances (a few seconds).
    #[arg(long)]
    quick: bool,
}

/// The sweep's settings: `config` as given, or its quick version.
pub fn config(base: SimulatorTradeoffConfig, quick: bool) -> SimulatorTradeoffConfig {
    if quick {
        SimulatorTradeoffConfig {
            trials: 1,
            tolerances: vec![0.02, 0.067, 0.2],
            ..base
        }
    } else {
        base
    }
}

/// Measures the sweep and writes `simulator.{csv,md,svg}` to `out`.
pub fn report(
    config: &SimulatorTradeoffConfig,
    out: &Path,
) -> anyhow::Result<Vec<SimulatorTradeoffRow>> {
    let rows = simulator_tradeoff(config)?;
    write_files(
        out,
        &[
            ("simulator.csv", to_csv(&rows)),
            ("simulator.md", to_markdown(&rows, config)),
            ("simulator.svg", to_svg(&rows)),
        ],
    )?;
    Ok(rows)
}

pub fn run(args: SimulatorArgs) -> anyhow::Result<()> {
    let base = SimulatorTradeoffConfig {
        trials: args.trials,
        seed: args.seed,
        params: match &args.params {
            Some(p) => SimParams::from_json_file(p)?,
            None => SimParams::default(),
        },
        ..SimulatorTradeoffConfig::default()
    };
    let config = config(base, args.quick);
    let start = std::time::Instant::now();
    let rows = report(&config, &args.out)?;
    println!("{}", to_markdown(&rows, &config));
    println!(
        "{} tolerances in {:.1} s → {}/simulator.{{csv,md,svg}}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
