//! `neurotac distances`: the N×N distance matrix of a spike dataset, as JSON
//! (`{"matrix": [[…]]}`), `.npy` or `.npz` by the output's extension.

use super::coding_parameters::coding_parameters;
use super::inputs::load_dataset;
use super::options::ForceOption;
use super::outputs::{Output, check_outputs};
use crate::commands::args::{self, Time};
use anyhow::bail;
use clap::{Args, ValueEnum};
use neurotac_core::Ranks;
use neurotac_experiments::coding::{CodingName, coding_distances, mean_spikes_per_channel};
use neurotac_experiments::export::{MATRIX_FORMATS, OutputFormat, Replace, write_matrix};
use neurotac_experiments::menu::Menu;
use neurotac_experiments::timing::timed;
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
    /// Van Rossum kernel time constant τ (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_tau, allow_negative_numbers = true, long)]
    tau: Option<Time>,
    /// Van Rossum cos θ in [0, 1] (0 labelled line, 1 summed population).
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long)]
    cos: Option<f64>,
    /// Coding whose features the Euclidean distance compares.
    #[arg(long, value_parser = args::menu::<CodingName>())]
    coding: Option<CodingName>,
    /// Temporal-coding window Δt, a whole number of ms (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_window, allow_negative_numbers = true, long)]
    dt: Option<Time>,
    /// Sample duration, a whole number of ms (ms, or with a unit: 20ms, 0.02s); default:
    /// meta.duration_s, else one ms past the latest spike.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long)]
    duration: Option<Time>,
    /// Output file, format by extension: `.json` ({"matrix": [[…]]}), `.npy` (float64 N×N)
    /// or `.npz` (member `matrix`).
    #[arg(long)]
    output: PathBuf,
    #[command(flatten)]
    force: ForceOption,
}

/// On several ranks the matrix's rows are split over them ([`coding_distances`]); every
/// rank checks the output path first, rank 0 alone writes the matrix and prints.
pub fn run(args: DistancesArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    neurotac_core::io::check_distinct(&args.input, &args.output)?;
    OutputFormat::from_path(&args.output, &MATRIX_FORMATS)?;
    check_outputs([Output::file("--output", &args.output)], args.force.force)?;
    let data = load_dataset(&args.input)?;
    let coding = match (args.metric, args.coding) {
        (Metric::VanRossum, _) => CodingName::Spatiotemporal,
        (Metric::Euclidean, None | Some(CodingName::Spatiotemporal)) => {
            let euclidean: Vec<&str> = (CodingName::ALL.iter())
                .filter(|&&c| c != CodingName::Spatiotemporal)
                .map(|c| c.key())
                .collect();
            bail!("--metric euclidean needs --coding {}", euclidean.join("|"))
        }
        (Metric::Euclidean, Some(coding)) => coding,
    };
    let parameters = coding_parameters(&data, args.dt, args.duration, args.tau, args.cos)?;
    let (matrix, timing) =
        timed(|| coding_distances(data.observations(), coding, &parameters, ranks));
    let matrix = matrix?;
    if !ranks.is_root() {
        return Ok(());
    }
    write_matrix(&args.output, matrix.view(), Replace::when(args.force.force))?;
    let n = data.len();
    println!(
        "{n}×{n} {:?} distance matrix of {} channels (mean {:.1} spikes/channel) → {} in {timing}",
        args.metric,
        data.n_channels(),
        mean_spikes_per_channel(&data),
        args.output.display()
    );
    Ok(())
}
