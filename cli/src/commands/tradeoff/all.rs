//! `neurotac tradeoff [--out DIR] [--quick]`: runs every trade with its default settings (or
//! the quick ones), writes each trade's files to a sub-folder of DIR and the summary of all of
//! them to DIR/tradeoff.md.

use crate::commands::inputs::load_dataset;
use crate::commands::outputs::refuse_existing;
use crate::commands::progress::Bars;
use clap::Args;
use neurotac_cli::tradeoff::{TradeoffAllConfig, run_all};
use neurotac_experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct AllArgs {
    /// Output folder (created if needed): tradeoff.md and one sub-folder per trade.
    #[arg(long, default_value = "tradeoff")]
    out: PathBuf,
    /// Each trade's quick settings (a few seconds in all) instead of the defaults (about half a
    /// minute).
    #[arg(long)]
    quick: bool,
    /// Replace existing output files (without it, an existing output is refused).
    #[arg(long)]
    force: bool,
    /// Spike dataset for the Van Rossum trade (default: a seeded synthetic one, 100 samples of
    /// 49 taxels over 4.5 s, 10 classes; 60 samples with --quick).
    #[arg(long)]
    vr_input: Option<PathBuf>,
}

pub fn run(args: AllArgs) -> anyhow::Result<()> {
    refuse_existing([args.out.as_path()], args.force)?;
    let config = TradeoffAllConfig::new(args.quick);
    let data = match &args.vr_input {
        Some(path) => load_dataset(path)?,
        None => synthetic_dataset(&SyntheticConfig {
            samples: config.vr.samples.unwrap_or(100),
            classes: 10,
            ..SyntheticConfig::default()
        }),
    };
    let all = run_all(&config, &data, &args.out, &Bars::new())?;
    println!("{}", all.summary);
    println!("wrote {}", args.out.join("tradeoff.md").display());
    Ok(())
}
