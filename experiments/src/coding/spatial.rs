//! The spatial coding: the spike count of each taxel over the sample, one number per taxel,
//! compared by Euclidean distance ([`SpatialCoding`]; the paper's "Spatial coding").

use crate::coding::counts::CountScorer;
use crate::coding::encoded::{EncodedSet, SetReadout};
use crate::coding::scheme::{
    CodingParameters, CodingScheme, OnlineScorer, ReadoutContext, SampleReader, readout_of,
    sample_reader,
};
use crate::error::ExperimentError;
use crate::scoring::{PipelineRun, Scored};
use ndarray::Array2;
use neurotac_core::coding::{FeatureCoding, SpatialCoding, feature_matrix};
use neurotac_core::distance::euclidean_distance_matrix;
use neurotac_core::{MultiSpikeTrain, NetworkBuilder, Ranks, ReadoutSource};

/// The spatial coding (module docs). Its readout: one count per channel per sample.
pub struct Spatial;

const KEY: &str = "spatial";

impl CodingScheme for Spatial {
    fn key(&self) -> &'static str {
        KEY
    }

    fn label(&self) -> &'static str {
        "Spatial"
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
        let id = builder.add_readout(source, SpatialCoding::new())?;
        Ok(sample_reader(move |n| Ok(n.readout(id)?.features())))
    }

    fn encode(
        &self,
        trains: &[MultiSpikeTrain],
        _: &ReadoutContext,
    ) -> Result<Box<dyn SetReadout>, ExperimentError> {
        let m = feature_matrix(&SpatialCoding::new(), trains)?;
        Ok(Box::new(
            m.rows().into_iter().map(|r| r.to_vec()).collect::<Vec<_>>(),
        ))
    }

    fn distances(
        &self,
        set: &EncodedSet,
        _: &CodingParameters,
        ranks: &dyn Ranks,
    ) -> Result<Array2<f64>, ExperimentError> {
        let counts = readout_of::<Vec<f64>>(set, KEY)?;
        let mut features = Array2::zeros((counts.len(), set.n_channels));
        for (row, mut out) in counts.iter().zip(features.rows_mut()) {
            out.assign(&ndarray::ArrayView1::from(row));
        }
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
            per_channel: true,
        }))
    }
}
