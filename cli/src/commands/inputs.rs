//! Reading the commands' spike datasets: one error naming the file, and the labels checked
//! where a command needs them.

use neurotac_core::SpikeDataset;
use std::path::Path;

/// Reads a spike dataset (JSON or binary); the error names the file once and keeps its causes
/// (`{:#}` prints them on one line): where in the file, which observation, channel and spike, and
/// what is wrong with it.
pub fn load_dataset(path: &Path) -> anyhow::Result<SpikeDataset> {
    SpikeDataset::load(path).map_err(|e| {
        // File-level errors (I/O, JSON syntax, binary layout) name the file themselves.
        let context = match e.path() {
            Some(_) => "reading the spike dataset".to_owned(),
            None => format!("reading the spike dataset {}", path.display()),
        };
        anyhow::Error::new(e).context(context)
    })
}

/// Reads a labelled spike dataset (classification and searches need labels).
pub fn load_labelled(path: &Path) -> anyhow::Result<SpikeDataset> {
    let data = load_dataset(path)?;
    if data.labels().is_empty() {
        anyhow::bail!("{}: the dataset has no labels", path.display());
    }
    Ok(data)
}
