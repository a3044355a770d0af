//! `neurotac tradeoff neurons`: writes neurons.csv, neurons.md and neurons.svg.

use super::write_files;
use clap::Args;
use neurotac_experiments::neuron_tradeoff::{
    NeuronTradeoffConfig, NeuronTradeoffRow, neuron_tradeoff, to_csv, to_markdown, to_svg,
};
use std::path::{Path, PathBuf};

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

/// Measures the sweep of `--duration` and `--quick` and writes `neurons.{csv,md,svg}` to `out`.
pub fn report(duration: f64, quick: bool, out: &Path) -> anyhow::Result<Vec<NeuronTradeoffRow>> {
    if !(duration.is_finite() && duration > 0.0) {
        anyhow::bail!("--duration {duration} must be finite and > 0");
    }
    let mut config = NeuronTradeoffConfig {
        duration_s: duration,
        ..NeuronTradeoffConfig::default()
    };
    if quick {
        config.dts_s = vec![1e-5, 1e-4, 1e-3];
        config.speed_neurons = 20_000;
    }
    let rows = neuron_tradeoff(&config)?;
    write_files(
        out,
        &[
            ("neurons.csv", to_csv(&rows)),
            ("neurons.md", to_markdown(&rows, config.speed_neurons)),
            ("neurons.svg", to_svg(&rows)),
        ],
    )?;
    Ok(rows)
}

pub fn run(args: NeuronsArgs) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    let rows = report(args.duration, args.quick, &args.out)?;
    let markdown = std::fs::read_to_string(args.out.join("neurons.md"))?;
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
