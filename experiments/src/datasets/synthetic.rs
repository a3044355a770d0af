//! Seeded synthetic NeuroTac-like texture datasets, for benchmarks, tests and trying the
//! commands without a recording.
//!
//! Each class (texture) has its own per-taxel rate profile and its own temporal signature: the
//! rate of taxel `n` in class `k` is `r·g_{k,n}·(1 + m·sin(2π·f_k·t + φ_{k,n}))`, with `g` a gain
//! drawn in [0.5, 1.5], `f_k` a "bump frequency" drawn in [2, 12] Hz, `m = 0.8`, and `r` set so
//! a taxel fires `spikes_per_unit` spikes on average over the sample. Spikes are a Poisson
//! process (thinning), stamped to the microsecond like DAVIS events. Class `k` gets samples
//! `k, k + K, k + 2K, …` (balanced). Every sample is drawn from its own ChaCha8 stream seeded
//! from `(seed, sample index)`, so the dataset is the same at any thread count.
//!
//! Classes that differ this strongly are easy (near-100 % accuracy for most codings): use these
//! data for correctness and timing, not for accuracy claims.

use crate::error::ExperimentError;
use neurotac_core::dataset::{DURATION_S_KEY, MAX_CLASSES};
use neurotac_core::time::us_to_s;
use neurotac_core::{MultiSpikeTrain, SpikeDataset};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Shape of a synthetic dataset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticConfig {
    /// Number of samples. Default 1100 (100 per class, as the paper's artificial textures).
    pub samples: usize,
    /// Number of classes, at most [`MAX_CLASSES`]. Default 11.
    pub classes: usize,
    /// Channels (taxels) per sample. Default 49.
    pub channels: usize,
    /// Mean spikes per channel over a sample. Default 10.
    pub spikes_per_unit: f64,
    /// Sample duration (s). Default 4.5 s.
    pub duration_s: f64,
    /// Seed of every random draw.
    pub seed: u64,
}

impl Default for SyntheticConfig {
    fn default() -> Self {
        Self {
            samples: 1100,
            classes: 11,
            channels: 49,
            spikes_per_unit: 10.0,
            duration_s: 4.5,
            seed: 1,
        }
    }
}

const MODULATION: f64 = 0.8;

/// The most spike candidates one synthetic dataset may draw (samples × channels × spikes per
/// unit × the modulation's peak factor): 2 × 10⁸ candidates take minutes and the spikes
/// gigabytes.
pub const MAX_SYNTHETIC_SPIKES: f64 = 2e8;

impl SyntheticConfig {
    /// Refuses a configuration that [`synthetic_dataset`] cannot draw, or would draw for longer
    /// than its budget allows: more than [`MAX_CLASSES`] classes, non-finite or non-positive
    /// spikes per unit or duration, or more than [`MAX_SYNTHETIC_SPIKES`] spike candidates.
    pub fn check(&self) -> Result<(), ExperimentError> {
        if self.classes > MAX_CLASSES {
            return Err(ExperimentError::InvalidParameter {
                what: "classes",
                value: self.classes as f64,
                expected: "at most 1024 (the most classes a spike dataset may have)",
            });
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !positive(self.spikes_per_unit) {
            return Err(ExperimentError::InvalidParameter {
                what: "spikes_per_unit",
                value: self.spikes_per_unit,
                expected: "finite and > 0",
            });
        }
        if !positive(self.duration_s) {
            return Err(ExperimentError::InvalidParameter {
                what: "duration_s",
                value: self.duration_s,
                expected: "finite and > 0",
            });
        }
        let candidates =
            self.samples as f64 * self.channels as f64 * self.spikes_per_unit * (1.0 + MODULATION);
        if candidates > MAX_SYNTHETIC_SPIKES {
            return Err(ExperimentError::InvalidParameter {
                what: "spikes_per_unit",
                value: self.spikes_per_unit,
                expected: "at most 2 × 10⁸ spike candidates in all (samples × channels × spikes per unit × 1.8)",
            });
        }
        Ok(())
    }
}

/// Draws the dataset described by `config` (labels `i mod classes`, class names `texture k`,
/// `meta.duration_s` set). Check a configuration from outside with [`SyntheticConfig::check`]
/// first: this draws whatever it is given.
pub fn synthetic_dataset(config: &SyntheticConfig) -> SpikeDataset {
    let classes = config.classes.max(1);
    let mut class_rng = ChaCha8Rng::seed_from_u64(config.seed);
    let profiles: Vec<(f64, Vec<(f64, f64)>)> = (0..classes)
        .map(|_| {
            let freq = 2.0 + 10.0 * class_rng.random::<f64>();
            let taxels = (0..config.channels)
                .map(|_| {
                    let gain = 0.5 + class_rng.random::<f64>();
                    let phase = std::f64::consts::TAU * class_rng.random::<f64>();
                    (gain, phase)
                })
                .collect();
            (freq, taxels)
        })
        .collect();
    let base_rate = config.spikes_per_unit / config.duration_s;
    let observations: Vec<MultiSpikeTrain> = (0..config.samples)
        .into_par_iter()
        .map(|i| {
            let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
            rng.set_stream(1 + i as u64);
            let (freq, taxels) = &profiles[i % classes];
            let channels: Vec<Vec<f64>> = taxels
                .iter()
                .map(|&(gain, phase)| {
                    let max_rate = base_rate * gain * (1.0 + MODULATION);
                    let mut times = Vec::new();
                    let mut t = 0.0;
                    loop {
                        t += -(1.0 - rng.random::<f64>()).ln() / max_rate;
                        if t >= config.duration_s {
                            break;
                        }
                        let rate = base_rate
                            * gain
                            * (1.0 + MODULATION * (std::f64::consts::TAU * freq * t + phase).sin());
                        if rng.random::<f64>() * max_rate < rate {
                            times.push(us_to_s((t * 1e6).floor() as i64));
                        }
                    }
                    times
                })
                .collect();
            MultiSpikeTrain::from_channels(channels).expect("increasing finite times")
        })
        .collect();
    let labels = (0..config.samples).map(|i| i % classes).collect();
    let names = (0..classes).map(|k| format!("texture {k}")).collect();
    let mut meta = serde_json::Map::new();
    meta.insert("source".into(), "neurotac synthetic".into());
    meta.insert(DURATION_S_KEY.into(), config.duration_s.into());
    meta.insert("seed".into(), config.seed.into());
    SpikeDataset::new(observations, labels, names, meta).expect("consistent by construction")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_config_over_its_spike_budget_or_without_rate_is_refused() {
        assert!(SyntheticConfig::default().check().is_ok());
        for config in [
            SyntheticConfig {
                spikes_per_unit: 1e300,
                ..SyntheticConfig::default()
            },
            SyntheticConfig {
                samples: 1 << 40,
                ..SyntheticConfig::default()
            },
            SyntheticConfig {
                spikes_per_unit: f64::NAN,
                ..SyntheticConfig::default()
            },
            SyntheticConfig {
                duration_s: 0.0,
                ..SyntheticConfig::default()
            },
        ] {
            assert!(config.check().is_err(), "{config:?}");
        }
        let too_many = SyntheticConfig {
            classes: MAX_CLASSES + 1,
            ..SyntheticConfig::default()
        };
        let message = too_many.check().unwrap_err().to_string();
        assert!(
            message.contains(&format!("at most {MAX_CLASSES} ")),
            "{message}"
        );
    }

    #[test]
    fn seeded_balanced_and_at_the_asked_rate() {
        let config = SyntheticConfig {
            samples: 44,
            seed: 7,
            ..Default::default()
        };
        let a = synthetic_dataset(&config);
        let b = synthetic_dataset(&config);
        assert_eq!(a, b);
        assert_ne!(a, synthetic_dataset(&SyntheticConfig { seed: 8, ..config }));
        assert_eq!(a.n_channels(), 49);
        assert_eq!(a.labels().iter().filter(|&&l| l == 3).count(), 4);
        let spikes: usize = a.observations().iter().map(|o| o.total_spikes()).sum();
        let mean = spikes as f64 / (44.0 * 49.0);
        assert!((mean - 10.0).abs() < 0.6, "{mean}");
        let last = a
            .observations()
            .iter()
            .filter_map(|o| o.time_range())
            .map(|r| r.1)
            .fold(0.0, f64::max);
        assert!(last < 4.5);
    }
}
