//! Spatial coding: the spike count of each channel, `R_n = I_n`.

use super::{Coding, FeatureCoding};

/// Spike count per channel (the paper's spatial coding: 49 numbers for the 49 taxels).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpatialCoding {
    counts: Vec<u64>,
}

impl SpatialCoding {
    /// A coding with no channels yet (a network or [`Coding::encode`] sizes it).
    pub fn new() -> Self {
        Self::default()
    }

    /// Spike count per channel.
    pub fn counts(&self) -> &[u64] {
        &self.counts
    }
}

impl Coding for SpatialCoding {
    fn reset(&mut self, n_channels: usize) {
        self.counts.clear();
        self.counts.resize(n_channels, 0);
    }

    #[inline]
    fn add_spike(&mut self, channel: usize, _t_s: f64) {
        if let Some(c) = self.counts.get_mut(channel) {
            *c += 1;
        }
    }
}

impl FeatureCoding for SpatialCoding {
    fn n_features(&self, n_channels: usize) -> usize {
        n_channels
    }

    fn write_features(&self, out: &mut [f64]) {
        for (o, &c) in out.iter_mut().zip(&self.counts) {
            *o = c as f64;
        }
    }

    fn features(&self) -> Vec<f64> {
        self.counts.iter().map(|&c| c as f64).collect()
    }
}
