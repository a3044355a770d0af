//! `neurotac tradeoff simulator`: writes simulator.csv, simulator.md, simulator.svg and simulator.png.

use crate::commands::args;
use crate::commands::outputs::refuse_existing;
use clap::Args;
use neurotac_cli::tradeoff::simulator::{SimulatorTradeoffConfig, quick, report, to_markdown};
use neurotac_sensor::sim::SimParams;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct SimulatorArgs {
    /// Output folder (created if needed).
    #[arg(long, default_value = "tradeoff")]
    out: PathBuf,
    /// Slides per texture (flat plate and 5 mm grid).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 3)]
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
    /// Replace existing output files (without it, an existing output is refused).
    #[arg(long)]
    force: bool,
}

pub fn run(args: SimulatorArgs) -> anyhow::Result<()> {
    refuse_existing([args.out.join("simulator.csv").as_path()], args.force)?;
    let mut config = SimulatorTradeoffConfig {
        trials: args.trials,
        seed: args.seed,
        params: match &args.params {
            Some(p) => SimParams::from_json_file(p)?,
            None => SimParams::default(),
        },
        ..SimulatorTradeoffConfig::default()
    };
    if args.quick {
        quick(&mut config);
    }
    let start = std::time::Instant::now();
    let rows = report(&config, &args.out)?;
    println!("{}", to_markdown(&rows, &config));
    println!(
        "{} tolerances in {:.1} s → {}/simulator.{{csv,md,svg,png}}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
