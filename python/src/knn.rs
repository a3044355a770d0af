//! The KNN head on precomputed distances (`neurotac_core::knn`), with its documented tie
//! rules: distance ties at the k-th neighbour go to the lowest sample index, vote ties to the
//! smallest class label (scikit-learn's rule).

use crate::dataset::{array_vec, contiguous, labels_from};
use crate::errors::{OrRaise, invalid};
use ndarray::Ix2;
use neurotac_core::knn::{FittedKnn, Knn as CoreKnn};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;

/// A k-nearest-neighbour classifier on precomputed distance matrices (k = 4 in the paper).
///
/// ``Knn(k).fit(labels)`` keeps the training labels; ``predict(d)`` classifies new samples from
/// their ``n_new × n_train`` distances to the training samples; ``leave_one_out(d)`` classifies
/// each training sample from all the others given the ``n_train × n_train`` matrix. Distance
/// ties at the k-th neighbour go to the lowest index, vote ties to the smallest label.
#[pyclass(name = "Knn", module = "neurotac")]
pub(crate) struct Knn {
    knn: CoreKnn,
    fitted: Option<FittedKnn>,
}

impl Knn {
    /// The fitted classifier, or an error saying to fit it first.
    fn fitted(&self) -> PyResult<&FittedKnn> {
        self.fitted
            .as_ref()
            .ok_or_else(|| invalid("the classifier is not fitted: call fit(labels) first"))
    }
}

/// Predicted classes as int64.
fn classes(py: Python<'_>, classes: Vec<usize>) -> Bound<'_, PyArray1<i64>> {
    classes
        .into_iter()
        .map(|c| c as i64)
        .collect::<Vec<_>>()
        .into_pyarray(py)
}

#[pymethods]
impl Knn {
    /// A classifier with `k` ≥ 1 neighbours.
    #[new]
    #[pyo3(signature = (k=4))]
    fn new(k: usize) -> PyResult<Self> {
        Ok(Self {
            knn: CoreKnn::new(k).or_value_error()?,
            fitted: None,
        })
    }

    /// The number of neighbours.
    #[getter]
    fn k(&self) -> usize {
        self.knn.k()
    }

    /// Keeps the training `labels` (class indices ≥ 0, one per column of the distance matrices
    /// given later); returns the classifier. Needs at least `k` samples.
    fn fit<'py>(
        mut slf: PyRefMut<'py, Self>,
        labels: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let labels = labels_from(&array_vec::<i64>(labels)?)?;
        slf.fitted = Some(slf.knn.fit(&labels).or_value_error()?);
        Ok(slf)
    }

    /// The class (int64) of each new sample from its row of `distances` (`n_new × n_train`,
    /// numbers ≥ 0).
    fn predict<'py>(
        &self,
        py: Python<'py>,
        distances: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let fitted = self.fitted()?;
        let distances = contiguous::<f64, Ix2>(distances)?;
        let d = distances.as_array();
        let predicted = fitted.predict(d).or_value_error()?;
        Ok(classes(py, predicted))
    }

    /// The class (int64) of each training sample from all the others (leave-one-out in one
    /// pass): `square_distances` is the `n_train × n_train` matrix of the training samples;
    /// needs `k` < `n_train`.
    fn leave_one_out<'py>(
        &self,
        py: Python<'py>,
        square_distances: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let fitted = self.fitted()?;
        let square_distances = contiguous::<f64, Ix2>(square_distances)?;
        let d = square_distances.as_array();
        let predicted = fitted.leave_one_out(d).or_value_error()?;
        Ok(classes(py, predicted))
    }

    fn __repr__(&self) -> String {
        match &self.fitted {
            Some(f) => format!("Knn(k={}, fitted on {} samples)", self.knn.k(), f.n_train()),
            None => format!("Knn(k={})", self.knn.k()),
        }
    }
}
