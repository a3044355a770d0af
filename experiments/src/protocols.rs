//! Evaluation protocols of the paper on a precomputed distance matrix: leave-one-out (one pass),
//! a seeded stratified 80/20 split, stratified k-fold; confusion matrices; accuracy as the paper
//! reports it (mean ± standard deviation of the per-sample hits) and with a Wilson 95 % interval.

use crate::error::ExperimentError;
use ndarray::ArrayView2;
use neurotac_core::{Knn, KnnError};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// z for a two-sided 95 % normal interval.
pub const Z_95: f64 = 1.959_963_984_540_054;

/// Which protocol to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Protocol {
    /// Leave-one-out: every sample predicted from all others.
    LeaveOneOut,
    /// One stratified split: `test_fraction` of each class (rounded) held out, drawn with `seed`.
    Split {
        /// Fraction of each class in the test set, in (0, 1). The paper: 0.2.
        test_fraction: f64,
        /// Seed of the shuffle.
        seed: u64,
    },
    /// Stratified k-fold: every sample tested once, each fold predicted from the other folds.
    KFold {
        /// Number of folds (≥ 2).
        folds: usize,
        /// Seed of the shuffle.
        seed: u64,
    },
}

/// Accuracy of a set of predictions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Accuracy {
    /// Number of predictions.
    pub n: usize,
    /// Correct predictions.
    pub hits: usize,
    /// Mean of the per-sample hits (0 or 1): the accuracy.
    pub mean: f64,
    /// Population standard deviation of the per-sample hits, `√(p(1 − p))` (the paper's ±).
    pub std: f64,
    /// Lower end of the Wilson 95 % interval.
    pub wilson_low: f64,
    /// Upper end of the Wilson 95 % interval.
    pub wilson_high: f64,
}

/// Wilson score interval for `hits` successes in `n` trials at normal quantile `z`:
/// `(p̂ + z²/2n ± z·√(p̂(1 − p̂)/n + z²/4n²)) / (1 + z²/n)`; `(0, 1)` when `n = 0`.
pub fn wilson_interval(hits: usize, n: usize, z: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let n_f = n as f64;
    let p = hits as f64 / n_f;
    let z2 = z * z;
    let denom = 1.0 + z2 / n_f;
    let centre = (p + z2 / (2.0 * n_f)) / denom;
    let half = z * (p * (1.0 - p) / n_f + z2 / (4.0 * n_f * n_f)).sqrt() / denom;
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// McNemar's exact test of two classifiers on the same samples: `b` samples the first got
/// right and the second wrong, `c` the reverse, and the two-sided p-value of the exact
/// binomial test of `b` against `Bin(b + c, ½)`: `min(1, 2 · P[X ≤ min(b, c)])`
/// ([`mcnemar_exact_p`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct McNemar {
    /// Samples the first classifier (the reference) got right and the second wrong.
    pub b: usize,
    /// Samples the second got right and the first wrong.
    pub c: usize,
    /// Two-sided exact p-value (1 when `b = c`).
    pub p: f64,
}

impl McNemar {
    /// The test of `predicted` against `reference`, both predictions of the samples whose
    /// classes are `truth`, in the same order; `None` when the three lengths differ.
    pub fn of(reference: &[usize], predicted: &[usize], truth: &[usize]) -> Option<Self> {
        if reference.len() != truth.len() || predicted.len() != truth.len() {
            return None;
        }
        let (mut b, mut c) = (0, 0);
        for ((&r, &p), &t) in reference.iter().zip(predicted).zip(truth) {
            match (r == t, p == t) {
                (true, false) => b += 1,
                (false, true) => c += 1,
                _ => {}
            }
        }
        Some(Self {
            b,
            c,
            p: mcnemar_exact_p(b, c),
        })
    }
}

/// The two-sided exact McNemar p-value of `b` and `c` discordant pairs:
/// `min(1, 2 · Σ_{i ≤ min(b, c)} C(b + c, i) / 2^(b + c))`, summed in log space so that any
/// count is finite; 1 when `b + c = 0`.
pub fn mcnemar_exact_p(b: usize, c: usize) -> f64 {
    let n = b + c;
    let k = b.min(c);
    // C(n, i) / 2^n term by term, C(n, i + 1) = C(n, i) · (n − i) / (i + 1): from 2^−n itself
    // (exact) while it is a normal f64, else in log space.
    let step = |i: usize| (n - i) as f64 / (i + 1) as f64;
    let mut tail = 0.0;
    if n <= 1000 {
        let mut term = 0.5f64.powi(n as i32);
        for i in 0..=k {
            tail += term;
            term *= step(i);
        }
    } else {
        let mut ln_term = n as f64 * 0.5f64.ln();
        for i in 0..=k {
            tail += ln_term.exp();
            ln_term += step(i).ln();
        }
    }
    (2.0 * tail).min(1.0)
}

impl Accuracy {
    /// The accuracy of `predicted` against `truth` (same length).
    pub fn of(predicted: &[usize], truth: &[usize]) -> Self {
        let n = predicted.len().min(truth.len());
        let hits = predicted.iter().zip(truth).filter(|(p, t)| p == t).count();
        let mean = if n == 0 { 0.0 } else { hits as f64 / n as f64 };
        let (wilson_low, wilson_high) = wilson_interval(hits, n, Z_95);
        Self {
            n,
            hits,
            mean,
            std: (mean * (1.0 - mean)).sqrt(),
            wilson_low,
            wilson_high,
        }
    }
}

/// Counts of (true class, predicted class): `counts[t][p]`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ConfusionMatrix {
    /// Row = true class, column = predicted class.
    pub counts: Vec<Vec<usize>>,
}

impl ConfusionMatrix {
    /// The confusion matrix of `predicted` against `truth` over `n_classes` classes (labels
    /// beyond are counted in an enlarged matrix, never dropped).
    pub fn of(predicted: &[usize], truth: &[usize], n_classes: usize) -> Self {
        let size = predicted
            .iter()
            .chain(truth)
            .map(|&l| l + 1)
            .max()
            .unwrap_or(0)
            .max(n_classes);
        let mut counts = vec![vec![0; size]; size];
        for (&p, &t) in predicted.iter().zip(truth) {
            counts[t][p] += 1;
        }
        Self { counts }
    }

    /// Samples of class `truth` (the row's sum).
    pub fn class_samples(&self, truth: usize) -> usize {
        self.counts.get(truth).map_or(0, |row| row.iter().sum())
    }

    /// The fraction of class `truth`'s samples predicted as `predicted`; `None` when the class
    /// has no samples.
    pub fn rate(&self, truth: usize, predicted: usize) -> Option<f64> {
        let n = self.class_samples(truth);
        let count = self.counts.get(truth)?.get(predicted).copied().unwrap_or(0);
        (n > 0).then(|| count as f64 / n as f64)
    }

    /// The recall of every class (its samples predicted as itself, the diagonal over the row);
    /// `None` for a class without samples.
    pub fn recall(&self) -> Vec<Option<f64>> {
        (0..self.counts.len()).map(|c| self.rate(c, c)).collect()
    }

    /// Every off-diagonal cell with a count: `(true class, predicted class, count)`.
    pub fn errors(&self) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
        self.counts.iter().enumerate().flat_map(|(t, row)| {
            row.iter()
                .enumerate()
                .filter(move |&(p, &n)| p != t && n > 0)
                .map(move |(p, &n)| (t, p, n))
        })
    }
}

/// The outcome of a protocol.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Indices of the samples that were predicted (all for LOO and k-fold; the test set for a split).
    pub tested: Vec<usize>,
    /// The prediction for each tested sample.
    pub predicted: Vec<usize>,
    /// Accuracy over all tested samples.
    pub accuracy: Accuracy,
    /// Accuracy of each fold (k-fold only; empty otherwise).
    pub fold_accuracies: Vec<f64>,
    /// Confusion matrix over the tested samples.
    pub confusion: ConfusionMatrix,
}

impl Evaluation {
    /// Mean and (population) standard deviation of the per-fold accuracies; `None` without
    /// folds (leave-one-out, split).
    pub fn fold_mean_std(&self) -> Option<(f64, f64)> {
        let f = &self.fold_accuracies;
        if f.is_empty() {
            return None;
        }
        let n = f.len() as f64;
        let mean = f.iter().sum::<f64>() / n;
        let var = f.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
        Some((mean, var.sqrt()))
    }
}

fn by_class(labels: &[usize], seed: u64) -> Vec<Vec<usize>> {
    let n_classes = labels.iter().map(|&l| l + 1).max().unwrap_or(0);
    let mut classes = vec![Vec::new(); n_classes];
    for (i, &l) in labels.iter().enumerate() {
        classes[l].push(i);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for members in &mut classes {
        // Fisher–Yates.
        for i in (1..members.len()).rev() {
            let j = rng.random_range(0..=i);
            members.swap(i, j);
        }
    }
    classes
}

/// A seeded stratified split: from each class, `round(test_fraction · n_class)` samples (shuffled
/// with `seed`) go to the test set. Returns `(train, test)`, each sorted. A class that would
/// end up only in one of the two sets (too few samples for the fraction, e.g. one sample) is
/// an error, [`ExperimentError::ClassTooSmallToSplit`].
pub fn stratified_split(
    labels: &[usize],
    test_fraction: f64,
    seed: u64,
) -> Result<(Vec<usize>, Vec<usize>), ExperimentError> {
    if !(test_fraction > 0.0 && test_fraction < 1.0) {
        return Err(ExperimentError::InvalidParameter {
            what: "test_fraction",
            value: test_fraction,
            expected: "in (0, 1)",
        });
    }
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for (class, members) in by_class(labels, seed).into_iter().enumerate() {
        let n_test = (test_fraction * members.len() as f64).round() as usize;
        if !members.is_empty() && (n_test == 0 || n_test == members.len()) {
            return Err(ExperimentError::ClassTooSmallToSplit {
                class,
                samples: members.len(),
                test_fraction,
            });
        }
        test.extend_from_slice(&members[..n_test]);
        train.extend_from_slice(&members[n_test..]);
    }
    train.sort_unstable();
    test.sort_unstable();
    Ok((train, test))
}

/// Seeded stratified k-fold: each class is shuffled with `seed` and dealt round-robin into
/// `folds` test folds (the dealing continues across classes, so fold sizes differ by at most
/// one). Returns the test folds, each sorted.
pub fn stratified_kfold(
    labels: &[usize],
    folds: usize,
    seed: u64,
) -> Result<Vec<Vec<usize>>, ExperimentError> {
    if folds < 2 || folds > labels.len() {
        return Err(ExperimentError::InvalidParameter {
            what: "folds",
            value: folds as f64,
            expected: "≥ 2 and ≤ the number of samples",
        });
    }
    let mut out = vec![Vec::new(); folds];
    let mut position = 0;
    for members in by_class(labels, seed) {
        for i in members {
            out[position % folds].push(i);
            position += 1;
        }
    }
    out.iter_mut().for_each(|f| f.sort_unstable());
    Ok(out)
}

/// Runs `protocol` with `knn` on the full `N × N` `distances` of samples labelled `labels`.
pub fn evaluate(
    distances: ArrayView2<'_, f64>,
    labels: &[usize],
    n_classes: usize,
    knn: Knn,
    protocol: Protocol,
) -> Result<Evaluation, ExperimentError> {
    if labels.is_empty() && distances.nrows() > 0 {
        return Err(KnnError::Unlabelled.into());
    }
    let mut fold_accuracies = Vec::new();
    let (tested, predicted) = match protocol {
        Protocol::LeaveOneOut => (
            (0..labels.len()).collect(),
            knn.leave_one_out(distances, labels)?,
        ),
        Protocol::Split {
            test_fraction,
            seed,
        } => {
            let (train, test) = stratified_split(labels, test_fraction, seed)?;
            let predicted = knn.predict(distances, labels, &train, &test)?;
            (test, predicted)
        }
        Protocol::KFold { folds, seed } => {
            let folds = stratified_kfold(labels, folds, seed)?;
            let mut predicted = vec![0; labels.len()];
            for test in &folds {
                let mut in_test = vec![false; labels.len()];
                test.iter().for_each(|&i| in_test[i] = true);
                let train: Vec<usize> = (0..labels.len()).filter(|&i| !in_test[i]).collect();
                let p = knn.predict(distances, labels, &train, test)?;
                let truth: Vec<usize> = test.iter().map(|&i| labels[i]).collect();
                fold_accuracies.push(Accuracy::of(&p, &truth).mean);
                for (&i, p) in test.iter().zip(p) {
                    predicted[i] = p;
                }
            }
            ((0..labels.len()).collect(), predicted)
        }
    };
    let truth: Vec<usize> = tested.iter().map(|&i: &usize| labels[i]).collect();
    Ok(Evaluation {
        accuracy: Accuracy::of(&predicted, &truth),
        confusion: ConfusionMatrix::of(&predicted, &truth, n_classes),
        tested,
        predicted,
        fold_accuracies,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;

    #[test]
    fn mcnemar_exact_p_values_match_the_binomial_tables() {
        // 0 of 6 discordant pairs one way: 2 · (1/2)^6.
        assert_eq!(mcnemar_exact_p(0, 6), 0.03125);
        assert_eq!(mcnemar_exact_p(6, 0), 0.03125);
        // Balanced discordance is no evidence at all.
        for n in [0, 1, 5, 40] {
            assert_eq!(mcnemar_exact_p(n, n), 1.0);
        }
        // b = 2, c = 10: 2 · (1 + 12 + 66) / 4096 = 0.03857…
        assert!((mcnemar_exact_p(2, 10) - 158.0 / 4096.0).abs() < 1e-12);
        // b = 1, c = 9: 2 · 11 / 1024.
        assert!((mcnemar_exact_p(1, 9) - 22.0 / 1024.0).abs() < 1e-12);
        // Large counts stay finite and tiny where the imbalance is large.
        let p = mcnemar_exact_p(100, 2000);
        assert!((0.0..1e-300).contains(&p));
        assert!((mcnemar_exact_p(1000, 1001) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn mcnemar_counts_only_the_discordant_samples() {
        let truth = [0, 1, 2, 0, 1, 2];
        let reference = [0, 1, 2, 1, 1, 0]; // right on 0, 1, 2, 4
        let other = [0, 2, 2, 0, 0, 2]; // right on 0, 2, 3, 5
        let t = McNemar::of(&reference, &other, &truth).unwrap();
        assert_eq!((t.b, t.c), (2, 2));
        assert_eq!(t.p, 1.0);
        assert!(McNemar::of(&reference, &other[..5], &truth).is_none());
    }

    #[test]
    fn recall_rates_and_errors_are_read_from_the_rows() {
        // Class 0: 3 of 4 right, 1 predicted as 2; class 1: none; class 2: 1 of 2 right.
        let m = ConfusionMatrix::of(&[0, 0, 2, 0, 2, 0], &[0, 0, 0, 0, 2, 2], 3);
        assert_eq!(m.recall(), vec![Some(0.75), None, Some(0.5)]);
        assert_eq!(m.rate(0, 2), Some(0.25));
        assert_eq!(m.rate(1, 0), None);
        assert_eq!(m.rate(2, 0), Some(0.5));
        assert_eq!(m.class_samples(0), 4);
        assert_eq!(m.errors().collect::<Vec<_>>(), vec![(0, 2, 1), (2, 0, 1)]);
    }

    #[test]
    fn wilson_interval_known_values() {
        // Reference values (Wilson 1927; e.g. Newcombe 1998, Table I): 8/10 → 0.4902–0.9433,
        // 0/10 → 0–0.2775, 10/10 → 0.7225–1.
        let close =
            |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 5e-5 && (a.1 - b.1).abs() < 5e-5;
        assert!(
            close(wilson_interval(8, 10, Z_95), (0.4902, 0.9433)),
            "{:?}",
            wilson_interval(8, 10, Z_95)
        );
        assert!(close(wilson_interval(0, 10, Z_95), (0.0, 0.2775)));
        assert!(close(wilson_interval(10, 10, Z_95), (0.7225, 1.0)));
        assert_eq!(wilson_interval(0, 0, Z_95), (0.0, 1.0));
        // The paper's "78.5 ± 41.1": std of per-sample hits at p = 0.785.
        let hits = 785;
        let predicted: Vec<usize> = (0..1000).map(|i| usize::from(i >= hits)).collect();
        let a = Accuracy::of(&predicted, &vec![0; 1000]);
        assert!(
            (a.mean - 0.785).abs() < 1e-12 && (a.std - 0.411).abs() < 5e-4,
            "{a:?}"
        );
    }

    #[test]
    fn splits_are_stratified_seeded_and_partition_the_samples() {
        let labels: Vec<usize> = (0..55).map(|i| i % 11).collect();
        let (train, test) = stratified_split(&labels, 0.2, 3).unwrap();
        assert_eq!(test.len(), 11);
        assert_eq!(train.len() + test.len(), 55);
        for c in 0..11 {
            assert_eq!(test.iter().filter(|&&i| labels[i] == c).count(), 1);
        }
        assert_eq!(
            stratified_split(&labels, 0.2, 3).unwrap(),
            (train.clone(), test.clone())
        );
        assert_ne!(stratified_split(&labels, 0.2, 4).unwrap().1, test);
        let folds = stratified_kfold(&labels, 5, 1).unwrap();
        let mut all: Vec<usize> = folds.concat();
        all.sort_unstable();
        assert_eq!(all, (0..55).collect::<Vec<_>>());
        assert!(folds.iter().all(|f| f.len() == 11));
        assert!(stratified_split(&labels, 1.0, 0).is_err());
        // A one-sample class can be in the training or the test set, not both: refused.
        let mut lonely = labels.clone();
        lonely.push(11);
        let err = stratified_split(&lonely, 0.2, 3).unwrap_err();
        assert!(
            matches!(
                err,
                ExperimentError::ClassTooSmallToSplit {
                    class: 11,
                    samples: 1,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("leave-one-out"), "{err}");
        assert!(stratified_kfold(&labels, 1, 0).is_err());
        assert!(stratified_kfold(&labels, 56, 0).is_err());
    }

    #[test]
    fn protocols_classify_separable_data_and_fill_the_confusion_matrix() {
        // Two tight clusters far apart: every protocol is perfect.
        let x: Vec<f64> = (0..20)
            .map(|i| {
                if i % 2 == 0 {
                    i as f64 * 0.01
                } else {
                    100.0 + i as f64 * 0.01
                }
            })
            .collect();
        let labels: Vec<usize> = (0..20).map(|i| i % 2).collect();
        let d = Array2::from_shape_fn((20, 20), |(i, j)| (x[i] - x[j]).abs());
        for protocol in [
            Protocol::LeaveOneOut,
            Protocol::Split {
                test_fraction: 0.2,
                seed: 1,
            },
            Protocol::KFold { folds: 4, seed: 1 },
        ] {
            let e = evaluate(d.view(), &labels, 2, Knn::default(), protocol).unwrap();
            assert_eq!(e.accuracy.hits, e.accuracy.n, "{protocol:?}");
            assert_eq!(e.confusion.counts[0][1] + e.confusion.counts[1][0], 0);
            assert_eq!(
                e.confusion.counts[0][0] + e.confusion.counts[1][1],
                e.tested.len()
            );
        }
        let e = evaluate(
            d.view(),
            &labels,
            2,
            Knn::default(),
            Protocol::KFold { folds: 4, seed: 1 },
        )
        .unwrap();
        assert_eq!(e.fold_accuracies, vec![1.0; 4]);
        assert!(matches!(
            evaluate(
                d.view(),
                &labels,
                2,
                Knn::new(20).unwrap(),
                Protocol::LeaveOneOut
            ),
            Err(ExperimentError::Knn(KnnError::KTooLarge {
                k: 20,
                n_train: 19
            }))
        ));
    }

    #[test]
    fn fold_summary_is_the_mean_and_population_std_of_the_folds() {
        let accuracy = Accuracy::of(&[0, 1], &[0, 0]);
        let e = |folds: Vec<f64>| Evaluation {
            tested: Vec::new(),
            predicted: Vec::new(),
            accuracy,
            fold_accuracies: folds,
            confusion: ConfusionMatrix { counts: Vec::new() },
        };
        assert_eq!(e(vec![]).fold_mean_std(), None);
        assert_eq!(e(vec![0.5, 1.0]).fold_mean_std(), Some((0.75, 0.25)));
    }
}
