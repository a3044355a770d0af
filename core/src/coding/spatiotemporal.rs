//! Spatiotemporal coding: the exponential traces of the channels,
//! `f_n(t) = Σ_i H(t − t_n^i)·e^{−(t − t_n^i)/τ}`, compared with the multi-unit Van Rossum
//! distance ([`crate::distance::van_rossum`]).
//!
//! The coding keeps the spike trains it sees, which is all the exact distance needs. With
//! [`SpatiotemporalCoding::with_trace_record`] it also keeps each channel's synaptic trace as a
//! network advancing it at a step `h` holds it: a [`TraceRecord`] of the steps at which the
//! trace jumps and by how many spikes (bounded memory; the recursion is in its docs), which
//! [`crate::distance::trace_sampled`] turns into Van Rossum distances of the traces sampled at
//! `h`.

use super::Coding;
use crate::distance::check_tau;
use crate::distance::trace_record::{TraceArrivals, TraceRecord, trace_step_us};
use crate::error::CodingError;
use crate::spikes::MultiSpikeTrain;

/// The spike trains of a source (for the exact multi-unit Van Rossum distance) and, optionally,
/// its synaptic traces at a step `h` as a [`TraceRecord`].
#[derive(Debug, Clone, PartialEq)]
pub struct SpatiotemporalCoding {
    tau_s: f64,
    n_channels: usize,
    spikes: Vec<(u32, f64)>,
    /// The trace step in whole µs, when recording traces.
    trace_step_us: Option<i64>,
    /// The traces' jumps (fed only when recording traces).
    arrivals: TraceArrivals,
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
            n_channels: 0,
            spikes: Vec::new(),
            trace_step_us: None,
            arrivals: TraceArrivals::default(),
        })
    }

    /// The same coding, also keeping the traces at step `trace_dt_s` as a [`TraceRecord`]
    /// (`trace_dt_s` a whole number of µs, ≥ 1 µs; e.g. the network step).
    pub fn with_trace_record(self, trace_dt_s: f64) -> Result<Self, CodingError> {
        let us = trace_step_us(trace_dt_s)?;
        Ok(Self {
            trace_step_us: Some(us),
            ..self
        })
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

    /// The traces seen so far ([`TraceRecord`]), `None` without
    /// [`with_trace_record`](Self::with_trace_record); an error when a spike fell before 0 or
    /// beyond `u32::MAX` steps.
    pub fn trace_record(&self) -> Option<Result<TraceRecord, CodingError>> {
        let step_us = self.trace_step_us?;
        Some(self.arrivals.record(step_us))
    }
}

impl Coding for SpatiotemporalCoding {
    fn reset(&mut self, n_channels: usize) {
        self.n_channels = n_channels;
        self.spikes.clear();
        self.arrivals.reset(n_channels);
    }

    #[inline]
    fn add_spike(&mut self, channel: usize, t_s: f64) {
        if channel >= self.n_channels {
            return;
        }
        self.spikes.push((channel as u32, t_s));
        if let Some(h) = self.trace_step_us {
            self.arrivals.add(h, channel, t_s);
        }
    }
}
