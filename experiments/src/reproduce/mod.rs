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
    AfferentRun, Report, ReproduceConfig, ReproduceError, SetReport, Source, example_samples, run,
};

use crate::coding::{CodingName, class_means_of};
use crate::error::ExperimentError;
use crate::progress::Progress;
use crate::protocols::{Evaluation, Protocol, evaluate};
use crate::readouts::{EncodedSet, VrFrom, encode_offline};
use crate::search::bayes::{BayesConfig, BayesResult, VanRossumObjective, bayes_optimise};
use crate::search::dt_sweep::{DtSweep, dt_sweep_of_bins};
use crate::timing::{Timing, timed};
use ndarray::Array2;
use neurotac_core::coding::write_window_features;
use neurotac_core::distance::euclidean_distance_matrix;
use neurotac_core::{Knn, KnnError, Ranks, SpikeDataset};
use serde::Serialize;

/// Settings of the pipeline; [`PipelineConfig::paper`] is the paper's protocol.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PipelineConfig {
    /// KNN neighbours. Paper: 4.
    pub k: usize,
    /// Largest Δt of the sweep (ms, sweep 1…max in 1 ms steps). Paper: 200.
    pub max_window_ms: u32,
    /// The Bayesian optimisation of (τ, cos θ).
    pub bayes: BayesConfig,
    /// Test fraction of the split. Paper: 0.2.
    pub test_fraction: f64,
    /// Seed of the split.
    pub split_seed: u64,
    /// Van Rossum `LL²`/`SP²` matrix pairs kept in memory during the search (one per τ).
    pub vr_cache: usize,
    /// The Van Rossum distance exact or from traces (`--vr-from`). Paper: exact.
    pub vr_from: VrFrom,
}

impl PipelineConfig {
    /// The paper's protocol, with the optimisation's τ on a 5 ms grid (10, 15, …, 100 ms).
    ///
    /// Why 5 ms: every τ the search visits costs one exact Van Rossum matrix pair over all
    /// samples (seconds each for 1100 samples), while every cos θ at a known τ is nearly free;
    /// 1000 epochs visit almost every τ of the grid, so the paper's 1 ms grid (91 values) costs
    /// ≈ 5× the 5 ms grid (19 values) — set `bayes.tau_step_s = 0.001` for it.
    pub fn paper(seed: u64) -> Self {
        Self {
            k: 4,
            max_window_ms: 200,
            bayes: BayesConfig {
                epochs: 1000,
                seed,
                tau_step_s: 0.005,
                ..BayesConfig::default()
            },
            test_fraction: 0.2,
            split_seed: seed,
            vr_cache: 24,
            vr_from: VrFrom::Exact,
        }
    }
}

/// One coding's results.
#[derive(Debug, Clone, Serialize)]
pub struct CodingResult {
    /// The coding.
    pub coding: CodingName,
    /// Its parameters as used (`"Δt = 159 ms"`, `"τ = 76 ms, cos θ = 0.40"`, or empty).
    pub parameters: String,
    /// Leave-one-out (the paper's tables).
    pub loo: Evaluation,
    /// The stratified split (the paper's confusion matrices); `None` when refused.
    pub split: Option<Evaluation>,
    /// Why the split was refused (a class too small for it).
    pub split_refused: Option<String>,
    /// Time of the distances and both protocols (the parameter search not included).
    pub time: Timing,
}

/// Where the pipeline searched its three parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SearchSpace {
    /// Δt swept over 1…`dt_max_ms` ms in 1 ms steps.
    pub dt_max_ms: u32,
    /// τ searched over [`tau_min_s`, `tau_max_s`] on a grid of `tau_step_s`.
    pub tau_min_s: f64,
    /// Largest τ (s).
    pub tau_max_s: f64,
    /// τ grid step (s).
    pub tau_step_s: f64,
    /// cos θ searched over [0, 1] on a grid of `cos_step`.
    pub cos_step: f64,
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
    /// The Δt sweep (leave-one-out accuracy at every window).
    pub dt_sweep: DtSweep,
    /// Its time.
    pub dt_sweep_time: Timing,
    /// The Bayesian optimisation of (τ, cos θ), with its convergence trace.
    pub bayes: BayesResult,
    /// Its time.
    pub bayes_time: Timing,
    /// Distinct τ visited (Van Rossum matrix pairs computed).
    pub vr_matrices_computed: usize,
    /// Where Δt, τ and cos θ were searched (to flag a choice on a bound).
    pub search_space: SearchSpace,
    /// The four codings, in the paper's order.
    pub codings: Vec<CodingResult>,
    /// Time of the whole set.
    pub time: Timing,
}

impl SetResult {
    /// The result of `coding`.
    pub fn coding(&self, coding: CodingName) -> &CodingResult {
        self.codings
            .iter()
            .find(|c| c.coding == coding)
            .expect("all four codings are run")
    }
}

/// Runs `distances` through leave-one-out and the split.
fn score(
    coding: CodingName,
    parameters: String,
    labels: &[usize],
    n_classes: usize,
    config: &PipelineConfig,
    distances: impl FnOnce() -> Result<Array2<f64>, ExperimentError>,
) -> Result<CodingResult, ExperimentError> {
    let knn = Knn::new(config.k)?;
    let (result, time) = timed(|| -> Result<_, ExperimentError> {
        let d = distances()?;
        let loo = evaluate(d.view(), labels, n_classes, knn, Protocol::LeaveOneOut)?;
        let split = evaluate(
            d.view(),
            labels,
            n_classes,
            knn,
            Protocol::Split {
                test_fraction: config.test_fraction,
                seed: config.split_seed,
            },
        );
        Ok((loo, split))
    });
    let (loo, split) = result?;
    let (split, split_refused) = match split {
        Ok(e) => (Some(e), None),
        Err(e @ ExperimentError::ClassTooSmallToSplit { .. }) => (None, Some(e.to_string())),
        Err(e) => return Err(e),
    };
    Ok(CodingResult {
        coding,
        parameters,
        loo,
        split,
        split_refused,
        time,
    })
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

/// The temporal features at window `window_ms` of every sample, from its per-ms bins.
fn temporal_features(set: &EncodedSet, window_ms: u32) -> Array2<f64> {
    let width = (set.duration_ms - window_ms + 1) as usize;
    let mut out = Array2::zeros((set.len(), width));
    for (bins, mut row) in set.bins.iter().zip(out.rows_mut()) {
        let row = row
            .as_slice_mut()
            .expect("rows of a fresh array are contiguous");
        write_window_features(bins, window_ms, set.spatial.ncols(), row);
    }
    out
}

/// Runs the paper's pipeline on the coding readouts of one labelled set (see the module docs
/// and [`crate::readouts`]).
///
/// [`run_encoded`] split over `ranks`: the distance matrices
/// ([`euclidean_distance_matrix`], [`VanRossumObjective::on_ranks`]) and the Δt sweep
/// ([`dt_sweep_of_bins`]) are computed by all ranks together, the rest (KNN protocols, the
/// optimiser) by every rank alike, so every rank returns the one-process result. Collective:
/// every rank must call it.
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
    let knn = Knn::new(config.k)?;
    let (result, time) = timed(|| -> Result<SetResult, ExperimentError> {
        let duration_ms = set.duration_ms;
        let (samples_per_class, intensive_class_means) =
            class_means_of(set.intensive.column(0).iter().copied(), labels, n_classes);
        let mean_spikes_per_taxel = set.intensive.column(0).sum() / set.len().max(1) as f64;

        progress.stage(
            &format!("{name}: intensive and spatial codings (LOO, 80/20 split)"),
            2,
        );
        let intensive = score(
            CodingName::Intensive,
            String::new(),
            labels,
            n_classes,
            config,
            || Ok(euclidean_distance_matrix(set.intensive.view(), ranks)?),
        )?;
        progress.advance(1);
        let spatial = score(
            CodingName::Spatial,
            String::new(),
            labels,
            n_classes,
            config,
            || Ok(euclidean_distance_matrix(set.spatial.view(), ranks)?),
        )?;
        progress.finish();

        let max_window = config.max_window_ms.min(duration_ms);
        progress.stage(
            &format!("{name}: Δt sweep 1…{max_window} ms (LOO at each)"),
            0,
        );
        let (sweep, dt_sweep_time) =
            timed(|| dt_sweep_of_bins(&set.bins, labels, max_window, knn, ranks));
        let sweep = sweep?;
        progress.finish();
        let dt = sweep.best_window_ms;
        progress.stage(
            &format!("{name}: temporal coding, Δt = {dt} ms (LOO, 80/20 split)"),
            0,
        );
        let temporal = score(
            CodingName::Temporal,
            format!("Δt = {dt} ms"),
            labels,
            n_classes,
            config,
            || {
                let features = temporal_features(set, dt);
                Ok(euclidean_distance_matrix(features.view(), ranks)?)
            },
        )?;

        progress.finish();
        progress.stage(
            &format!("{name}: Bayesian optimisation of τ, cos θ (epochs)"),
            config.bayes.epochs as u64,
        );
        let mut objective =
            VanRossumObjective::new(set.van_rossum_input(), labels, knn, config.vr_cache)
                .on_ranks(ranks);
        let (bayes, bayes_time) = timed(|| {
            bayes_optimise(&config.bayes, |i, tau, cos| {
                let a = objective.accuracy(i, tau, cos);
                progress.advance(1);
                a
            })
        });
        let bayes = bayes?;
        progress.finish();
        progress.stage(
            &format!("{name}: spatiotemporal coding (LOO, 80/20 split)"),
            0,
        );
        let spatiotemporal = score(
            CodingName::Spatiotemporal,
            format!(
                "τ = {:.0} ms, cos θ = {:.2}",
                bayes.best_tau_s * 1e3,
                bayes.best_cos
            ),
            labels,
            n_classes,
            config,
            || {
                Ok(objective
                    .matrices(bayes.best_tau_index, bayes.best_tau_s)?
                    .distances(bayes.best_cos)?)
            },
        )?;
        progress.finish();
        Ok(SetResult {
            name: name.to_owned(),
            path: set.path.clone(),
            van_rossum: set.vr_from.describe(),
            class_names: set.class_names.clone(),
            samples_per_class,
            duration_ms,
            mean_spikes_per_taxel,
            intensive_class_means,
            dt_sweep: sweep,
            dt_sweep_time,
            vr_matrices_computed: objective.matrices_computed,
            search_space: SearchSpace {
                dt_max_ms: max_window,
                tau_min_s: config.bayes.tau_min_s,
                tau_max_s: config.bayes.tau_max_s,
                tau_step_s: config.bayes.tau_step_s,
                cos_step: config.bayes.cos_step,
            },
            bayes,
            bayes_time,
            codings: vec![intensive, spatial, temporal, spatiotemporal],
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
        assert_eq!(r.bayes.trace.len(), 20);
        // The temporal coding's LOO is the sweep's at the chosen Δt.
        assert_eq!(r.coding(CodingName::Temporal).loo.accuracy, r.dt_sweep.best);
        assert_eq!(
            r.coding(CodingName::Spatiotemporal).loo.accuracy.mean,
            r.bayes.best_value
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
