//! The on-disk cache of simulated datasets: keyed by everything that determines a dataset
//! ([`cache_path`]), read or simulated and stored ([`load_or_simulate`]).

use super::{DatasetsError, SIMULATED_DATASET_VERSION, TextureSet, dataset_meta, simulate_set};
use neurotac_core::{Ranks, SpikeDataset};
use neurotac_sensor::sim::{SimParams, check_trials};
use std::path::{Path, PathBuf};

/// FNV-1a 64 of the metadata's JSON text: the cache key.
pub(super) fn cache_key(meta: &serde_json::Map<String, serde_json::Value>) -> u64 {
    let text = serde_json::to_string(meta).expect("metadata serialises");
    neurotac_core::seed_hash::fnv1a(text.as_bytes())
}

/// The cache folder of simulated datasets shared by `neurotac reproduce` and `neurotac
/// simulate`: `$NEUROTAC_CACHE` if set, else `$XDG_CACHE_HOME/neurotac`, else
/// `~/.cache/neurotac` (`./.neurotac-cache` without a home folder). A variable set to the
/// empty string counts as unset (as the XDG base-directory specification says of
/// `$XDG_CACHE_HOME`). Deleting the folder clears the cache; a dataset is simulated again when
/// next needed.
pub fn default_cache_dir() -> PathBuf {
    let set = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(p) = set("NEUROTAC_CACHE") {
        return p.into();
    }
    if let Some(p) = set("XDG_CACHE_HOME") {
        return PathBuf::from(p).join("neurotac");
    }
    match set("HOME") {
        Some(h) => PathBuf::from(h).join(".cache").join("neurotac"),
        None => PathBuf::from(".neurotac-cache"),
    }
}

/// The cache file of a dataset in `cache_dir`.
pub fn cache_path(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
) -> PathBuf {
    let key = cache_key(&dataset_meta(set, trials, seed, params));
    cache_dir.join(format!(
        "{}-v{SIMULATED_DATASET_VERSION}-n{trials}-s{seed}-{key:016x}.bin",
        set.name()
    ))
}

/// The dataset of `set` with `trials` slides per texture, simulated from `seed` with `params`:
/// read from `cache_dir` when a dataset with exactly the same metadata (version, set, trials,
/// seed, parameters, transduction) is there, else simulated in parallel and stored (binary
/// [`SpikeDataset`], written atomically). `progress` is called once per simulated trial.
///
/// On several `ranks` every rank reads the cache, or the ranks simulate the dataset together
/// ([`simulate_set`]) and rank 0 stores it. Collective; `&OneProcess` for one process.
pub fn load_or_simulate(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
    progress: &(dyn Fn() + Sync),
    ranks: &dyn Ranks,
) -> Result<SpikeDataset, DatasetsError> {
    Ok(load_or_simulate_cached(set, trials, seed, params, cache_dir, progress, ranks)?.0)
}

/// [`load_or_simulate`], also saying whether the dataset came from the cache (the cache
/// file is read once).
pub(super) fn load_or_simulate_cached(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
    progress: &(dyn Fn() + Sync),
    ranks: &dyn Ranks,
) -> Result<(SpikeDataset, bool), DatasetsError> {
    check_trials(trials, set.textures().len())?;
    params.validate()?;
    let path = cache_path(set, trials, seed, params, cache_dir);
    // Every rank must take the same branch: they agree on whether the cache was usable.
    let cached = read_cached(&path, &dataset_meta(set, trials, seed, params));
    let usable = ranks.all_gather_bytes(&[u8::from(cached.is_some())])?;
    if let Some(cached) = cached.filter(|_| usable.iter().all(|b| b == &[1])) {
        return Ok((cached, true));
    }
    // A cache that cannot take the dataset is said before the simulation, not after it, and
    // the run goes on without it.
    let cache_usable = ranks.is_root() && {
        let usable = usable_cache_dir(cache_dir);
        if let Err(e) = &usable {
            warn_about_cache_once(
                cache_dir,
                &format!(
                    "warning: the cache folder {} is unusable ({e}); simulating without caching",
                    cache_dir.display()
                ),
            );
        }
        usable.is_ok()
    };
    let simulated = simulate_set(set, trials, seed, params, &|_, _| Ok(()), progress, ranks)?;
    if cache_usable && let Err(e) = store(&simulated.dataset, cache_dir, &path) {
        let e = neurotac_core::error_chain(&e);
        eprintln!("warning: the dataset could not be cached ({e}); going on without the cache");
    }
    Ok((simulated.dataset, false))
}

/// Prints `warning` on stderr, unless a warning about the cache folder `dir` was printed
/// before in this process: a command that checked its cache before any work has said it (with
/// the fix), and each set simulated later does not say it again.
pub fn warn_about_cache_once(dir: &Path, warning: &str) {
    static SAID: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());
    let mut said = SAID.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    if !said.iter().any(|d| d == dir) {
        said.push(dir.to_owned());
        eprintln!("{warning}");
    }
}

/// Whether `dir` can take a cache file: created if missing, then a probe file created in it
/// and removed (a folder that is a file, read-only or gone is refused here).
fn usable_cache_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    drop(neurotac_core::io::AtomicFile::create(
        dir.join("probe"),
        neurotac_core::io::Replace::Yes,
    )?);
    Ok(())
}

/// The cached dataset at `path` if it exists, decodes and carries every entry of `meta`
/// (besides them it holds the event statistics of the run).
fn read_cached(
    path: &Path,
    meta: &serde_json::Map<String, serde_json::Value>,
) -> Option<SpikeDataset> {
    let data = match SpikeDataset::load(path) {
        Ok(data) => data,
        Err(e) if path.exists() => {
            let e = neurotac_core::error_chain(&e);
            eprintln!("warning: cached dataset unusable ({e}); simulating it again");
            return None;
        }
        Err(_) => return None,
    };
    meta.iter()
        .all(|(k, v)| data.meta().get(k) == Some(v))
        .then_some(data)
}

/// Writes `dataset` to `path` (binary, checksummed) through a temporary file and a rename.
pub fn store(dataset: &SpikeDataset, dir: &Path, path: &Path) -> Result<(), DatasetsError> {
    std::fs::create_dir_all(dir).map_err(|source| DatasetsError::Io {
        path: dir.to_owned(),
        source,
    })?;
    Ok(dataset.save_binary(path)?)
}
