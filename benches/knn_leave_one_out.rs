//! The KNN head's leave-one-out (k = 4) on one 1100 × 1100 distance matrix, one thread: the
//! step every evaluation of the spatiotemporal coding's optimisation ends with (`reproduce`'s
//! artificial set has 1100 samples). Distances are seeded uniform numbers.

use criterion::{Criterion, criterion_group, criterion_main};
use ndarray::Array2;
use neurotac::core::Knn;
use rand::{RngExt, SeedableRng};
use std::hint::black_box;

fn knn_leave_one_out_1100(c: &mut Criterion) {
    let n = 1100;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let mut d = Array2::<f64>::zeros((n, n));
    for i in 0..n {
        for j in 0..i {
            let v = rng.random_range(0.0..1.0);
            d[[i, j]] = v;
            d[[j, i]] = v;
        }
    }
    let labels: Vec<usize> = (0..n).map(|i| i % 11).collect();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    c.bench_function("knn_leave_one_out_1100_k4", |b| {
        b.iter(|| {
            one_thread
                .install(|| black_box(Knn::default().leave_one_out(d.view(), &labels).unwrap()))
        })
    });
}

criterion_group!(benches, knn_leave_one_out_1100);
criterion_main!(benches);
