//! `neurotac search dt`: the temporal coding's Δt brute force.

use crate::commands::args::{self, Time};
use crate::commands::coding_parameters::whole_duration_s;
use crate::commands::inputs::load_labelled;
use clap::Args;
use neurotac_core::{Knn, Ranks};
use neurotac_experiments::coding::sample_duration_ms;
use neurotac_experiments::search::dt_sweep::dt_sweep;
use neurotac_experiments::timing::timed;
use std::path::PathBuf;

/// CPU seconds of the NumPy + scikit-learn sweep (1…200 ms, LOO, 1100 samples × 49 taxels,
/// ~10 spikes/taxel) measured for the spec on a 2-core machine; not measured here.
const NUMPY_ANCHOR_CPU_S: f64 = 47.8;

#[derive(Debug, Args)]
pub struct DtArgs {
    /// Spike dataset (JSON or binary), labelled.
    #[arg(long)]
    input: PathBuf,
    /// Largest window Δt, a whole number of ms (ms, or with a unit: 20ms, 0.02s); windows
    /// 1 ms, 2 ms, …, this.
    #[arg(value_parser = args::time_window, allow_negative_numbers = true, long, alias = "max-window-ms", default_value = "200ms")]
    max_window: Time,
    /// Neighbours.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 4)]
    k: usize,
    /// Sample duration, a whole number of ms (ms, or with a unit: 20ms, 0.02s); default:
    /// meta.duration_s, else one ms past the latest spike.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long)]
    duration: Option<Time>,
    /// Print one JSON object (with the accuracy at every Δt) instead of text.
    #[arg(long)]
    json: bool,
}

/// On several ranks the pairs of samples are split over them ([`dt_sweep`]); rank 0 alone
/// prints.
pub fn run(args: DtArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    let data = load_labelled(&args.input)?;
    let max_window_ms = args.max_window.whole_ms("--max-window")?;
    let t = sample_duration_ms(&data, whole_duration_s(args.duration)?)?;
    let knn = Knn::new(args.k)?;
    let (sweep, timing) = timed(|| {
        dt_sweep(
            data.observations(),
            data.labels(),
            t,
            max_window_ms,
            knn,
            ranks,
        )
    });
    let sweep = sweep?;
    if !ranks.is_root() {
        return Ok(());
    }
    if args.json {
        println!(
            "{}",
            serde_json::json!({ "duration_ms": t, "sweep": sweep, "timing": timing })
        );
        return Ok(());
    }
    let b = sweep.best;
    println!(
        "Δt sweep 1…{} ms over {} samples (T = {t} ms), leave-one-out k = {}: best Δt = {} ms, accuracy {:.1} ± {:.1} % (Wilson 95 % [{:.1}, {:.1}] %)",
        max_window_ms,
        data.len(),
        args.k,
        sweep.best_window_ms,
        100.0 * b.mean,
        100.0 * b.std,
        100.0 * b.wilson_low,
        100.0 * b.wilson_high
    );
    println!("time: {timing}");
    // The anchor is a measurement of one case (1100 samples, Δt = 1…200 ms): a ratio against any
    // other case would compare unlike work, so it is printed for that case only.
    let like_anchor = data.len() == 1100 && max_window_ms == 200;
    if let Some(cpu) = timing.cpu_s.filter(|c| like_anchor && *c > 0.0) {
        println!(
            "vs the spec's measured NumPy/scikit-learn anchor ({NUMPY_ANCHOR_CPU_S} s CPU for 1100 samples, 200 windows; not run here): {:.1}× less CPU",
            NUMPY_ANCHOR_CPU_S / cpu
        );
    }
    Ok(())
}
