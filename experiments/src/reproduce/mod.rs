//! The NeuroTac paper's texture experiments end to end (what `neurotac reproduce` runs): for a
//! labelled taxel spike dataset, the four codings, the Δt sweep of the temporal coding, the
//! Bayesian optimisation of the spatiotemporal coding's (τ, cos θ), then KNN (k = 4) under
//! leave-one-out (the paper's Tables 1 and 2) and a seeded stratified 80/20 split (its
//! confusion matrices).
//!
//! As in the paper, Δt and (τ, cos θ) are chosen by the leave-one-out accuracy on the same
//! samples that are then scored, so the temporal and spatiotemporal scores are the best over
//! the search (optimistic, like the paper's).
//!
//! [`run`] is a whole reproduction (datasets from each [`Source`], the pipeline, the afferent
//! variant) into one [`Report`] ([`run`]: its simulation, distance matrices and searches
//! split over ranks, every rank ending with the one-process report); [`run_set`] is one
//! labelled set through the pipeline;
//! [`paper`] holds the paper's numbers to compare with; [`phases`] splits a simulated set's
//! spikes by slide phase; [`confusions`] reads the leave-one-out predictions class by class
//! (recall, the paper's named confusions); `neurotac_cli::report` writes a run's folder (JSON, CSV,
//! SVG and PNG figures, `report.md`).
//!
//! ```no_run
//! use neurotac_experiments::datasets::simulated::TextureSet;
//! use neurotac_experiments::progress::NoProgress;
//! use neurotac_experiments::reproduce::{ReproduceConfig, Source, run};
//! let config = ReproduceConfig::quick(1, "cache".into());
//! let artificial = [Source::Simulated(TextureSet::Artificial)];
//! let report = run(&config, &artificial, &NoProgress, &neurotac_core::OneProcess)?;
//! println!("{:.2}", report.sets[0].direct.mean_spikes_per_taxel);
//! # Ok::<(), neurotac_experiments::reproduce::ReproduceError>(())
//! ```

pub mod confusions;
pub mod paper;
pub mod phases;
mod run;

pub use run::{
    AfferentRun, MountingRun, Report, ReproduceConfig, ReproduceError, SetReport, Source,
    example_samples, load_source, run,
};

use crate::coding::{CodingName, class_means_of};
use crate::error::ExperimentError;
use crate::menu::Menu;
use crate::progress::Progress;
use crate::readouts::{EncodedSet, encode_offline};
use crate::scoring::PipelineRun;
use crate::timing::{Timing, timed};
use neurotac_core::{KnnError, Ranks, SpikeDataset};
use serde::Serialize;

pub use crate::scoring::{BayesSearch, DtSearch, PipelineConfig, Scored, Search};

/// One coding's results: its run through the pipeline ([`Scored`], read through this
/// result: `result.loo`), under its name.
#[derive(Debug, Clone, Serialize)]
pub struct CodingResult {
    /// The coding.
    pub coding: CodingName,
    /// Its parameters, protocols, time and search.
    #[serde(flatten)]
    pub scored: Scored,
}

impl std::ops::Deref for CodingResult {
    type Target = Scored;
    fn deref(&self) -> &Scored {
        &self.scored
    }
}

impl std::ops::DerefMut for CodingResult {
    fn deref_mut(&mut self) -> &mut Scored {
        &mut self.scored
    }
}

impl CodingResult {
    /// Its wall time including its parameter search (s).
    pub fn seconds_with_search(&self) -> f64 {
        self.time.wall_s + self.search.as_ref().map_or(0.0, |s| s.time().wall_s)
    }
}

/// One set's results.
#[derive(Debug, Clone, Serialize)]
pub struct SetResult {
    /// Set name (`artificial`, `natural`, or the recorded dataset's folder name).
    pub name: String,
    /// What produced the codings: the network path of [`crate::readouts`], or the offline
    /// encoders.
    pub path: String,
    /// Where the spatiotemporal coding's Van Rossum distance came from.
    pub van_rossum: String,
    /// Class names (index = label).
    pub class_names: Vec<String>,
    /// Samples per class.
    pub samples_per_class: Vec<usize>,
    /// Sample duration used by the temporal coding (ms).
    pub duration_ms: u32,
    /// Mean spikes per taxel over all samples.
    pub mean_spikes_per_taxel: f64,
    /// Mean of the intensive coding (spikes per taxel) over each class's samples.
    pub intensive_class_means: Vec<f64>,
    /// Every coding of the menu, in its order (the paper's).
    pub codings: Vec<CodingResult>,
    /// Time of the whole set.
    pub time: Timing,
}

impl SetResult {
    /// The result of `coding` (the pipeline runs every coding of the menu).
    pub fn coding(&self, coding: CodingName) -> &CodingResult {
        self.codings
            .iter()
            .find(|c| c.coding == coding)
            .expect("the pipeline runs every coding of the menu")
    }

    /// The Δt sweep of the coding that ran one (the temporal coding).
    pub fn dt_search(&self) -> Option<&DtSearch> {
        self.codings.iter().find_map(|c| match &c.search {
            Some(Search::DtSweep(s)) => Some(s),
            _ => None,
        })
    }

    /// The Bayesian optimisation of the coding that ran one (the spatiotemporal coding).
    pub fn bayes_search(&self) -> Option<&BayesSearch> {
        self.codings.iter().find_map(|c| match &c.search {
            Some(Search::Bayes(s)) => Some(s),
            _ => None,
        })
    }
}

/// Runs the paper's pipeline on one labelled set (see the module docs), encoded offline
/// ([`encode_offline`]); [`run_encoded`] takes the readouts of a network instead.
pub fn run_set(
    name: &str,
    data: &SpikeDataset,
    config: &PipelineConfig,
    progress: &dyn Progress,
) -> Result<SetResult, ExperimentError> {
    if data.labels().len() != data.len() {
        return Err(KnnError::Unlabelled.into());
    }
    run_encoded(
        name,
        &encode_offline(data, config.vr_from)?,
        config,
        progress,
        &neurotac_core::OneProcess,
    )
}

/// Runs the paper's pipeline on the coding readouts of one labelled set (see the module docs
/// and [`crate::readouts`]): every coding of the menu in its order, each through its
/// [`CodingScheme::pipeline`](crate::coding::CodingScheme::pipeline) (its parameter search,
/// then leave-one-out and the split).
///
/// Split over `ranks`: the distance matrices and the searches are computed by all ranks
/// together, the rest (KNN protocols, the optimiser) by every rank alike, so every rank
/// returns the one-process result. Collective: every rank must call it.
pub fn run_encoded(
    name: &str,
    set: &EncodedSet,
    config: &PipelineConfig,
    progress: &dyn Progress,
    ranks: &dyn Ranks,
) -> Result<SetResult, ExperimentError> {
    let labels = &set.labels[..];
    let n_classes = set.n_classes();
    if n_classes < 2 {
        return Err(ExperimentError::InvalidParameter {
            what: "classes",
            value: n_classes as f64,
            expected: "≥ 2 to classify",
        });
    }
    if labels.len() != set.len() {
        return Err(KnnError::Unlabelled.into());
    }
    let run = PipelineRun {
        name,
        labels,
        n_classes,
        config,
        progress,
        ranks,
    };
    let (result, time) = timed(|| -> Result<SetResult, ExperimentError> {
        let n_channels = set.n_channels.max(1) as f64;
        let intensive = set
            .trains
            .iter()
            .map(|o| o.total_spikes() as f64 / n_channels);
        let (samples_per_class, intensive_class_means) =
            class_means_of(intensive.clone(), labels, n_classes);
        // Summed as an array (ndarray's order), as the intensive readout column always was.
        let mean_spikes_per_taxel =
            ndarray::Array1::from_iter(intensive).sum() / set.len().max(1) as f64;
        let codings = (CodingName::ALL.iter())
            .map(|&c| {
                let scored = c.scheme().pipeline(set, &run)?;
                Ok(CodingResult { coding: c, scored })
            })
            .collect::<Result<_, ExperimentError>>()?;
        Ok(SetResult {
            name: name.to_owned(),
            path: set.path.clone(),
            van_rossum: set.vr_from.describe(),
            class_names: set.class_names.clone(),
            samples_per_class,
            duration_ms: set.duration_ms,
            mean_spikes_per_taxel,
            intensive_class_means,
            codings,
            time: Timing::default(),
        })
    });
    let mut result = result?;
    result.time = time;
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::menu::Menu;
    use crate::progress::NoProgress;
    use neurotac_core::MultiSpikeTrain;

    /// Three classes told apart by rate (intensive), place (spatial) and timing (temporal).
    fn toy(per_class: usize) -> SpikeDataset {
        let mut observations = Vec::new();
        let mut labels = Vec::new();
        for class in 0..3 {
            for trial in 0..per_class {
                let jitter = trial as f64 * 1e-3;
                let channels: Vec<Vec<f64>> = (0..4)
                    .map(|ch| {
                        let n = 3 + class * 2 + (ch == class) as usize * 3;
                        (0..n)
                            .map(|i| 0.05 + (class as f64 * 0.1 + i as f64 * 0.03) + jitter)
                            .collect()
                    })
                    .collect();
                observations.push(MultiSpikeTrain::from_channels(channels).unwrap());
                labels.push(class);
            }
        }
        let names = ["a", "b", "c"].map(String::from).to_vec();
        SpikeDataset::new(observations, labels, names, Default::default()).unwrap()
    }

    fn quick() -> PipelineConfig {
        let mut c = PipelineConfig::paper(1);
        c.bayes.epochs = 20;
        c.bayes.tau_step_s = 0.03;
        c.bayes.cos_step = 0.25;
        c
    }

    #[test]
    fn separable_toy_set_is_classified_and_reported_in_the_paper_order() {
        let data = toy(10);
        let r = run_set("toy", &data, &quick(), &NoProgress).unwrap();
        let order: Vec<CodingName> = r.codings.iter().map(|c| c.coding).collect();
        assert_eq!(order, CodingName::ALL);
        for c in &r.codings {
            assert_eq!(c.loo.accuracy.n, 30);
            assert!(
                c.loo.accuracy.mean > 0.9,
                "{:?}: {:?}",
                c.coding,
                c.loo.accuracy
            );
            assert_eq!(c.split.as_ref().unwrap().accuracy.n, 6);
        }
        assert_eq!(r.samples_per_class, vec![10, 10, 10]);
        // Class 0: 3 spikes on three channels, 6 on one → 15/4.
        assert!((r.intensive_class_means[0] - 3.75).abs() < 1e-12);
        assert_eq!(r.bayes_search().unwrap().result.trace.len(), 20);
        // The temporal coding's LOO is the sweep's at the chosen Δt.
        assert_eq!(
            r.coding(CodingName::Temporal).loo.accuracy,
            r.dt_search().unwrap().sweep.best
        );
        assert_eq!(
            r.coding(CodingName::Spatiotemporal).loo.accuracy.mean,
            r.bayes_search().unwrap().result.best_value
        );
    }

    #[test]
    fn a_one_sample_class_keeps_leave_one_out_and_refuses_the_split() {
        let data = toy(10);
        let mut obs = data.observations().to_vec();
        let mut labels = data.labels().to_vec();
        obs.truncate(21);
        labels.truncate(21);
        let d = SpikeDataset::new(obs, labels, data.class_names().to_vec(), Default::default())
            .unwrap();
        let r = run_set("lonely", &d, &quick(), &NoProgress).unwrap();
        for c in &r.codings {
            assert_eq!(c.loo.accuracy.n, 21);
            assert!(c.split.is_none());
            let why = c.split_refused.as_deref().unwrap();
            assert!(why.contains("class 2 has 1 sample"), "{why}");
        }
    }
}
