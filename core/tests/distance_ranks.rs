//! The `…_on` distance matrices split over ranks equal the one-process matrices bit for bit, on
//! every rank, for 1, 2, 3 ranks and for more ranks than samples: exact Van Rossum (centred and
//! decayed evaluations), Euclidean and trace-sampled.

use ndarray::Array2;
use neurotac_core::coding::TraceRecord;
use neurotac_core::distance::{
    VanRossumMatrices, euclidean_distance_matrix, squared_euclidean_matrix, trace_matrices,
};
use neurotac_core::ranks::ThreadRanks;
use neurotac_core::{MultiSpikeTrain, VanRossum};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Rank counts checked: one, two, three, and more than the smallest sample count.
const RANK_COUNTS: [usize; 4] = [1, 2, 3, 5];

/// `n` samples of `channels` channels, up to 8 spikes each at 1-µs stamps in `[0, span_s)`.
fn samples(n: usize, channels: usize, span_s: f64, seed: u64) -> Vec<MultiSpikeTrain> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            MultiSpikeTrain::from_unsorted_channels((0..channels).map(|_| {
                let k = rng.random_range(0..=8);
                (0..k)
                    .map(|_| (rng.random::<f64>() * span_s * 1e6).floor() / 1e6)
                    .collect::<Vec<_>>()
            }))
            .unwrap()
        })
        .collect()
}

fn bits(m: &Array2<f64>) -> Vec<u64> {
    m.iter().map(|v| v.to_bits()).collect()
}

fn assert_same_matrices(got: &VanRossumMatrices, want: &VanRossumMatrices, what: &str) {
    assert_eq!(got.tau_s.to_bits(), want.tau_s.to_bits(), "{what}");
    assert_eq!(got.ll2.dim(), want.ll2.dim(), "{what}");
    assert_eq!(bits(&got.ll2), bits(&want.ll2), "{what}: LL²");
    assert_eq!(bits(&got.sp2), bits(&want.sp2), "{what}: SP²");
}

/// Exact Van Rossum on `samples` at `tau_s`, in the evaluation `centred` when given.
fn check_van_rossum(samples: &[MultiSpikeTrain], tau_s: f64, centred: Option<bool>) {
    let vr = VanRossum::new(tau_s).unwrap();
    let prepared = vr.prepare(samples).unwrap();
    if let Some(centred) = centred {
        assert_eq!(prepared.is_centred(), centred);
    }
    let want = prepared.matrices(&neurotac_core::OneProcess).unwrap();
    for size in RANK_COUNTS {
        let got = ThreadRanks::run(size, |r| vr.matrices(samples, r).unwrap());
        for (rank, m) in got.iter().enumerate() {
            let what = format!("{} samples, rank {rank} of {size}", samples.len());
            assert_same_matrices(m, &want, &what);
        }
    }
}

#[test]
fn centred_van_rossum_on_ranks_is_the_one_process_matrix() {
    // 7 samples: blocks of two rows start at odd rows on some ranks.
    check_van_rossum(&samples(7, 5, 1.0, 1), 0.02, Some(true));
    check_van_rossum(&samples(3, 5, 1.0, 2), 0.02, Some(true));
}

#[test]
fn decayed_van_rossum_on_ranks_is_the_one_process_matrix() {
    // Spikes 2 s apart at τ = 1 ms: half the span is 1000 τ, beyond the centred exponentials.
    check_van_rossum(&samples(7, 5, 2.0, 3), 0.001, Some(false));
    check_van_rossum(&samples(3, 5, 2.0, 4), 0.001, Some(false));
}

#[test]
fn no_and_one_sample_on_ranks() {
    for n in [0, 1] {
        check_van_rossum(&samples(n, 3, 1.0, 5), 0.02, None);
    }
}

#[test]
fn euclidean_on_ranks_is_the_one_process_matrix() {
    for n in [3, 11] {
        // 19 columns: lanes and remainder of the summation both count.
        let f = Array2::from_shape_fn((n, 19), |(i, j)| ((i * 31 + j * 7) as f64).sin() * 1e3);
        let (squared, plain) = (
            squared_euclidean_matrix(f.view(), &neurotac_core::OneProcess).unwrap(),
            euclidean_distance_matrix(f.view(), &neurotac_core::OneProcess).unwrap(),
        );
        for size in RANK_COUNTS {
            let got = ThreadRanks::run(size, |r| {
                (
                    squared_euclidean_matrix(f.view(), r).unwrap(),
                    euclidean_distance_matrix(f.view(), r).unwrap(),
                )
            });
            for (rank, (s, p)) in got.iter().enumerate() {
                assert_eq!(bits(s), bits(&squared), "{n} rows, rank {rank} of {size}");
                assert_eq!(bits(p), bits(&plain), "{n} rows, rank {rank} of {size}");
            }
        }
    }
}

#[test]
fn trace_sampled_on_ranks_is_the_one_process_matrix() {
    let records: Vec<TraceRecord> = samples(6, 4, 0.5, 6)
        .iter()
        .map(|o| TraceRecord::of_trains(o, 1e-4).unwrap())
        .collect();
    let (want64, want32) = (
        trace_matrices::<f64>(&records, 0.02, &neurotac_core::OneProcess).unwrap(),
        trace_matrices::<f32>(&records, 0.02, &neurotac_core::OneProcess).unwrap(),
    );
    for size in RANK_COUNTS {
        let got = ThreadRanks::run(size, |r| {
            (
                trace_matrices::<f64>(&records, 0.02, r).unwrap(),
                trace_matrices::<f32>(&records, 0.02, r).unwrap(),
            )
        });
        for (rank, (m64, m32)) in got.iter().enumerate() {
            assert_same_matrices(m64, &want64, &format!("f64, rank {rank} of {size}"));
            assert_same_matrices(m32, &want32, &format!("f32, rank {rank} of {size}"));
        }
    }
}

#[test]
fn errors_are_the_same_on_every_rank() {
    // A channel-count mismatch is found before any exchange, on every rank alike.
    let mut mixed = samples(4, 3, 1.0, 7);
    mixed.push(MultiSpikeTrain::empty(2));
    let vr = VanRossum::new(0.02).unwrap();
    let errors = ThreadRanks::run(3, |r| vr.matrices(&mixed, r).unwrap_err().to_string());
    assert!(errors.iter().all(|e| e == &errors[0]), "{errors:?}");
    assert!(errors[0].contains("sample 4"), "{}", errors[0]);
}
