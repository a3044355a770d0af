//! Long computations run without the GIL, on rayon's global pool or on a pool of a chosen size.

use crate::errors::OrRaise;
use neurotac_experiments::threads::with_threads;
use pyo3::marker::Ungil;
use pyo3::prelude::*;

/// Runs `work` with the GIL released (other Python threads go on meanwhile): on rayon's global
/// pool when `threads` is `None` (one thread per core, or `RAYON_NUM_THREADS` if set when the
/// pool first starts), else on a pool of `threads` threads (0: one per core).
pub(crate) fn detached<T, F>(py: Python<'_>, threads: Option<usize>, work: F) -> PyResult<T>
where
    T: Ungil + Send,
    F: Ungil + Send + FnOnce() -> T,
{
    py.detach(|| match threads {
        None => Ok(work()),
        Some(n) => with_threads(n, work),
    })
    .or_raise()
}
