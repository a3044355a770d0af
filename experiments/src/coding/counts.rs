//! The online side of the count codings (intensive, spatial): each training sample's spike
//! counts before the decision time, moved on by cursors, against the live sample's.

use crate::coding::scheme::{LiveScorer, OnlineScorer, before};
use crate::error::ExperimentError;
use neurotac_core::MultiSpikeTrain;
use neurotac_core::distance::squared_euclidean;

/// Spike counts before `T` of every training sample, compared per channel (spatial) or as
/// their mean (intensive).
pub struct CountScorer<'a> {
    /// The training samples' trains.
    pub trains: &'a [MultiSpikeTrain],
    /// Channels per sample.
    pub n_channels: usize,
    /// Per channel (spatial) or the mean over channels (intensive).
    pub per_channel: bool,
}

impl OnlineScorer for CountScorer<'_> {
    fn live(&self) -> Box<dyn LiveScorer + '_> {
        Box::new(LiveCounts {
            scorer: self,
            counts: vec![0.0; self.trains.len() * self.n_channels],
        })
    }
}

/// Per training sample and channel, its spikes before the last decision's time (also where
/// its next one starts).
struct LiveCounts<'s, 'a> {
    scorer: &'s CountScorer<'a>,
    counts: Vec<f64>,
}

impl LiveScorer for LiveCounts<'_, '_> {
    fn distances(
        &mut self,
        live: &MultiSpikeTrain,
        t_end_s: f64,
    ) -> Result<Vec<f64>, ExperimentError> {
        let n = self.scorer.n_channels;
        // Each training sample's counts before T, which only ever move on.
        for (o, counts) in (self.scorer.trains.iter()).zip(self.counts.chunks_exact_mut(n)) {
            for (train, count) in o.channels().zip(counts.iter_mut()) {
                let mut k = *count as usize;
                while train.get(k).is_some_and(|&t| t < t_end_s) {
                    k += 1;
                }
                *count = k as f64;
            }
        }
        let live: Vec<f64> = live
            .channels()
            .map(|c| before(c, t_end_s).len() as f64)
            .collect();
        let mean = |counts: &[f64]| [counts.iter().sum::<f64>() / n as f64];
        Ok(self
            .counts
            .chunks_exact(n)
            .map(|counts| match self.scorer.per_channel {
                true => squared_euclidean(&live, counts).sqrt(),
                false => squared_euclidean(&mean(&live), &mean(counts)).sqrt(),
            })
            .collect())
    }
}
