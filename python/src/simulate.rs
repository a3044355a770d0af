//! The simulated texture datasets of `neurotac simulate` / `neurotac reproduce`.

use crate::dataset::dataset_to_py;
use crate::errors::{OrRaise, invalid};
use crate::threads::detached;
use neurotac_core::OneProcess;
use neurotac_experiments::datasets::simulated::{
    DatasetsError, TextureSet, default_cache_dir, load_or_simulate, simulate_set,
};
use neurotac_sensor::sim::{SimParams, check_trials};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// The simulated taxel dataset of texture set `set` (`"artificial"`: 11 bump grids, 0–5 mm;
/// `"natural"`: the paper's 20 textures) with `trials` slides per texture (default: the
/// paper's, 100 artificial / 50 natural), simulated from `seed` (the same seed gives the same
/// dataset at any thread count), as a dataset dict (labels = texture index, `meta` records
/// every parameter and `duration_s`).
///
/// `params` is a simulator parameter file (JSON, see `neurotac simulate params`; default the
/// calibrated parameters). The dataset is read from the cache when it was simulated before
/// with exactly the same settings, else simulated and stored there: the cache of `neurotac
/// simulate` and `reproduce` (`cache_dir`, default `$NEUROTAC_CACHE`, else
/// `$XDG_CACHE_HOME/neurotac`, else `~/.cache/neurotac`). A default cache that cannot be made
/// gives a `UserWarning` and the dataset is simulated; `cache=False` never reads nor writes
/// one. `threads`: worker threads (default: one per core).
#[pyfunction]
#[pyo3(signature = (set, trials=None, seed=1, *, params=None, cache_dir=None, cache=true, threads=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    set: &str,
    trials: Option<usize>,
    seed: u64,
    params: Option<PathBuf>,
    cache_dir: Option<PathBuf>,
    cache: bool,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    if !cache && cache_dir.is_some() {
        return Err(invalid(
            "cache=False with a cache_dir: give one or the other",
        ));
    }
    let set = match set {
        "artificial" => TextureSet::Artificial,
        "natural" => TextureSet::Natural,
        other => {
            return Err(invalid(format!(
                "set = '{other}': expected 'artificial' or 'natural'"
            )));
        }
    };
    let trials = trials.unwrap_or_else(|| set.paper_trials());
    check_trials(trials, set.textures().len()).or_value_error()?;
    let params = match params {
        Some(path) => py.detach(|| SimParams::from_json_file(&path)).or_raise()?,
        None => SimParams::default(),
    };
    let cache_dir = match (cache, cache_dir) {
        (false, _) => None,
        (true, Some(dir)) => Some(dir),
        (true, None) => {
            let dir = default_cache_dir();
            match std::fs::create_dir_all(&dir) {
                Ok(()) => Some(dir),
                Err(e) => {
                    let message = format!(
                        "the cache folder {} is unusable ({e}); simulating without it (cache_dir= chooses another)",
                        dir.display()
                    );
                    let c_message = std::ffi::CString::new(message).or_raise()?;
                    PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyUserWarning>(), &c_message, 1)?;
                    None
                }
            }
        }
    };
    let data = detached(py, threads, || -> Result<_, DatasetsError> {
        match &cache_dir {
            Some(dir) => load_or_simulate(set, trials, seed, &params, dir, &|| {}, &OneProcess),
            None => Ok(simulate_set(
                set,
                trials,
                seed,
                &params,
                &|_, _| Ok(()),
                &|| {},
                &OneProcess,
            )?
            .dataset),
        }
    })?
    .or_raise()?;
    dataset_to_py(py, &data)
}
