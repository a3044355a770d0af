//! The spatiotemporal coding: the multi-unit Van Rossum distance between samples at kernel τ
//! and channel mixing cos θ ([`SpatiotemporalCoding`]; the paper's "Spatiotemporal coding",
//! after Houghton & Sen 2008). Its readout is the output spike trains (exact distance) or,
//! with [`VrFrom::Traces`], each sample's synaptic trace record (trace-sampled distance); the
//! pipeline chooses (τ, cos θ) by Bayesian optimisation of the leave-one-out accuracy
//! ([`bayes_optimise`]). Online, the distances of the prefixes grow spike by spike
//! ([`GrowingVanRossum`]).

use crate::coding::encoded::{EncodedSet, SetReadout, VrFrom};
use crate::coding::scheme::{
    CodingParameters, CodingScheme, LiveScorer, OnlineScorer, ReadoutContext, SampleReader, before,
    missing, sample_reader,
};
use crate::error::ExperimentError;
use crate::scoring::{BayesSearch, PipelineRun, Scored, Search};
use crate::search::bayes::{VanRossumInput, VanRossumObjective, bayes_optimise};
use crate::timing::timed;
use ndarray::Array2;
use neurotac_core::coding::{SpatiotemporalCoding, TraceRecord};
use neurotac_core::distance::{
    GrowingLive, GrowingVanRossum, PreparedVanRossum, VanRossum, check_cos, combine_squared,
};
use neurotac_core::{CodingError, MultiSpikeTrain, NetworkBuilder, Ranks, ReadoutSource};
use rayon::prelude::*;

/// The spatiotemporal coding (module docs). Its readout: each sample's trace record with
/// [`VrFrom::Traces`], none for the exact distance (which reads the set's trains).
pub struct Spatiotemporal;

const KEY: &str = "spatiotemporal";

/// The Van Rossum input of `set`: its trace records with [`VrFrom::Traces`], else its trains.
pub fn van_rossum_input(set: &EncodedSet) -> VanRossumInput<'_> {
    match (set.readout::<TraceRecord>(KEY), set.vr_from) {
        (Some(records), VrFrom::Traces { precision, .. }) if records.len() == set.len() => {
            VanRossumInput::Traces { records, precision }
        }
        _ => VanRossumInput::Exact(&set.trains),
    }
}

/// The (τ, cos θ) of `parameters`, or the error naming the one missing.
fn tau_and_cos(parameters: &CodingParameters) -> Result<(f64, f64), ExperimentError> {
    let tau_s =
        (parameters.tau_s).ok_or_else(|| missing(KEY, "the Van Rossum τ (--tau SECONDS)"))?;
    let cos = (parameters.cos).ok_or_else(|| missing(KEY, "cos θ in [0, 1] (--cos C)"))?;
    Ok((tau_s, check_cos(cos)?))
}

impl CodingScheme for Spatiotemporal {
    fn key(&self) -> &'static str {
        KEY
    }

    fn label(&self) -> &'static str {
        "Spatiotemporal"
    }

    fn describe(&self, parameters: &CodingParameters) -> String {
        match (parameters.tau_s, parameters.cos) {
            (Some(tau_s), Some(cos)) => format!("τ = {:.0} ms, cos θ = {cos:.2}", tau_s * 1e3),
            _ => String::new(),
        }
    }

    fn add_readout(
        &self,
        builder: &mut NetworkBuilder,
        source: ReadoutSource,
        context: &ReadoutContext,
    ) -> Result<SampleReader, ExperimentError> {
        let VrFrom::Traces { trace_dt_s, .. } = context.vr_from else {
            // The exact distance reads the set's trains: nothing of its own to record.
            return Ok(Box::new(|_| Ok(Box::new(Vec::<TraceRecord>::new()))));
        };
        let coding = SpatiotemporalCoding::new(1.0)?.with_trace_record(trace_dt_s)?;
        let id = builder.add_readout(source, coding)?;
        Ok(sample_reader(move |n| {
            let record = n.readout(id)?.trace_record();
            Ok(record.ok_or_else(|| missing(KEY, "the readout's trace record"))??)
        }))
    }

    fn encode(
        &self,
        trains: &[MultiSpikeTrain],
        context: &ReadoutContext,
    ) -> Result<Box<dyn SetReadout>, ExperimentError> {
        let records = match context.vr_from {
            VrFrom::Exact => Vec::new(),
            VrFrom::Traces { trace_dt_s, .. } => (trains.par_iter())
                .map(|o| TraceRecord::of_trains(o, trace_dt_s))
                .collect::<Result<Vec<_>, CodingError>>()?,
        };
        Ok(Box::new(records))
    }

    fn distances(
        &self,
        set: &EncodedSet,
        parameters: &CodingParameters,
        ranks: &dyn Ranks,
    ) -> Result<Array2<f64>, ExperimentError> {
        let (tau_s, cos) = tau_and_cos(parameters)?;
        Ok(van_rossum_input(set)
            .matrices(tau_s, ranks)?
            .distances(cos)?)
    }

    fn pipeline(&self, set: &EncodedSet, run: &PipelineRun<'_>) -> Result<Scored, ExperimentError> {
        let bayes = &run.config.bayes;
        run.progress.stage(
            &format!("{}: Bayesian optimisation of τ, cos θ (epochs)", run.name),
            bayes.epochs as u64,
        );
        let input = van_rossum_input(set);
        let mut objective =
            VanRossumObjective::new(input, run.labels, run.knn()?, run.config.vr_cache)
                .on_ranks(run.ranks);
        let (result, time) = timed(|| {
            bayes_optimise(bayes, |i, tau, cos| {
                let a = objective.accuracy(i, tau, cos);
                run.progress.advance(1);
                a
            })
        });
        let result = result?;
        run.progress.finish();
        let parameters = CodingParameters {
            tau_s: Some(result.best_tau_s),
            cos: Some(result.best_cos),
            ..CodingParameters::default()
        };
        let (tau_index, tau_s, cos) = (result.best_tau_index, result.best_tau_s, result.best_cos);
        let search = |matrices_computed| {
            Search::Bayes(BayesSearch {
                result,
                tau_min_s: bayes.tau_min_s,
                tau_max_s: bayes.tau_max_s,
                tau_step_s: bayes.tau_step_s,
                cos_step: bayes.cos_step,
                matrices_computed,
                time,
            })
        };
        let mut scored = run.score(self.label(), self.describe(&parameters), None, || {
            Ok(objective.matrices(tau_index, tau_s)?.distances(cos)?)
        })?;
        scored.search = Some(search(objective.matrices_computed));
        Ok(scored)
    }

    fn online<'a>(
        &self,
        training: &'a EncodedSet,
        parameters: &CodingParameters,
    ) -> Result<Box<dyn OnlineScorer + 'a>, ExperimentError> {
        let (tau_s, cos) = tau_and_cos(parameters)?;
        Ok(Box::new(VanRossumScorer {
            prepared: VanRossum::new(tau_s)?.prepare(&training.trains)?,
            growing: GrowingVanRossum::new(&training.trains, tau_s)?,
            n_train: training.len(),
            n_channels: training.n_channels,
            cos,
        }))
    }
}

/// The training side of the online Van Rossum distance.
struct VanRossumScorer {
    /// Whole samples and prefixes from scratch (the final decision, and windows when the
    /// spans are too long for the growing sums).
    prepared: PreparedVanRossum,
    /// Prefixes window by window.
    growing: Option<GrowingVanRossum>,
    n_train: usize,
    n_channels: usize,
    cos: f64,
}

impl OnlineScorer for VanRossumScorer {
    fn live(&self) -> Box<dyn LiveScorer + '_> {
        Box::new(LiveVanRossum {
            scorer: self,
            growing: self.growing.as_ref().map(|g| g.live()),
            given: vec![0; self.n_channels],
        })
    }
}

/// The growing Van Rossum sums (when the spans allow them), and how many live spikes of each
/// channel they hold.
struct LiveVanRossum<'s> {
    scorer: &'s VanRossumScorer,
    growing: Option<GrowingLive>,
    given: Vec<usize>,
}

impl LiveScorer for LiveVanRossum<'_> {
    fn distances(
        &mut self,
        live: &MultiSpikeTrain,
        t_end_s: f64,
    ) -> Result<Vec<f64>, ExperimentError> {
        let s = self.scorer;
        match (&s.growing, &mut self.growing) {
            (Some(g), Some(state)) if t_end_s.is_finite() => {
                // The live spikes of this window, per channel.
                let new: Vec<&[f64]> = (live.channels())
                    .zip(self.given.iter_mut())
                    .map(|(c, given)| {
                        let (from, to) = (*given, before(c, t_end_s).len());
                        *given = to;
                        &c[from..to]
                    })
                    .collect();
                g.advance(state, &new, t_end_s)?;
                Ok((0..s.n_train)
                    .map(|i| {
                        let (ll, sp) = g.squared_parts(state, i);
                        combine_squared(ll, sp, s.cos).sqrt()
                    })
                    .collect())
            }
            _ => {
                let m = s
                    .prepared
                    .cross_matrices_until(std::slice::from_ref(live), t_end_s)?;
                Ok((m.ll2.iter().zip(&m.sp2))
                    .map(|(&ll, &sp)| combine_squared(ll, sp, s.cos).sqrt())
                    .collect())
            }
        }
    }
}
