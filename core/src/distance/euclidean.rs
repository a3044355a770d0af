//! Euclidean distances between feature rows (intensive, spatial and temporal codings):
//! `d(x, y) = √(Σ_f (x_f − y_f)²)`.

use super::{row_matrices, symmetric_matrices_on};
use crate::error::DistanceError;
use crate::ranks::Ranks;
use ndarray::{Array2, ArrayView2};

/// `Σ_f (x_f − y_f)²`, summed in eight fixed lanes then in lane order (vectorises; the order,
/// and so the rounding, is the same on every run). Panics if the lengths differ.
#[inline]
pub fn squared_euclidean(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "feature rows of different lengths");
    let mut lanes = [0.0f64; 8];
    let (xc, yc) = (x.chunks_exact(8), y.chunks_exact(8));
    let (xr, yr) = (xc.remainder(), yc.remainder());
    for (a, b) in xc.zip(yc) {
        for l in 0..8 {
            let d = a[l] - b[l];
            lanes[l] += d * d;
        }
    }
    for (l, (a, b)) in xr.iter().zip(yr).enumerate() {
        let d = a - b;
        lanes[l] += d * d;
    }
    lanes.iter().sum()
}

fn check_features(features: &ArrayView2<'_, f64>) -> Result<(), DistanceError> {
    if let Some(((row, column), &value)) = features.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(DistanceError::NonFiniteFeature { row, column, value });
    }
    Ok(())
}

/// The `N × N` matrix of squared Euclidean distances between the rows of `features`
/// (rejecting NaN/±∞ features, naming row and column).
///
/// [`squared_euclidean_matrix`] split over `ranks`: each rank computes a block of
/// upper-triangle rows balanced by pair count, then the blocks are all-gathered, so every rank
/// returns the one-process matrix, bit for bit. Collective: every rank must call it.
///
/// ```
/// use neurotac_core::distance::{squared_euclidean_matrix};
/// use neurotac_core::ranks::ThreadRanks;
/// let f = ndarray::array![[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]];
/// let on_two = ThreadRanks::run(2, |r| squared_euclidean_matrix(f.view(), r).unwrap());
/// assert!(on_two.iter().all(|m| *m == squared_euclidean_matrix(f.view(), &neurotac_core::OneProcess).unwrap()));
/// ```
pub fn squared_euclidean_matrix(
    features: ArrayView2<'_, f64>,
    ranks: &dyn Ranks,
) -> Result<Array2<f64>, DistanceError> {
    check_features(&features)?;
    let rows = features.as_standard_layout();
    let width = rows.ncols();
    let flat = rows.as_slice().expect("standard layout is contiguous");
    let row = |i: usize| &flat[i * width..(i + 1) * width];
    let pair = |i: usize, j: usize| [squared_euclidean(row(i), row(j))];
    let [d2] = symmetric_matrices_on(rows.nrows(), pair, ranks)?;
    Ok(d2)
}

/// The `N × N` matrix of Euclidean distances between the rows of `features`.
///
/// [`euclidean_distance_matrix`] split over `ranks` (as [`squared_euclidean_matrix`]).
/// Collective.
pub fn euclidean_distance_matrix(
    features: ArrayView2<'_, f64>,
    ranks: &dyn Ranks,
) -> Result<Array2<f64>, DistanceError> {
    Ok(squared_euclidean_matrix(features, ranks)?.mapv_into(f64::sqrt))
}

/// The `n_new × n_train` matrix of squared Euclidean distances `‖x_i − y_j‖²` between the rows
/// `x_i` of `new` and `y_j` of `train`: bit for bit the entries of [`squared_euclidean_matrix`]
/// of the stacked rows (the same [`squared_euclidean`], whose value does not depend on the
/// order of its arguments). Rows run in parallel.
///
/// `new` must have `train`'s column count ([`DistanceError::Shape`]); NaN/±∞ features are
/// rejected, `train` checked before `new`, with the row and column in that matrix.
pub fn squared_euclidean_cross_matrix(
    new: ArrayView2<'_, f64>,
    train: ArrayView2<'_, f64>,
) -> Result<Array2<f64>, DistanceError> {
    if new.ncols() != train.ncols() {
        return Err(DistanceError::Shape {
            what: "new feature rows (new samples × features of the training rows)",
            expected: (new.nrows(), train.ncols()),
            got: new.dim(),
        });
    }
    check_features(&train)?;
    check_features(&new)?;
    let (new, train) = (new.as_standard_layout(), train.as_standard_layout());
    let contiguous = "standard layout is contiguous";
    let (x, y) = (
        new.as_slice().expect(contiguous),
        train.as_slice().expect(contiguous),
    );
    let width = train.ncols();
    let [d2] = row_matrices(new.nrows(), train.nrows(), |i| {
        let xi = &x[i * width..(i + 1) * width];
        (0..train.nrows())
            .map(|j| [squared_euclidean(xi, &y[j * width..(j + 1) * width])])
            .collect()
    });
    Ok(d2)
}

/// The `n_new × n_train` matrix of Euclidean distances `‖x_i − y_j‖` between the rows of `new`
/// and of `train`: bit for bit the entries of [`euclidean_distance_matrix`] of the stacked rows.
///
/// ```
/// use neurotac_core::distance::{euclidean_cross_matrix, euclidean_distance_matrix};
/// use ndarray::{array, concatenate, Axis};
/// let train = array![[0.0, 0.0], [3.0, 4.0]];
/// let live = array![[6.0, 8.0]];
/// let d = euclidean_cross_matrix(live.view(), train.view())?;
/// assert_eq!(d, array![[10.0, 5.0]]);
/// let all = euclidean_distance_matrix(concatenate![Axis(0), train, live].view(), &neurotac_core::OneProcess)?;
/// assert_eq!(d.row(0), all.row(2).slice(ndarray::s![..2]));
/// # Ok::<(), neurotac_core::DistanceError>(())
/// ```
pub fn euclidean_cross_matrix(
    new: ArrayView2<'_, f64>,
    train: ArrayView2<'_, f64>,
) -> Result<Array2<f64>, DistanceError> {
    Ok(squared_euclidean_cross_matrix(new, train)?.mapv_into(f64::sqrt))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn matrix_is_symmetric_with_known_values() {
        let f = array![[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]];
        let d = euclidean_distance_matrix(f.view(), &crate::OneProcess).unwrap();
        assert_eq!(
            d,
            array![[0.0, 5.0, 10.0], [5.0, 0.0, 5.0], [10.0, 5.0, 0.0]]
        );
        // Lanes and remainder both count.
        let x: Vec<f64> = (0..19).map(f64::from).collect();
        let y = vec![0.0; 19];
        assert_eq!(
            squared_euclidean(&x, &y),
            (0..19).map(|i| (i * i) as f64).sum::<f64>()
        );
    }

    #[test]
    fn cross_matrix_is_the_stacked_matrix_bit_for_bit() {
        // Irregular values (rounding differs with the order of the subtraction if anything does),
        // 19 columns for lanes and remainder, and a row repeated across the two sets.
        let f = Array2::from_shape_fn((11, 19), |(i, j)| ((i * 31 + j * 7) as f64).sin() * 1e3);
        let (train, new) = (f.slice(ndarray::s![..7, ..]), f.slice(ndarray::s![6.., ..]));
        let square = euclidean_distance_matrix(f.view(), &crate::OneProcess).unwrap();
        let squared = squared_euclidean_matrix(f.view(), &crate::OneProcess).unwrap();
        let cross = euclidean_cross_matrix(new, train).unwrap();
        let cross2 = squared_euclidean_cross_matrix(new, train).unwrap();
        assert_eq!(cross.dim(), (5, 7));
        for ((i, j), &d) in cross.indexed_iter() {
            assert_eq!(d.to_bits(), square[[6 + i, j]].to_bits(), "({i},{j})");
            assert_eq!(cross2[[i, j]].to_bits(), squared[[6 + i, j]].to_bits());
        }
        assert_eq!(cross[[0, 6]], 0.0);
        // Column-major input, and empty sets.
        let train_t = train.t().to_owned();
        let column_major = euclidean_cross_matrix(new, train_t.t()).unwrap();
        assert_eq!(column_major, cross);
        assert_eq!(
            euclidean_cross_matrix(new.slice(ndarray::s![..0, ..]), train)
                .unwrap()
                .dim(),
            (0, 7)
        );
        assert_eq!(
            euclidean_cross_matrix(new, train.slice(ndarray::s![..0, ..]))
                .unwrap()
                .dim(),
            (5, 0)
        );
    }

    #[test]
    fn cross_matrix_errors_are_typed() {
        let train = array![[0.0, 1.0], [2.0, 3.0]];
        let wide = array![[0.0, 1.0, 2.0]];
        assert!(matches!(
            euclidean_cross_matrix(wide.view(), train.view()),
            Err(DistanceError::Shape {
                what: "new feature rows (new samples × features of the training rows)",
                expected: (1, 2),
                got: (1, 3)
            })
        ));
        let nan = array![[0.0, 1.0], [f64::INFINITY, 0.0]];
        assert!(matches!(
            euclidean_cross_matrix(nan.view(), train.view()),
            Err(DistanceError::NonFiniteFeature {
                row: 1,
                column: 0,
                ..
            })
        ));
        assert!(matches!(
            euclidean_cross_matrix(train.view(), nan.view()),
            Err(DistanceError::NonFiniteFeature {
                row: 1,
                column: 0,
                ..
            })
        ));
    }

    #[test]
    fn non_finite_features_are_named() {
        let f = array![[0.0, 1.0], [f64::NAN, 2.0]];
        match squared_euclidean_matrix(f.view(), &crate::OneProcess) {
            Err(DistanceError::NonFiniteFeature {
                row: 1,
                column: 0,
                value,
            }) => {
                assert!(value.is_nan())
            }
            other => panic!("{other:?}"),
        }
        let empty = Array2::<f64>::zeros((0, 3));
        assert_eq!(
            squared_euclidean_matrix(empty.view(), &crate::OneProcess)
                .unwrap()
                .dim(),
            (0, 0)
        );
    }
}
