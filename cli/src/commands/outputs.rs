//! The overwrite rule of every command that writes (README, "Outputs, cache and overwriting"):
//! an output file or folder that already exists is refused unless `--force`
//! ([`ForceOption`](super::options::ForceOption)) is given — checked before the work starts
//! ([`refuse_existing`]) and again when the outputs are committed (each command creates them
//! with [`Replace::when`]`(force)`; [`exists_as_refusal`] words a commit's refusal the same
//! way). An output may not be, hold or lie inside an input ([`refuse_nested`]).

use neurotac_core::io::{check_not_nested, existing_output};
use std::path::Path;

/// Fails on the first of `outputs` that exists, unless `force`.
pub fn refuse_existing<'a>(
    outputs: impl IntoIterator<Item = &'a Path>,
    force: bool,
) -> anyhow::Result<()> {
    if force {
        return Ok(());
    }
    match outputs.into_iter().find(|p| p.exists()) {
        Some(p) => Err(refusal(p)),
        None => Ok(()),
    }
}

/// The refusal of an existing output.
fn refusal(path: &Path) -> anyhow::Error {
    anyhow::anyhow!(
        "{} already exists (use --force to replace it)",
        path.display()
    )
}

/// `e` as [`refuse_existing`]'s line when it comes from a commit that found its target existing
/// (another run wrote it after this one checked), else `e` unchanged.
pub fn exists_as_refusal(e: anyhow::Error) -> anyhow::Error {
    match existing_output(e.as_ref()) {
        Some(path) => refusal(path),
        None => e,
    }
}

/// Fails when the report folder `out` of a pipeline run is, holds or lies inside one of its
/// inputs: the recorded dataset, the simulator parameters and the dataset cache (`reproduce`,
/// `tradeoff`).
pub fn refuse_report_over_inputs(
    out: &Path,
    dataset: Option<&Path>,
    params: Option<&Path>,
    cache: &Path,
) -> anyhow::Result<()> {
    let inputs: Vec<&Path> = [dataset, params, Some(cache)]
        .into_iter()
        .flatten()
        .collect();
    refuse_nested([out], &inputs)
}

/// Fails when one of `outputs` is, holds or lies inside one of `inputs` (see
/// [`check_not_nested`]): `reproduce --dataset ds --out ds --force` would delete the recordings.
pub fn refuse_nested<'a>(
    outputs: impl IntoIterator<Item = &'a Path>,
    inputs: &[&Path],
) -> anyhow::Result<()> {
    for output in outputs {
        for input in inputs {
            check_not_nested(input, output)?;
        }
    }
    Ok(())
}
