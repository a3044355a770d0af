//! Special functions shared by the crates (the sensor simulator's pin edges, the Bayesian
//! optimisation's normal CDF).

/// The complementary error function `erfc(x) = (2/√π)·∫ₓ^∞ e^(−u²) du`, by the Chebyshev fit of
/// Numerical Recipes (§6.2, `erfcc`): fractional error below 1.2·10⁻⁷ for every `x`.
///
/// ```
/// use neurotac_core::special::erfc;
/// assert!((erfc(0.0) - 1.0).abs() < 1e-7);
/// assert!((erfc(1.0) - 0.157_299_207).abs() < 1e-7);
/// assert!((erfc(-1.0) - 1.842_700_793).abs() < 1e-7);
/// ```
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 { r } else { 2.0 - r }
}
