//! Spike trains: one channel ([`SpikeTrain`]) and many channels in one compact buffer
//! ([`MultiSpikeTrain`]).
//!
//! Spike times are `f64` seconds (see [`crate::time`]). Every constructor validates: times must
//! be finite and, within a channel, non-decreasing (equal times are allowed — pooled taxel
//! events and coincident spikes are real). The `from_unsorted…` constructors sort instead of
//! rejecting, but still reject NaN and ±∞.

use crate::error::SpikeError;
use serde::{Deserialize, Serialize};

/// Checks spike `index` of `channel`, at `t` after `previous` (−∞ for the first spike): `t`
/// must be finite and not before `previous`.
pub(crate) fn check_spike(
    channel: usize,
    index: usize,
    previous: f64,
    t: f64,
) -> Result<(), SpikeError> {
    if !t.is_finite() {
        return Err(SpikeError::NonFinite {
            channel,
            index,
            value: t,
        });
    }
    if t < previous {
        return Err(SpikeError::Unsorted {
            channel,
            index,
            previous,
            value: t,
        });
    }
    Ok(())
}

fn check_channel(channel: usize, times: &[f64]) -> Result<(), SpikeError> {
    let mut previous = f64::NEG_INFINITY;
    for (index, &t) in times.iter().enumerate() {
        check_spike(channel, index, previous, t)?;
        previous = t;
    }
    Ok(())
}

fn check_finite(channel: usize, times: &[f64]) -> Result<(), SpikeError> {
    match times.iter().position(|t| !t.is_finite()) {
        Some(index) => Err(SpikeError::NonFinite {
            channel,
            index,
            value: times[index],
        }),
        None => Ok(()),
    }
}

fn check_window(start_s: f64, end_s: f64) -> Result<(), SpikeError> {
    if start_s.is_nan() || end_s.is_nan() || start_s > end_s {
        return Err(SpikeError::InvalidWindow { start_s, end_s });
    }
    Ok(())
}

/// The half-open slice `[start_s, end_s)` of a sorted time slice, found by binary search.
#[inline]
fn window_of(times: &[f64], start_s: f64, end_s: f64) -> &[f64] {
    let lo = times.partition_point(|&t| t < start_s);
    let hi = times.partition_point(|&t| t < end_s);
    &times[lo..hi.max(lo)]
}

/// The spike times of one neuron or taxel, in seconds, sorted and finite.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(try_from = "Vec<f64>", into = "Vec<f64>")]
pub struct SpikeTrain {
    times: Vec<f64>,
}

impl SpikeTrain {
    /// Validates `times` (finite, non-decreasing) and wraps them.
    pub fn new(times: Vec<f64>) -> Result<Self, SpikeError> {
        check_channel(0, &times)?;
        Ok(Self { times })
    }

    /// Sorts `times` (after rejecting NaN/±∞) and wraps them.
    pub fn from_unsorted(mut times: Vec<f64>) -> Result<Self, SpikeError> {
        check_finite(0, &times)?;
        times.sort_unstable_by(f64::total_cmp);
        Ok(Self { times })
    }

    /// The spike times, in seconds.
    #[inline]
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Number of spikes.
    #[inline]
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// `true` when there is no spike.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The spikes in the half-open window `[start_s, end_s)`, without copying.
    pub fn window(&self, start_s: f64, end_s: f64) -> Result<&[f64], SpikeError> {
        check_window(start_s, end_s)?;
        Ok(window_of(&self.times, start_s, end_s))
    }

    /// Consumes the train and returns its times.
    pub fn into_times(self) -> Vec<f64> {
        self.times
    }
}

impl TryFrom<Vec<f64>> for SpikeTrain {
    type Error = SpikeError;
    fn try_from(times: Vec<f64>) -> Result<Self, SpikeError> {
        SpikeTrain::new(times)
    }
}

impl From<SpikeTrain> for Vec<f64> {
    fn from(train: SpikeTrain) -> Self {
        train.times
    }
}

/// The most channels a [`MultiSpikeTrain`] built from labelled spikes may have: 2²⁰, more than the
/// pixels of a 1280 × 720 event camera; its offsets then take 8 MiB per sample.
pub const MAX_CHANNELS: usize = 1 << 20;

/// Spike trains of `N` channels (neurons, taxels) in one compressed-sparse-row buffer.
///
/// All times live in one flat `Vec<f64>`; channel `i` is `times[offsets[i]..offsets[i + 1]]`.
/// Each channel is sorted and finite. Serialises as a list of per-channel lists of seconds,
/// `[[t, …], …]`, which is the per-observation layout of the spike-dataset JSON.
///
/// ```
/// use neurotac_core::MultiSpikeTrain;
/// let trains = MultiSpikeTrain::from_channels(vec![vec![0.1, 0.3], vec![], vec![0.1]])?;
/// assert_eq!(trains.n_channels(), 3);
/// assert_eq!(trains.channel(0), &[0.1, 0.3]);
/// assert_eq!(trains.pooled(), vec![0.1, 0.1, 0.3]); // duplicates kept
/// # Ok::<(), neurotac_core::SpikeError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<Vec<f64>>", into = "Vec<Vec<f64>>")]
pub struct MultiSpikeTrain {
    times: Vec<f64>,
    offsets: Vec<usize>,
}

impl Default for MultiSpikeTrain {
    fn default() -> Self {
        Self::empty(0)
    }
}

impl MultiSpikeTrain {
    /// `n_channels` channels without spikes.
    pub fn empty(n_channels: usize) -> Self {
        Self {
            times: Vec::new(),
            offsets: vec![0; n_channels + 1],
        }
    }

    /// Validates each channel (finite, non-decreasing) and packs them.
    pub fn from_channels<I, C>(channels: I) -> Result<Self, SpikeError>
    where
        I: IntoIterator<Item = C>,
        C: AsRef<[f64]>,
    {
        let mut times = Vec::new();
        let mut offsets = vec![0];
        for (channel, c) in channels.into_iter().enumerate() {
            let c = c.as_ref();
            check_channel(channel, c)?;
            times.extend_from_slice(c);
            offsets.push(times.len());
        }
        Ok(Self { times, offsets })
    }

    /// Like [`from_channels`](Self::from_channels) but sorts each channel instead of rejecting
    /// unsorted input (NaN/±∞ are still rejected).
    pub fn from_unsorted_channels<I, C>(channels: I) -> Result<Self, SpikeError>
    where
        I: IntoIterator<Item = C>,
        C: AsRef<[f64]>,
    {
        let mut times = Vec::new();
        let mut offsets = vec![0];
        for (channel, c) in channels.into_iter().enumerate() {
            let c = c.as_ref();
            check_finite(channel, c)?;
            let start = times.len();
            times.extend_from_slice(c);
            times[start..].sort_unstable_by(f64::total_cmp);
            offsets.push(times.len());
        }
        Ok(Self { times, offsets })
    }

    /// Packs `(channel, time)` pairs given in any order into `n_channels` sorted channels.
    ///
    /// Rejects a channel `≥ n_channels` ([`SpikeError::ChannelOutOfRange`]), non-finite times
    /// and more than [`MAX_CHANNELS`] channels.
    pub fn from_labelled_spikes(
        n_channels: usize,
        spikes: &[(u32, f64)],
    ) -> Result<Self, SpikeError> {
        if n_channels > MAX_CHANNELS {
            return Err(SpikeError::TooManyChannels {
                n_channels,
                limit: MAX_CHANNELS,
            });
        }
        let mut offsets = vec![0usize; n_channels + 1];
        for (index, &(c, t)) in spikes.iter().enumerate() {
            let channel = c as usize;
            if channel >= n_channels {
                return Err(SpikeError::ChannelOutOfRange {
                    channel,
                    n_channels,
                });
            }
            if !t.is_finite() {
                return Err(SpikeError::NonFinite {
                    channel,
                    index,
                    value: t,
                });
            }
            offsets[channel + 1] += 1;
        }
        for i in 0..n_channels {
            offsets[i + 1] += offsets[i];
        }
        let mut cursor = offsets.clone();
        let mut times = vec![0.0; spikes.len()];
        for &(c, t) in spikes {
            times[cursor[c as usize]] = t;
            cursor[c as usize] += 1;
        }
        for c in 0..n_channels {
            times[offsets[c]..offsets[c + 1]].sort_unstable_by(f64::total_cmp);
        }
        Ok(Self { times, offsets })
    }

    /// Rebuilds from the raw CSR parts, validating offsets (start at 0, non-decreasing, end at
    /// `times.len()`) and every channel.
    pub fn from_parts(times: Vec<f64>, offsets: Vec<usize>) -> Result<Self, SpikeError> {
        let valid = offsets.first() == Some(&0)
            && offsets.last() == Some(&times.len())
            && offsets.windows(2).all(|w| w[0] <= w[1]);
        if !valid {
            return Err(SpikeError::InvalidOffsets {
                n_times: times.len(),
            });
        }
        for c in 0..offsets.len() - 1 {
            check_channel(c, &times[offsets[c]..offsets[c + 1]])?;
        }
        Ok(Self { times, offsets })
    }

    /// Wraps CSR parts whose offsets and channels the caller has already checked (as
    /// [`from_parts`](Self::from_parts) would), without checking them again.
    pub(crate) fn from_checked_parts(times: Vec<f64>, offsets: Vec<usize>) -> Self {
        debug_assert!(Self::from_parts(times.clone(), offsets.clone()).is_ok());
        Self { times, offsets }
    }

    /// Number of channels.
    #[inline]
    pub fn n_channels(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Total number of spikes over all channels.
    #[inline]
    pub fn total_spikes(&self) -> usize {
        self.times.len()
    }

    /// The spike times of channel `c`. Panics when `c ≥ n_channels()`, like slice indexing.
    #[inline]
    pub fn channel(&self, c: usize) -> &[f64] {
        &self.times[self.offsets[c]..self.offsets[c + 1]]
    }

    /// Number of spikes in channel `c`. Panics when `c ≥ n_channels()`.
    #[inline]
    pub fn count(&self, c: usize) -> usize {
        self.offsets[c + 1] - self.offsets[c]
    }

    /// Spike count per channel.
    pub fn counts(&self) -> Vec<usize> {
        self.offsets.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// Iterates over the channels in order.
    pub fn channels(&self) -> impl ExactSizeIterator<Item = &[f64]> + '_ {
        self.offsets
            .windows(2)
            .map(move |w| &self.times[w[0]..w[1]])
    }

    /// All spikes of all channels merged in time order, duplicates kept.
    pub fn pooled(&self) -> Vec<f64> {
        let mut all = self.times.clone();
        all.sort_by(f64::total_cmp);
        all
    }

    /// All spikes merged in time order as `(channel, time)`; equal times are ordered by channel.
    pub fn pooled_with_channels(&self) -> Vec<(u32, f64)> {
        let mut all: Vec<(u32, f64)> = Vec::with_capacity(self.times.len());
        for (c, w) in self.offsets.windows(2).enumerate() {
            all.extend(self.times[w[0]..w[1]].iter().map(|&t| (c as u32, t)));
        }
        // Stable sort: the channel-major collection order breaks ties by channel.
        all.sort_by(|a, b| a.1.total_cmp(&b.1));
        all
    }

    /// A copy restricted to the half-open window `[start_s, end_s)`; times are not shifted.
    pub fn window(&self, start_s: f64, end_s: f64) -> Result<Self, SpikeError> {
        check_window(start_s, end_s)?;
        let mut times = Vec::new();
        let mut offsets = vec![0];
        for c in self.channels() {
            times.extend_from_slice(window_of(c, start_s, end_s));
            offsets.push(times.len());
        }
        Ok(Self { times, offsets })
    }

    /// Earliest and latest spike over all channels, or `None` when there is none.
    pub fn time_range(&self) -> Option<(f64, f64)> {
        let first = self
            .channels()
            .filter_map(|c| c.first())
            .copied()
            .reduce(f64::min)?;
        let last = self
            .channels()
            .filter_map(|c| c.last())
            .copied()
            .reduce(f64::max)?;
        Some((first, last))
    }

    /// The flat time buffer (all channels, channel-major).
    #[inline]
    pub fn flat_times(&self) -> &[f64] {
        &self.times
    }

    /// The CSR offsets: `n_channels() + 1` entries, the first 0, the last `total_spikes()`.
    #[inline]
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// Copies channel `c` into a [`SpikeTrain`]. Panics when `c ≥ n_channels()`.
    pub fn to_train(&self, c: usize) -> SpikeTrain {
        SpikeTrain {
            times: self.channel(c).to_vec(),
        }
    }
}

impl TryFrom<Vec<Vec<f64>>> for MultiSpikeTrain {
    type Error = SpikeError;
    fn try_from(channels: Vec<Vec<f64>>) -> Result<Self, SpikeError> {
        MultiSpikeTrain::from_channels(channels)
    }
}

impl From<MultiSpikeTrain> for Vec<Vec<f64>> {
    fn from(trains: MultiSpikeTrain) -> Self {
        trains.channels().map(<[f64]>::to_vec).collect()
    }
}

impl From<SpikeTrain> for MultiSpikeTrain {
    fn from(train: SpikeTrain) -> Self {
        let n = train.times.len();
        Self {
            times: train.times,
            offsets: vec![0, n],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructors_reject_unsorted_and_non_finite_with_location() {
        assert_eq!(
            SpikeTrain::new(vec![0.1, 0.05]),
            Err(SpikeError::Unsorted {
                channel: 0,
                index: 1,
                previous: 0.1,
                value: 0.05
            })
        );
        match MultiSpikeTrain::from_channels(vec![vec![0.1], vec![0.2, f64::NAN]]) {
            Err(SpikeError::NonFinite {
                channel: 1,
                index: 1,
                value,
            }) => assert!(value.is_nan()),
            other => panic!("expected NonFinite, got {other:?}"),
        }
        assert!(matches!(
            MultiSpikeTrain::from_unsorted_channels(vec![vec![f64::INFINITY]]),
            Err(SpikeError::NonFinite {
                channel: 0,
                index: 0,
                ..
            })
        ));
        assert_eq!(
            MultiSpikeTrain::from_labelled_spikes(2, &[(0, 0.1), (2, 0.2)]),
            Err(SpikeError::ChannelOutOfRange {
                channel: 2,
                n_channels: 2
            })
        );
        assert_eq!(
            MultiSpikeTrain::from_parts(vec![0.1, 0.2], vec![0, 3]),
            Err(SpikeError::InvalidOffsets { n_times: 2 })
        );
    }

    #[test]
    fn a_channel_count_over_the_budget_is_refused_before_allocation() {
        let e = MultiSpikeTrain::from_labelled_spikes(1 << 40, &[(0, 0.1)]).unwrap_err();
        assert!(
            matches!(e, SpikeError::TooManyChannels { n_channels, .. } if n_channels == 1 << 40)
        );
        assert!(MultiSpikeTrain::from_labelled_spikes(MAX_CHANNELS, &[]).is_ok());
    }

    #[test]
    fn unsorted_constructors_sort() {
        let t = SpikeTrain::from_unsorted(vec![0.3, 0.1, 0.2]).unwrap();
        assert_eq!(t.times(), &[0.1, 0.2, 0.3]);
        let m = MultiSpikeTrain::from_unsorted_channels(vec![vec![0.2, 0.1], vec![0.5]]).unwrap();
        assert_eq!(m.channel(0), &[0.1, 0.2]);
        let l = MultiSpikeTrain::from_labelled_spikes(3, &[(2, 0.4), (0, 0.3), (2, 0.1)]).unwrap();
        assert_eq!(l.channel(0), &[0.3]);
        assert!(l.channel(1).is_empty());
        assert_eq!(l.channel(2), &[0.1, 0.4]);
    }

    #[test]
    fn csr_round_trips_through_parts_and_channels() {
        let chans = vec![vec![0.0, 0.5, 0.5], vec![], vec![1e-6], vec![]];
        let m = MultiSpikeTrain::from_channels(&chans).unwrap();
        assert_eq!(m.offsets(), &[0, 3, 3, 4, 4]);
        assert_eq!(m.counts(), vec![3, 0, 1, 0]);
        let back: Vec<Vec<f64>> = m.clone().into();
        assert_eq!(back, chans);
        let again = MultiSpikeTrain::from_parts(m.flat_times().to_vec(), m.offsets().to_vec());
        assert_eq!(again.unwrap(), m);
        assert_eq!(MultiSpikeTrain::empty(3).channels().count(), 3);
    }

    #[test]
    fn pooled_merge_keeps_duplicates_in_time_order() {
        let m = MultiSpikeTrain::from_channels(vec![vec![0.1, 0.3], vec![0.1, 0.2], vec![0.3]])
            .unwrap();
        assert_eq!(m.pooled(), vec![0.1, 0.1, 0.2, 0.3, 0.3]);
        assert_eq!(
            m.pooled_with_channels(),
            vec![(0, 0.1), (1, 0.1), (1, 0.2), (0, 0.3), (2, 0.3)]
        );
        assert_eq!(m.pooled().len(), m.total_spikes());
    }

    #[test]
    fn window_is_half_open_and_validated() {
        let m = MultiSpikeTrain::from_channels(vec![vec![0.0, 0.1, 0.2], vec![0.2, 0.25]]).unwrap();
        let w = m.window(0.1, 0.2).unwrap();
        assert_eq!(w.channel(0), &[0.1]);
        assert!(w.channel(1).is_empty());
        assert_eq!(m.window(0.2, 0.2).unwrap().total_spikes(), 0);
        assert!(matches!(
            m.window(0.3, 0.2),
            Err(SpikeError::InvalidWindow { .. })
        ));
        assert!(m.window(f64::NAN, 1.0).is_err());
        let t = SpikeTrain::new(vec![0.0, 0.1, 0.2]).unwrap();
        assert_eq!(t.window(0.05, 1.0).unwrap(), &[0.1, 0.2]);
        assert_eq!(m.time_range(), Some((0.0, 0.25)));
        assert_eq!(MultiSpikeTrain::empty(2).time_range(), None);
    }

    #[test]
    fn serde_uses_nested_lists_and_validates_on_load() {
        let m = MultiSpikeTrain::from_channels(vec![vec![0.5, 1.0], vec![]]).unwrap();
        let json = serde_json::to_string(&m).unwrap();
        assert_eq!(json, "[[0.5,1.0],[]]");
        let back: MultiSpikeTrain = serde_json::from_str(&json).unwrap();
        assert_eq!(back, m);
        let bad = serde_json::from_str::<MultiSpikeTrain>("[[1.0, 0.5]]").unwrap_err();
        assert!(bad.to_string().contains("not sorted"), "{bad}");
        let single: SpikeTrain = serde_json::from_str("[0.25]").unwrap();
        assert_eq!(single.times(), &[0.25]);
    }
}
