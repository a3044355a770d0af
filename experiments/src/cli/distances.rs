//! `neurotac distances`: the N×N distance matrix of a spike dataset, as `{"matrix": [[…]]}`.

use super::common::{
    CodingArg, feature_distances, load, mean_spikes_per_unit, timed, van_rossum_distances,
};
use anyhow::{Context, bail};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Metric {
    /// Exact multi-unit Van Rossum (needs --tau and --cos).
    VanRossum,
    /// Euclidean distance of a coding's features (needs --coding).
    Euclidean,
}

#[derive(Debug, Args)]
pub struct DistancesArgs {
    /// Spike dataset (JSON or binary).
    #[arg(long)]
    input: PathBuf,
    /// Distance.
    #[arg(long, value_enum)]
    metric: Metric,
    /// Van Rossum kernel time constant τ (s).
    #[arg(long)]
    tau: Option<f64>,
    /// Van Rossum cos θ in [0, 1] (0 labelled line, 1 summed population).
    #[arg(long)]
    cos: Option<f64>,
    /// Coding whose features the Euclidean distance compares.
    #[arg(long, value_enum)]
    coding: Option<CodingArg>,
    /// Temporal-coding window Δt (s, whole ms).
    #[arg(long)]
    dt: Option<f64>,
    /// Sample duration (s, whole ms); default: meta.duration_s, else one ms past the latest spike.
    #[arg(long)]
    duration: Option<f64>,
    /// Output JSON file.
    #[arg(long)]
    output: PathBuf,
}

pub fn run(args: DistancesArgs) -> anyhow::Result<()> {
    neurotac_core::io::check_distinct(&args.input, &args.output)?;
    let data = load(&args.input)?;
    let (matrix, timing) = timed(|| match args.metric {
        Metric::VanRossum => van_rossum_distances(&data, args.tau, args.cos),
        Metric::Euclidean => match args.coding {
            None => bail!("--metric euclidean needs --coding intensive|spatial|temporal"),
            Some(coding) => feature_distances(&data, coding, args.dt, args.duration),
        },
    });
    let matrix = matrix?;
    let rows: Vec<Vec<f64>> = matrix.outer_iter().map(|r| r.to_vec()).collect();
    let text = serde_json::to_string(&serde_json::json!({ "matrix": rows }))?;
    neurotac_core::io::write(&args.output, text)
        .with_context(|| format!("writing {}", args.output.display()))?;
    let n = data.len();
    println!(
        "{n}×{n} {:?} distance matrix of {} channels (mean {:.1} spikes/channel) → {} in {timing}",
        args.metric,
        data.n_channels(),
        mean_spikes_per_unit(&data),
        args.output.display()
    );
    Ok(())
}
