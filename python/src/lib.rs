//! # neurotac-python
//!
//! The Python bindings of neurotac (PyO3 + rust-numpy): the extension module
//! `neurotac._native`, which the Python package `neurotac/` beside this crate re-exports.
//! Rust does the work; the package only builds structured event arrays and names submodules.
//!
//! | concern | module | Python |
//! |---|---|---|
//! | event files, transduction | [`events`] | `read_events`, `write_events`, `transduce` |
//! | simulated texture datasets | [`simulate`] | `simulate` |
//! | spike datasets as NumPy arrays | [`dataset`] | dataset dicts, `load_dataset`, `save_dataset`, `to_pymuvr`, `from_pymuvr` |
//! | multi-unit Van Rossum (pymuvr's API) | [`van_rossum`] | `neurotac.van_rossum.square_distance_matrix`, `distance_matrix`, `square_distance_matrix_flat` |
//! | the four codings | [`coding`] | `neurotac.coding.intensive`, `spatial`, `temporal`, `spatiotemporal`, `distances` |
//! | KNN | [`knn`] | `neurotac.Knn` |
//! | spiking networks: load, describe, run, spikes, state traces, rates, weights, save | [`network`] | `neurotac.Network` (and `neurotac.NetworkBuilder`, `neurotac.nir`, in Python) |
//! | neuron models' descriptions, defaults and presets | [`models`] | `neurotac.NetworkBuilder.add_population` |
//! | errors | [`errors`] | `NeurotacError`, `NeurotacValueError`, `NeurotacOSError` |
//!
//! Every library error becomes an exception whose message is the one the `neurotac` CLI prints
//! (the error and its causes); long calls release the GIL ([`threads`]).
#![deny(missing_docs)]

pub mod coding;
pub mod dataset;
pub mod errors;
pub mod events;
pub mod knn;
pub mod models;
pub mod network;
pub mod simulate;
pub mod threads;
pub mod van_rossum;

use pyo3::prelude::*;

/// The extension module `neurotac._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("NeurotacError", py.get_type::<errors::NeurotacError>())?;
    m.add("NeurotacValueError", errors::value_error_type(py)?)?;
    m.add("NeurotacOSError", errors::os_error_type(py)?)?;
    m.add_class::<knn::Knn>()?;
    m.add_class::<network::Network>()?;
    m.add_function(wrap_pyfunction!(events::read_event_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(events::write_event_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(events::transduce_path, m)?)?;
    m.add_function(wrap_pyfunction!(events::transduce_events, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(models::model_description, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::load_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::save_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::to_pymuvr, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::from_pymuvr, m)?)?;
    m.add_function(wrap_pyfunction!(van_rossum::square_distance_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(van_rossum::distance_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(
        van_rossum::square_distance_matrix_flat,
        m
    )?)?;
    m.add_function(wrap_pyfunction!(coding::intensive, m)?)?;
    m.add_function(wrap_pyfunction!(coding::spatial, m)?)?;
    m.add_function(wrap_pyfunction!(coding::temporal, m)?)?;
    m.add_function(wrap_pyfunction!(coding::spatiotemporal, m)?)?;
    m.add_function(wrap_pyfunction!(coding::distances, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
