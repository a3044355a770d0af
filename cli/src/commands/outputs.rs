//! The overwrite rule of every command that writes (README, "Outputs, cache and overwriting"):
//! an output file or folder that already exists is refused unless `--force`
//! ([`ForceOption`](super::options::ForceOption)) is given.

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
        Some(p) => anyhow::bail!("{} already exists (use --force to replace it)", p.display()),
        None => Ok(()),
    }
}
