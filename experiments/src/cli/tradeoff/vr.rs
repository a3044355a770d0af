//! `neurotac tradeoff vr`: the trace-sampled Van Rossum distance (traces advanced at step dt by
//! the graph's synapse filter) against the exact one, as dt shrinks.

use crate::cli::args;
use crate::cli::load_dataset;
use clap::Args;
use neurotac_experiments::tradeoff::vr::{VrTradeoffConfig, measure};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct VrArgs {
    /// Spike dataset (JSON or binary).
    #[arg(long)]
    input: PathBuf,
    /// Kernel time constant τ (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 0.076)]
    tau: f64,
    /// cos θ in [0, 1].
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long, default_value_t = 0.4)]
    cos: f64,
    /// Time steps to try (s), comma-separated.
    #[arg(
        value_parser = args::positive_f64, allow_negative_numbers = true,
        long,
        value_delimiter = ',',
        default_value = "0.01,0.005,0.002,0.001,0.0005"
    )]
    dts: Vec<f64>,
    /// Use only the first N samples (the sampled matrices cost N²·steps).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 100)]
    samples: usize,
    /// Sample duration (s, whole ms); default: meta.duration_s, else one ms past the latest spike.
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long)]
    duration: Option<f64>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: VrArgs) -> anyhow::Result<()> {
    let data = load_dataset(&args.input)?;
    let config = VrTradeoffConfig {
        tau_s: args.tau,
        cos: args.cos,
        dts_s: args.dts.clone(),
        samples: args.samples,
    };
    let sweep = measure(&data, args.duration, &config)?;
    if args.json {
        let out = serde_json::json!({
            "samples": sweep.samples, "tau_s": sweep.tau_s, "cos": sweep.cos,
            "exact": sweep.exact,
            "sampled": sweep.rows.iter().map(|r| serde_json::json!({
                "dt_s": r.dt_s, "timing": r.timing,
                "mean_relative_error": r.mean_relative_error,
                "max_relative_error": r.max_relative_error
            })).collect::<Vec<_>>(),
        });
        println!("{out}");
        return Ok(());
    }
    println!(
        "trace-sampled vs exact Van Rossum distance, {} samples, τ = {} s, cos θ = {}",
        sweep.samples, sweep.tau_s, sweep.cos
    );
    println!("  exact (markage)           {}", sweep.exact);
    println!(
        "  {:>9}  {:>14}  {:>14}  time",
        "dt (s)", "mean rel. err", "max rel. err"
    );
    for r in &sweep.rows {
        println!(
            "  {:>9}  {:>14.3e}  {:>14.3e}  {}",
            r.dt_s, r.mean_relative_error, r.max_relative_error, r.timing
        );
    }
    Ok(())
}
