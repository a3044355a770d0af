//! Library errors as Python exceptions, with the message the `neurotac` CLI prints after
//! `error: ` (the error and its chain of causes, [`neurotac_core::error_chain`]).
//!
//! | exception | raised for | also a |
//! |---|---|---|
//! | `NeurotacError` | anything the library refuses (a malformed event file, a corrupt dataset) | `Exception` |
//! | `NeurotacValueError` | an argument the library refuses (`cos` outside [0, 1], NaN spike times, shapes) | `NeurotacError`, `ValueError` |
//! | `NeurotacOSError` | a file that cannot be opened, read or written (an `io::Error` in the chain) | `NeurotacError`, `OSError` |

use pyo3::exceptions::{PyException, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use std::error::Error;

pyo3::create_exception!(
    neurotac,
    NeurotacError,
    PyException,
    "An error of the neurotac library; its message is the one the `neurotac` CLI prints."
);

static VALUE_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static OS_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// The subclass `name` of both `NeurotacError` and `builtin`, created once.
fn subclass<'py>(
    py: Python<'py>,
    cell: &'static PyOnceLock<Py<PyType>>,
    name: &str,
    builtin: Bound<'py, PyType>,
    doc: &str,
) -> PyResult<Bound<'py, PyType>> {
    let ty = cell.get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let bases = PyTuple::new(py, [py.get_type::<NeurotacError>(), builtin])?;
        let namespace = PyDict::new(py);
        namespace.set_item("__module__", "neurotac")?;
        namespace.set_item("__doc__", doc)?;
        let ty = py
            .get_type::<PyType>()
            .call1((name, bases, namespace))?
            .cast_into::<PyType>()?;
        Ok(ty.unbind())
    })?;
    Ok(ty.bind(py).clone())
}

/// `NeurotacValueError(NeurotacError, ValueError)`.
pub(crate) fn value_error_type(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    subclass(
        py,
        &VALUE_ERROR,
        "NeurotacValueError",
        py.get_type::<PyValueError>(),
        "An argument the neurotac library refuses (also a ValueError).",
    )
}

/// `NeurotacOSError(NeurotacError, OSError)`.
pub(crate) fn os_error_type(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    subclass(
        py,
        &OS_ERROR,
        "NeurotacOSError",
        py.get_type::<PyOSError>(),
        "A file neurotac cannot open, read or write (also an OSError).",
    )
}

/// Which exception an error becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// The caller's argument was refused.
    Value,
    /// Anything else; an `io::Error` among the causes makes it an OS error.
    Library,
}

/// `true` when `e` or one of its causes is an `io::Error`.
fn has_io_cause(e: &(dyn Error + 'static)) -> bool {
    let mut next = Some(e);
    while let Some(e) = next {
        if e.is::<std::io::Error>() {
            return true;
        }
        next = e.source();
    }
    false
}

/// The exception of `e`, with the CLI's message.
fn to_py_err(e: &(dyn Error + 'static), kind: Kind) -> PyErr {
    let message = neurotac_core::error_chain(e);
    Python::attach(|py| {
        let ty = match kind {
            Kind::Value => value_error_type(py),
            Kind::Library if has_io_cause(e) => os_error_type(py),
            Kind::Library => Ok(py.get_type::<NeurotacError>()),
        };
        match ty {
            Ok(ty) => PyErr::from_type(ty, message),
            Err(creating) => creating,
        }
    })
}

/// A `NeurotacValueError` with `message` (a binding-level check of an argument).
pub(crate) fn invalid(message: impl Into<String>) -> PyErr {
    let message = message.into();
    Python::attach(|py| match value_error_type(py) {
        Ok(ty) => PyErr::from_type(ty, message),
        Err(creating) => creating,
    })
}

/// Turns library results into Python exceptions.
pub(crate) trait OrRaise<T> {
    /// A refused argument: `NeurotacValueError`.
    fn or_value_error(self) -> PyResult<T>;
    /// Any other failure: `NeurotacOSError` when caused by I/O, else `NeurotacError`.
    fn or_raise(self) -> PyResult<T>;
}

impl<T, E: Error + 'static> OrRaise<T> for Result<T, E> {
    fn or_value_error(self) -> PyResult<T> {
        self.map_err(|e| to_py_err(&e, Kind::Value))
    }

    fn or_raise(self) -> PyResult<T> {
        self.map_err(|e| to_py_err(&e, Kind::Library))
    }
}
