//! Event files and the NeuroTac transduction: pixel events in, 49 taxel spike trains out.
//!
//! Events cross the boundary as four arrays (`t` int64 µs, `x` and `y` uint16 top-left pixel
//! coordinates, `p` bool ON); the Python package builds the structured array from them.

use crate::dataset::{array_vec, dataset_to_py};
use crate::errors::{OrRaise, invalid};
use neurotac_core::time::s_to_us;
use neurotac_core::{EventBuffer, SpikeDataset};
use neurotac_experiments::transduce::{
    LayoutSpec, TransduceError, check_reliable, resolve_layout, transduce_file, transduced_dataset,
};
use neurotac_sensor::filter::MapStart;
use neurotac_sensor::format::{DAVIS240_SIZE, ReadStats, read_file, write_file};
use neurotac_sensor::taxel::{Transducer, TransductionConfig};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ffi::CString;
use std::path::{Path, PathBuf};

/// The four event arrays `(t, x, y, p)`.
type EventArrays<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<u16>>,
    Bound<'py, PyArray1<u16>>,
    Bound<'py, PyArray1<bool>>,
);

/// Emits the reader's warning (skipped events, timestamps going backwards), which the CLI
/// prints to standard error, as a Python `UserWarning`.
fn warn_read(py: Python<'_>, read: &ReadStats, input: &Path) -> PyResult<()> {
    if let Some(warning) = read.warning(input) {
        let message = CString::new(warning.replace('\0', " ")).expect("NUL bytes replaced");
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &message, 2)?;
    }
    Ok(())
}

/// Reads every event of an event file (AEDAT 2.0, 3.1, 4.0, ECD text or CSV, detected from its
/// first bytes) as the arrays `(t, x, y, p)`: t int64 µs, x and y uint16 top-left, p bool ON.
/// Events the reader skips are reported by a `UserWarning`, as the CLI reports them.
#[pyfunction]
pub(crate) fn read_event_arrays(py: Python<'_>, path: PathBuf) -> PyResult<EventArrays<'_>> {
    let (events, stats) = py.detach(|| read_file(&path)).or_raise()?;
    warn_read(py, &stats, &path)?;
    Ok((
        events.t.into_pyarray(py),
        events.x.into_pyarray(py),
        events.y.into_pyarray(py),
        events.polarity.into_pyarray(py),
    ))
}

/// The events of the arrays `t` (µs), `x`, `y` (pixels) and `p` (ON when true or non-zero).
fn event_buffer(
    t: &Bound<'_, PyAny>,
    x: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
) -> PyResult<EventBuffer> {
    let t = array_vec::<i64>(t)?;
    let coordinate = |a: &Bound<'_, PyAny>, name: &str| -> PyResult<Vec<u16>> {
        array_vec::<i64>(a)?
            .into_iter()
            .enumerate()
            .map(|(i, v)| {
                u16::try_from(v).map_err(|_| {
                    invalid(format!(
                        "event {i}: {name} = {v} is not a pixel coordinate (0 … 65535)"
                    ))
                })
            })
            .collect()
    };
    let (x, y) = (coordinate(x, "x")?, coordinate(y, "y")?);
    let polarity = array_vec::<bool>(p)?;
    if [x.len(), y.len(), polarity.len()]
        .iter()
        .any(|&n| n != t.len())
    {
        return Err(invalid(format!(
            "event fields of different lengths: t {}, x {}, y {}, p {}",
            t.len(),
            x.len(),
            y.len(),
            polarity.len()
        )));
    }
    Ok(EventBuffer { t, x, y, polarity })
}

/// Writes the events `(t, x, y, p)` of a `sensor` (width, height; 240 × 180 when `None`)
/// recording to `path` in the format of its extension (`.aedat` / `.aedat2` AEDAT 2.0,
/// `.aedat3` AEDAT 3.1, `.aedat4` AEDAT 4.0 with LZ4, `.txt` ECD text, `.csv` CSV), stating the
/// sensor size in the format's own way, atomically: a failed write leaves the old file or none.
/// A size the format cannot state, or an event outside it, is an error.
#[pyfunction]
#[pyo3(signature = (path, t, x, y, p, sensor=None))]
pub(crate) fn write_event_arrays(
    py: Python<'_>,
    path: PathBuf,
    t: &Bound<'_, PyAny>,
    x: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
    sensor: Option<(u16, u16)>,
) -> PyResult<()> {
    let events = event_buffer(t, x, y, p)?;
    let sensor = sensor.unwrap_or(DAVIS240_SIZE);
    py.detach(|| write_file(&path, &events, sensor)).or_raise()
}

/// The transduction settings of the keyword arguments (the CLI's defaults and checks).
fn transduction_config(
    ba_window_us: i64,
    ba_empty_start: bool,
    rf_radius_px: f64,
    pool_ms: f64,
    gain: f64,
) -> PyResult<TransductionConfig> {
    if !(pool_ms.is_finite() && pool_ms > 0.0) {
        return Err(invalid(format!("pool_ms {pool_ms} must be finite and > 0")));
    }
    if ba_window_us < 0 {
        return Err(invalid(format!(
            "ba_window_us {ba_window_us} must be ≥ 0 (0 disables the filter)"
        )));
    }
    Ok(TransductionConfig {
        ba_window_us: (ba_window_us > 0).then_some(ba_window_us),
        ba_start: match ba_empty_start {
            true => MapStart::Empty,
            false => MapStart::Zero,
        },
        rf_radius_px,
        pool_window_us: s_to_us(pool_ms / 1e3),
        recentre_gain: gain,
        ..TransductionConfig::default()
    })
}

/// `default`, `auto` or a layout file, as the CLI's `--layout` (None is `default`).
fn layout_spec(layout: Option<&Path>, calibration_ms: f64) -> (LayoutSpec, String) {
    let layout = layout.unwrap_or(Path::new("default"));
    let name = layout.to_string_lossy().into_owned();
    let spec = match layout.to_str() {
        Some(s @ ("default" | "auto")) => LayoutSpec::parse(s, calibration_ms),
        _ => LayoutSpec::File(layout.to_owned()),
    };
    (spec, name)
}

/// The taxel spike trains of an event file as a one-sample dataset dict, as `neurotac
/// transduce FILE` makes them: background-activity filter (`ba_window_us`, 0 disables;
/// `ba_empty_start` starts its time surface empty) → receptive fields of `rf_radius_px` around
/// the `layout`'s 49 taxels (`None`/`"default"`, `"auto"` to detect them in the first
/// `calibration_ms` of the file, or a JSON file of `[x, y]` centres) → pooling over `pool_ms` →
/// re-centring with `gain`. `label` names the class (then `labels == [0]`); `meta` records the
/// source, layout, settings, time origin and stage counts.
#[pyfunction]
/// An automatic layout whose confidence is below [`LayoutDetection::RELIABLE_CONFIDENCE`](neurotac_sensor::taxel::LayoutDetection::RELIABLE_CONFIDENCE) is
/// refused (`NeurotacValueError`) unless `accept_uncertain_layout`, as the CLI's `transduce
/// --layout auto` does.
#[pyo3(signature = (path, layout=None, *, label=None, ba_window_us=5000, ba_empty_start=false, rf_radius_px=3.0, pool_ms=20.0, gain=0.5, calibration_ms=500.0, accept_uncertain_layout=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn transduce_path(
    py: Python<'_>,
    path: PathBuf,
    layout: Option<PathBuf>,
    label: Option<String>,
    ba_window_us: i64,
    ba_empty_start: bool,
    rf_radius_px: f64,
    pool_ms: f64,
    gain: f64,
    calibration_ms: f64,
    accept_uncertain_layout: bool,
) -> PyResult<Bound<'_, PyDict>> {
    let config = transduction_config(ba_window_us, ba_empty_start, rf_radius_px, pool_ms, gain)?;
    let (spec, layout_name) = layout_spec(layout.as_deref(), calibration_ms);
    let (layout, detection) = py
        .detach(|| resolve_layout(&spec, &path, rf_radius_px))
        .or_raise()?;
    if let Some(Err(why)) = detection
        .filter(|_| !accept_uncertain_layout)
        .map(|d| check_reliable(&d, &path))
    {
        return Err(invalid(format!(
            "{why}; give layout=\"default\" or a layout file, or accept_uncertain_layout=True to use it anyway"
        )));
    }
    let t = py
        .detach(|| transduce_file(&path, &layout, &layout_name, config, label.as_deref()))
        .or_raise()?;
    warn_read(py, &t.read, &path)?;
    dataset_to_py(py, &t.dataset)
}

/// `neurotac.transduce` of events in memory, the arrays `(t, x, y, p)`: the same stages and
/// metadata (`source` is `<events>`); `layout="auto"` needs a file.
#[pyfunction]
#[pyo3(signature = (t, x, y, p, layout=None, *, label=None, ba_window_us=5000, ba_empty_start=false, rf_radius_px=3.0, pool_ms=20.0, gain=0.5))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn transduce_events<'py>(
    py: Python<'py>,
    t: &Bound<'py, PyAny>,
    x: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    p: &Bound<'py, PyAny>,
    layout: Option<PathBuf>,
    label: Option<String>,
    ba_window_us: i64,
    ba_empty_start: bool,
    rf_radius_px: f64,
    pool_ms: f64,
    gain: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let events = event_buffer(t, x, y, p)?;
    let config = transduction_config(ba_window_us, ba_empty_start, rf_radius_px, pool_ms, gain)?;
    let (spec, layout_name) = layout_spec(layout.as_deref(), 0.0);
    if matches!(spec, LayoutSpec::Auto { .. }) {
        return Err(invalid(
            "layout='auto' detects the taxels in the head of a recording file: transduce the file's path, or give a layout file",
        ));
    }
    let source = Path::new("<events>");
    let data = py
        .detach(|| -> Result<SpikeDataset, TransduceError> {
            let transduction = |source_error| TransduceError::Transduction {
                path: source.to_owned(),
                source: source_error,
            };
            let (layout, _) = resolve_layout(&spec, source, rf_radius_px)?;
            let mut transducer = Transducer::new(&layout, config).map_err(transduction)?;
            transducer.push(&events).map_err(transduction)?;
            transducer.finish();
            let trains = transducer.spike_trains();
            Ok(transduced_dataset(
                &transducer,
                trains,
                source,
                &layout_name,
                config,
                label.as_deref(),
            )?)
        })
        .or_raise()?;
    dataset_to_py(py, &data)
}
