//! `neurotac tradeoff [--out DIR] [--quick]`: runs every trade with its default settings (or
//! the quick ones), writes each trade's files to a sub-folder of DIR and the summary of all of
//! them to DIR/tradeoff.md.

use super::{neurons, simulator, vr, write_files};
use crate::cli::common::load;
use clap::Args;
use neurotac_experiments::simulator_tradeoff::SimulatorTradeoffConfig;
use neurotac_experiments::synthetic::{SyntheticConfig, synthetic_dataset};
use neurotac_experiments::tradeoff_summary::{
    NEURONS_DIR, SIMULATOR_DIR, VR_DIR, summary_markdown,
};
use neurotac_experiments::vr_tradeoff::VrTradeoffConfig;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct AllArgs {
    /// Output folder (created if needed): tradeoff.md and one sub-folder per trade.
    #[arg(long, default_value = "tradeoff")]
    out: PathBuf,
    /// Each trade's quick settings (a few seconds in all) instead of the defaults (about half a
    /// minute).
    #[arg(long)]
    quick: bool,
    /// Spike dataset for the Van Rossum trade (default: a seeded synthetic one, 100 samples of
    /// 49 taxels over 4.5 s; 30 with --quick).
    #[arg(long)]
    vr_input: Option<PathBuf>,
}

pub fn run(args: AllArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let step = |name: &str, since: Instant| {
        eprintln!("{name}: {:.1} s", since.elapsed().as_secs_f64());
    };

    let t = Instant::now();
    let neuron_rows = neurons::report(1.0, args.quick, &args.out.join(NEURONS_DIR))?;
    step("neurons", t);

    let t = Instant::now();
    let mut vr_config = VrTradeoffConfig::default();
    if args.quick {
        vr_config.samples = 30;
        vr_config.dts_s = vec![0.01, 0.005, 0.002];
    }
    let data = match &args.vr_input {
        Some(path) => load(path)?,
        None => synthetic_dataset(&SyntheticConfig {
            samples: vr_config.samples,
            classes: 10,
            ..SyntheticConfig::default()
        }),
    };
    let sweep = vr::measure(&data, None, &vr_config)?;
    vr::write_report(&sweep, &args.out.join(VR_DIR))?;
    step("vr", t);

    let t = Instant::now();
    let sim_config = simulator::config(SimulatorTradeoffConfig::default(), args.quick);
    let sim_rows = simulator::report(&sim_config, &args.out.join(SIMULATOR_DIR))?;
    step("simulator", t);

    let header = format!(
        "Made by `neurotac tradeoff{}` in {:.0} s on {} threads (speeds: one thread unless stated).",
        if args.quick { " --quick" } else { "" },
        start.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    let summary = summary_markdown(&header, &neuron_rows, &sweep, &sim_rows, &sim_config);
    write_files(&args.out, &[("tradeoff.md", summary.clone())])?;
    println!("{summary}");
    println!("wrote {}", args.out.join("tradeoff.md").display());
    Ok(())
}
