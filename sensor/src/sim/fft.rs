//! A small radix-2 complex FFT (1-D and 2-D, power-of-two sizes), used once per texture to
//! filter height fields in the Fourier domain (spec §2.2 step 3). Not a hot path.

/// A complex number as `(re, im)`.
pub(crate) type Complex = (f64, f64);

/// The twiddle factors `e^(∓2πik/n)`, k < n/2, of an `n`-point transform.
pub(crate) fn twiddles(n: usize, inverse: bool) -> Vec<Complex> {
    let sign = if inverse { 1.0 } else { -1.0 };
    (0..n / 2)
        .map(|k| {
            let (s, c) = (sign * std::f64::consts::TAU * k as f64 / n as f64).sin_cos();
            (c, s)
        })
        .collect()
}

/// In-place FFT of `data` (length a power of two) with the [`twiddles`] of its length and
/// direction; the inverse is unnormalised (divide by the length afterwards).
pub(crate) fn fft_with(data: &mut [Complex], twiddles: &[Complex]) {
    let n = data.len();
    debug_assert!(n.is_power_of_two() && twiddles.len() == n / 2);
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            data.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let stride = n / len;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (c, s) = twiddles[k * stride];
                let a = data[start + k];
                let b = data[start + k + len / 2];
                let bw = (b.0 * c - b.1 * s, b.0 * s + b.1 * c);
                data[start + k] = (a.0 + bw.0, a.1 + bw.1);
                data[start + k + len / 2] = (a.0 - bw.0, a.1 - bw.1);
            }
        }
        len <<= 1;
    }
}

/// In-place FFT of `data` (length a power of two); `inverse` computes the unnormalised
/// inverse.
#[cfg(test)]
pub(crate) fn fft(data: &mut [Complex], inverse: bool) {
    fft_with(data, &twiddles(data.len(), inverse));
}

/// In-place 2-D FFT of a row-major `nx × ny` grid (both powers of two); the inverse is
/// normalised (divided by `nx·ny`).
pub(crate) fn fft2(data: &mut [Complex], nx: usize, ny: usize, inverse: bool) {
    let row_twiddles = twiddles(nx, inverse);
    for row in data.chunks_exact_mut(nx) {
        fft_with(row, &row_twiddles);
    }
    let column_twiddles = twiddles(ny, inverse);
    let mut column = vec![(0.0, 0.0); ny];
    for x in 0..nx {
        for (y, c) in column.iter_mut().enumerate() {
            *c = data[y * nx + x];
        }
        fft_with(&mut column, &column_twiddles);
        for (y, c) in column.iter().enumerate() {
            data[y * nx + x] = *c;
        }
    }
    if inverse {
        let scale = 1.0 / (nx * ny) as f64;
        for c in data.iter_mut() {
            *c = (c.0 * scale, c.1 * scale);
        }
    }
}

/// The signed wavenumber index of bin `i` of an `n`-point transform.
pub(crate) fn frequency_index(i: usize, n: usize) -> f64 {
    if i <= n / 2 {
        i as f64
    } else {
        i as f64 - n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fft_matches_the_direct_transform_and_inverts() {
        let n = 16;
        let x: Vec<Complex> = (0..n)
            .map(|i| {
                (
                    (i as f64 * 0.7).sin() + 0.1 * i as f64,
                    (i as f64 * 0.3).cos(),
                )
            })
            .collect();
        let mut y = x.clone();
        fft(&mut y, false);
        for (k, yk) in y.iter().enumerate() {
            let mut d = (0.0, 0.0);
            for (i, xi) in x.iter().enumerate() {
                let a = -std::f64::consts::TAU * (k * i) as f64 / n as f64;
                d.0 += xi.0 * a.cos() - xi.1 * a.sin();
                d.1 += xi.0 * a.sin() + xi.1 * a.cos();
            }
            assert!((d.0 - yk.0).abs() < 1e-9 && (d.1 - yk.1).abs() < 1e-9);
        }
        let mut grid: Vec<Complex> = (0..32).map(|i| (i as f64, -(i as f64))).collect();
        let original = grid.clone();
        fft2(&mut grid, 8, 4, false);
        fft2(&mut grid, 8, 4, true);
        for (a, b) in grid.iter().zip(&original) {
            assert!((a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9);
        }
    }
}
