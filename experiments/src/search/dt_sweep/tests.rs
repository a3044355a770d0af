use super::*;
use crate::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use ndarray::Array2;
use neurotac_core::coding::{Coding, FeatureCoding, TemporalCoding};

fn small() -> neurotac_core::SpikeDataset {
    synthetic_dataset(&SyntheticConfig {
        samples: 33,
        channels: 5,
        spikes_per_unit: 6.0,
        duration_s: 0.6,
        seed: 11,
        ..Default::default()
    })
}

/// Samples of one channel with `spikes[i]` spikes at the given times (ms).
fn samples(spikes: &[Vec<f64>]) -> Vec<MultiSpikeTrain> {
    spikes
        .iter()
        .map(|ms| {
            MultiSpikeTrain::from_unsorted_channels([ms
                .iter()
                .map(|t| t / 1e3)
                .collect::<Vec<_>>()])
            .unwrap()
        })
        .collect()
}

/// The temporal features of `o` times the channel count: exact window counts.
fn window_counts(o: &MultiSpikeTrain, delta: u32, t: u32) -> Vec<i64> {
    let mut coding = TemporalCoding::from_ms(delta, t).unwrap();
    coding.encode(o);
    let channels = o.n_channels() as f64;
    coding
        .features()
        .iter()
        .map(|x| (x * channels).round() as i64)
        .collect()
}

/// Squared distances of the feature vectors, exact (integers, held exactly in f64).
fn reference_squared(obs: &[MultiSpikeTrain], delta: u32, t: u32) -> Array2<f64> {
    let rows: Vec<Vec<i64>> = obs.iter().map(|o| window_counts(o, delta, t)).collect();
    Array2::from_shape_fn((obs.len(), obs.len()), |(i, j)| {
        rows[i]
            .iter()
            .zip(&rows[j])
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<i64>() as f64
    })
}

/// Short samples, many and few spikes, bins beyond a byte, long windows.
fn kernel_cases() -> Vec<(Vec<MultiSpikeTrain>, u32, u32)> {
    let d = small();
    let mut crowded = vec![vec![10.5; 300], vec![]];
    crowded[0].extend([0.5, 3.5, 44.5, 599.5]);
    crowded[1].extend((0..600).map(|t| t as f64 + 0.25));
    // Bins of 200 and 150 spikes: the byte correlogram is flushed after every spike.
    let mut full = vec![vec![300.5; 200], vec![301.5; 150]];
    full[0].extend((250..350).map(|t| t as f64 + 0.5));
    full[1].extend((240..360).step_by(2).map(|t| t as f64 + 0.5));
    vec![
        (d.observations().to_vec(), 600, 130),
        // Spikes near both ends for the longest windows.
        (d.observations().to_vec(), 150, 150),
        // Two blocks of windows and two of lags.
        (d.observations().to_vec(), 600, 300),
        // A bin with 300 spikes (no byte correlogram), sparse against dense.
        (samples(&crowded), 600, 220),
        (samples(&full), 600, 220),
    ]
}

#[test]
fn kernel_distances_equal_the_feature_vectors_for_every_window() {
    for (obs, t, dm) in kernel_cases() {
        let pairs = [(0, 1), (1, 0), (0, 0), (1, 1)].into_iter().chain(
            [(2, 30), (5, 5), (7, 12)]
                .into_iter()
                .filter(|_| obs.len() > 30),
        );
        for (a, b) in pairs {
            let fast = window_squared_distances(&obs[a], &obs[b], t, dm);
            for delta in 1..=dm {
                let want: i64 = window_counts(&obs[a], delta, t)
                    .iter()
                    .zip(window_counts(&obs[b], delta, t))
                    .map(|(x, y)| (x - y) * (x - y))
                    .sum();
                assert_eq!(
                    fast[delta as usize - 1],
                    want,
                    "T={t} pair ({a},{b}) Δ={delta}"
                );
            }
        }
    }
}

/// Every window's leave-one-out predictions against [`Knn::leave_one_out`] on the exact
/// feature distances (same tie rules), and the sweep's accuracies from them.
fn assert_predictions_match(obs: &[MultiSpikeTrain], labels: &[usize], t: u32, dm: u32) {
    let knn = Knn::default();
    let fast = leave_one_out_predictions(obs, labels, t, dm, knn).unwrap();
    assert_eq!(fast.len(), dm as usize);
    for delta in 1..=dm {
        let d2 = reference_squared(obs, delta, t);
        let want = knn.leave_one_out(d2.view(), labels).unwrap();
        assert_eq!(fast[delta as usize - 1], want, "T={t} Δ={delta}");
    }
    let sweep = dt_sweep(obs, labels, t, dm, knn, &neurotac_core::OneProcess).unwrap();
    for (p, &acc) in fast.iter().zip(&sweep.accuracy) {
        assert_eq!(acc, Accuracy::of(p, labels).mean);
    }
}

#[test]
fn predictions_equal_leave_one_out_on_the_feature_vectors() {
    let d = small();
    assert_predictions_match(d.observations(), d.labels(), 600, 85);
    // Two blocks of windows.
    assert_predictions_match(d.observations(), d.labels(), 600, 230);
}

#[test]
fn distance_ties_go_to_the_lowest_index_as_in_the_knn_head() {
    // One or two spikes per sample on a coarse grid: many equal distances at the k-th
    // neighbour, and 2–2 votes.
    let spikes: Vec<Vec<f64>> = (0..40)
        .map(|i| {
            let first = ((i * 7) % 5) as f64 * 20.0 + 0.5;
            if i % 3 == 0 {
                vec![first]
            } else {
                vec![first, first + ((i % 4) * 30) as f64]
            }
        })
        .collect();
    let labels: Vec<usize> = (0..40).map(|i| (i * 5 / 3) % 4).collect();
    assert_predictions_match(&samples(&spikes), &labels, 200, 120);
}

#[test]
fn dense_samples_use_exact_64_bit_lanes() {
    // ~1500 spikes in 0.6 s: the window bound exceeds 32-bit lanes.
    let d = synthetic_dataset(&SyntheticConfig {
        samples: 12,
        classes: 3,
        channels: 2,
        spikes_per_unit: 750.0,
        duration_s: 0.6,
        seed: 5,
    });
    assert_predictions_match(d.observations(), d.labels(), 600, 40);
}

#[test]
fn predictions_are_identical_at_any_thread_count() {
    let d = small();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                leave_one_out_predictions(d.observations(), d.labels(), 600, 90, Knn::default())
                    .unwrap()
            })
    };
    let one = run(1);
    for threads in [2, 3, 7] {
        assert_eq!(run(threads), one, "{threads} threads");
    }
}

#[test]
fn the_best_window_is_the_first_with_the_highest_accuracy() {
    let d = small();
    let sweep = dt_sweep(
        d.observations(),
        d.labels(),
        600,
        85,
        Knn::default(),
        &neurotac_core::OneProcess,
    )
    .unwrap();
    assert_eq!(sweep.windows_ms.len(), 85);
    let best = sweep.accuracy.iter().cloned().fold(0.0, f64::max);
    assert_eq!(sweep.best.mean, best);
    assert_eq!(sweep.accuracy[sweep.best_window_ms as usize - 1], best);
    assert!(
        sweep.accuracy[..sweep.best_window_ms as usize - 1]
            .iter()
            .all(|&a| a < best)
    );
}

#[test]
fn row_chunks_of_all_ranks_cover_every_row_once() {
    for (n, parts) in [(0, 3), (1, 4), (2, 1), (33, 4), (1100, 4), (5, 64)] {
        for size in [1, 2, 3, 7] {
            let mut rows = Vec::new();
            for rank in 0..size {
                let chunks = row_chunks(n, rank, size, parts);
                assert!(chunks.len() <= parts.max(1), "{n} {parts}");
                assert!(chunks.iter().all(|c| !c.is_empty()), "{n} {parts}");
                rows.extend(chunks.into_iter().flatten());
            }
            assert_eq!(rows, (0..n).collect::<Vec<_>>(), "{n} rows, {size} ranks");
        }
    }
}

#[test]
fn bad_sweeps_are_typed_errors() {
    let d = small();
    assert!(
        dt_sweep(
            d.observations(),
            d.labels(),
            600,
            601,
            Knn::default(),
            &neurotac_core::OneProcess
        )
        .is_err()
    );
    assert!(
        dt_sweep(
            d.observations(),
            d.labels(),
            600,
            0,
            Knn::default(),
            &neurotac_core::OneProcess
        )
        .is_err()
    );
    assert!(matches!(
        dt_sweep(
            &d.observations()[..3],
            &d.labels()[..3],
            600,
            10,
            Knn::default(),
            &neurotac_core::OneProcess
        ),
        Err(ExperimentError::Knn(KnnError::KTooLarge {
            k: 4,
            n_train: 2
        }))
    ));
    assert!(
        dt_sweep(
            d.observations(),
            &d.labels()[1..],
            600,
            10,
            Knn::default(),
            &neurotac_core::OneProcess
        )
        .is_err()
    );
}
