//! `neurotac export`: a spike dataset (JSON or binary) into another form, chosen by the
//! output's extension — `.npz` for numpy (flat arrays, see `neurotac_experiments::export`),
//! `.json` or `.bin`.

use super::inputs::load_dataset;
use super::options::{ForceOption, help};
use super::outputs::{Output, check_outputs};
use clap::Args;
use neurotac_experiments::export::{DATASET_FORMATS, OutputFormat, Replace, write_dataset};
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(mut_args(help("force", "Replace an existing output file")))]
pub struct ExportArgs {
    /// Spike dataset to read (JSON or binary).
    dataset: PathBuf,
    /// Output file, format by extension: `.npz` (numpy: `times`, `units`, `offsets`, `labels`,
    /// `meta.json`), `.json` or `.bin`.
    out: PathBuf,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    neurotac_core::io::check_distinct(&args.dataset, &args.out)?;
    OutputFormat::from_path(&args.out, &DATASET_FORMATS)?;
    check_outputs([Output::file("OUT", &args.out)], args.force.force)?;
    let data = load_dataset(&args.dataset)?;
    write_dataset(&data, &args.out, Replace::when(args.force.force))?;
    let spikes: usize = data.observations().iter().map(|o| o.total_spikes()).sum();
    println!(
        "{} samples × {} units, {spikes} spikes → {}",
        data.len(),
        data.n_channels(),
        args.out.display()
    );
    Ok(())
}
