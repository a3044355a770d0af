//! The simulated texture datasets of `neurotac simulate` / `neurotac reproduce`.

use crate::dataset::dataset_to_py;
use crate::errors::{OrRaise, invalid};
use crate::threads::detached;
use neurotac_core::OneProcess;
use neurotac_experiments::datasets::simulated::{
    DatasetsError, TextureSet, load_or_simulate, simulate_set,
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
/// calibrated parameters). With `cache_dir`, the dataset is read from that folder when it was
/// simulated before with exactly the same settings, else simulated and stored there (the cache
/// of `neurotac simulate --cache`). `threads`: worker threads (default: one per core).
#[pyfunction]
#[pyo3(signature = (set, trials=None, seed=1, *, params=None, cache_dir=None, threads=None))]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    set: &str,
    trials: Option<usize>,
    seed: u64,
    params: Option<PathBuf>,
    cache_dir: Option<PathBuf>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
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
