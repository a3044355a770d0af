//! Spatiotemporal coding: the exponential traces of the channels,
//! `f_n(t) = Σ_i H(t − t_n^i)·e^{−(t − t_n^i)/τ}`, compared with the multi-unit Van Rossum
//! distance ([`crate::distance::van_rossum`]).
//!
//! The coding keeps the spike trains it sees, which is all the exact distance needs. With
//! [`SpatiotemporalCoding::with_trace_record`] it also keeps each channel's synaptic trace as a
//! network advancing it at a step `h` holds it: a [`TraceRecord`] of the steps at which the
//! trace jumps and by how many spikes. That is the whole trace in bounded memory — one entry per
//! step with a spike, not one value per channel and step — because between jumps the graph's
//! synapse filter only decays it: with `q = e^{−h/τ}` its state after the jump at step `k_i` is
//!
//! ```text
//! F_i = F_{i−1}·q^{k_i − k_{i−1}} + c_i        (c_i spikes in step k_i)
//! ```
//!
//! the recursion an [`ExpSynapse`](crate::ExpSynapse) runs step by step. The record does not
//! depend on τ, so one run serves every τ of a search; [`crate::distance::trace_sampled`]
//! turns records into Van Rossum distances of the traces sampled at `h`.

use super::Coding;
use crate::distance::check_tau;
use crate::error::CodingError;
use crate::spikes::MultiSpikeTrain;
use crate::time::s_to_us;

/// The spike trains of a source (for the exact multi-unit Van Rossum distance) and, optionally,
/// its synaptic traces at a step `h` as a [`TraceRecord`].
#[derive(Debug, Clone, PartialEq)]
pub struct SpatiotemporalCoding {
    tau_s: f64,
    n_channels: usize,
    spikes: Vec<(u32, f64)>,
    /// The trace step in whole µs, when recording traces.
    trace_step_us: Option<i64>,
    /// Per channel: `(step, spikes in it)` in step order.
    arrivals: Vec<Vec<(u32, u32)>>,
    /// The first spike time no step can hold (before 0 or beyond `u32::MAX` steps).
    out_of_range: Option<f64>,
}

/// A sample's synaptic traces at a step `h`, kept sparse: for each channel the steps at which its
/// trace jumps and the number of spikes of each jump (module docs). Memory is one `(u32, u32)`
/// pair per step holding a spike.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceRecord {
    step_us: i64,
    /// Per channel: `(step, spikes)`, steps strictly increasing.
    channels: Vec<Vec<(u32, u32)>>,
}

impl TraceRecord {
    /// The record of `trains` at step `trace_dt_s` (a whole number of µs, ≥ 1 µs): spike
    /// `t` falls in step `⌊round(t·10⁶) / h_µs⌋`, as the coding places it when fed by a network.
    pub fn of_trains(trains: &MultiSpikeTrain, trace_dt_s: f64) -> Result<Self, CodingError> {
        let mut coding = SpatiotemporalCoding::new(1.0)
            .expect("τ = 1 s is valid")
            .with_trace_record(trace_dt_s)?;
        coding.encode(trains);
        coding.trace_record().expect("trace recording is on")
    }

    /// The trace step `h` (s).
    pub fn trace_dt_s(&self) -> f64 {
        self.step_us as f64 * 1e-6
    }

    /// The trace step `h` in µs.
    pub fn trace_step_us(&self) -> i64 {
        self.step_us
    }

    /// Number of channels.
    pub fn n_channels(&self) -> usize {
        self.channels.len()
    }

    /// Channel `c`'s jumps: `(step, spikes)` in step order.
    pub fn channel(&self, c: usize) -> &[(u32, u32)] {
        &self.channels[c]
    }

    /// The pooled trace `Σ_n f_n`'s jumps: every channel's merged, counts of a shared step summed.
    pub fn pooled(&self) -> Vec<(u32, u32)> {
        let mut all: Vec<(u32, u32)> = self.channels.iter().flatten().copied().collect();
        all.sort_unstable_by_key(|&(step, _)| step);
        let mut pooled: Vec<(u32, u32)> = Vec::with_capacity(all.len());
        for (step, count) in all {
            match pooled.last_mut() {
                Some(last) if last.0 == step => last.1 += count,
                _ => pooled.push((step, count)),
            }
        }
        pooled
    }

    /// Bytes held (the bounded-memory claim, measurable).
    pub fn heap_bytes(&self) -> usize {
        self.channels
            .iter()
            .map(|c| c.capacity() * std::mem::size_of::<(u32, u32)>())
            .sum::<usize>()
            + self.channels.capacity() * std::mem::size_of::<Vec<(u32, u32)>>()
    }
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
            arrivals: Vec::new(),
            out_of_range: None,
        })
    }

    /// The same coding, also keeping the traces at step `trace_dt_s` as a [`TraceRecord`]
    /// (`trace_dt_s` a whole number of µs, ≥ 1 µs; e.g. the network step).
    pub fn with_trace_record(self, trace_dt_s: f64) -> Result<Self, CodingError> {
        let us = s_to_us(trace_dt_s);
        if !(trace_dt_s.is_finite() && us >= 1 && (trace_dt_s * 1e6 - us as f64).abs() < 1e-6) {
            return Err(CodingError::InvalidParameter {
                what: "spatiotemporal trace_dt_s",
                value: trace_dt_s,
                expected: "a whole number of µs, at least 1 µs",
            });
        }
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
        Some(match self.out_of_range {
            Some(time_s) if time_s < 0.0 => Err(CodingError::SpikeBeforeZero { sample: 0, time_s }),
            Some(time_s) => Err(CodingError::InvalidParameter {
                what: "spike time for the trace record",
                value: time_s,
                expected: "fewer than 2³² trace steps from 0",
            }),
            None => {
                let mut channels = self.arrivals.clone();
                for c in &mut channels {
                    // A network and `encode` feed each channel in time order; a caller of
                    // `add_spike` may not, so out-of-order steps are sorted and merged here.
                    if !c.is_sorted_by(|a, b| a.0 < b.0) {
                        c.sort_unstable_by_key(|&(s, _)| s);
                        c.dedup_by(|later, kept| {
                            let same = later.0 == kept.0;
                            if same {
                                kept.1 += later.1;
                            }
                            same
                        });
                    }
                }
                Ok(TraceRecord { step_us, channels })
            }
        })
    }
}

impl Coding for SpatiotemporalCoding {
    fn reset(&mut self, n_channels: usize) {
        self.n_channels = n_channels;
        self.spikes.clear();
        self.arrivals.iter_mut().for_each(Vec::clear);
        self.arrivals.resize(n_channels, Vec::new());
        self.out_of_range = None;
    }

    #[inline]
    fn add_spike(&mut self, channel: usize, t_s: f64) {
        if channel >= self.n_channels {
            return;
        }
        self.spikes.push((channel as u32, t_s));
        if let Some(h) = self.trace_step_us {
            let us = s_to_us(t_s);
            match u32::try_from(us.div_euclid(h)) {
                Ok(step) if us >= 0 => {
                    let c = &mut self.arrivals[channel];
                    match c.last_mut() {
                        Some(last) if last.0 == step => last.1 += 1,
                        _ => c.push((step, 1)),
                    }
                }
                _ => {
                    self.out_of_range.get_or_insert(t_s);
                }
            }
        }
    }
}
