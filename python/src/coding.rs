//! The paper's four codings of a dataset dict (`neurotac_core::coding`), and the distance
//! matrix of any of them as `neurotac distances` computes it
//! (`neurotac_experiments::coding::coding_distances`).
//!
//! | coding | function | result |
//! |---|---|---|
//! | intensive | `intensive(ds)` | `N × 1` features: mean spike count per unit |
//! | spatial | `spatial(ds)` | `N × n_units` features: spike count of each unit |
//! | temporal | `temporal(ds, dt, duration=None)` | `N × W` features: Δt-window pooled counts / `n_units` in 1 ms steps, `W = T − Δt + 1` |
//! | spatiotemporal | `spatiotemporal(ds, tau, cos)` | `N × N` multi-unit Van Rossum distances |

use crate::dataset::dataset_from_py;
use crate::errors::{OrRaise, invalid};
use crate::threads::detached;
use ndarray::Array2;
use neurotac_core::SpikeDataset;
use neurotac_core::coding::{
    FeatureCoding, IntensiveCoding, SpatialCoding, TemporalCoding, feature_matrix, whole_ms,
};
use neurotac_experiments::ExperimentError;
use neurotac_experiments::coding::{
    CodingName, CodingParameters, coding_distances, sample_duration_ms,
};
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;

/// The features of every sample of `dataset` under `coding`, computed without the GIL.
fn features<'py, C: FeatureCoding>(
    dataset: &Bound<'py, PyAny>,
    coding: impl FnOnce(&SpikeDataset) -> Result<C, ExperimentError>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let py = dataset.py();
    let data = dataset_from_py(dataset)?;
    let coding = coding(&data).or_value_error()?;
    let m =
        detached(py, None, || feature_matrix(&coding, data.observations()))?.or_value_error()?;
    Ok(m.into_pyarray(py))
}

/// Intensive coding: an `N × 1` matrix, the mean spike count per unit of each sample.
#[pyfunction]
pub(crate) fn intensive<'py>(dataset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    features(dataset, |_| Ok(IntensiveCoding::new()))
}

/// Spatial coding: an `N × n_units` matrix, the spike count of each unit of each sample.
#[pyfunction]
pub(crate) fn spatial<'py>(dataset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    features(dataset, |_| Ok(SpatialCoding::new()))
}

/// Temporal coding: an `N × W` matrix; feature `s` of a sample is the number of spikes of all
/// units in the window `[s, s + dt)` ms divided by `n_units`, for `s = 0, 1, …, T − dt` ms
/// (`W = T − dt + 1`). `dt` and `duration` are seconds, whole milliseconds; `duration` (`T`)
/// defaults to `meta["duration_s"]`, else one ms past the latest spike.
#[pyfunction]
#[pyo3(signature = (dataset, dt, duration=None))]
pub(crate) fn temporal<'py>(
    dataset: &Bound<'py, PyAny>,
    dt: f64,
    duration: Option<f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    features(dataset, |data| {
        let window_ms = whole_ms(dt, "dt")?;
        Ok(TemporalCoding::from_ms(
            window_ms,
            sample_duration_ms(data, duration)?,
        )?)
    })
}

/// Spatiotemporal coding: the `N × N` multi-unit Van Rossum distances of the samples at `tau`
/// (s) and `cos` ∈ [0, 1] (pymuvr's normalisation). The GIL is released while computing.
#[pyfunction]
#[pyo3(signature = (dataset, tau, cos, *, threads=None))]
pub(crate) fn spatiotemporal<'py>(
    dataset: &Bound<'py, PyAny>,
    tau: f64,
    cos: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    distances(
        dataset,
        "spatiotemporal",
        None,
        None,
        Some(tau),
        Some(cos),
        threads,
    )
}

/// The `N × N` distance matrix of `dataset` under `coding` (`"intensive"`, `"spatial"`,
/// `"temporal"` — Euclidean distances of the features — or `"spatiotemporal"`, the Van Rossum
/// distance), as `neurotac distances` computes it: the temporal coding needs `dt` (s, whole
/// ms; `duration` as in `temporal`), the spatiotemporal `tau` (s) and `cos`. The GIL is
/// released while computing; `threads` as in `van_rossum.square_distance_matrix`.
#[pyfunction]
#[pyo3(signature = (dataset, coding, *, dt=None, duration=None, tau=None, cos=None, threads=None))]
pub(crate) fn distances<'py>(
    dataset: &Bound<'py, PyAny>,
    coding: &str,
    dt: Option<f64>,
    duration: Option<f64>,
    tau: Option<f64>,
    cos: Option<f64>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let py = dataset.py();
    let name: CodingName = coding
        .parse()
        .map_err(|e| invalid(format!("coding = '{coding}': {e}")))?;
    let data = dataset_from_py(dataset)?;
    let parameters = || -> Result<CodingParameters, ExperimentError> {
        let window_ms = dt.map(|dt| whole_ms(dt, "dt")).transpose()?;
        let duration_ms = match window_ms {
            Some(_) => Some(sample_duration_ms(&data, duration)?),
            None => None,
        };
        Ok(CodingParameters {
            window_ms,
            duration_ms,
            tau_s: tau,
            cos,
        })
    };
    let parameters = parameters().or_value_error()?;
    let matrix: Array2<f64> = detached(py, threads, || {
        coding_distances(
            data.observations(),
            name,
            &parameters,
            &neurotac_core::OneProcess,
        )
    })?
    .or_value_error()?;
    Ok(matrix.into_pyarray(py))
}
