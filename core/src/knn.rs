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
//!
//! # Fit, then classify new samples
//! [`Knn::fit`] keeps the training labels in a [`FittedKnn`], which classifies new samples from
//! their rectangular distances to the training set (`n_new × n_train`, e.g.
//! [`euclidean_cross_matrix`](crate::distance::euclidean_cross_matrix) or
//! [`PreparedVanRossum::cross_matrices`](crate::distance::PreparedVanRossum::cross_matrices)),
//! with the same neighbour search and tie rules. A [`Decision`] also reports the winning class's
//! share of the `k` votes.

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

    /// Offers every entry of `distances`, entry `o` as candidate `first_index + o` (the same
    /// list as [`offer`](Self::offer) on each in turn). Once `k` are kept, an entry farther
    /// than the k-th is skipped with one comparison, so a long row costs little more than
    /// reading it.
    pub fn offer_all(&mut self, distances: &[D], first_index: usize) {
        let mut rest = distances.iter().enumerate();
        while self.best.len() < self.k {
            match rest.next() {
                Some((o, &d)) => self.offer(d, first_index + o),
                None => return,
            }
        }
        let Some(&(mut farthest, _)) = self.best.last() else {
            return; // k = 0 keeps nothing
        };
        for (o, &d) in rest {
            if d > farthest {
                continue; // NaN is not farther: `offer` decides, as one by one
            }
            farthest = self.offer_when_full(d, first_index + o);
        }
    }

    /// [`offer`](Self::offer) on a full list, returning the k-th distance after it (out of
    /// line: [`offer_all`](Self::offer_all)'s loop stays a load and a compare).
    #[inline(never)]
    fn offer_when_full(&mut self, distance: D, index: usize) -> D {
        self.offer(distance, index);
        self.best[self.best.len() - 1].0
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
    vote_count(neighbour_labels).map(|(label, _)| label)
}

/// The majority label of `neighbour_labels` and its number of votes, `(label, votes)`; ties go
/// to the smallest label (the rule of [`vote`]).
pub fn vote_count(neighbour_labels: impl IntoIterator<Item = usize>) -> Option<(usize, usize)> {
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
}

/// One classification: the majority class of the `k` nearest neighbours and how many of them
/// voted for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Decision {
    /// The predicted class: the majority label of the neighbours (vote ties to the smallest).
    pub class: usize,
    /// Neighbours of that class.
    pub votes: usize,
    /// Neighbours that voted (the classifier's `k`).
    pub k: usize,
}

impl Decision {
    /// The winning class's share of the votes, `votes / k`, in `(0, 1]` (at least `1/k`; ties
    /// can leave it at `1/2` or below).
    pub fn vote_share(&self) -> f64 {
        self.votes as f64 / self.k as f64
    }
}

/// The `k` nearest columns of `row`, leaving out column `except` (leave-one-out's own sample).
fn nearest_in_row(k: usize, row: &[f64], except: Option<usize>) -> TopK<f64> {
    let mut top = TopK::new(k);
    match except {
        Some(i) => {
            top.offer_all(&row[..i], 0);
            top.offer_all(&row[i + 1..], i + 1);
        }
        None => top.offer_all(row, 0),
    }
    top
}

/// The decision of the neighbours in `top` (module tie rules).
fn decide(top: &TopK<f64>, labels: &[usize]) -> Decision {
    let neighbours = top.neighbours();
    let (class, votes) =
        vote_count(neighbours.iter().map(|&(_, j)| labels[j])).expect("k ≥ 1 neighbours");
    Decision {
        class,
        votes,
        k: neighbours.len(),
    }
}

/// Rejects the first NaN or negative entry (row-major order), naming its row and column.
fn check_values(d: &ArrayView2<'_, f64>) -> Result<(), KnnError> {
    let invalid = |v: &f64| v.is_nan() || *v < 0.0;
    // The common case, every value valid, as a branch-free scan (`!(v >= 0)` is NaN or
    // negative); the first invalid one is located only when there is one.
    let all_valid =
        |flat: &[f64]| (flat.chunks(512)).all(|c| c.iter().fold(true, |ok, &v| ok & (v >= 0.0)));
    if d.as_slice().is_some_and(all_valid) {
        return Ok(());
    }
    let first = match d.as_slice() {
        // Row-major already: a flat scan, and the index gives row and column.
        Some(flat) => flat.iter().position(invalid).map(|k| {
            let cols = d.ncols();
            ((k / cols, k % cols), flat[k])
        }),
        None => (d.indexed_iter()).find_map(|(at, v)| invalid(v).then_some((at, *v))),
    };
    match first {
        Some(((row, col), value)) => Err(KnnError::InvalidDistance { row, col, value }),
        None => Ok(()),
    }
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
        check_values(d)
    }

    /// A classifier for new samples against the training set with these `labels` (one class per
    /// training sample, in the order of the distance matrices' columns). Errors with
    /// [`KnnError::KTooLarge`] when there are fewer than `k` training samples (an empty
    /// training set is `n_train: 0`).
    pub fn fit(&self, labels: &[usize]) -> Result<FittedKnn, KnnError> {
        if self.k > labels.len() {
            return Err(KnnError::KTooLarge {
                k: self.k,
                n_train: labels.len(),
            });
        }
        Ok(FittedKnn {
            k: self.k,
            labels: labels.to_vec(),
        })
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
                decide(&nearest_in_row(self.k, row, Some(i)), labels).class
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
            .map(|&i| {
                let row = &flat[i * n..(i + 1) * n];
                let mut top = TopK::new(self.k);
                for &j in train {
                    top.offer(row[j], j);
                }
                decide(&top, labels).class
            })
            .collect())
    }
}

/// A KNN classifier fitted to a training set ([`Knn::fit`]): `k` and one label per training
/// sample. It classifies new samples from their distances to the training samples, an
/// `n_new × n_train` matrix (or one row of `n_train` distances), with the rules of
/// [`Knn`]: the `k` nearest by `(distance, index)`, the majority label, vote ties to the
/// smallest label. Distances must be numbers `≥ 0` ([`KnnError::InvalidDistance`] names the
/// first that is not) in as many columns as there are labels ([`KnnError::Shape`]).
///
/// ```
/// use neurotac_core::knn::Knn;
/// use ndarray::array;
/// let knn = Knn::new(3)?.fit(&[0, 0, 1, 1])?;
/// // Distances of two live samples to the four training samples.
/// let d = array![[0.1, 0.2, 0.3, 9.0], [5.0, 0.4, 0.3, 0.2]];
/// assert_eq!(knn.predict(d.view())?, vec![0, 1]);
/// let decision = knn.decide(&[0.1, 0.2, 0.3, 9.0])?;
/// assert_eq!((decision.class, decision.votes, decision.k), (0, 2, 3));
/// assert!((decision.vote_share() - 2.0 / 3.0).abs() < 1e-15);
/// # Ok::<(), neurotac_core::KnnError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FittedKnn {
    k: usize,
    labels: Vec<usize>,
}

impl FittedKnn {
    /// The number of neighbours.
    pub fn k(&self) -> usize {
        self.k
    }

    /// The training labels, one per column of the distance matrices.
    pub fn labels(&self) -> &[usize] {
        &self.labels
    }

    /// The number of training samples.
    pub fn n_train(&self) -> usize {
        self.labels.len()
    }

    /// Refuses a row that is not one distance ≥ 0 per training sample (errors name row 0).
    fn check_row(&self, row: &[f64]) -> Result<(), KnnError> {
        let n = self.labels.len();
        if row.len() != n {
            return Err(KnnError::Shape {
                rows: 1,
                cols: row.len(),
                labels: n,
            });
        }
        check_values(&ArrayView2::from_shape((1, n), row).expect("one row of n"))
    }

    /// The decision for one new sample from its distances to the `n_train` training samples
    /// (errors name row 0).
    pub fn decide(&self, row: &[f64]) -> Result<Decision, KnnError> {
        self.check_row(row)?;
        Ok(decide(&nearest_in_row(self.k, row, None), &self.labels))
    }

    /// `true` when the neighbours of `row` are not determined by the data: more training
    /// samples lie at the k-th neighbour's distance than places are left for them, and they
    /// are not all of one class, so the lowest indices picked decide the vote. A sample equally
    /// far from every training sample of several classes — a silent prefix — is such a tie. (A
    /// vote tie between classes of determined neighbours is not: its vote share says it.)
    pub fn is_distance_tie(&self, row: &[f64]) -> Result<bool, KnnError> {
        Ok(self.decide_noting_distance_tie(row)?.1)
    }

    /// [`decide`](Self::decide) and [`is_distance_tie`](Self::is_distance_tie) of `row` at
    /// once: the row checked and its neighbours found one time.
    pub fn decide_noting_distance_tie(&self, row: &[f64]) -> Result<(Decision, bool), KnnError> {
        self.check_row(row)?;
        let top = nearest_in_row(self.k, row, None);
        let decision = decide(&top, &self.labels);
        let neighbours = top.neighbours();
        let Some(&(kth, _)) = neighbours.last() else {
            return Ok((decision, false));
        };
        let places = neighbours.iter().filter(|&&(d, _)| d == kth).count();
        let mut at_kth = (row.iter().zip(&self.labels)).filter(|&(&d, _)| d == kth);
        let first_label = at_kth.clone().next().map(|(_, &l)| l);
        let tie = at_kth.clone().count() > places && at_kth.any(|(_, &l)| Some(l) != first_label);
        Ok((decision, tie))
    }

    /// The decision for each new sample: row `i` of `distances` (`n_new × n_train`) holds the
    /// distances of new sample `i` to the training samples. Rows run in parallel.
    pub fn decisions(&self, distances: ArrayView2<'_, f64>) -> Result<Vec<Decision>, KnnError> {
        let n = self.labels.len();
        let (rows, cols) = distances.dim();
        if cols != n {
            return Err(KnnError::Shape {
                rows,
                cols,
                labels: n,
            });
        }
        check_values(&distances)?;
        let d = distances.as_standard_layout();
        let flat = d.as_slice().expect("standard layout is contiguous");
        Ok(flat
            .par_chunks(n)
            .map(|row| decide(&nearest_in_row(self.k, row, None), &self.labels))
            .collect())
    }

    /// The class of each new sample ([`decisions`](Self::decisions) without the votes).
    pub fn predict(&self, distances: ArrayView2<'_, f64>) -> Result<Vec<usize>, KnnError> {
        Ok(self.decisions(distances)?.iter().map(|d| d.class).collect())
    }

    /// The decision for each training sample from all the others: `distances` is the training
    /// set's `n_train × n_train` matrix and row `i` skips column `i`, which is
    /// [`Knn::leave_one_out`]. Errors with [`KnnError::KTooLarge`] when `k > n_train − 1`.
    pub fn leave_one_out_decisions(
        &self,
        distances: ArrayView2<'_, f64>,
    ) -> Result<Vec<Decision>, KnnError> {
        let n = self.labels.len();
        let (rows, cols) = distances.dim();
        if rows != n || cols != n {
            return Err(KnnError::Shape {
                rows,
                cols,
                labels: n,
            });
        }
        if self.k > n - 1 {
            return Err(KnnError::KTooLarge {
                k: self.k,
                n_train: n - 1,
            });
        }
        check_values(&distances)?;
        let d = distances.as_standard_layout();
        let flat = d.as_slice().expect("standard layout is contiguous");
        Ok(flat
            .par_chunks(n)
            .enumerate()
            .map(|(i, row)| decide(&nearest_in_row(self.k, row, Some(i)), &self.labels))
            .collect())
    }

    /// The class of each training sample from all the others
    /// ([`leave_one_out_decisions`](Self::leave_one_out_decisions) without the votes).
    pub fn leave_one_out(&self, distances: ArrayView2<'_, f64>) -> Result<Vec<usize>, KnnError> {
        Ok(self
            .leave_one_out_decisions(distances)?
            .iter()
            .map(|d| d.class)
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
    fn offering_a_row_at_once_keeps_the_neighbours_of_offering_one_by_one() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..2000 {
            let n = rng.random_range(0..40);
            let k = rng.random_range(0..6);
            // Few distinct values: many ties at the k-th place.
            let row: Vec<f64> = (0..n)
                .map(|_| f64::from(rng.random_range(0..4u8)))
                .collect();
            let mut one_by_one = TopK::new(k);
            for (j, &d) in row.iter().enumerate() {
                one_by_one.offer(d, j);
            }
            let split = rng.random_range(0..=n);
            let mut at_once = TopK::new(k);
            // Either half first: the kept list does not depend on the order.
            if rng.random_range(0..2) == 0 {
                at_once.offer_all(&row[..split], 0);
                at_once.offer_all(&row[split..], split);
            } else {
                at_once.offer_all(&row[split..], split);
                at_once.offer_all(&row[..split], 0);
            }
            assert_eq!(
                at_once, one_by_one,
                "row {row:?}, k = {k}, split at {split}"
            );
        }
    }

    #[test]
    fn neighbours_picked_by_index_among_equally_far_classes_are_a_distance_tie() {
        // Labels 0 0 1 1, k = 2.
        let fitted = Knn::new(2).unwrap().fit(&[0, 0, 1, 1]).unwrap();
        // Equally far from every sample: the lowest indices (class 0) were picked.
        assert!(fitted.is_distance_tie(&[0.0; 4]).unwrap());
        // The two nearest are of class 0: no tie, whatever lies beyond.
        assert!(!fitted.is_distance_tie(&[0.1, 0.2, 0.5, 0.5]).unwrap());
        // One of each class nearest: a vote tie, but the neighbours are determined.
        assert!(!fitted.is_distance_tie(&[0.1, 0.9, 0.1, 0.9]).unwrap());
        // The second place is shared by classes 0 and 1 at the same distance.
        assert!(fitted.is_distance_tie(&[0.5, 0.1, 0.5, 0.9]).unwrap());
        // ... but not when the samples sharing it are of one class.
        let fitted = Knn::new(2).unwrap().fit(&[0, 1, 1, 1]).unwrap();
        assert!(!fitted.is_distance_tie(&[0.9, 0.1, 0.5, 0.5]).unwrap());
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
    fn decisions_report_the_votes_and_the_tie_rules_of_vote() {
        assert_eq!(vote_count([3, 1, 3, 1]), Some((1, 2)));
        assert_eq!(vote_count([2, 2, 0, 1]), Some((2, 2)));
        assert_eq!(vote_count([]), None);
        let fitted = Knn::new(4).unwrap().fit(&[0, 4, 2, 4, 2, 7]).unwrap();
        // Neighbours 1..=4 (index 5 is as near as 4 but has the higher index): 2–2 → label 2.
        let row = [9.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let tie = Decision {
            class: 2,
            votes: 2,
            k: 4,
        };
        assert_eq!(fitted.decide(&row).unwrap(), tie);
        assert_eq!(tie.vote_share(), 0.5);
        let d = array![
            [9.0, 1.0, 1.0, 1.0, 1.0, 1.0],
            [0.0, 0.5, 3.0, 0.2, 3.0, 0.1]
        ];
        let all = fitted.decisions(d.view()).unwrap();
        assert_eq!(all[0], tie);
        assert_eq!((all[1].class, all[1].votes), (4, 2));
        assert_eq!(fitted.predict(d.view()).unwrap(), vec![2, 4]);
        // k = 1 on exact duplicates: the lowest index.
        let one = Knn::new(1).unwrap().fit(&[5, 6]).unwrap();
        assert_eq!(one.decide(&[0.0, 0.0]).unwrap().class, 5);
        assert_eq!(one.decide(&[0.0, 0.0]).unwrap().vote_share(), 1.0);
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
        // A view in another memory order is named in its own rows and columns.
        let negative = array![[0.0, 1.0, 2.0], [-2.0, 0.0, 1.0], [3.0, -1.0, 0.0]];
        assert!(matches!(
            Knn::new(1).unwrap().leave_one_out(negative.t(), &[0, 1, 2]),
            Err(KnnError::InvalidDistance { row: 0, col: 1, value }) if value == -2.0
        ));
        assert_eq!(
            Knn::new(1).unwrap().predict(d.view(), &[0, 1], &[0], &[2]),
            Err(KnnError::IndexOutOfRange {
                what: "test",
                index: 2,
                n: 2
            })
        );
        // Fitted: empty or too small training sets, wrong widths, NaN or negative distances.
        let k2 = Knn::new(2).unwrap();
        assert_eq!(k2.fit(&[]), Err(KnnError::KTooLarge { k: 2, n_train: 0 }));
        assert_eq!(k2.fit(&[1]), Err(KnnError::KTooLarge { k: 2, n_train: 1 }));
        let fitted = k2.fit(&[0, 1, 1]).unwrap();
        let shape = |rows, cols| KnnError::Shape {
            rows,
            cols,
            labels: 3,
        };
        assert_eq!(fitted.decide(&[0.0, 1.0]), Err(shape(1, 2)));
        assert_eq!(fitted.predict(d.view()), Err(shape(2, 2)));
        assert_eq!(fitted.leave_one_out(d.view()), Err(shape(2, 2)));
        let bad = array![[0.0, 1.0, 2.0], [1.0, -0.5, 2.0]];
        assert_eq!(
            fitted.predict(bad.view()),
            Err(KnnError::InvalidDistance {
                row: 1,
                col: 1,
                value: -0.5
            })
        );
        assert!(matches!(
            fitted.decide(&[0.0, 1.0, f64::NAN]),
            Err(KnnError::InvalidDistance { row: 0, col: 2, .. })
        ));
        let square = array![[0.0, 1.0, 2.0], [1.0, 0.0, 2.0], [2.0, 2.0, 0.0]];
        assert_eq!(
            Knn::new(3)
                .unwrap()
                .fit(&[0, 1, 1])
                .unwrap()
                .leave_one_out(square.view()),
            Err(KnnError::KTooLarge { k: 3, n_train: 2 })
        );
        // 1–1 vote ties for samples 1 and 2 go to label 0.
        assert_eq!(fitted.leave_one_out(square.view()), Ok(vec![1, 0, 0]));
        assert_eq!(
            fitted.leave_one_out(square.view()),
            k2.leave_one_out(square.view(), &[0, 1, 1])
        );
    }
}
