//! What every command that writes checks before any work (README, "Outputs, cache and
//! overwriting"), in one place: [`check_outputs`] takes each output with the flag that names it
//! and its kind ([`Output`]) and fails on the first that
//!
//! - is of the wrong kind: a file where the flag wants a folder, or a folder where it wants a
//!   file (`--out must be a folder: sim/artificial.bin is a file`), or lies under a file;
//! - exists, unless `--force` ([`ForceOption`](super::options::ForceOption)): the overwrite
//!   rule. It is checked again when the outputs are committed (each command creates them with
//!   [`Replace::when`](neurotac_core::io::Replace::when)`(force)`; [`exists_as_refusal`] words a
//!   commit's refusal the same way);
//! - cannot be written: a probe file is created and removed in the folder the output will be
//!   created in (permission bits alone say nothing when running as root, or on a read-only
//!   mount), so a read-only folder fails now, not after an hour of simulation.
//!
//! [`cache_folder`] resolves the dataset cache (`--cache`, `$NEUROTAC_CACHE`, the default) and
//! probes it the same way; an unusable cache is said at once, with the flag and variable that
//! choose another, and the run goes on without it. An output may not be, hold or lie inside an
//! input ([`refuse_nested`], [`refuse_report_over_inputs`]).

use anyhow::Context;
use neurotac_core::io::{check_not_nested, existing_output};
use neurotac_experiments::datasets::simulated::{default_cache_dir, warn_about_cache_once};
use std::path::{Path, PathBuf};

/// What an output path must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A file, refused when it exists (unless `--force`).
    File,
    /// A folder written whole (a report), refused when it exists (unless `--force`).
    Folder,
    /// A folder the command writes its files into, created if needed; it may exist (its files
    /// are checked as [`Kind::File`]s).
    Into,
}

/// One output of a command: the flag (or argument) that names it, its path and its kind.
#[derive(Debug, Clone, Copy)]
pub struct Output<'a> {
    flag: &'a str,
    path: &'a Path,
    kind: Kind,
}

impl<'a> Output<'a> {
    /// The file `path`, named by `flag` (`--out`, `OUTPUT`).
    pub fn file(flag: &'a str, path: &'a Path) -> Self {
        Self {
            flag,
            path,
            kind: Kind::File,
        }
    }

    /// The folder `path`, written whole, named by `flag`.
    pub fn folder(flag: &'a str, path: &'a Path) -> Self {
        Self {
            flag,
            path,
            kind: Kind::Folder,
        }
    }

    /// The folder `path` the command writes into, named by `flag`.
    pub fn into_folder(flag: &'a str, path: &'a Path) -> Self {
        Self {
            flag,
            path,
            kind: Kind::Into,
        }
    }

    /// `files` under `flag` (the files a command writes into an [`Output::into_folder`]).
    pub fn files(flag: &'a str, files: &'a [PathBuf]) -> impl Iterator<Item = Self> + 'a {
        files.iter().map(move |p| Self::file(flag, p))
    }

    /// The folder `folder` named by `flag` and the `files` the command writes into it.
    pub fn folder_with_files(
        flag: &'a str,
        folder: &'a Path,
        files: &'a [PathBuf],
    ) -> impl Iterator<Item = Self> + 'a {
        std::iter::once(Self::into_folder(flag, folder)).chain(Self::files(flag, files))
    }
}

/// Fails on the first of `outputs` of the wrong kind, existing (unless `force`) or not
/// writable, in that order over all of them; call it before any work.
pub fn check_outputs<'a>(
    outputs: impl IntoIterator<Item = Output<'a>>,
    force: bool,
) -> anyhow::Result<()> {
    let outputs: Vec<Output> = outputs.into_iter().collect();
    outputs.iter().try_for_each(check_kind)?;
    if !force
        && let Some(o) = outputs
            .iter()
            .find(|o| o.kind != Kind::Into && o.path.exists())
    {
        return Err(refusal(o.path));
    }
    for o in &outputs {
        probe(creation_folder(o.path, o.kind))
            .with_context(|| format!("{} {}: cannot write there", o.flag, o.path.display()))?;
    }
    Ok(())
}

/// A flag that wants a folder given a file, one that wants a file given a folder, or a path
/// under a file.
fn check_kind(o: &Output) -> anyhow::Result<()> {
    let (flag, path) = (o.flag, o.path.display());
    match (o.kind, std::fs::metadata(o.path)) {
        (Kind::File, Ok(m)) if m.is_dir() => {
            anyhow::bail!("{flag} must be a file: {path} is a folder")
        }
        (Kind::Folder | Kind::Into, Ok(m)) if !m.is_dir() => {
            anyhow::bail!("{flag} must be a folder: {path} is a file")
        }
        _ => {}
    }
    let folder = nearest_existing(parent(o.path));
    if !folder.is_dir() {
        anyhow::bail!(
            "{flag} {path}: cannot create it under {}, which is a file, not a folder",
            folder.display()
        );
    }
    Ok(())
}

/// The folder `path` is created in: itself for an existing [`Kind::Into`] folder, else its
/// nearest existing ancestor (the folders between are created by the command).
fn creation_folder(path: &Path, kind: Kind) -> PathBuf {
    match kind == Kind::Into && path.is_dir() {
        true => path.to_owned(),
        false => nearest_existing(parent(path)),
    }
}

/// The folder `path` names an entry of (`""` for a bare name or a root).
fn parent(path: &Path) -> &Path {
    path.parent().unwrap_or(Path::new(""))
}

/// `path` or its nearest ancestor that exists (`.` for a relative path none of whose parts do).
fn nearest_existing(path: &Path) -> PathBuf {
    path.ancestors()
        .find(|p| !p.as_os_str().is_empty() && p.exists())
        .unwrap_or(Path::new("."))
        .to_owned()
}

/// Whether files can be created in the folder `dir`: a hidden probe file is created there and
/// removed (the only test that holds for root, read-only mounts and ACLs alike).
fn probe(dir: PathBuf) -> anyhow::Result<()> {
    let file = dir.join(format!(".neurotac-probe-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(&file)
        .with_context(|| format!("cannot create a file in {}", dir.display()))?;
    match std::fs::remove_file(&file) {
        // Another rank of the same run on a shared folder may have removed it.
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("cannot remove {}", file.display()))
        }
        _ => Ok(()),
    }
}

/// The dataset cache: `--cache` (`flag`) when given, else `$NEUROTAC_CACHE`, else the default
/// (`$XDG_CACHE_HOME/neurotac` or `~/.cache/neurotac`). When it cannot be written (a file, a
/// read-only folder), one warning naming it, the cause and the fix is printed now (when
/// `say`: rank 0 of a distributed run) and the run goes on: datasets it must simulate are then
/// not cached.
pub fn cache_folder(flag: Option<&Path>, say: bool) -> PathBuf {
    let (cache, from) = match flag {
        Some(p) => (p.to_owned(), "--cache"),
        None if std::env::var_os("NEUROTAC_CACHE").is_some_and(|v| !v.is_empty()) => {
            (default_cache_dir(), "NEUROTAC_CACHE")
        }
        None => (default_cache_dir(), "the default cache"),
    };
    let usable = check_outputs([Output::into_folder(from, &cache)], true);
    if let (Err(e), true) = (usable, say) {
        let warning = format!(
            "warning: the cache folder is unusable: {e:#}; simulating without caching \
             (choose a writable one with --cache DIR or NEUROTAC_CACHE=DIR)"
        );
        warn_about_cache_once(&cache, &warning);
    }
    cache
}

/// The refusal of an existing output.
fn refusal(path: &Path) -> anyhow::Error {
    anyhow::anyhow!(
        "{} already exists (use --force to replace it)",
        path.display()
    )
}

/// `e` as [`check_outputs`]'s line when it comes from a commit that found its target existing
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A path under a regular file can never be created, even by root: the reliable
    /// unwritable target.
    fn under_a_file(dir: &Path) -> PathBuf {
        let file = dir.join("plain");
        std::fs::write(&file, "x").unwrap();
        file.join("sub").join("out.json")
    }

    #[test]
    fn an_output_under_a_file_is_refused_naming_the_flag_and_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = under_a_file(dir.path());
        let e = check_outputs([Output::file("--out", &out)], false).unwrap_err();
        let text = format!("{e:#}");
        assert!(text.starts_with("--out "), "{text}");
        assert!(
            text.contains("plain, which is a file, not a folder"),
            "{text}"
        );
    }

    #[test]
    fn a_file_where_a_folder_is_wanted_and_the_reverse_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.bin");
        std::fs::write(&file, "x").unwrap();
        let e = check_outputs([Output::into_folder("--out", &file)], true).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("--out must be a folder: {} is a file", file.display())
        );
        let e = check_outputs([Output::file("--matrix", dir.path())], true).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "--matrix must be a file: {} is a folder",
                dir.path().display()
            )
        );
    }

    #[test]
    fn a_writable_new_output_passes_and_leaves_no_probe_behind() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new").join("report");
        check_outputs([Output::folder("--out", &out)], false).unwrap();
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn an_existing_output_is_refused_without_force_and_probed_with_it() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("m.json");
        std::fs::write(&out, "{}").unwrap();
        let e = check_outputs([Output::file("--out", &out)], false).unwrap_err();
        let text = e.to_string();
        assert!(
            text.ends_with("already exists (use --force to replace it)"),
            "{text}"
        );
        check_outputs([Output::file("--out", &out)], true).unwrap();
    }

    #[test]
    fn an_unwritable_folder_fails_the_probe_with_the_system_cause() {
        // A "folder" that is a file: creating the probe inside it fails for root too.
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plain");
        std::fs::write(&file, "x").unwrap();
        let e = probe(file.clone()).unwrap_err();
        let text = format!("{e:#}");
        assert!(
            text.starts_with(&format!("cannot create a file in {}: ", file.display())),
            "{text}"
        );
        assert!(text.contains("os error"), "{text}");
    }
}
