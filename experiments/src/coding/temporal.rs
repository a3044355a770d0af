//! The temporal coding: the taxels' pooled spike count in a window of Δt sliding over the
//! sample in 1 ms steps, compared by Euclidean distance ([`TemporalCoding`]; the paper's
//! "Temporal coding"). Its readout is the pooled count of every 1 ms bin, from which the
//! features of any Δt follow ([`write_window_features`]); the pipeline chooses Δt by a sweep
//! of the leave-one-out accuracy ([`dt_sweep_of_bins`]).

use crate::coding::encoded::{EncodedSet, SetReadout};
use crate::coding::scheme::{
    CodingParameters, CodingScheme, LiveScorer, OnlineScorer, ReadoutContext, SampleReader,
    missing, readout_of, sample_reader,
};
use crate::error::ExperimentError;
use crate::scoring::{DtSearch, PipelineRun, Scored, Search};
use crate::search::dt_sweep::dt_sweep_of_bins;
use crate::timing::timed;
use ndarray::Array2;
use neurotac_core::coding::{TemporalCoding, pooled_bin_counts, write_window_features};
use neurotac_core::distance::euclidean_distance_matrix;
use neurotac_core::{MultiSpikeTrain, NetworkBuilder, Ranks, ReadoutSource};
use rayon::prelude::*;

/// The temporal coding (module docs). Its readout: the pooled count of every 1 ms bin of a
/// sample.
pub struct Temporal;

const KEY: &str = "temporal";

/// The window Δt of `parameters`, checked against the samples' duration.
fn window_ms(parameters: &CodingParameters, duration_ms: u32) -> Result<u32, ExperimentError> {
    let window_ms =
        (parameters.window_ms).ok_or_else(|| missing(KEY, "the window Δt (--dt SECONDS)"))?;
    // The coding's own check of the window against the duration.
    TemporalCoding::from_ms(window_ms, duration_ms)?;
    Ok(window_ms)
}

/// The features at window `window_ms` of every sample, one row each.
fn features(set: &EncodedSet, window_ms: u32) -> Result<Array2<f64>, ExperimentError> {
    let bins = readout_of::<Vec<u32>>(set, KEY)?;
    let width = (set.duration_ms - window_ms + 1) as usize;
    let mut out = Array2::zeros((bins.len(), width));
    for (bins, mut row) in bins.iter().zip(out.rows_mut()) {
        let row = row
            .as_slice_mut()
            .expect("rows of a fresh array are contiguous");
        write_window_features(bins, window_ms, set.n_channels, row);
    }
    Ok(out)
}

impl CodingScheme for Temporal {
    fn key(&self) -> &'static str {
        KEY
    }

    fn label(&self) -> &'static str {
        "Temporal"
    }

    fn describe(&self, parameters: &CodingParameters) -> String {
        (parameters.window_ms).map_or_else(String::new, |w| format!("Δt = {w} ms"))
    }

    fn add_readout(
        &self,
        builder: &mut NetworkBuilder,
        source: ReadoutSource,
        context: &ReadoutContext,
    ) -> Result<SampleReader, ExperimentError> {
        // The window does not matter: the pipeline reads the per-ms bins.
        let coding = TemporalCoding::from_ms(1, context.duration_ms)?;
        let id = builder.add_readout(source, coding)?;
        Ok(sample_reader(move |n| {
            Ok(n.readout(id)?.bin_counts().to_vec())
        }))
    }

    fn encode(
        &self,
        trains: &[MultiSpikeTrain],
        context: &ReadoutContext,
    ) -> Result<Box<dyn SetReadout>, ExperimentError> {
        let bins: Vec<Vec<u32>> = (trains.par_iter())
            .map(|o| pooled_bin_counts(o, context.duration_ms))
            .collect();
        Ok(Box::new(bins))
    }

    fn distances(
        &self,
        set: &EncodedSet,
        parameters: &CodingParameters,
        ranks: &dyn Ranks,
    ) -> Result<Array2<f64>, ExperimentError> {
        let features = features(set, window_ms(parameters, set.duration_ms)?)?;
        Ok(euclidean_distance_matrix(features.view(), ranks)?)
    }

    fn pipeline(&self, set: &EncodedSet, run: &PipelineRun<'_>) -> Result<Scored, ExperimentError> {
        let max_window_ms = run.config.max_window_ms.min(set.duration_ms);
        run.progress.stage(
            &format!("{}: Δt sweep 1…{max_window_ms} ms (LOO at each)", run.name),
            0,
        );
        let bins = readout_of::<Vec<u32>>(set, KEY)?;
        let (sweep, time) =
            timed(|| dt_sweep_of_bins(bins, run.labels, max_window_ms, run.knn()?, run.ranks));
        let sweep = sweep?;
        run.progress.finish();
        let parameters = CodingParameters {
            window_ms: Some(sweep.best_window_ms),
            ..CodingParameters::default()
        };
        let search = Search::DtSweep(DtSearch {
            sweep,
            max_window_ms,
            time,
        });
        run.score(
            self.label(),
            self.describe(&parameters),
            Some(search),
            || self.distances(set, &parameters, run.ranks),
        )
    }

    fn online<'a>(
        &self,
        training: &'a EncodedSet,
        parameters: &CodingParameters,
    ) -> Result<Box<dyn OnlineScorer + 'a>, ExperimentError> {
        let d = training.duration_ms;
        let window_ms =
            (parameters.window_ms).ok_or_else(|| missing(KEY, "the window Δt (--dt SECONDS)"))?;
        if window_ms == 0 || window_ms > d {
            return Err(ExperimentError::InvalidParameter {
                what: "temporal window Δt (ms)",
                value: window_ms as f64,
                expected: "≥ 1 ms and ≤ the training samples' duration",
            });
        }
        Ok(Box::new(TemporalScorer {
            window_ms,
            duration_ms: d,
            n_channels: training.n_channels,
            train: features(training, window_ms)?,
        }))
    }
}

/// The training side: every training sample's features over the whole duration.
struct TemporalScorer {
    window_ms: u32,
    duration_ms: u32,
    n_channels: usize,
    /// One row per training sample.
    train: Array2<f64>,
}

impl OnlineScorer for TemporalScorer {
    fn live(&self) -> Box<dyn LiveScorer + '_> {
        Box::new(LiveTemporal {
            scorer: self,
            lanes: vec![[0.0; 8]; self.train.nrows()],
            done: 0,
        })
    }
}

/// Per training sample, the lanes of [`squared_euclidean`](neurotac_core::distance::squared_euclidean)
/// over the first `done` features (so the last distance equals the offline one bit for bit).
struct LiveTemporal<'s> {
    scorer: &'s TemporalScorer,
    lanes: Vec<[f64; 8]>,
    done: usize,
}

impl LiveScorer for LiveTemporal<'_> {
    fn distances(
        &mut self,
        live: &MultiSpikeTrain,
        t_end_s: f64,
    ) -> Result<Vec<f64>, ExperimentError> {
        let s = self.scorer;
        let d = s.duration_ms;
        let t_ms = if t_end_s.is_finite() {
            ((t_end_s * 1e3).round() as u32).min(d)
        } else {
            d
        };
        let width = (t_ms + 1).saturating_sub(s.window_ms) as usize;
        if width > self.done {
            let bins = pooled_bin_counts(live, t_ms);
            let mut x = vec![0.0; width];
            write_window_features(&bins, s.window_ms, s.n_channels, &mut x);
            for (row, lanes) in s.train.rows().into_iter().zip(self.lanes.iter_mut()) {
                for f in self.done..width {
                    let diff = x[f] - row[f];
                    lanes[f % 8] += diff * diff;
                }
            }
            self.done = width;
        }
        Ok(self
            .lanes
            .iter()
            .map(|l| l.iter().sum::<f64>().sqrt())
            .collect())
    }
}
