//! `neurotac tradeoff neurons`: writes neurons.csv, neurons.md and neurons.svg.

use anyhow::Context;
use clap::Args;
use neurotac_experiments::neuron_tradeoff::{
    NeuronTradeoffConfig, neuron_tradeoff, to_csv, to_markdown, to_svg,
};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct NeuronsArgs {
    /// Output folder (created if needed).
    #[arg(long, default_value = "tradeoff")]
    out: PathBuf,
    /// Simulated time of each accuracy run (s).
    #[arg(long, default_value_t = 1.0)]
    duration: f64,
    /// Fewer time steps and smaller speed runs (a few seconds).
    #[arg(long)]
    quick: bool,
}

pub fn run(args: NeuronsArgs) -> anyhow::Result<()> {
    let mut config = NeuronTradeoffConfig {
        duration_s: args.duration,
        ..NeuronTradeoffConfig::default()
    };
    if !(args.duration.is_finite() && args.duration > 0.0) {
        anyhow::bail!("--duration {} must be finite and > 0", args.duration);
    }
    if args.quick {
        config.dts_s = vec![1e-5, 1e-4, 1e-3];
        config.speed_neurons = 20_000;
    }
    let start = std::time::Instant::now();
    let rows = neuron_tradeoff(&config)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let write = |name: &str, text: String| {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
    };
    let markdown = to_markdown(&rows);
    write("neurons.csv", to_csv(&rows))?;
    write("neurons.md", markdown.clone())?;
    write("neurons.svg", to_svg(&rows))?;
    let front_end = markdown.find("\n## Every point").unwrap_or(markdown.len());
    println!("{}", &markdown[..front_end]);
    println!(
        "{} points in {:.1} s → {}/neurons.{{csv,md,svg}}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
