//! `neurotac tradeoff simulator`: writes simulator.csv and simulator.md.

use anyhow::Context;
use clap::Args;
use neurotac_experiments::simulator_tradeoff::{
    SimulatorTradeoffConfig, simulator_tradeoff, to_csv, to_markdown,
};
use neurotac_sensor::sim::SimParams;
use std::path::PathBuf;

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

pub fn run(args: SimulatorArgs) -> anyhow::Result<()> {
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
        config.trials = 1;
        config.tolerances = vec![0.02, 0.067, 0.2];
    }
    let start = std::time::Instant::now();
    let rows = simulator_tradeoff(&config)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let markdown = to_markdown(&rows, &config);
    for (name, text) in [
        ("simulator.csv", to_csv(&rows)),
        ("simulator.md", markdown.clone()),
    ] {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    println!("{markdown}");
    println!(
        "{} tolerances in {:.1} s → {}/simulator.{{csv,md}}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
