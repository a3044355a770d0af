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
//!
//! The square matrices can be split over several processes ([`Ranks`], e.g. MPI ranks): the
//! `…_on` functions ([`squared_euclidean_matrix`], [`euclidean_distance_matrix`],
//! [`PreparedVanRossum::matrices`], [`trace_matrices`]) have each rank compute a
//! contiguous block of rows, balanced by cost (an upper-triangle row `i` of `N` costs
//! `N − i − 1` pairs; a full row of the centred Van Rossum evaluation costs `N`), and
//! all-gather the blocks. Since entries do not depend on how rows are blocked, every rank then
//! holds the one-process matrices, bit for bit, at any rank count. They are collective: every
//! rank must call them, in the same order.

pub mod euclidean;
pub(crate) mod trace_record;
pub mod trace_sampled;
pub mod van_rossum;

pub use euclidean::{
    euclidean_cross_matrix, euclidean_distance_matrix, squared_euclidean,
    squared_euclidean_cross_matrix, squared_euclidean_matrix,
};
pub use trace_record::TraceRecord;
pub use trace_sampled::{TracePrecision, trace_matrices, trace_sampled_matrices};
pub use van_rossum::{
    GrowingLive, GrowingVanRossum, PreparedVanRossum, VanRossum, VanRossumMatrices, combine_squared,
};

use crate::error::DistanceError;
use crate::ranks::{Ranks, RanksError, all_gather_f64, balanced_blocks};
use ndarray::Array2;
use rayon::prelude::*;
use std::ops::Range;

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
    symmetric_from_triangle(n, &triangle_rows(n, 0..n, &pair))
}

/// [`symmetric_matrices`] split over `ranks`: each rank computes a block of upper-triangle rows
/// balanced by their pair counts (row `i` has `n − i − 1`), then the blocks are all-gathered,
/// so every rank returns the one-process matrices, bit for bit. Collective.
pub(crate) fn symmetric_matrices_on<const M: usize, F>(
    n: usize,
    pair: F,
    ranks: &dyn Ranks,
) -> Result<[Array2<f64>; M], RanksError>
where
    F: Fn(usize, usize) -> [f64; M] + Sync,
{
    let widths: Vec<usize> = (0..n).map(|i| M * (n - i - 1)).collect();
    let values = rows_on(ranks, &widths, |rows| triangle_rows(n, rows, &pair))?;
    Ok(symmetric_from_triangle(n, &values))
}

/// The values `pair(i, j)`, `j = i + 1 … n − 1`, of the upper-triangle rows `rows`, row after
/// row (`M` per pair); rows in parallel.
fn triangle_rows<const M: usize, F>(n: usize, rows: Range<usize>, pair: &F) -> Vec<f64>
where
    F: Fn(usize, usize) -> [f64; M] + Sync,
{
    let rows: Vec<Vec<f64>> = rows
        .into_par_iter()
        .map(|i| (i + 1..n).flat_map(|j| pair(i, j)).collect())
        .collect();
    rows.concat()
}

/// The symmetric matrices, zero diagonal, of the [`triangle_rows`] of every row.
fn symmetric_from_triangle<const M: usize>(n: usize, values: &[f64]) -> [Array2<f64>; M] {
    let mut out: [Array2<f64>; M] = std::array::from_fn(|_| Array2::zeros((n, n)));
    let pairs = (0..n).flat_map(|i| (i + 1..n).map(move |j| (i, j)));
    for ((i, j), values) in pairs.zip(values.chunks_exact(M)) {
        for (m, &v) in out.iter_mut().zip(values) {
            m[[i, j]] = v;
            m[[j, i]] = v;
        }
    }
    out
}

/// The values of rows `0 … widths.len() − 1` (row `i` has `widths[i]`), concatenated in row
/// order, on every rank: rank `r` computes block `r` of [`balanced_blocks`] of the widths (a
/// row costs its width) as `compute(block)`, its rows' values concatenated, and the blocks are
/// all-gathered. A group of one computes every row, without communication. Collective.
pub(crate) fn rows_on(
    ranks: &dyn Ranks,
    widths: &[usize],
    compute: impl FnOnce(Range<usize>) -> Vec<f64>,
) -> Result<Vec<f64>, RanksError> {
    if ranks.size() == 1 {
        return Ok(compute(0..widths.len()));
    }
    let costs: Vec<f64> = widths.iter().map(|&w| w as f64).collect();
    let block = balanced_blocks(&costs, ranks.size()).swap_remove(ranks.rank());
    let values = all_gather_f64(ranks, &compute(block))?;
    let expected: usize = widths.iter().sum();
    if values.len() != expected {
        return Err(RanksError::Communication {
            during: "all-gather of distance-matrix rows",
            reason: format!("{} values gathered, expected {expected}", values.len()),
        });
    }
    Ok(values)
}
