//! `neurotac synth`: writes a seeded synthetic NeuroTac-like texture dataset.

use super::options::{ForceOption, SeedOption};
use super::outputs::{Output, check_outputs};
use crate::commands::args::{self, Time};
use clap::Args;
use neurotac_experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct SynthArgs {
    /// Output file, format by extension: `.json`, `.bin` (or `.ntspk`, compact binary) or
    /// `.npz` (numpy arrays).
    #[arg(long)]
    output: PathBuf,
    /// Number of samples.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 1100)]
    samples: usize,
    /// Number of classes (textures).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 11)]
    classes: usize,
    /// Channels (taxels) per sample.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 49)]
    channels: usize,
    /// Mean spikes per channel.
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 10.0)]
    spikes_per_unit: f64,
    /// Sample duration (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "4.5s")]
    duration: Time,
    #[command(flatten)]
    seed: SeedOption,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run(args: SynthArgs) -> anyhow::Result<()> {
    neurotac_experiments::export::OutputFormat::from_path(
        &args.output,
        &neurotac_experiments::export::DATASET_FORMATS,
    )?;
    check_outputs([Output::file("--output", &args.output)], args.force.force)?;
    let config = SyntheticConfig {
        samples: args.samples,
        classes: args.classes,
        channels: args.channels,
        spikes_per_unit: args.spikes_per_unit,
        duration_s: args.duration.s(),
        seed: args.seed.seed,
    };
    config.check()?;
    let data = synthetic_dataset(&config);
    neurotac_experiments::export::write_dataset(
        &data,
        &args.output,
        neurotac_experiments::export::Replace::when(args.force.force),
    )?;
    println!(
        "{} samples × {} channels, {} classes → {}",
        data.len(),
        data.n_channels(),
        data.n_classes(),
        args.output.display()
    );
    Ok(())
}
