//! [`TraceRecord`] (a sample's synaptic traces at a step, kept sparse) and [`TraceArrivals`],
//! which fills one, a spike at a time. Written by the spatiotemporal coding and
//! [`TraceRecord::of_trains`], read by the trace-sampled Van Rossum distance
//! ([`trace_sampled`](super::trace_sampled)); it sits below both.

use crate::error::CodingError;
use crate::spikes::MultiSpikeTrain;
use crate::time::s_to_us;

/// A sample's synaptic traces at a step `h` as a network advancing them holds them, kept
/// sparse: for each channel the steps at which its trace jumps and the number of spikes of each
/// jump. Memory is one `(u32, u32)` pair per step holding a spike, not one value per channel and
/// step, and that is the whole trace, because between jumps the graph's synapse filter only
/// decays it: with `q = e^{−h/τ}` its state after the jump at step `k_i` is
///
/// ```text
/// F_i = F_{i−1}·q^{k_i − k_{i−1}} + c_i        (c_i spikes in step k_i)
/// ```
///
/// the recursion an [`ExpSynapse`](crate::ExpSynapse) runs step by step. The record does not
/// depend on τ, so one run serves every τ of a search. It is filled by a
/// [`SpatiotemporalCoding`](crate::SpatiotemporalCoding) recording traces, or by
/// [`of_trains`](Self::of_trains); [`trace_sampled`](super::trace_sampled) turns records into Van
/// Rossum distances of the traces sampled at `h`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceRecord {
    step_us: i64,
    /// Per channel: `(step, spikes)`, steps strictly increasing.
    channels: Vec<Vec<(u32, u32)>>,
}

impl TraceRecord {
    /// The record of `trains` at step `trace_dt_s` (a whole number of µs, ≥ 1 µs): spike
    /// `t` falls in step `⌊round(t·10⁶) / h_µs⌋`, as the coding places it when fed by a network.
    /// Fed channel by channel, as [`Coding::encode`](crate::coding::Coding::encode) feeds a
    /// [`SpatiotemporalCoding`](crate::SpatiotemporalCoding) recording traces.
    pub fn of_trains(trains: &MultiSpikeTrain, trace_dt_s: f64) -> Result<Self, CodingError> {
        let step_us = trace_step_us(trace_dt_s)?;
        let mut arrivals = TraceArrivals::default();
        arrivals.reset(trains.n_channels());
        for (c, times) in trains.channels().enumerate() {
            for &t in times {
                arrivals.add(step_us, c, t);
            }
        }
        arrivals.record(step_us)
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

/// The trace step `trace_dt_s` in whole µs: a whole number of µs, at least 1 µs.
pub(crate) fn trace_step_us(trace_dt_s: f64) -> Result<i64, CodingError> {
    let us = s_to_us(trace_dt_s);
    if !(trace_dt_s.is_finite() && us >= 1 && (trace_dt_s * 1e6 - us as f64).abs() < 1e-6) {
        return Err(CodingError::InvalidParameter {
            what: "spatiotemporal trace_dt_s",
            value: trace_dt_s,
            expected: "a whole number of µs, at least 1 µs",
        });
    }
    Ok(us)
}

/// The jumps of a source's traces, fed one spike at a time: what a [`TraceRecord`] is made of.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct TraceArrivals {
    /// Per channel: `(step, spikes in it)` in step order.
    arrivals: Vec<Vec<(u32, u32)>>,
    /// The first spike no step can hold (before 0 or beyond `u32::MAX` steps): its channel and
    /// time.
    out_of_range: Option<(usize, f64)>,
}

impl TraceArrivals {
    /// Clears the jumps for a source of `n_channels` channels (keeping capacity).
    pub(crate) fn reset(&mut self, n_channels: usize) {
        self.arrivals.iter_mut().for_each(Vec::clear);
        self.arrivals.resize(n_channels, Vec::new());
        self.out_of_range = None;
    }

    /// One spike of `channel` (`< n_channels`) at `t_s`: it falls in step
    /// `⌊round(t·10⁶) / step_us⌋`.
    #[inline]
    pub(crate) fn add(&mut self, step_us: i64, channel: usize, t_s: f64) {
        let us = s_to_us(t_s);
        match u32::try_from(us.div_euclid(step_us)) {
            Ok(step) if us >= 0 => {
                let c = &mut self.arrivals[channel];
                match c.last_mut() {
                    Some(last) if last.0 == step => last.1 += 1,
                    _ => c.push((step, 1)),
                }
            }
            _ => {
                self.out_of_range.get_or_insert((channel, t_s));
            }
        }
    }

    /// The record of the spikes fed so far at step `step_us`; an error when a spike fell before
    /// 0 or beyond `u32::MAX` steps.
    pub(crate) fn record(&self, step_us: i64) -> Result<TraceRecord, CodingError> {
        match self.out_of_range {
            Some((channel, time_s)) if time_s < 0.0 => Err(CodingError::SpikeBeforeZero {
                sample: 0,
                channel,
                time_s,
            }),
            Some((_, time_s)) => Err(CodingError::InvalidParameter {
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
        }
    }
}
