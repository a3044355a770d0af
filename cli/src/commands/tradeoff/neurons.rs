//! `neurotac tradeoff neurons`: writes neurons.csv, neurons.md, neurons.svg and neurons.png.

use crate::commands::args::{self, Time};
use crate::commands::options::{ForceOption, TradeoffOutOption};
use crate::commands::outputs::{Output, check_outputs};
use anyhow::Context;
use clap::Args;
use neurotac_cli::tradeoff::neurons::{NeuronTradeoffConfig, quick, report, to_markdown};
use neurotac_cli::tradeoff::trade_files;
use neurotac_core::io::{AtomicFileSet, Replace};

#[derive(Debug, Args)]
pub struct NeuronsArgs {
    #[command(flatten)]
    out: TradeoffOutOption,
    /// Simulated time of each accuracy run (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "1s")]
    duration: Time,
    /// Fewer time steps and smaller speed runs (a few seconds).
    #[arg(long)]
    quick: bool,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run(args: NeuronsArgs) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    let mut config = NeuronTradeoffConfig {
        duration_s: args.duration.s(),
        ..NeuronTradeoffConfig::default()
    };
    if args.quick {
        quick(&mut config);
    }
    let outputs = trade_files(&args.out.out, "neurons");
    check_outputs(
        Output::folder_with_files("--out", &args.out.out, &outputs),
        args.force.force,
    )?;
    let mut files = AtomicFileSet::new(Replace::when(args.force.force));
    let rows = report(&config, &args.out.out, &mut files)?;
    files.commit().context("writing the trade's files")?;
    let markdown = to_markdown(&rows, config.speed_neurons);
    let front_end = markdown.find("\n## Every point").unwrap_or(markdown.len());
    println!("{}", &markdown[..front_end]);
    println!(
        "{} points in {:.1} s → {}/neurons.{{csv,md,svg,png}}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        args.out.out.display()
    );
    Ok(())
}
