//! Spatiotemporal coding: the exponential traces of the channels,
//! `f_n(t) = Σ_i H(t − t_n^i)·e^{−(t − t_n^i)/τ}`, compared with the multi-unit Van Rossum
//! distance ([`crate::distance::van_rossum`]).
//!
//! The coding keeps the spike trains it sees, which is all the exact distance needs. With
//! [`SpatiotemporalCoding::with_trace_sampling`] it also advances the traces at the network step
//! with the graph's synapse filter (decay `e^{−dt/τ}`, flush below
//! [`FLUSH_TO_ZERO`](crate::FLUSH_TO_ZERO), then `+1` per spike of the step, exactly as a
//! projection delivers a spike) and samples them after every step: the trace-sampled variant.
//!
//! # Trace-sampled features
//! Between samples a trace decays exactly, so with `q = e^{−dt/τ}` the Van Rossum integral
//! over one step is `(2/τ)∫_0^{dt} δ(t_k)²·e^{−2s/τ} ds = (1 − q²)·δ(t_k)²`, and the tail after
//! the last sample `t_{K−1}` sums to `δ(t_K)²` with `δ(t_K) = q·δ(t_{K−1})`. The features are
//! therefore `√(1 − q²)·f(t_k)` for `k < K` followed by the tail value `q·f(t_{K−1})`, and the
//! squared Euclidean distance between two samples' features is their trace-sampled `D²`. It is
//! exact when every spike lies on the step grid; otherwise a spike enters its trace at the start
//! of its step, an error that vanishes as `dt → 0`.

use super::Coding;
use crate::distance::check_tau;
use crate::error::{CodingError, DistanceError, GraphError};
use crate::graph::{
    NetworkBuilder, NetworkConfig, ReadoutSource, SpikeArrayInput, decay_and_flush,
};
use crate::spikes::MultiSpikeTrain;
use rayon::prelude::*;

/// The spike trains of a source (for the exact multi-unit Van Rossum distance) and, optionally,
/// its exponential traces sampled at every network step.
#[derive(Debug, Clone, PartialEq)]
pub struct SpatiotemporalCoding {
    tau_s: f64,
    sample_traces: bool,
    n_channels: usize,
    spikes: Vec<(u32, f64)>,
    /// Trace sampling: decay per step, current traces, this step's spike counts, and the samples
    /// (row-major, one row of `n_channels` per step).
    decay: f64,
    traces: Vec<f64>,
    pending: Vec<f64>,
    samples: Vec<f64>,
    steps: usize,
}

/// Trace-sampled features of one sample (see the module docs): per-channel traces (channel-
/// major, `K + 1` values per channel) and the pooled trace `Σ_n f_n` (`K + 1` values).
#[derive(Debug, Clone, PartialEq)]
pub struct TraceFeatures {
    /// Scaled per-channel samples; squared Euclidean distances of these are `LL²`.
    pub channels: Vec<f64>,
    /// Scaled pooled samples; squared Euclidean distances of these are `SP²`.
    pub pooled: Vec<f64>,
}

impl SpatiotemporalCoding {
    /// A coding with kernel time constant `tau_s` (seconds, finite and > 0) that records spikes.
    pub fn new(tau_s: f64) -> Result<Self, CodingError> {
        check_tau(tau_s).map_err(|_| CodingError::InvalidParameter {
            what: "spatiotemporal tau_s",
            value: tau_s,
            expected: "finite and > 0",
        })?;
        Ok(Self {
            tau_s,
            sample_traces: false,
            n_channels: 0,
            spikes: Vec::new(),
            decay: 0.0,
            traces: Vec::new(),
            pending: Vec::new(),
            samples: Vec::new(),
            steps: 0,
        })
    }

    /// The same coding, also sampling the traces after every network step.
    pub fn with_trace_sampling(self) -> Self {
        Self {
            sample_traces: true,
            ..self
        }
    }

    /// Kernel time constant τ (s).
    pub fn tau_s(&self) -> f64 {
        self.tau_s
    }

    /// The spikes seen so far, one train per channel.
    pub fn trains(&self) -> MultiSpikeTrain {
        MultiSpikeTrain::from_labelled_spikes(self.n_channels, &self.spikes)
            .expect("recorded spikes have finite times on existing channels")
    }

    /// Number of trace samples taken (network steps seen while sampling).
    pub fn n_samples(&self) -> usize {
        self.steps
    }

    /// The trace-sampled features (module docs), or `None` without trace sampling.
    pub fn trace_features(&self) -> Option<TraceFeatures> {
        if !self.sample_traces {
            return None;
        }
        let n = self.n_channels;
        let k = self.steps;
        let q = self.decay;
        let scale = (1.0 - q * q).sqrt();
        let mut channels = vec![0.0; n * (k + 1)];
        let mut pooled = vec![0.0; k + 1];
        for step in 0..k {
            let row = &self.samples[step * n..(step + 1) * n];
            for (c, &f) in row.iter().enumerate() {
                channels[c * (k + 1) + step] = scale * f;
            }
            pooled[step] = scale * row.iter().sum::<f64>();
        }
        // The exact tail: the last sample decayed once more (zero traces before any step).
        let last = if k > 0 {
            &self.samples[(k - 1) * n..k * n]
        } else {
            &self.traces[..]
        };
        for (c, &f) in last.iter().enumerate() {
            channels[c * (k + 1) + k] = q * f;
        }
        pooled[k] = q * last.iter().sum::<f64>();
        Some(TraceFeatures { channels, pooled })
    }
}

impl Coding for SpatiotemporalCoding {
    fn reset(&mut self, n_channels: usize) {
        self.n_channels = n_channels;
        self.spikes.clear();
        self.traces.clear();
        self.traces.resize(n_channels, 0.0);
        self.pending.clear();
        self.pending.resize(n_channels, 0.0);
        self.samples.clear();
        self.steps = 0;
    }

    #[inline]
    fn add_spike(&mut self, channel: usize, t_s: f64) {
        if channel < self.n_channels {
            self.spikes.push((channel as u32, t_s));
            self.pending[channel] += 1.0;
        }
    }

    fn end_step(&mut self, _t_start_s: f64, dt_s: f64) {
        if !self.sample_traces {
            return;
        }
        // The graph's synapse filter: decay, then deliver this step's spikes.
        self.decay = (-dt_s / self.tau_s).exp();
        decay_and_flush(&mut self.traces, self.decay);
        for (f, p) in self.traces.iter_mut().zip(self.pending.iter_mut()) {
            *f += *p;
            *p = 0.0;
        }
        self.samples.extend_from_slice(&self.traces);
        self.steps += 1;
    }
}

/// Trace-sampled features of every observation: each is replayed through a network (a
/// [`SpikeArrayInput`] watched by a trace-sampling [`SpatiotemporalCoding`]) at step `dt_s` for
/// `duration_s` (parallel over observations; each row depends only on its observation).
///
/// Returns the per-channel feature matrix (for `LL²`) and the pooled one (for `SP²`), one row per
/// observation.
pub fn trace_features_of_dataset(
    observations: &[MultiSpikeTrain],
    tau_s: f64,
    dt_s: f64,
    duration_s: f64,
) -> Result<(ndarray::Array2<f64>, ndarray::Array2<f64>), DistanceError> {
    check_tau(tau_s)?;
    for (what, value) in [("trace dt_s", dt_s), ("trace duration_s", duration_s)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(DistanceError::InvalidParameter {
                what,
                value,
                expected: "finite and > 0",
            });
        }
    }
    let n_channels = super::check_channels(observations).map_err(|e| match e {
        CodingError::ChannelCount {
            sample,
            expected,
            got,
        } => DistanceError::ChannelCount {
            sample,
            expected,
            got,
        },
        _ => unreachable!("check_channels only reports channel counts"),
    })?;
    let rows: Vec<TraceFeatures> = observations
        .par_iter()
        .map(|obs| -> Result<TraceFeatures, GraphError> {
            let mut b = NetworkBuilder::new();
            let input = b.add_spike_input("trains", SpikeArrayInput::new(obs.clone()))?;
            let coding = SpatiotemporalCoding::new(tau_s)
                .expect("τ checked above")
                .with_trace_sampling();
            let id = b.add_readout(ReadoutSource::Node(input), coding)?;
            let mut net = b.build(NetworkConfig { dt_s })?;
            net.run(duration_s)?;
            Ok(net
                .readout(id)
                .trace_features()
                .expect("trace sampling is on"))
        })
        .collect::<Result<_, _>>()
        .map_err(|e| DistanceError::InvalidParameter {
            what: "trace sampling network",
            value: dt_s,
            expected: match e {
                GraphError::InvalidParameter { expected, .. } => expected,
                _ => "a network that builds and runs",
            },
        })?;
    let k = rows.first().map_or(0, |r| r.pooled.len());
    let mut channels = ndarray::Array2::zeros((rows.len(), n_channels * k));
    let mut pooled = ndarray::Array2::zeros((rows.len(), k));
    for (i, r) in rows.iter().enumerate() {
        channels
            .row_mut(i)
            .as_slice_mut()
            .expect("rows of a standard array are contiguous")
            .copy_from_slice(&r.channels);
        pooled
            .row_mut(i)
            .as_slice_mut()
            .expect("rows of a standard array are contiguous")
            .copy_from_slice(&r.pooled);
    }
    Ok((channels, pooled))
}
