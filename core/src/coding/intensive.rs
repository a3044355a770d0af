//! Intensive coding: the mean spike count per channel, `R = (1/N)·Σ_n I_n`.

use super::{Coding, FeatureCoding};

/// Mean spike count per channel over the sample (the paper's intensive coding: one number).
///
/// With no channel at all the mean is defined as 0 (there is nothing to count).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IntensiveCoding {
    n_channels: usize,
    total: u64,
}

impl IntensiveCoding {
    /// A coding with no channels yet (a network or [`Coding::encode`] sizes it).
    pub fn new() -> Self {
        Self::default()
    }

    /// The mean spike count per channel, `total / N` (0 when `N = 0`).
    pub fn value(&self) -> f64 {
        if self.n_channels == 0 {
            0.0
        } else {
            self.total as f64 / self.n_channels as f64
        }
    }
}

impl Coding for IntensiveCoding {
    fn reset(&mut self, n_channels: usize) {
        self.n_channels = n_channels;
        self.total = 0;
    }

    #[inline]
    fn add_spike(&mut self, channel: usize, _t_s: f64) {
        if channel < self.n_channels {
            self.total += 1;
        }
    }
}

impl FeatureCoding for IntensiveCoding {
    fn n_features(&self, _n_channels: usize) -> usize {
        1
    }

    fn write_features(&self, out: &mut [f64]) {
        out[0] = self.value();
    }

    fn features(&self) -> Vec<f64> {
        vec![self.value()]
    }
}
