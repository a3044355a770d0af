//! pymuvr's `square_distance_matrix` and `distance_matrix`, computed by the exact multi-unit
//! Van Rossum distance of `neurotac_core::distance::van_rossum`.
//!
//! Same arguments and the same values as pymuvr 1.3.3: `D = √((1 − c)·LL² + c·SP²)` with the
//! kernel `e^{−|s−t|/τ}` (one spike against none is 1), τ in the unit of the spike times. Where
//! pymuvr is wrong or crashes, these are exact: repeated spike times, unsorted trains (sorted
//! here), times far from 0, NumPy arrays or tuples as trains, no observation at all. Refused
//! with `NeurotacValueError` where pymuvr returns garbage: `cos ∉ [0, 1]`, `tau ≤ 0` or not
//! finite (pymuvr's `tau = 0`, coincidence counting, is not supported), NaN or infinite spike
//! times, samples with different unit counts.

use crate::dataset::{array_vec, observations_from_flat, observations_from_nested};
use crate::errors::OrRaise;
use crate::threads::detached;
use ndarray::Array2;
use neurotac_core::distance::{VanRossum, check_cos};
use neurotac_core::{DistanceError, MultiSpikeTrain};
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;

/// The `N × N` distances of `observations` (symmetric, zero diagonal).
fn square(
    observations: &[MultiSpikeTrain],
    cos: f64,
    tau: f64,
) -> Result<Array2<f64>, DistanceError> {
    check_cos(cos)?;
    VanRossum::new(tau)?
        .matrices(observations, &neurotac_core::OneProcess)?
        .distances(cos)
}

/// pymuvr's `square_distance_matrix(observations, cos, tau)`: the `N × N` matrix (float64) of
/// multi-unit Van Rossum distances between the `N` observations, each a list of units, each a
/// list of spike times (s). `cos` ∈ [0, 1] (0 labelled line, 1 summed population), `tau` > 0
/// in the unit of the times. `threads`: worker threads (default: all cores, or
/// `RAYON_NUM_THREADS`). The GIL is released while computing.
#[pyfunction]
#[pyo3(signature = (observations, cos, tau, *, threads=None))]
pub(crate) fn square_distance_matrix<'py>(
    observations: &Bound<'py, PyAny>,
    cos: f64,
    tau: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let py = observations.py();
    let observations = observations_from_nested(observations)?;
    let matrix = detached(py, threads, || square(&observations, cos, tau))?.or_value_error()?;
    Ok(matrix.into_pyarray(py))
}

/// pymuvr's `distance_matrix(observations1, observations2, cos, tau)`: the `N1 × N2` matrix
/// (float64) of distances between each of `observations1` (rows) and each of `observations2`
/// (columns); arguments as `square_distance_matrix`. Entries equal those of the square
/// matrix of both lists up to rounding (about 1e-15 of the squared norms).
#[pyfunction]
#[pyo3(signature = (observations1, observations2, cos, tau, *, threads=None))]
pub(crate) fn distance_matrix<'py>(
    observations1: &Bound<'py, PyAny>,
    observations2: &Bound<'py, PyAny>,
    cos: f64,
    tau: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let py = observations1.py();
    let rows = observations_from_nested(observations1)?;
    let columns = observations_from_nested(observations2)?;
    let matrix = detached(py, threads, || -> Result<_, DistanceError> {
        check_cos(cos)?;
        VanRossum::new(tau)?
            .prepare(&columns)?
            .cross_matrices(&rows)?
            .distances(cos)
    })?
    .or_value_error()?;
    Ok(matrix.into_pyarray(py))
}

/// `square_distance_matrix` of samples given as flat arrays, without Python lists: sample
/// `s` holds the spikes `times[offsets[s]:offsets[s + 1]]` (s) of the channels
/// `units[offsets[s]:offsets[s + 1]]` (0 … `n_units` − 1), in any order — the `times`,
/// `units`, `offsets`, `n_units` of a dataset dict.
#[pyfunction]
#[pyo3(signature = (times, units, offsets, n_units, cos, tau, *, threads=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn square_distance_matrix_flat<'py>(
    py: Python<'py>,
    times: &Bound<'py, PyAny>,
    units: &Bound<'py, PyAny>,
    offsets: &Bound<'py, PyAny>,
    n_units: usize,
    cos: f64,
    tau: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (times, units) = (array_vec::<f64>(times)?, array_vec::<u32>(units)?);
    let offsets = array_vec::<i64>(offsets)?;
    let observations = observations_from_flat(&times, &units, &offsets, n_units)?;
    let matrix = detached(py, threads, || square(&observations, cos, tau))?.or_value_error()?;
    Ok(matrix.into_pyarray(py))
}
