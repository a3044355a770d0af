//! `neurotac tradeoff simulator`: writes simulator.csv, simulator.md, simulator.svg and simulator.png.

use crate::commands::args;
use crate::commands::options::{ForceOption, SeedOption, TradeoffOutOption};
use crate::commands::outputs::{Output, check_outputs};
use anyhow::Context;
use clap::Args;
use neurotac_cli::tradeoff::simulator::{SimulatorTradeoffConfig, quick, report, to_markdown};
use neurotac_cli::tradeoff::trade_files;
use neurotac_core::io::{AtomicFileSet, Replace};
use neurotac_sensor::sim::SimParams;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct SimulatorArgs {
    #[command(flatten)]
    out: TradeoffOutOption,
    /// Slides per texture (flat plate and 5 mm grid).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 3)]
    trials: usize,
    #[command(flatten)]
    seed: SeedOption,
    /// Simulator parameter file (JSON).
    #[arg(long)]
    params: Option<PathBuf>,
    /// One slide per texture and three tolerances (a few seconds).
    #[arg(long)]
    quick: bool,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run(args: SimulatorArgs) -> anyhow::Result<()> {
    let outputs = trade_files(&args.out.out, "simulator");
    check_outputs(
        Output::folder_with_files("--out", &args.out.out, &outputs),
        args.force.force,
    )?;
    let mut config = SimulatorTradeoffConfig {
        trials: args.trials,
        seed: args.seed.seed,
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
    let mut files = AtomicFileSet::new(Replace::when(args.force.force));
    let rows = report(&config, &args.out.out, &mut files)?;
    files.commit().context("writing the trade's files")?;
    println!("{}", to_markdown(&rows, &config));
    println!(
        "{} tolerances in {:.1} s → {}/simulator.{{csv,md,svg,png}}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        args.out.out.display()
    );
    Ok(())
}
