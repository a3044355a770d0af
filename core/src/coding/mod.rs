//! The paper's four spike codings (Methods, "Spike train encoding methods"), each a readout
//! population that can watch any population or spike input of a network, and each usable
//! directly on a [`MultiSpikeTrain`] or a whole dataset without a network.
//!
//! | coding | type | representation of one sample of `N` channels | distance |
//! |---|---|---|---|
//! | intensive | [`IntensiveCoding`] | `R = (1/N)·Σ_n I_n`, the mean spike count per channel (1 value) | Euclidean |
//! | spatial | [`SpatialCoding`] | `R_n = I_n`, the spike count of each channel (`N` values) | Euclidean |
//! | temporal | [`TemporalCoding`] | `R(s) = (1/N)·#{spikes of all channels in [s, s + Δt)}`, `s = 0, 1 ms, …, T − Δt` | Euclidean |
//! | spatiotemporal | [`SpatiotemporalCoding`] | the spike trains themselves, or their exponential traces `f_n(t)` sampled at the network step | multi-unit Van Rossum ([`crate::distance::van_rossum`]) |
//!
//! `I_n` is the number of spikes of channel `n`. (The paper's formulas write spike *times*
//! `t_n^i` inside the sums where they mean one count per spike.)
//!
//! # One spike at a time
//! Every coding implements [`Coding`]: [`reset`](Coding::reset) for a source of `N` channels,
//! then [`add_spike`](Coding::add_spike) per spike, and [`end_step`](Coding::end_step) after
//! each network step. As a [`Readout`] it is fed by the network (spike time
//! `t_k + φ·dt`, see [`crate::model`]); [`Coding::encode`] feeds it a recorded train directly.
//! Both paths run the same code, so a coding attached to a spike input that replays a sample
//! gives the same features as encoding that sample directly.
//!
//! ```
//! use neurotac_core::coding::{Coding, FeatureCoding, SpatialCoding, TemporalCoding};
//! use neurotac_core::{MultiSpikeTrain, NetworkBuilder, NetworkConfig, ReadoutSource, SpikeArrayInput};
//! let sample = MultiSpikeTrain::from_channels(vec![vec![0.0101, 0.0203], vec![0.0207]])?;
//! // Directly:
//! let mut spatial = SpatialCoding::new();
//! spatial.encode(&sample);
//! assert_eq!(spatial.features(), vec![2.0, 1.0]);
//! // As a readout of a spike input replaying the same sample:
//! let mut b = NetworkBuilder::new();
//! let taxels = b.add_spike_input("taxels", SpikeArrayInput::new(sample.clone()))?;
//! let temporal = b.add_readout(taxels, TemporalCoding::new(0.010, 0.030)?)?;
//! let mut net = b.build(NetworkConfig { dt_s: 1e-4 })?;
//! net.run(0.030, &neurotac_core::OneProcess)?;
//! let mut direct = TemporalCoding::new(0.010, 0.030)?;
//! direct.encode(&sample);
//! assert_eq!(net.readout(temporal)?.features(), direct.features());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod intensive;
mod spatial;
mod spatiotemporal;
mod temporal;

pub use crate::distance::TraceRecord;
pub use intensive::IntensiveCoding;
pub use spatial::SpatialCoding;
pub use spatiotemporal::SpatiotemporalCoding;
pub use temporal::{
    MAX_TEMPORAL_DURATION_MS, TemporalCoding, check_temporal_duration_ms, duration_ms_of,
    pooled_bin_counts, spike_bin_ms, whole_ms, write_window_features,
};

use crate::error::CodingError;
use crate::graph::{Readout, ReadoutContext, StepView};
use crate::spikes::MultiSpikeTrain;
use ndarray::Array2;
use rayon::prelude::*;
use std::ops::ControlFlow;

/// A coding fed one spike at a time (by a network as a [`Readout`], or by [`Coding::encode`]).
pub trait Coding: Send + 'static {
    /// Clears the state for a source of `n_channels` channels.
    fn reset(&mut self, n_channels: usize);

    /// One spike of `channel` at time `t_s` (seconds). Spikes arrive in time order per step.
    fn add_spike(&mut self, channel: usize, t_s: f64);

    /// Called after the spikes of the network step `[t_start_s, t_start_s + dt_s)`; codings that
    /// sample traces advance them here. The default does nothing.
    fn end_step(&mut self, t_start_s: f64, dt_s: f64) {
        let _ = (t_start_s, dt_s);
    }

    /// Resets for `trains.n_channels()` channels and feeds every spike of `trains`, channel by
    /// channel (no network, so [`end_step`](Self::end_step) is never called).
    fn encode(&mut self, trains: &MultiSpikeTrain) {
        self.reset(trains.n_channels());
        for (c, times) in trains.channels().enumerate() {
            for &t in times {
                self.add_spike(c, t);
            }
        }
    }
}

/// A coding whose representation is a fixed-length feature vector (intensive, spatial,
/// temporal), compared with the Euclidean distance.
pub trait FeatureCoding: Coding + Clone + Sync {
    /// Number of features after [`reset`](Coding::reset) for `n_channels` channels.
    fn n_features(&self, n_channels: usize) -> usize;

    /// Writes the features of the spikes fed so far into `out` (length
    /// [`n_features`](Self::n_features)).
    fn write_features(&self, out: &mut [f64]);

    /// The features of the spikes fed so far.
    fn features(&self) -> Vec<f64>;
}

/// The most values a feature matrix may hold: 2²⁸ (2 GiB of `f64`).
pub const MAX_FEATURE_VALUES: usize = 1 << 28;

/// Encodes every observation with a copy of `coding`, one row per observation (parallel over
/// observations; each row depends only on its observation, so the result does not depend on
/// the thread count).
///
/// All observations must have the same number of channels ([`CodingError::ChannelCount`] names
/// the first that differs); a matrix over [`MAX_FEATURE_VALUES`] is refused before allocation.
pub fn feature_matrix<C: FeatureCoding>(
    coding: &C,
    observations: &[MultiSpikeTrain],
) -> Result<Array2<f64>, CodingError> {
    let n_channels = check_channels(observations)?;
    let width = coding.n_features(n_channels);
    if observations.len().saturating_mul(width) > MAX_FEATURE_VALUES {
        return Err(CodingError::TooManyFeatures {
            samples: observations.len(),
            features: width,
            limit: MAX_FEATURE_VALUES,
        });
    }
    let mut out = Array2::zeros((observations.len(), width));
    if width == 0 {
        return Ok(out);
    }
    out.as_slice_mut()
        .expect("a fresh array is contiguous")
        .par_chunks_mut(width)
        .zip(observations.par_iter())
        .for_each_init(
            || coding.clone(),
            |c, (row, obs)| {
                c.encode(obs);
                c.write_features(row);
            },
        );
    Ok(out)
}

/// The common channel count of `observations` (0 when there are none).
pub(crate) fn check_channels(observations: &[MultiSpikeTrain]) -> Result<usize, CodingError> {
    let expected = observations.first().map_or(0, MultiSpikeTrain::n_channels);
    match observations.iter().position(|o| o.n_channels() != expected) {
        Some(sample) => Err(CodingError::ChannelCount {
            sample,
            expected,
            got: observations[sample].n_channels(),
        }),
        None => Ok(expected),
    }
}

/// Implements [`Readout`] for codings: `begin` resets for the source's size, `on_step` feeds
/// the step's spikes (at `t_k + φ·dt`) then calls `end_step`.
macro_rules! coding_readout {
    ($($coding:ty),* $(,)?) => {$(
        impl Readout for $coding {
            fn reads_population_state(&self) -> bool {
                false
            }

            fn begin(&mut self, context: &ReadoutContext<'_>) {
                Coding::reset(self, context.source_size);
            }

            fn on_step(&mut self, view: &StepView<'_>) -> ControlFlow<()> {
                let s = view.spikes;
                for (&i, &phi) in s.indices().iter().zip(s.fractions()) {
                    self.add_spike(i as usize, view.t_start_s + phi * view.dt_s);
                }
                self.end_step(view.t_start_s, view.dt_s);
                ControlFlow::Continue(())
            }
        }
    )*};
}

coding_readout!(
    IntensiveCoding,
    SpatialCoding,
    TemporalCoding,
    SpatiotemporalCoding
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MultiSpikeTrain;

    #[test]
    fn feature_matrices_and_temporal_samples_over_the_budget_are_refused_before_allocation() {
        let long = TemporalCoding::from_ms(1, MAX_TEMPORAL_DURATION_MS + 1).unwrap_err();
        assert!(long.to_string().contains("at most 3 600 000 ms"), "{long}");
        // 100 one-channel samples × 3 600 000 windows > 2²⁸ values.
        let temporal = TemporalCoding::from_ms(1, MAX_TEMPORAL_DURATION_MS).unwrap();
        let sample = MultiSpikeTrain::from_channels(vec![vec![0.5]]).unwrap();
        let e = feature_matrix(&temporal, &vec![sample; 100]).unwrap_err();
        assert!(matches!(
            e,
            CodingError::TooManyFeatures {
                samples: 100,
                features: 3_600_000,
                ..
            }
        ));
        assert!(
            e.to_string().contains("more than the limit of 268435456"),
            "{e}"
        );
    }

    use crate::graph::{NetworkBuilder, NetworkConfig, SpikeArrayInput};

    fn sample() -> MultiSpikeTrain {
        // Stamps that are awkward in binary (0.159 s, 0.0999999 s) and a within-bin repeat.
        MultiSpikeTrain::from_channels(vec![
            vec![0.0, 0.0999999, 0.159, 0.159],
            vec![],
            vec![0.001, 0.1, 0.2999],
        ])
        .unwrap()
    }

    /// Replays `trains` through a spike input watched by `coding`; returns the readout.
    fn through_network<C: Coding + Readout + Clone>(
        trains: &MultiSpikeTrain,
        coding: C,
        dt_s: f64,
    ) -> C {
        let mut b = NetworkBuilder::new();
        let input = b
            .add_spike_input("taxels", SpikeArrayInput::new(trains.clone()))
            .unwrap();
        let id = b.add_readout(input, coding).unwrap();
        let mut net = b.build(NetworkConfig { dt_s }).unwrap();
        net.run(0.3, &crate::OneProcess).unwrap();
        net.readout(id).unwrap().clone()
    }

    #[test]
    fn readouts_equal_direct_encoding() {
        let s = sample();
        for dt in [1e-3, 1e-4] {
            let mut i = IntensiveCoding::new();
            i.encode(&s);
            assert_eq!(
                through_network(&s, IntensiveCoding::new(), dt).features(),
                i.features()
            );
            assert_eq!(i.features(), vec![7.0 / 3.0]);
            let mut sp = SpatialCoding::new();
            sp.encode(&s);
            assert_eq!(
                through_network(&s, SpatialCoding::new(), dt).features(),
                sp.features()
            );
            assert_eq!(sp.features(), vec![4.0, 0.0, 3.0]);
            let t = TemporalCoding::new(0.05, 0.3).unwrap();
            let mut direct = t.clone();
            direct.encode(&s);
            assert_eq!(through_network(&s, t, dt).features(), direct.features());
            let st = SpatiotemporalCoding::new(0.01).unwrap();
            assert_eq!(through_network(&s, st, dt).trains(), {
                let mut d = SpatiotemporalCoding::new(0.01).unwrap();
                d.encode(&s);
                d.trains()
            });
        }
    }

    #[test]
    fn temporal_windows_follow_the_documented_convention() {
        let mut t = TemporalCoding::from_ms(100, 300).unwrap();
        t.encode(&sample());
        // Bins: 0, 99, 159, 159 (channel 0); 1, 100, 299 (channel 2).
        let f = t.features();
        assert_eq!(f.len(), 201);
        // Bins after rounding to the µs: 0.0999999 s is 100 000 µs, so bin 100.
        let bins = [0u32, 100, 159, 159, 1, 100, 299];
        for s in 0..=200u32 {
            let want = bins.iter().filter(|&&b| b >= s && b < s + 100).count() as f64 / 3.0;
            assert_eq!(f[s as usize], want, "window [{s}, {}) ms", s + 100);
        }
        assert_eq!(f[0], 2.0 / 3.0);
        assert_eq!(f[60], 4.0 / 3.0);
    }

    #[test]
    fn feature_matrix_rows_are_the_codings_and_bad_input_is_typed() {
        let a = sample();
        let b = MultiSpikeTrain::empty(3);
        let m = feature_matrix(&SpatialCoding::new(), &[a.clone(), b.clone()]).unwrap();
        assert_eq!(m.row(0).to_vec(), vec![4.0, 0.0, 3.0]);
        assert_eq!(m.row(1).to_vec(), vec![0.0; 3]);
        let two = MultiSpikeTrain::empty(2);
        assert_eq!(
            feature_matrix(&IntensiveCoding::new(), &[a, b, two]),
            Err(CodingError::ChannelCount {
                sample: 2,
                expected: 3,
                got: 2
            })
        );
        assert!(matches!(
            TemporalCoding::new(0.0, 1.0),
            Err(CodingError::InvalidParameter { .. })
        ));
        assert!(matches!(
            TemporalCoding::new(0.0105, 1.0),
            Err(CodingError::InvalidParameter { .. })
        ));
        assert!(matches!(
            TemporalCoding::new(f64::NAN, 1.0),
            Err(CodingError::InvalidParameter { .. })
        ));
        assert_eq!(
            TemporalCoding::new(0.2, 0.1),
            Err(CodingError::WindowLongerThanSample {
                window_ms: 200,
                duration_ms: 100
            })
        );
        assert!(SpatiotemporalCoding::new(-1.0).is_err());
        let early =
            MultiSpikeTrain::from_channels(vec![vec![0.1], vec![], vec![-0.5, 0.2]]).unwrap();
        let e = duration_ms_of(&[MultiSpikeTrain::empty(3), early]);
        assert_eq!(
            e,
            Err(CodingError::SpikeBeforeZero {
                sample: 1,
                channel: 2,
                time_s: -0.5
            })
        );
        assert_eq!(
            e.unwrap_err().to_string(),
            "sample 1, channel 2: spike at -0.5 s, before the sample start (0 s)"
        );
        assert_eq!(duration_ms_of(&[sample()]), Ok(300));
    }

    #[test]
    fn trace_sampling_is_exact_on_the_grid_and_converges_off_it() {
        use crate::distance::{VanRossum, trace_sampled_matrices};
        let tau = 0.02;
        let on_grid = vec![
            MultiSpikeTrain::from_channels(vec![vec![0.010, 0.030], vec![0.020]]).unwrap(),
            MultiSpikeTrain::from_channels(vec![vec![0.015], vec![0.020, 0.050]]).unwrap(),
        ];
        let exact = VanRossum::new(tau)
            .unwrap()
            .matrices(&on_grid, &crate::OneProcess)
            .unwrap();
        let sampled = trace_sampled_matrices(&on_grid, tau, 1e-3).unwrap();
        for c in [0.0, 0.4, 1.0] {
            let (e, s) = (
                exact.squared(c).unwrap()[[0, 1]],
                sampled.squared(c).unwrap()[[0, 1]],
            );
            assert!((e - s).abs() < 1e-12 * e, "c={c}: {e} vs {s}");
        }
        // Off the grid: the mean relative error over random pairs shrinks with dt.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let off_grid: Vec<MultiSpikeTrain> = (0..6)
            .map(|_| {
                MultiSpikeTrain::from_unsorted_channels((0..3).map(|_| {
                    (0..4)
                        .map(|_| 0.2 * rng.random::<f64>())
                        .collect::<Vec<_>>()
                }))
                .unwrap()
            })
            .collect();
        let exact = VanRossum::new(tau)
            .unwrap()
            .matrices(&off_grid, &crate::OneProcess)
            .unwrap()
            .squared(0.4)
            .unwrap();
        let errors: Vec<f64> = [1e-3, 1e-4, 1e-5]
            .iter()
            .map(|&dt| {
                let s = trace_sampled_matrices(&off_grid, tau, dt)
                    .unwrap()
                    .squared(0.4)
                    .unwrap();
                let rel = (&s - &exact).mapv(f64::abs) / exact.mapv(|e| e.max(1e-300));
                rel.sum() / 30.0
            })
            .collect();
        assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
        assert!(errors[2] < 1e-3, "{errors:?}");
    }
}
