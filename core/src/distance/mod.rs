//! Distances between samples and N×N distance matrices (`ndarray`, rayon over rows).
//!
//! | distance | for | module |
//! |---|---|---|
//! | Euclidean `‖x − y‖` between feature rows | intensive, spatial, temporal codings | [`euclidean`] |
//! | multi-unit Van Rossum (Houghton & Sen), exact, `D²(c) = (1 − c)·LL² + c·SP²` | spatiotemporal coding | [`van_rossum`] |
//! | the same from traces sampled at a network step | the speed ↔ accuracy trade | [`trace_sampled`] |
//!
//! Every `N × N` matrix is symmetric with a zero diagonal; each entry is computed from its two
//! samples alone, in a fixed order, so matrices are bit-identical at any thread count. The
//! rectangular matrices between new samples and a training set
//! ([`euclidean_cross_matrix`], [`PreparedVanRossum::cross_matrices`]), for classifying samples
//! that are not in the training set, hold the entries the square matrix of both sets would.

pub mod euclidean;
pub mod trace_sampled;
pub mod van_rossum;

pub use euclidean::{
    euclidean_cross_matrix, euclidean_distance_matrix, squared_euclidean,
    squared_euclidean_cross_matrix, squared_euclidean_matrix,
};
pub use trace_sampled::{TracePrecision, trace_matrices, trace_sampled_matrices};
pub use van_rossum::{
    GrowingLive, GrowingVanRossum, PreparedVanRossum, VanRossum, VanRossumMatrices, combine_squared,
};

use crate::error::DistanceError;
use ndarray::Array2;
use rayon::prelude::*;

/// Checks a kernel time constant: finite and > 0.
pub fn check_tau(tau_s: f64) -> Result<f64, DistanceError> {
    if tau_s.is_finite() && tau_s > 0.0 {
        Ok(tau_s)
    } else {
        Err(DistanceError::InvalidParameter {
            what: "tau_s",
            value: tau_s,
            expected: "finite and > 0 (seconds)",
        })
    }
}

/// Checks a Houghton–Sen cos θ: in [0, 1] (0 = labelled line, 1 = summed population). Outside
/// it the unit-vector Gram matrix is not a metric's for every unit count, so it is rejected.
pub fn check_cos(cos: f64) -> Result<f64, DistanceError> {
    if (0.0..=1.0).contains(&cos) {
        Ok(cos)
    } else {
        Err(DistanceError::InvalidParameter {
            what: "cos",
            value: cos,
            expected: "in [0, 1]",
        })
    }
}

/// `M` matrices `rows × cols` whose row `i` is `row(i)` (`cols` entries); rows are computed in
/// parallel, each by one call.
pub(crate) fn row_matrices<const M: usize, F>(rows: usize, cols: usize, row: F) -> [Array2<f64>; M]
where
    F: Fn(usize) -> Vec<[f64; M]> + Sync + Send,
{
    let computed: Vec<Vec<[f64; M]>> = (0..rows).into_par_iter().map(row).collect();
    std::array::from_fn(|m| Array2::from_shape_fn((rows, cols), |(i, j)| computed[i][j][m]))
}

/// `M` symmetric `n × n` matrices whose entries `(i, j)`, `i < j`, are `pair(i, j)`, with a zero
/// diagonal. Rows of the upper triangle are computed in parallel; each entry by one call.
pub(crate) fn symmetric_matrices<const M: usize, F>(n: usize, pair: F) -> [Array2<f64>; M]
where
    F: Fn(usize, usize) -> [f64; M] + Sync,
{
    let rows: Vec<Vec<[f64; M]>> = (0..n)
        .into_par_iter()
        .map(|i| (i + 1..n).map(|j| pair(i, j)).collect())
        .collect();
    let mut out: [Array2<f64>; M] = std::array::from_fn(|_| Array2::zeros((n, n)));
    for (i, row) in rows.iter().enumerate() {
        for (j, values) in (i + 1..n).zip(row) {
            for (m, &v) in out.iter_mut().zip(values) {
                m[[i, j]] = v;
                m[[j, i]] = v;
            }
        }
    }
    out
}
