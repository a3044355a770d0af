//! Euclidean distances between feature rows (intensive, spatial and temporal codings):
//! `d(x, y) = √(Σ_f (x_f − y_f)²)`.

use super::symmetric_matrices;
use crate::error::DistanceError;
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
pub fn squared_euclidean_matrix(
    features: ArrayView2<'_, f64>,
) -> Result<Array2<f64>, DistanceError> {
    check_features(&features)?;
    let rows = features.as_standard_layout();
    let width = rows.ncols();
    let flat = rows.as_slice().expect("standard layout is contiguous");
    let row = |i: usize| &flat[i * width..(i + 1) * width];
    let [d2] = symmetric_matrices(rows.nrows(), |i, j| [squared_euclidean(row(i), row(j))]);
    Ok(d2)
}

/// The `N × N` matrix of Euclidean distances between the rows of `features`.
pub fn euclidean_distance_matrix(
    features: ArrayView2<'_, f64>,
) -> Result<Array2<f64>, DistanceError> {
    Ok(squared_euclidean_matrix(features)?.mapv_into(f64::sqrt))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn matrix_is_symmetric_with_known_values() {
        let f = array![[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]];
        let d = euclidean_distance_matrix(f.view()).unwrap();
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
    fn non_finite_features_are_named() {
        let f = array![[0.0, 1.0], [f64::NAN, 2.0]];
        match squared_euclidean_matrix(f.view()) {
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
            squared_euclidean_matrix(empty.view()).unwrap().dim(),
            (0, 0)
        );
    }
}
