//! Temporal coding: a window of width Δt rolled over the sample in 1 ms steps.
//!
//! # Window convention (exact)
//! Time is binned to whole milliseconds: a spike at `t` seconds lies in bin
//! `b = ⌊round(t·10⁶ µs) / 1000⌋` (via [`crate::s_to_us`], so a spike stamped 0.159 s is in bin
//! 159 whatever the rounding of `0.159·1000`). A sample covers `T` bins, `[0, T)` ms; spikes
//! outside it are not part of the sample. With `x[b]` the number of spikes of all channels in
//! bin `b` and the prefix sum `C[m] = Σ_{b<m} x[b]`, the features are
//!
//! ```text
//! R(s) = (C[s + Δt] − C[s]) / N      for s = 0, 1, …, T − Δt   (W = T − Δt + 1 windows [s, s + Δt))
//! ```
//!
//! Every window is a difference of two integer prefix sums, so it is exact, and the features
//! of every Δt come from the same prefix sum (the Δt sweep of `neurotac-experiments` relies on it).

use super::{Coding, FeatureCoding};
use crate::error::CodingError;
use crate::spikes::MultiSpikeTrain;
use crate::time::s_to_us;

/// The longest sample the temporal coding takes (ms): one hour, a bin of 4 bytes per ms (14 MB)
/// in each thread that encodes.
pub const MAX_TEMPORAL_DURATION_MS: u32 = 3_600_000;

/// Refuses a sample longer than [`MAX_TEMPORAL_DURATION_MS`].
pub fn check_temporal_duration_ms(duration_ms: u32) -> Result<(), CodingError> {
    if duration_ms > MAX_TEMPORAL_DURATION_MS {
        return Err(CodingError::InvalidParameter {
            what: "temporal duration_ms",
            value: f64::from(duration_ms),
            expected: "at most 3 600 000 ms (one hour; the coding holds a count per ms)",
        });
    }
    Ok(())
}

/// Converts a duration in seconds to whole milliseconds, rejecting non-finite, non-positive and
/// fractional values (`what` names the parameter in the error).
pub fn whole_ms(seconds: f64, what: &'static str) -> Result<u32, CodingError> {
    let ms = seconds * 1e3;
    let rounded = ms.round();
    if !(seconds.is_finite() && seconds > 0.0) || rounded < 1.0 || rounded > u32::MAX as f64 {
        return Err(CodingError::InvalidParameter {
            what,
            value: seconds,
            expected: "finite and ≥ 1 ms",
        });
    }
    if (ms - rounded).abs() > 1e-6 {
        return Err(CodingError::InvalidParameter {
            what,
            value: seconds,
            expected: "a whole number of milliseconds",
        });
    }
    Ok(rounded as u32)
}

/// The 1-ms bin of a spike at `t_s` seconds, or `None` before time 0.
#[inline]
pub fn spike_bin_ms(t_s: f64) -> Option<u64> {
    let us = s_to_us(t_s);
    (us >= 0).then_some(us as u64 / 1000)
}

/// The shortest whole-ms duration that holds every spike of `observations`: one bin past the
/// latest spike's bin (1 ms when there is no spike). Errors on a spike before time 0, naming the
/// sample and the channel, since no window convention covers it.
pub fn duration_ms_of(observations: &[MultiSpikeTrain]) -> Result<u32, CodingError> {
    let mut last_bin = 0u64;
    for (sample, o) in observations.iter().enumerate() {
        for (channel, times) in o.channels().enumerate() {
            // Channels are sorted: their first spike is their earliest.
            if let (Some(&first), Some(&last)) = (times.first(), times.last()) {
                if spike_bin_ms(first).is_none() {
                    return Err(CodingError::SpikeBeforeZero {
                        sample,
                        channel,
                        time_s: first,
                    });
                }
                last_bin = last_bin.max(spike_bin_ms(last).unwrap_or(0));
            }
        }
    }
    u32::try_from(last_bin + 1).map_err(|_| CodingError::InvalidParameter {
        what: "sample duration (ms)",
        value: (last_bin + 1) as f64,
        expected: "at most 2³² − 1 ms",
    })
}

/// Spike counts of all channels pooled in 1-ms bins over `[0, duration_ms)`; spikes outside are
/// dropped (see the module docs).
pub fn pooled_bin_counts(trains: &MultiSpikeTrain, duration_ms: u32) -> Vec<u32> {
    let mut bins = vec![0u32; duration_ms as usize];
    for &t in trains.flat_times() {
        if let Some(b) = spike_bin_ms(t).filter(|&b| b < duration_ms as u64) {
            bins[b as usize] += 1;
        }
    }
    bins
}

/// The temporal features from per-ms pooled bin counts ([`TemporalCoding::bin_counts`],
/// [`pooled_bin_counts`]): `R(s) = (1/N)·Σ_{b ∈ [s, s + Δt)} bins[b]` for `s = 0 … T − Δt`, written
/// to `out` (length `T − Δt + 1`, `window_ms ≤ T = bins.len()`), so one recorded bin series
/// gives the features of every window.
pub fn write_window_features(bins: &[u32], window_ms: u32, n_channels: usize, out: &mut [f64]) {
    // Running window count = C[s + Δt] − C[s], advanced by one bin in, one bin out.
    let dt = window_ms as usize;
    let scale = 1.0 / n_channels.max(1) as f64;
    let mut count: u64 = bins[..dt].iter().map(|&b| b as u64).sum();
    out[0] = count as f64 * scale;
    for (s, o) in out.iter_mut().enumerate().take(bins.len() + 1 - dt).skip(1) {
        count = count + bins[s + dt - 1] as u64 - bins[s - 1] as u64;
        *o = count as f64 * scale;
    }
}

/// Rolling-window spike counts pooled over channels and divided by `N` (the paper's temporal
/// coding). See the module docs for the exact window convention.
#[derive(Debug, Clone, PartialEq)]
pub struct TemporalCoding {
    window_ms: u32,
    duration_ms: u32,
    n_channels: usize,
    bins: Vec<u32>,
}

impl TemporalCoding {
    /// Windows of `window_s` over samples of `duration_s`, both whole milliseconds, the window
    /// no longer than the sample.
    pub fn new(window_s: f64, duration_s: f64) -> Result<Self, CodingError> {
        let window_ms = whole_ms(window_s, "temporal window_s")?;
        let duration_ms = whole_ms(duration_s, "temporal duration_s")?;
        Self::from_ms(window_ms, duration_ms)
    }

    /// Like [`new`](Self::new) with both lengths already in whole milliseconds.
    pub fn from_ms(window_ms: u32, duration_ms: u32) -> Result<Self, CodingError> {
        if window_ms == 0 {
            return Err(CodingError::InvalidParameter {
                what: "temporal window_ms",
                value: 0.0,
                expected: "≥ 1 ms",
            });
        }
        check_temporal_duration_ms(duration_ms)?;
        if window_ms > duration_ms {
            return Err(CodingError::WindowLongerThanSample {
                window_ms,
                duration_ms,
            });
        }
        Ok(Self {
            window_ms,
            duration_ms,
            n_channels: 0,
            bins: vec![0; duration_ms as usize],
        })
    }

    /// Window width Δt (ms).
    pub fn window_ms(&self) -> u32 {
        self.window_ms
    }

    /// Sample duration T (ms).
    pub fn duration_ms(&self) -> u32 {
        self.duration_ms
    }

    /// Number of windows, `W = T − Δt + 1`.
    pub fn n_windows(&self) -> usize {
        (self.duration_ms - self.window_ms + 1) as usize
    }

    /// Pooled spike count per 1-ms bin of the spikes fed so far.
    pub fn bin_counts(&self) -> &[u32] {
        &self.bins
    }
}

impl Coding for TemporalCoding {
    fn reset(&mut self, n_channels: usize) {
        self.n_channels = n_channels;
        self.bins.iter_mut().for_each(|b| *b = 0);
    }

    #[inline]
    fn add_spike(&mut self, channel: usize, t_s: f64) {
        if channel >= self.n_channels {
            return;
        }
        if let Some(b) = spike_bin_ms(t_s).filter(|&b| b < self.duration_ms as u64) {
            self.bins[b as usize] += 1;
        }
    }
}

impl FeatureCoding for TemporalCoding {
    fn n_features(&self, _n_channels: usize) -> usize {
        self.n_windows()
    }

    fn write_features(&self, out: &mut [f64]) {
        write_window_features(&self.bins, self.window_ms, self.n_channels, out);
    }

    fn features(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.n_windows()];
        self.write_features(&mut out);
        out
    }
}
