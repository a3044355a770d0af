//! The paper's pipeline from Rust code: simulate the artificial texture set (bump grids 0–5 mm),
//! transduce it to taxel spikes, run the four codings (with the Δt sweep and the Bayesian
//! optimisation of τ, cos θ) through KNN, and write the report folder. A small configuration
//! (a few slides per grid, 20 epochs): its numbers are not comparable with the paper's; use
//! `ReproduceConfig::paper` for the real run.
//!
//! Run with `cargo run --release --example reproduce_pipeline`.

use neurotac::experiments::datasets::simulated::TextureSet;
use neurotac::experiments::progress::NoProgress;
use neurotac::experiments::reproduce::{self, Report, ReproduceConfig, ReproduceError, Source};
use std::path::Path;

/// The pipeline on `trials` slides per grid, simulated datasets cached in `cache`.
pub fn run(trials: usize, cache: &Path) -> Result<Report, ReproduceError> {
    let mut config = ReproduceConfig::quick(1, cache.to_owned());
    config.trials = Some(trials);
    config.pipeline.bayes.epochs = 20;
    let artificial = [Source::Simulated(TextureSet::Artificial)];
    reproduce::run(
        &config,
        &artificial,
        &NoProgress,
        &neurotac_core::OneProcess,
    )
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let report = run(4, &std::env::temp_dir().join("neurotac-example-cache"))?;
    let out = Path::new("neurotac-example-report");
    neurotac_cli::report::write_report(out, &report, true)?;
    println!(
        "{}",
        neurotac_cli::report::tables::accuracy_table(&report.sets[0])
    );
    println!("report: {}", out.display());
    Ok(())
}
