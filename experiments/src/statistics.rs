//! Two-sample statistics: the Kolmogorov–Smirnov test ([`kolmogorov_smirnov`]) with its
//! asymptotic p-value from the Kolmogorov distribution ([`kolmogorov_survival`]).
//!
//! ```text
//! D = sup_x |F_a(x) − F_b(x)|                      F: empirical CDFs of the two samples
//! p = Q(√(n·m/(n + m)) · D)                        asymptotic (Kolmogorov 1933, Smirnov 1948)
//! Q(λ) = 2 Σ_{k≥1} (−1)^(k−1) e^(−2k²λ²)          = 1 − (√(2π)/λ) Σ_{k≥1} e^(−(2k−1)²π²/(8λ²))
//! ```
//!
//! The p-value is the large-sample limit (scipy's `ks_2samp(…, method="asymp")` without its
//! finite-size correction); with ties between the samples (weights clipped at a bound) it is
//! conservative.

use crate::ExperimentError;

/// The two-sample Kolmogorov–Smirnov test of two samples.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct KolmogorovSmirnov {
    /// The statistic `D`, the largest distance between the two empirical CDFs, in [0, 1].
    pub statistic: f64,
    /// The asymptotic p-value `Q(√(n·m/(n + m))·D)` of "both samples come from one
    /// distribution".
    pub p_value: f64,
    /// Size of the first sample.
    pub n_a: usize,
    /// Size of the second sample.
    pub n_b: usize,
}

/// The two-sample Kolmogorov–Smirnov statistic of `a` and `b` and its asymptotic p-value (see
/// the [module docs](self)). Equal values in both samples (ties) are taken together, as the
/// empirical CDFs are right-continuous.
///
/// Errors: an empty sample or a value that is not a number ([`ExperimentError::InvalidParameter`]).
///
/// ```
/// use neurotac_experiments::statistics::kolmogorov_smirnov;
/// let ks = kolmogorov_smirnov(&[0.1, 0.4, 0.7, 0.9], &[0.3, 0.4, 0.5, 1.2, 1.5])?;
/// assert!((ks.statistic - 0.4).abs() < 1e-12); // at x = 0.9: F_a = 1, F_b = 0.6
/// # Ok::<(), neurotac_experiments::ExperimentError>(())
/// ```
pub fn kolmogorov_smirnov(a: &[f64], b: &[f64]) -> Result<KolmogorovSmirnov, ExperimentError> {
    let sorted = |x: &[f64], what: &'static str| {
        if x.is_empty() {
            return Err(ExperimentError::InvalidParameter {
                what,
                value: 0.0,
                expected: "at least one value in each sample",
            });
        }
        if let Some(&bad) = x.iter().find(|v| v.is_nan()) {
            return Err(ExperimentError::InvalidParameter {
                what,
                value: bad,
                expected: "numbers only",
            });
        }
        let mut x = x.to_vec();
        x.sort_by(f64::total_cmp);
        Ok(x)
    };
    let (a, b) = (sorted(a, "first sample")?, sorted(b, "second sample")?);
    let (n, m) = (a.len() as f64, b.len() as f64);
    let (mut i, mut j, mut d) = (0usize, 0usize, 0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] == x {
            i += 1;
        }
        while j < b.len() && b[j] == x {
            j += 1;
        }
        d = d.max((i as f64 / n - j as f64 / m).abs());
    }
    // Once one sample is used up its CDF is 1 and the other's only climbs towards it.
    let effective = (n * m / (n + m)).sqrt();
    Ok(KolmogorovSmirnov {
        statistic: d,
        p_value: kolmogorov_survival(effective * d),
        n_a: a.len(),
        n_b: b.len(),
    })
}

/// The survival function `Q(λ) = P(K > λ)` of the Kolmogorov distribution (the limit of
/// `√n·D_n`), from the series that converges fastest at `λ` (see the [module docs](self));
/// 1 for `λ ≤ 0`, accurate to 1e-15 absolute.
///
/// ```
/// use neurotac_experiments::statistics::kolmogorov_survival;
/// // The 5 % critical value of the Kolmogorov distribution is 1.3581.
/// assert!((kolmogorov_survival(1.3581) - 0.05).abs() < 1e-5);
/// ```
pub fn kolmogorov_survival(lambda: f64) -> f64 {
    if lambda.is_nan() || lambda <= 0.0 {
        return 1.0;
    }
    let l2 = lambda * lambda;
    if lambda < 1.18 {
        // Jacobi's form: terms fall as e^(−(2k−1)²π²/(8λ²)), at most e^(−0.89·(2k−1)²).
        let c = -std::f64::consts::PI.powi(2) / (8.0 * l2);
        let sum: f64 = (1..=20)
            .map(|k| c * f64::from(2 * k - 1).powi(2))
            .map(f64::exp)
            .sum();
        (1.0 - (2.0 * std::f64::consts::PI).sqrt() / lambda * sum).clamp(0.0, 1.0)
    } else {
        // Alternating: terms fall as e^(−2k²λ²), at most e^(−2.78·k²).
        let sum: f64 = (1..=20)
            .map(|k| {
                let sign = if k % 2 == 1 { 1.0 } else { -1.0 };
                sign * (-2.0 * f64::from(k * k) * l2).exp()
            })
            .sum();
        (2.0 * sum).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kolmogorov_distribution_gives_its_published_critical_values() {
        // Critical values of √n·D (Smirnov 1948's table): P(K > λ) = α.
        for (lambda, alpha) in [
            (1.2238, 0.10),
            (1.3581, 0.05),
            (1.6276, 0.01),
            (1.9495, 0.001),
        ] {
            let q = kolmogorov_survival(lambda);
            assert!((q - alpha).abs() < 3e-5, "{lambda}: {q}");
        }
        // P(K ≤ 1) = 0.7300003283 (both series meet at 1.18 and agree there).
        assert!((kolmogorov_survival(1.0) - 0.269_999_671_7).abs() < 1e-9);
        let (below, above) = (kolmogorov_survival(1.18 - 1e-12), kolmogorov_survival(1.18));
        assert!((below - above).abs() < 1e-12, "{below} {above}");
        assert_eq!(kolmogorov_survival(0.0), 1.0);
        assert!(kolmogorov_survival(0.2) > 0.999_999);
        assert!(kolmogorov_survival(5.0) < 1e-20);
    }

    #[test]
    fn the_statistic_is_the_largest_gap_between_the_empirical_cdfs() {
        // By hand: at x = 0.9, F_a = 4/4 and F_b = 3/5.
        let ks = kolmogorov_smirnov(&[0.9, 0.1, 0.4, 0.7], &[0.3, 1.5, 0.4, 0.5, 1.2]).unwrap();
        assert!((ks.statistic - 0.4).abs() < 1e-12, "{ks:?}");
        let lambda = (20.0f64 / 9.0).sqrt() * 0.4;
        assert!((ks.p_value - kolmogorov_survival(lambda)).abs() < 1e-15);
        assert_eq!((ks.n_a, ks.n_b), (4, 5));
        // Disjoint samples: D = 1.
        let ks = kolmogorov_smirnov(&[1.0, 2.0], &[3.0, 4.0, 5.0]).unwrap();
        assert_eq!(ks.statistic, 1.0);
    }

    #[test]
    fn ties_between_the_samples_are_taken_together() {
        // Weights clipped at the bounds: equal samples full of ties are at distance 0.
        let a = [0.0, 0.0, 0.0, 0.6, 0.6, 0.3];
        let ks = kolmogorov_smirnov(&a, &a).unwrap();
        assert_eq!((ks.statistic, ks.p_value), (0.0, 1.0));
        // 3 of 4 at 0 against 1 of 2 at 0: the gap at x = 0 is 0.25.
        let ks = kolmogorov_smirnov(&[0.0, 0.0, 0.0, 1.0], &[0.0, 1.0]).unwrap();
        assert!((ks.statistic - 0.25).abs() < 1e-12, "{ks:?}");
    }

    #[test]
    fn an_empty_sample_or_a_nan_is_refused() {
        assert!(kolmogorov_smirnov(&[], &[1.0]).is_err());
        let e = kolmogorov_smirnov(&[1.0], &[f64::NAN]).unwrap_err();
        assert!(e.to_string().contains("second sample"), "{e}");
    }
}
