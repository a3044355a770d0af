//! The count codings (intensive, spatial) as one [`CodingScheme`]: a core [`FeatureCoding`]
//! of spike counts read per sample, Euclidean distances, no parameter; online, each training
//! sample's spike counts before the decision time, moved on by cursors, against the live
//! sample's, per channel or as their mean.

use crate::coding::encoded::{EncodedSet, SetReadout};
use crate::coding::scheme::{
    CodingParameters, CodingScheme, LiveScorer, OnlineScorer, ReadoutContext, SampleReader, before,
    readout_of, sample_reader,
};
use crate::error::ExperimentError;
use crate::scoring::{PipelineRun, Scored};
use ndarray::Array2;
use neurotac_core::coding::{FeatureCoding, feature_matrix};
use neurotac_core::distance::{euclidean_distance_matrix, squared_euclidean};
use neurotac_core::{MultiSpikeTrain, NetworkBuilder, Ranks, ReadoutSource};

/// A coding of spike counts: the features of the core coding `C` (its readout: one row per
/// sample), compared by Euclidean distance. `per_channel` says what the online side compares:
/// the count of each channel, or their mean.
pub struct CountCoding<C> {
    /// Menu key.
    pub key: &'static str,
    /// Name in prose.
    pub label: &'static str,
    /// The core coding, fresh.
    pub new: fn() -> C,
    /// Spatial (per channel) or intensive (their mean).
    pub per_channel: bool,
}

impl<C: FeatureCoding + neurotac_core::Readout> CodingScheme for CountCoding<C> {
    fn key(&self) -> &'static str {
        self.key
    }

    fn label(&self) -> &'static str {
        self.label
    }

    fn describe(&self, _: &CodingParameters) -> String {
        String::new()
    }

    fn add_readout(
        &self,
        builder: &mut NetworkBuilder,
        source: ReadoutSource,
        _: &ReadoutContext,
    ) -> Result<SampleReader, ExperimentError> {
        let id = builder.add_readout(source, (self.new)())?;
        Ok(sample_reader(move |n| Ok(n.readout(id)?.features())))
    }

    fn encode(
        &self,
        trains: &[MultiSpikeTrain],
        _: &ReadoutContext,
    ) -> Result<Box<dyn SetReadout>, ExperimentError> {
        let m = feature_matrix(&(self.new)(), trains)?;
        let rows: Vec<Vec<f64>> = m.rows().into_iter().map(|r| r.to_vec()).collect();
        Ok(Box::new(rows))
    }

    fn distances(
        &self,
        set: &EncodedSet,
        _: &CodingParameters,
        ranks: &dyn Ranks,
    ) -> Result<Array2<f64>, ExperimentError> {
        let rows = readout_of::<Vec<f64>>(set, self.key)?;
        let width = (self.new)().n_features(set.n_channels);
        let mut features = Array2::zeros((rows.len(), width));
        for (row, mut out) in rows.iter().zip(features.rows_mut()) {
            out.assign(&ndarray::ArrayView1::from(row));
        }
        Ok(euclidean_distance_matrix(features.view(), ranks)?)
    }

    fn pipeline(&self, set: &EncodedSet, run: &PipelineRun<'_>) -> Result<Scored, ExperimentError> {
        run.score(self.label, String::new(), None, || {
            self.distances(set, &CodingParameters::default(), run.ranks)
        })
    }

    fn online<'a>(
        &self,
        training: &'a EncodedSet,
        _: &CodingParameters,
    ) -> Result<Box<dyn OnlineScorer + 'a>, ExperimentError> {
        Ok(Box::new(CountScorer {
            trains: &training.trains,
            n_channels: training.n_channels,
            per_channel: self.per_channel,
        }))
    }
}

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
