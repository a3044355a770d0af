//! A KNN fitted to a training set classifies new samples from rectangular distances (new ×
//! training) exactly as the square-matrix KNN does, for the distances of all four codings.

use ndarray::{Array2, ArrayView2, s};
use neurotac_core::coding::{FeatureCoding, feature_matrix};
use neurotac_core::distance::{euclidean_cross_matrix, euclidean_distance_matrix};
use neurotac_core::knn::{FittedKnn, Knn};
use neurotac_core::{
    IntensiveCoding, KnnError, MultiSpikeTrain, SpatialCoding, TemporalCoding, VanRossum,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const CHANNELS: usize = 49;
const N: usize = 44;
const N_TRAIN: usize = 33;
/// Van Rossum τ (s) and cos θ.
const TAU_S: f64 = 0.02;
const COS: f64 = 0.4;

/// `N` samples of 49 channels over 1 s in 4 classes (class `c` fires about `2 + 2c` spikes per
/// channel, at 1-ms stamps so that counts and bins tie often), with their labels.
fn labelled_samples(seed: u64) -> (Vec<MultiSpikeTrain>, Vec<usize>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let labels: Vec<usize> = (0..N).map(|i| (i * 7) % 4).collect();
    let samples = labels
        .iter()
        .map(|&class| {
            MultiSpikeTrain::from_unsorted_channels((0..CHANNELS).map(|_| {
                let k = rng.random_range(0..=(4 + 4 * class));
                (0..k)
                    .map(|_| f64::from(rng.random_range(0..1000u32)) / 1e3)
                    .collect::<Vec<_>>()
            }))
            .unwrap()
        })
        .collect();
    (samples, labels)
}

/// For every k: the fitted leave-one-out on the training set equals [`Knn::leave_one_out`] on
/// its square matrix, and the fitted predictions from `cross` (test × training rows of `d`, or
/// computed apart) equal [`Knn::predict`] on the square matrix of all samples.
fn assert_fitted_equals_square(
    d: ArrayView2<'_, f64>,
    cross: ArrayView2<'_, f64>,
    labels: &[usize],
    what: &str,
) {
    let train: Vec<usize> = (0..N_TRAIN).collect();
    let test: Vec<usize> = (N_TRAIN..N).collect();
    let d_train = d.slice(s![..N_TRAIN, ..N_TRAIN]);
    for k in 1..=5 {
        let knn = Knn::new(k).unwrap();
        let fitted: FittedKnn = knn.fit(&labels[..N_TRAIN]).unwrap();
        assert_eq!(
            fitted.leave_one_out(d_train).unwrap(),
            knn.leave_one_out(d_train, &labels[..N_TRAIN]).unwrap(),
            "{what}, k = {k}: leave-one-out"
        );
        let expected = knn.predict(d, labels, &train, &test).unwrap();
        assert_eq!(
            fitted.predict(d.slice(s![N_TRAIN.., ..N_TRAIN])).unwrap(),
            expected,
            "{what}, k = {k}: rows of the square matrix"
        );
        let decisions = fitted.decisions(cross).unwrap();
        let classes: Vec<usize> = decisions.iter().map(|d| d.class).collect();
        assert_eq!(classes, expected, "{what}, k = {k}: cross distances");
        for (i, decision) in decisions.iter().enumerate() {
            assert_eq!(decision.k, k);
            assert!(decision.votes >= 1 && decision.votes <= k);
            assert_eq!(
                fitted.decide(cross.row(i).as_slice().unwrap()).unwrap(),
                *decision
            );
        }
    }
}

/// The Euclidean codings: square matrix of all samples, and new × training computed apart,
/// equal bit for bit to the square matrix's rows.
fn check_feature_coding<C: FeatureCoding>(coding: &C, what: &str) {
    let (samples, labels) = labelled_samples(1);
    let features = feature_matrix(coding, &samples).unwrap();
    let d = euclidean_distance_matrix(features.view(), &neurotac_core::OneProcess).unwrap();
    let cross = euclidean_cross_matrix(
        features.slice(s![N_TRAIN.., ..]),
        features.slice(s![..N_TRAIN, ..]),
    )
    .unwrap();
    assert_eq!(
        cross,
        d.slice(s![N_TRAIN.., ..N_TRAIN]),
        "{what}: bit for bit"
    );
    assert_fitted_equals_square(d.view(), cross.view(), &labels, what);
}

#[test]
fn intensive_coding_fit_predict_equals_the_square_knn() {
    check_feature_coding(&IntensiveCoding::new(), "intensive");
}

#[test]
fn spatial_coding_fit_predict_equals_the_square_knn() {
    check_feature_coding(&SpatialCoding::new(), "spatial");
}

#[test]
fn temporal_coding_fit_predict_equals_the_square_knn() {
    check_feature_coding(&TemporalCoding::from_ms(100, 1000).unwrap(), "temporal");
}

#[test]
fn spatiotemporal_coding_fit_predict_equals_the_square_knn() {
    let (samples, labels) = labelled_samples(2);
    let vr = VanRossum::new(TAU_S).unwrap();
    let d = vr
        .matrices(&samples, &neurotac_core::OneProcess)
        .unwrap()
        .distances(COS)
        .unwrap();
    // New samples against the prepared training set only.
    let prepared = vr.prepare(&samples[..N_TRAIN]).unwrap();
    let cross = prepared
        .cross_matrices(&samples[N_TRAIN..])
        .unwrap()
        .distances(COS)
        .unwrap();
    let rows = d.slice(s![N_TRAIN.., ..N_TRAIN]);
    for (a, b) in cross.iter().zip(rows) {
        assert!((a - b).abs() <= 1e-12 * b, "{a} vs {b}");
    }
    assert_fitted_equals_square(d.view(), cross.view(), &labels, "spatiotemporal");
}

#[test]
fn a_live_prefix_is_classified_against_the_training_prefixes() {
    // The online use: after T seconds, the live sample's prefix against the training samples'
    // prefixes over the same elapsed time; the whole trial at T = ∞.
    let (samples, labels) = labelled_samples(3);
    let prepared = VanRossum::new(TAU_S)
        .unwrap()
        .prepare(&samples[..N_TRAIN])
        .unwrap();
    let fitted = Knn::default().fit(&labels[..N_TRAIN]).unwrap();
    let live = &samples[N_TRAIN..N_TRAIN + 1];
    for t_end_s in [0.25, 0.5, 1.0, f64::INFINITY] {
        let d = prepared
            .cross_matrices_until(live, t_end_s)
            .unwrap()
            .distances(COS)
            .unwrap();
        let decision = fitted.decide(d.row(0).as_slice().unwrap()).unwrap();
        assert!(decision.class < 4 && decision.vote_share() > 0.0 && decision.vote_share() <= 1.0);
        // The same as preparing the prefixes from scratch.
        let prefix = |o: &MultiSpikeTrain| o.window(f64::NEG_INFINITY, t_end_s).unwrap();
        let cut: Vec<MultiSpikeTrain> = samples[..=N_TRAIN].iter().map(prefix).collect();
        let all = VanRossum::new(TAU_S)
            .unwrap()
            .matrices(&cut, &neurotac_core::OneProcess)
            .unwrap()
            .distances(COS)
            .unwrap();
        let reference: Vec<f64> = all.slice(s![N_TRAIN, ..N_TRAIN]).to_vec();
        assert_eq!(
            fitted.decide(&reference).unwrap(),
            decision,
            "T = {t_end_s}"
        );
    }
}

#[test]
fn fitted_knn_errors_are_typed() {
    let knn = Knn::new(4).unwrap();
    assert_eq!(knn.fit(&[]), Err(KnnError::KTooLarge { k: 4, n_train: 0 }));
    assert_eq!(
        knn.fit(&[0, 1, 2]),
        Err(KnnError::KTooLarge { k: 4, n_train: 3 })
    );
    let fitted = knn.fit(&[0, 1, 2, 3, 4]).unwrap();
    let wrong = Array2::<f64>::zeros((2, 4));
    assert_eq!(
        fitted.predict(wrong.view()),
        Err(KnnError::Shape {
            rows: 2,
            cols: 4,
            labels: 5
        })
    );
    let mut nan = Array2::<f64>::zeros((3, 5));
    nan[[2, 3]] = f64::NAN;
    assert!(matches!(
        fitted.decisions(nan.view()),
        Err(KnnError::InvalidDistance { row: 2, col: 3, .. })
    ));
    // Leave-one-out needs k ≤ n_train − 1 and the square matrix.
    let square = Array2::<f64>::ones((5, 5));
    // All at distance 1: sample 0's neighbours 1..=4 vote once each, so the smallest label
    // wins, 1; every other sample has sample 0 (label 0) among its four.
    assert_eq!(fitted.leave_one_out(square.view()), Ok(vec![1, 0, 0, 0, 0]));
    assert_eq!(
        Knn::new(5)
            .unwrap()
            .fit(&[0; 5])
            .unwrap()
            .leave_one_out(square.view()),
        Err(KnnError::KTooLarge { k: 5, n_train: 4 })
    );
}
