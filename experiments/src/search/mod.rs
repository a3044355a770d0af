//! Parameter searches of the paper: the temporal coding's window Δt by brute force
//! ([`dt_sweep`]) and the spatiotemporal coding's (τ, cos θ) by Bayesian optimisation
//! ([`bayes`]).

pub mod bayes;
pub mod dt_sweep;

use crate::protocols::wilson_interval;

/// The candidates of a search whose accuracy cannot be told from the best's on the samples
/// scored: the span of their parameter values, and how many there are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseBand {
    /// Smallest parameter value indistinguishable from the best.
    pub low: f64,
    /// Largest parameter value indistinguishable from the best.
    pub high: f64,
    /// Candidates indistinguishable from the best (the best included).
    pub count: usize,
    /// Candidates scored.
    pub of: usize,
}

impl NoiseBand {
    /// Whether the best is the only candidate the data single out: when any other candidate
    /// scores within the noise, the chosen value is not determined beyond `low..=high`.
    pub fn determined(&self) -> bool {
        self.count <= 1
    }
}

/// The band of `candidates` (parameter value, leave-one-out accuracy on the same `n` samples)
/// indistinguishable from the best accuracy: those at or above the lower end of the best's
/// Wilson 95 % interval. The criterion treats each candidate's accuracy as exact and ignores
/// that all were scored on the same samples, so it errs towards a wider band (towards saying
/// "not determined"), never towards claiming a value the data do not single out. `None`
/// without candidates.
pub fn noise_band(candidates: &[(f64, f64)], n: usize) -> Option<NoiseBand> {
    let best = candidates
        .iter()
        .map(|c| c.1)
        .fold(f64::NEG_INFINITY, f64::max);
    if !best.is_finite() {
        return None;
    }
    let hits = (best * n as f64).round() as usize;
    let (low_accuracy, _) = wilson_interval(hits.min(n), n, 1.96);
    // The best itself is always in (its accuracy rounds onto n hits, within the interval).
    let within: Vec<f64> = (candidates.iter())
        .filter(|c| c.1 >= low_accuracy.min(best))
        .map(|c| c.0)
        .collect();
    Some(NoiseBand {
        low: within.iter().copied().fold(f64::INFINITY, f64::min),
        high: within.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        count: within.len(),
        of: candidates.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_surface_is_not_determined_and_a_sharp_peak_is() {
        // 1100 samples: the Wilson 95 % interval of 90 % is about ±1.8 points.
        let flat: Vec<(f64, f64)> = (1..=10)
            .map(|w| (w as f64, 0.89 + 0.001 * w as f64))
            .collect();
        let band = noise_band(&flat, 1100).unwrap();
        assert!(!band.determined());
        assert_eq!(
            (band.low, band.high, band.count, band.of),
            (1.0, 10.0, 10, 10)
        );
        let sharp = [(1.0, 0.5), (2.0, 0.6), (3.0, 0.9), (4.0, 0.7)];
        let band = noise_band(&sharp, 1100).unwrap();
        assert!(band.determined());
        assert_eq!((band.low, band.high), (3.0, 3.0));
        // The same curve on 20 samples cannot tell 0.7 from 0.9.
        let band = noise_band(&sharp, 20).unwrap();
        assert_eq!((band.low, band.high, band.count), (3.0, 4.0, 2));
        assert_eq!(noise_band(&[], 10), None);
    }
}
