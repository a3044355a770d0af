//! `neurotac tradeoff [--out DIR] [--quick]`: runs every trade with its default settings (or
//! the quick ones), writes each trade's files to a sub-folder of DIR and the summary of all of
//! them to DIR/tradeoff.md.

use crate::commands::inputs::load_dataset;
use crate::commands::options::{ForceOption, TradeoffOutOption, help};
use crate::commands::outputs::refuse_existing;
use crate::commands::progress::Bars;
use anyhow::Context;
use clap::Args;
use neurotac_cli::tradeoff::{TradeoffAllConfig, run_all};
use neurotac_core::io::{AtomicFileSet, Replace};
use neurotac_experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(mut_args(help(
    "out",
    "Output folder (created if needed): tradeoff.md and one sub-folder per trade"
)))]
pub struct AllArgs {
    #[command(flatten)]
    out: TradeoffOutOption,
    /// Each trade's quick settings (a few seconds in all) instead of the defaults (about half a
    /// minute).
    #[arg(long)]
    quick: bool,
    #[command(flatten)]
    force: ForceOption,
    /// Spike dataset for the Van Rossum trade (default: a seeded synthetic one, 100 samples of
    /// 49 taxels over 4.5 s, 10 classes; 60 samples with --quick).
    #[arg(long)]
    vr_input: Option<PathBuf>,
}

pub fn run(args: AllArgs) -> anyhow::Result<()> {
    refuse_existing([args.out.out.as_path()], args.force.force)?;
    let config = TradeoffAllConfig::new(args.quick);
    let data = match &args.vr_input {
        Some(path) => load_dataset(path)?,
        None => synthetic_dataset(&SyntheticConfig {
            samples: config.vr.samples.unwrap_or(100),
            classes: 10,
            ..SyntheticConfig::default()
        }),
    };
    let mut files = AtomicFileSet::new(Replace::when(args.force.force));
    let all = run_all(&config, &data, &args.out.out, &mut files, &Bars::new())?;
    files.commit().context("writing the trade-off files")?;
    println!("{}", all.summary);
    println!("wrote {}", args.out.out.join("tradeoff.md").display());
    Ok(())
}
