//! Reading the commands' spike datasets: one error naming the file, and the labels checked
//! where a command needs them.

use neurotac_core::SpikeDataset;
use std::path::Path;

/// Reads a spike dataset (JSON or binary); the error names the file once.
pub fn load_dataset(path: &Path) -> anyhow::Result<SpikeDataset> {
    // The dataset error names file, sample and field; its source chain would repeat it.
    SpikeDataset::load(path)
        .map_err(|e| anyhow::anyhow!("reading the spike dataset {}: {e}", path.display()))
}

/// Reads a labelled spike dataset (classification and searches need labels).
pub fn load_labelled(path: &Path) -> anyhow::Result<SpikeDataset> {
    let data = load_dataset(path)?;
    if data.labels().is_empty() {
        anyhow::bail!("{}: the dataset has no labels", path.display());
    }
    Ok(data)
}
