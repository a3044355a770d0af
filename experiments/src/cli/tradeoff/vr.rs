//! `neurotac tradeoff vr`: the trace-sampled Van Rossum distance (traces advanced at step dt by
//! the graph's synapse filter) against the exact one, as dt shrinks.

use crate::cli::common::{duration_ms, load, timed};
use anyhow::Context;
use clap::Args;
use neurotac_core::distance::{VanRossum, check_cos, trace_sampled_matrices};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct VrArgs {
    /// Spike dataset (JSON or binary).
    #[arg(long)]
    input: PathBuf,
    /// Kernel time constant τ (s).
    #[arg(long, default_value_t = 0.076)]
    tau: f64,
    /// cos θ in [0, 1].
    #[arg(long, default_value_t = 0.4)]
    cos: f64,
    /// Time steps to try (s), comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.01,0.005,0.002,0.001,0.0005"
    )]
    dts: Vec<f64>,
    /// Use only the first N samples (the sampled matrices cost N²·steps).
    #[arg(long, default_value_t = 100)]
    samples: usize,
    /// Sample duration (s, whole ms); default: meta.duration_s, else one ms past the latest spike.
    #[arg(long)]
    duration: Option<f64>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: VrArgs) -> anyhow::Result<()> {
    let data = load(&args.input)?;
    check_cos(args.cos)?;
    let obs = &data.observations()[..args.samples.min(data.len())];
    let n = obs.len();
    anyhow::ensure!(n >= 2, "need at least 2 samples, have {n}");
    let duration_s = duration_ms(&data, args.duration)? as f64 / 1e3;
    let (exact, exact_time) = timed(|| -> anyhow::Result<_> {
        Ok(VanRossum::new(args.tau)?.matrices(obs)?.squared(args.cos)?)
    });
    let exact = exact?;
    let mut rows = Vec::new();
    for &dt in &args.dts {
        let (sampled, time) = timed(|| -> anyhow::Result<_> {
            Ok(trace_sampled_matrices(obs, args.tau, dt, duration_s)?.squared(args.cos)?)
        });
        let sampled = sampled.with_context(|| format!("dt = {dt} s"))?;
        let (mut max_rel, mut sum_rel, mut pairs) = (0.0f64, 0.0, 0usize);
        for i in 0..n {
            for j in i + 1..n {
                let (e, s) = (exact[[i, j]].sqrt(), sampled[[i, j]].sqrt());
                if e > 0.0 {
                    let rel = (s - e).abs() / e;
                    max_rel = max_rel.max(rel);
                    sum_rel += rel;
                    pairs += 1;
                }
            }
        }
        let mean_rel = if pairs > 0 {
            sum_rel / pairs as f64
        } else {
            0.0
        };
        rows.push((dt, time, mean_rel, max_rel));
    }
    if args.json {
        let out = serde_json::json!({
            "samples": n, "tau_s": args.tau, "cos": args.cos,
            "exact": exact_time,
            "sampled": rows.iter().map(|(dt, t, mean, max)| serde_json::json!({
                "dt_s": dt, "timing": t, "mean_relative_error": mean, "max_relative_error": max
            })).collect::<Vec<_>>(),
        });
        println!("{out}");
        return Ok(());
    }
    println!(
        "trace-sampled vs exact Van Rossum distance, {n} samples, τ = {} s, cos θ = {}",
        args.tau, args.cos
    );
    println!("  exact (markage)           {exact_time}");
    println!(
        "  {:>9}  {:>14}  {:>14}  time",
        "dt (s)", "mean rel. err", "max rel. err"
    );
    for (dt, time, mean, max) in rows {
        println!("  {dt:>9}  {mean:>14.3e}  {max:>14.3e}  {time}");
    }
    Ok(())
}
