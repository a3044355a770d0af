//! The intensive coding: the mean spike count per taxel over the sample, one number, compared
//! by Euclidean distance ([`IntensiveCoding`]; the paper's "Intensive coding").

use crate::coding::counts::CountScorer;
use crate::coding::encoded::{EncodedSet, SetReadout};
use crate::coding::scheme::{
    CodingParameters, CodingScheme, OnlineScorer, ReadoutContext, SampleReader, readout_of,
    sample_reader,
};
use crate::error::ExperimentError;
use crate::scoring::{PipelineRun, Scored};
use ndarray::Array2;
use neurotac_core::coding::{IntensiveCoding, feature_matrix};
use neurotac_core::distance::euclidean_distance_matrix;
use neurotac_core::{MultiSpikeTrain, NetworkBuilder, Ranks, ReadoutSource};

/// The intensive coding (module docs). Its readout: one `f64` per sample.
pub struct Intensive;

const KEY: &str = "intensive";

impl CodingScheme for Intensive {
    fn key(&self) -> &'static str {
        KEY
    }

    fn label(&self) -> &'static str {
        "Intensive"
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
        let id = builder.add_readout(source, IntensiveCoding::new())?;
        Ok(sample_reader(move |n| Ok(n.readout(id)?.value())))
    }

    fn encode(
        &self,
        trains: &[MultiSpikeTrain],
        _: &ReadoutContext,
    ) -> Result<Box<dyn SetReadout>, ExperimentError> {
        let m = feature_matrix(&IntensiveCoding::new(), trains)?;
        Ok(Box::new(m.column(0).to_vec()))
    }

    fn distances(
        &self,
        set: &EncodedSet,
        _: &CodingParameters,
        ranks: &dyn Ranks,
    ) -> Result<Array2<f64>, ExperimentError> {
        let means = readout_of::<f64>(set, KEY)?;
        let features = Array2::from_shape_vec((means.len(), 1), means.to_vec())
            .expect("one column per sample");
        Ok(euclidean_distance_matrix(features.view(), ranks)?)
    }

    fn pipeline(&self, set: &EncodedSet, run: &PipelineRun<'_>) -> Result<Scored, ExperimentError> {
        run.score(self.label(), String::new(), None, || {
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
            per_channel: false,
        }))
    }
}
