//! Spike datasets in NumPy: a dict of flat arrays, and pymuvr's nested lists.
//!
//! A dataset of `S` samples of `n_units` channels is the dict
//!
//! | key | type | content |
//! |---|---|---|
//! | `times` | float64 array | every spike time (s), sample after sample, channel after channel, sorted within a channel |
//! | `units` | uint32 array | the channel of each spike (same length as `times`) |
//! | `offsets` | int64 array, length `S + 1` | sample `s` is `times[offsets[s]:offsets[s + 1]]` |
//! | `n_units` | int | channels per sample (49 taxels) |
//! | `labels` | int64 array | one class per sample, or empty when the dataset is unlabelled |
//! | `class_names` | list of str | index = label (may be empty) |
//! | `meta` | dict | the dataset's JSON metadata (`duration_s`, `transduction`, …) |
//!
//! Reading a dict back, `times`/`units` of a sample may come in any order (each channel is
//! sorted), `n_units` defaults to one more than the largest unit, and `labels`, `class_names`
//! and `meta` may be absent. pymuvr's form is a list of samples, each a list of units, each a
//! list of spike times.

use crate::errors::{OrRaise, invalid};
use ndarray::{Dimension, Ix1};
use neurotac_core::spikes::MAX_CHANNELS;
use neurotac_core::{DistanceError, MultiSpikeTrain, SpikeDataset};
use neurotac_experiments::export::DATASET_FORMATS;
use numpy::{Element, IntoPyArray, PyArray, PyArrayMethods, PyReadonlyArray};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// The samples of pymuvr-shaped `observations` (a sequence of samples, each a sequence of
/// units, each a sequence of spike times in seconds). Trains are sorted; NaN or infinite times
/// are refused, naming the sample.
pub(crate) fn observations_from_nested(
    observations: &Bound<'_, PyAny>,
) -> PyResult<Vec<MultiSpikeTrain>> {
    let not_a_sequence = |what: String| {
        invalid(format!(
            "{what}: expected a sequence (observations = list of samples, each a list of units, each a list of spike times)"
        ))
    };
    let samples = observations
        .try_iter()
        .map_err(|_| not_a_sequence("observations".into()))?;
    let mut out = Vec::new();
    for (s, sample) in samples.enumerate() {
        let sample = sample?;
        let units = sample
            .try_iter()
            .map_err(|_| not_a_sequence(format!("sample {s}")))?;
        let mut channels: Vec<Vec<f64>> = Vec::new();
        for (u, unit) in units.enumerate() {
            let times = unit?.extract::<Vec<f64>>().map_err(|_| {
                invalid(format!(
                    "sample {s}, unit {u}: expected a sequence of spike times (numbers)"
                ))
            })?;
            channels.push(times);
        }
        let trains = MultiSpikeTrain::from_unsorted_channels(&channels)
            .map_err(|source| DistanceError::Spikes { sample: s, source })
            .or_value_error()?;
        out.push(trains);
    }
    Ok(out)
}

/// `obj` (any array-like: a NumPy array of any dtype that casts to `T`, a list …) as a
/// C-contiguous NumPy array of `T` (`numpy.ascontiguousarray(obj, dtype)`; no copy when it
/// already is one). NumPy views with strides that are not multiples of the item size, such as
/// a field of a structured array, are copied: rust-numpy reads those wrongly.
pub(crate) fn contiguous<'py, T: Element, D: Dimension>(
    obj: &Bound<'py, PyAny>,
) -> PyResult<PyReadonlyArray<'py, T, D>> {
    let py = obj.py();
    let numpy = py.import("numpy")?;
    let dtype = T::get_dtype(py);
    let original = numpy.call_method1("asarray", (obj,))?;
    let array = numpy.call_method1("ascontiguousarray", (&original, &dtype))?;
    // NumPy's cast truncates fractions, wraps out-of-range integers and turns NaN into
    // INT64_MIN: an integer array must hold exactly the values given.
    let integer: bool = dtype.getattr("kind")?.extract::<String>()? != "f";
    if integer
        && !numpy
            .call_method1("array_equal", (&array, &original))?
            .is_truthy()?
    {
        return Err(invalid(format!(
            "expected integers that fit {} (no fractions, NaN or values out of its range), got {}",
            dtype.str()?,
            original.getattr("dtype")?.str()?
        )));
    }
    let ndim: usize = array.getattr("ndim")?.extract()?;
    let array = array.cast_into::<PyArray<T, D>>().map_err(|_| {
        let expected = D::NDIM.map_or("an".to_owned(), |n| format!("a {n}-D"));
        invalid(format!("expected {expected} array, got {ndim} dimensions"))
    })?;
    Ok(array.readonly())
}

/// A one-dimensional array-like as a vector ([`contiguous`]).
pub(crate) fn array_vec<T: Element + Copy>(obj: &Bound<'_, PyAny>) -> PyResult<Vec<T>> {
    Ok(contiguous::<T, Ix1>(obj)?.as_slice()?.to_vec())
}

/// The most units over all samples of a dataset (`samples × (n_units + 1)`): each takes an 8-byte
/// offset, so this bounds them to 2 GiB.
const MAX_CHANNEL_SLOTS: usize = 1 << 28;

/// The samples of the flat arrays `times`, `units`, `offsets` (see the module docs); `n_units`
/// is checked against [`MAX_CHANNELS`] and [`MAX_CHANNEL_SLOTS`] before anything is allocated.
pub(crate) fn observations_from_flat(
    times: &[f64],
    units: &[u32],
    offsets: &[i64],
    n_units: usize,
) -> PyResult<Vec<MultiSpikeTrain>> {
    if units.len() != times.len() {
        return Err(invalid(format!(
            "units has {} entries but times has {}",
            units.len(),
            times.len()
        )));
    }
    let valid = offsets.first() == Some(&0)
        && offsets.last() == Some(&(times.len() as i64))
        && offsets.windows(2).all(|w| w[0] <= w[1]);
    if !valid {
        return Err(invalid(format!(
            "offsets must start at 0, never decrease and end at len(times) = {} (got {} offsets)",
            times.len(),
            offsets.len()
        )));
    }
    let samples = offsets.len() - 1;
    if n_units > MAX_CHANNELS || samples.saturating_mul(n_units + 1) > MAX_CHANNEL_SLOTS {
        return Err(invalid(format!(
            "n_units = {n_units} over {samples} samples: more than the limit of {MAX_CHANNELS} \
             units per sample and {MAX_CHANNEL_SLOTS} units over all samples"
        )));
    }
    offsets
        .windows(2)
        .enumerate()
        .map(|(s, w)| {
            let range = w[0] as usize..w[1] as usize;
            let spikes: Vec<(u32, f64)> = units[range.clone()]
                .iter()
                .copied()
                .zip(times[range].iter().copied())
                .collect();
            MultiSpikeTrain::from_labelled_spikes(n_units, &spikes)
                .map_err(|source| DistanceError::Spikes { sample: s, source })
                .or_value_error()
        })
        .collect()
}

/// The flat arrays `(times, units, offsets)` of `observations`.
fn flat_arrays(observations: &[MultiSpikeTrain]) -> (Vec<f64>, Vec<u32>, Vec<i64>) {
    let total = observations.iter().map(|o| o.total_spikes()).sum();
    let (mut times, mut units) = (Vec::with_capacity(total), Vec::with_capacity(total));
    let mut offsets = Vec::with_capacity(observations.len() + 1);
    offsets.push(0i64);
    for o in observations {
        for (c, channel) in o.channels().enumerate() {
            times.extend_from_slice(channel);
            units.extend(std::iter::repeat_n(c as u32, channel.len()));
        }
        offsets.push(times.len() as i64);
    }
    (times, units, offsets)
}

/// `value` (JSON) as a Python object, through the `json` module.
fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).or_raise()?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A Python object as JSON, through the `json` module (`what` names it in errors).
fn py_to_json(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<serde_json::Value> {
    let text: String = obj
        .py()
        .import("json")?
        .call_method1("dumps", (obj,))
        .map_err(|e| invalid(format!("{what} is not JSON-serialisable: {e}")))?
        .extract()?;
    serde_json::from_str(&text).map_err(|e| invalid(format!("{what}: {e}")))
}

/// The dict form of `data` (module docs).
pub(crate) fn dataset_to_py<'py>(
    py: Python<'py>,
    data: &SpikeDataset,
) -> PyResult<Bound<'py, PyDict>> {
    let (times, units, offsets) = flat_arrays(data.observations());
    let labels: Vec<i64> = data.labels().iter().map(|&l| l as i64).collect();
    let meta = serde_json::Value::Object(data.meta().clone());
    let out = PyDict::new(py);
    out.set_item("times", times.into_pyarray(py))?;
    out.set_item("units", units.into_pyarray(py))?;
    out.set_item("offsets", offsets.into_pyarray(py))?;
    out.set_item("n_units", data.n_channels())?;
    out.set_item("labels", labels.into_pyarray(py))?;
    out.set_item("class_names", data.class_names().to_vec())?;
    out.set_item("meta", json_to_py(py, &meta)?)?;
    Ok(out)
}

/// `dataset[key]`, or `None` when the key is absent.
fn item<'py>(dataset: &Bound<'py, PyAny>, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    match dataset.get_item(key) {
        Ok(v) if v.is_none() => Ok(None),
        Ok(v) => Ok(Some(v)),
        Err(e) if e.is_instance_of::<pyo3::exceptions::PyKeyError>(dataset.py()) => Ok(None),
        Err(e) => Err(e),
    }
}

/// `dataset[key]`, required.
fn required<'py>(dataset: &Bound<'py, PyAny>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    item(dataset, key)?.ok_or_else(|| {
        invalid(format!(
            "the dataset has no '{key}' (a spike dataset is a dict with times, units, offsets, n_units, labels, class_names, meta)"
        ))
    })
}

/// Labels (`≥ 0`) as indices.
pub(crate) fn labels_from(labels: &[i64]) -> PyResult<Vec<usize>> {
    labels
        .iter()
        .enumerate()
        .map(|(i, &l)| {
            usize::try_from(l)
                .map_err(|_| invalid(format!("label {i} is {l}: labels are class indices ≥ 0")))
        })
        .collect()
}

/// A dataset from the labels, class names and metadata of a dict or keyword arguments.
fn assemble(
    observations: Vec<MultiSpikeTrain>,
    labels: Option<&Bound<'_, PyAny>>,
    class_names: Option<&Bound<'_, PyAny>>,
    meta: Option<&Bound<'_, PyAny>>,
) -> PyResult<SpikeDataset> {
    let labels = match labels {
        Some(l) => labels_from(&array_vec::<i64>(l)?)?,
        None => Vec::new(),
    };
    let class_names: Vec<String> = match class_names {
        Some(n) => n
            .extract()
            .map_err(|_| invalid("class_names must be a list of str"))?,
        None => Vec::new(),
    };
    let meta = match meta {
        Some(m) => match py_to_json(m, "meta")? {
            serde_json::Value::Object(map) => map,
            other => return Err(invalid(format!("meta must be a dict, got {other}"))),
        },
        None => serde_json::Map::new(),
    };
    SpikeDataset::new(observations, labels, class_names, meta).or_value_error()
}

/// The dataset of a dict (module docs).
pub(crate) fn dataset_from_py(dataset: &Bound<'_, PyAny>) -> PyResult<SpikeDataset> {
    let times = array_vec::<f64>(&required(dataset, "times")?)?;
    let units = array_vec::<u32>(&required(dataset, "units")?)?;
    let offsets = array_vec::<i64>(&required(dataset, "offsets")?)?;
    let n_units = match item(dataset, "n_units")? {
        Some(n) => n.extract::<usize>()?,
        None => units.iter().max().map_or(0, |&u| u as usize + 1),
    };
    let observations = observations_from_flat(&times, &units, &offsets, n_units)?;
    assemble(
        observations,
        item(dataset, "labels")?.as_ref(),
        item(dataset, "class_names")?.as_ref(),
        item(dataset, "meta")?.as_ref(),
    )
}

/// Reads a spike dataset file (JSON or neurotac's binary form, as written by `neurotac
/// transduce`, `neurotac simulate` or `save_dataset`) into the dataset dict.
#[pyfunction]
pub(crate) fn load_dataset(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let data = py.detach(|| SpikeDataset::load(&path)).or_raise()?;
    dataset_to_py(py, &data)
}

/// Writes a dataset dict to `path` in the format its extension names, as `neurotac synth
/// --output` does: `.bin` the compact checksummed binary form, `.json`, or `.npz` flat arrays
/// (see `neurotac_experiments::export`); any other extension is refused. The file is replaced
/// atomically.
#[pyfunction]
pub(crate) fn save_dataset(
    py: Python<'_>,
    path: PathBuf,
    dataset: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let data = dataset_from_py(dataset)?;
    neurotac_experiments::export::OutputFormat::from_path(&path, &DATASET_FORMATS)
        .or_value_error()?;
    let replace = neurotac_experiments::export::Replace::Yes;
    py.detach(|| neurotac_experiments::export::write_dataset(&data, &path, replace))
        .or_raise()
}

/// The samples of a dataset dict in pymuvr's form: a list of samples, each a list of
/// `n_units` lists of spike times (float, sorted).
#[pyfunction]
pub(crate) fn to_pymuvr<'py>(dataset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyList>> {
    let py = dataset.py();
    let data = dataset_from_py(dataset)?;
    let samples = data
        .observations()
        .iter()
        .map(|o| {
            PyList::new(
                py,
                o.channels()
                    .map(|c| PyList::new(py, c))
                    .collect::<PyResult<Vec<_>>>()?,
            )
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, samples)
}

/// A dataset dict from pymuvr-shaped `observations` (a list of samples, each a list of units,
/// each a list of spike times in seconds; trains may be unsorted and of any length, every
/// sample must have the same number of units), with optional `labels` (one class index per
/// sample), `class_names` and `meta` (a JSON-serialisable dict).
#[pyfunction]
#[pyo3(signature = (observations, labels=None, class_names=None, meta=None))]
pub(crate) fn from_pymuvr<'py>(
    observations: &Bound<'py, PyAny>,
    labels: Option<&Bound<'py, PyAny>>,
    class_names: Option<&Bound<'py, PyAny>>,
    meta: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let py = observations.py();
    let observations = observations_from_nested(observations)?;
    let data = assemble(observations, labels, class_names, meta)?;
    dataset_to_py(py, &data)
}
