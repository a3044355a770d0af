//! The KNN head: k nearest neighbours on a precomputed distance matrix (the paper uses k = 4).
//!
//! # Tie rules (documented, tested)
//! - **Distance ties at the k-th neighbour: the lowest sample index wins.** Neighbours are
//!   ordered by `(distance, index)`, so the result does not depend on scan order.
//! - **Vote ties: the smallest class label wins** (scikit-learn's rule: argmax over the vote
//!   counts returns the first maximum).
//!
//! Leave-one-out ([`Knn::leave_one_out`]) is one pass over the matrix: every sample's neighbours
//! among all others (itself excluded), which is exactly what `N` refits on `N − 1` samples would
//! predict. Rows run in parallel; each row's result depends only on that row.
//!
//! ```
//! use neurotac_core::knn::Knn;
//! use ndarray::array;
//! let d = array![[0.0, 1.0, 5.0], [1.0, 0.0, 4.0], [5.0, 4.0, 0.0]];
//! let knn = Knn::new(1)?;
//! assert_eq!(knn.leave_one_out(d.view(), &[7, 7, 2])?, vec![7, 7, 7]);
//! # Ok::<(), neurotac_core::KnnError>(())
//! ```

use crate::error::KnnError;
use ndarray::ArrayView2;
use rayon::prelude::*;

/// The `k` nearest candidates seen so far, ordered by `(distance, index)`.
///
/// Works with any totally ordered distance (`f64` without NaN, integer squared distances …).
#[derive(Debug, Clone, PartialEq)]
pub struct TopK<D> {
    k: usize,
    best: Vec<(D, usize)>,
}

impl<D: PartialOrd + Copy> TopK<D> {
    /// An empty list keeping at most `k` neighbours.
    pub fn new(k: usize) -> Self {
        Self {
            k,
            best: Vec::with_capacity(k + 1),
        }
    }

    /// Offers candidate `index` at `distance`; it is kept when it precedes the current k-th in
    /// `(distance, index)` order.
    #[inline]
    pub fn offer(&mut self, distance: D, index: usize) {
        let before = |a: &(D, usize)| a.0 < distance || (a.0 == distance && a.1 < index);
        if self.best.len() == self.k {
            match self.best.last() {
                Some(last) if before(last) => return,
                None => return,
                _ => {}
            }
            self.best.pop();
        }
        let at = self.best.partition_point(before);
        self.best.insert(at, (distance, index));
    }

    /// The neighbours, nearest first, as `(distance, index)`.
    pub fn neighbours(&self) -> &[(D, usize)] {
        &self.best
    }

    /// Empties the list, keeping `k`.
    pub fn clear(&mut self) {
        self.best.clear();
    }
}

/// The majority label of `neighbour_labels`; ties go to the smallest label.
pub fn vote(neighbour_labels: impl IntoIterator<Item = usize>) -> Option<usize> {
    let mut counts: Vec<(usize, usize)> = Vec::new();
    for l in neighbour_labels {
        match counts.iter_mut().find(|(label, _)| *label == l) {
            Some((_, c)) => *c += 1,
            None => counts.push((l, 1)),
        }
    }
    counts
        .into_iter()
        .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
        .map(|(label, _)| label)
}

/// A k-nearest-neighbour classifier on precomputed distances.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Knn {
    k: usize,
}

impl Default for Knn {
    /// k = 4, as in the paper.
    fn default() -> Self {
        Self { k: 4 }
    }
}

impl Knn {
    /// A classifier with `k ≥ 1` neighbours.
    pub fn new(k: usize) -> Result<Self, KnnError> {
        if k == 0 {
            return Err(KnnError::ZeroK);
        }
        Ok(Self { k })
    }

    /// The number of neighbours.
    pub fn k(&self) -> usize {
        self.k
    }

    fn check(
        &self,
        d: &ArrayView2<'_, f64>,
        labels: &[usize],
        n_train: usize,
    ) -> Result<(), KnnError> {
        let (rows, cols) = d.dim();
        if rows != cols || rows != labels.len() {
            return Err(KnnError::Shape {
                rows,
                cols,
                labels: labels.len(),
            });
        }
        if self.k > n_train {
            return Err(KnnError::KTooLarge { k: self.k, n_train });
        }
        if let Some(((row, col), &value)) = d.indexed_iter().find(|(_, v)| v.is_nan() || **v < 0.0)
        {
            return Err(KnnError::InvalidDistance { row, col, value });
        }
        Ok(())
    }

    fn predict_row(
        &self,
        row: &[f64],
        candidates: impl Iterator<Item = usize>,
        labels: &[usize],
    ) -> usize {
        let mut top = TopK::new(self.k);
        for j in candidates {
            top.offer(row[j], j);
        }
        vote(top.neighbours().iter().map(|&(_, j)| labels[j])).expect("k ≥ 1 neighbours")
    }

    /// Predicts every sample from all the others (leave-one-out in one pass). `distances` is the
    /// full `N × N` matrix, `labels` one class per sample.
    pub fn leave_one_out(
        &self,
        distances: ArrayView2<'_, f64>,
        labels: &[usize],
    ) -> Result<Vec<usize>, KnnError> {
        self.check(&distances, labels, labels.len().saturating_sub(1))?;
        let d = distances.as_standard_layout();
        let n = labels.len();
        let flat = d.as_slice().expect("standard layout is contiguous");
        Ok((0..n)
            .into_par_iter()
            .map(|i| {
                let row = &flat[i * n..(i + 1) * n];
                self.predict_row(row, (0..n).filter(|&j| j != i), labels)
            })
            .collect())
    }

    /// Predicts the samples `test` from the samples `train` (indices into the square matrix
    /// `distances` and into `labels`).
    pub fn predict(
        &self,
        distances: ArrayView2<'_, f64>,
        labels: &[usize],
        train: &[usize],
        test: &[usize],
    ) -> Result<Vec<usize>, KnnError> {
        self.check(&distances, labels, train.len())?;
        let n = labels.len();
        for (what, list) in [("train", train), ("test", test)] {
            if let Some(&index) = list.iter().find(|&&i| i >= n) {
                return Err(KnnError::IndexOutOfRange { what, index, n });
            }
        }
        let d = distances.as_standard_layout();
        let flat = d.as_slice().expect("standard layout is contiguous");
        Ok(test
            .par_iter()
            .map(|&i| self.predict_row(&flat[i * n..(i + 1) * n], train.iter().copied(), labels))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::{Array2, array};

    #[test]
    fn distance_ties_at_the_kth_neighbour_go_to_the_lowest_index() {
        let mut top = TopK::new(2);
        for (d, i) in [(1.0, 5), (1.0, 3), (0.5, 9), (1.0, 1)] {
            top.offer(d, i);
        }
        assert_eq!(top.neighbours(), &[(0.5, 9), (1.0, 1)]);
        // Any offering order gives the same result.
        let mut rev = TopK::new(2);
        for (d, i) in [(1.0, 1), (0.5, 9), (1.0, 3), (1.0, 5)] {
            rev.offer(d, i);
        }
        assert_eq!(rev.neighbours(), top.neighbours());
    }

    #[test]
    fn vote_ties_go_to_the_smallest_label() {
        assert_eq!(vote([3, 1, 3, 1]), Some(1));
        assert_eq!(vote([2, 2, 0, 1]), Some(2));
        assert_eq!(vote([5]), Some(5));
        assert_eq!(vote([]), None);
        // k = 4 with a 2–2 split between labels 4 and 2: label 2 wins.
        let d = array![
            [0.0, 1.0, 1.0, 1.0, 1.0],
            [1.0, 0.0, 9.0, 9.0, 9.0],
            [1.0, 9.0, 0.0, 9.0, 9.0],
            [1.0, 9.0, 9.0, 0.0, 9.0],
            [1.0, 9.0, 9.0, 9.0, 0.0]
        ];
        let labels = [0, 4, 2, 4, 2];
        let p = Knn::new(4)
            .unwrap()
            .predict(d.view(), &labels, &[1, 2, 3, 4], &[0])
            .unwrap();
        assert_eq!(p, vec![2]);
    }

    #[test]
    fn leave_one_out_equals_n_explicit_refits() {
        // 12 points on a line in 3 classes with some overlap and exact distance ties.
        let x: [f64; 12] = [0.0, 1.0, 2.0, 2.0, 3.0, 5.0, 6.0, 6.0, 7.0, 9.0, 10.0, 12.0];
        let labels = [0, 0, 1, 0, 1, 1, 2, 1, 2, 2, 2, 1];
        let n = x.len();
        let d = Array2::from_shape_fn((n, n), |(i, j)| (x[i] - x[j]).abs());
        for k in 1..=4 {
            let knn = Knn::new(k).unwrap();
            let loo = knn.leave_one_out(d.view(), &labels).unwrap();
            for (i, &predicted) in loo.iter().enumerate() {
                let train: Vec<usize> = (0..n).filter(|&j| j != i).collect();
                let refit = knn.predict(d.view(), &labels, &train, &[i]).unwrap();
                assert_eq!(predicted, refit[0], "k = {k}, sample {i}");
            }
        }
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        let d = array![[0.0, 1.0], [1.0, 0.0]];
        assert_eq!(Knn::new(0), Err(KnnError::ZeroK));
        assert_eq!(
            Knn::new(2).unwrap().leave_one_out(d.view(), &[0, 1]),
            Err(KnnError::KTooLarge { k: 2, n_train: 1 })
        );
        assert_eq!(
            Knn::new(1).unwrap().leave_one_out(d.view(), &[0, 1, 2]),
            Err(KnnError::Shape {
                rows: 2,
                cols: 2,
                labels: 3
            })
        );
        let nan = array![[0.0, f64::NAN], [1.0, 0.0]];
        assert!(matches!(
            Knn::new(1).unwrap().leave_one_out(nan.view(), &[0, 1]),
            Err(KnnError::InvalidDistance { row: 0, col: 1, .. })
        ));
        assert_eq!(
            Knn::new(1).unwrap().predict(d.view(), &[0, 1], &[0], &[2]),
            Err(KnnError::IndexOutOfRange {
                what: "test",
                index: 2,
                n: 2
            })
        );
    }
}
