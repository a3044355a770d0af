//! How the pipeline scores a coding ([`PipelineRun::score`]: its distance matrix through leave-one-out and
//! the seeded stratified split), its settings ([`PipelineConfig`]), what one coding's run
//! yields ([`Scored`]) and the parameter searches a coding may report ([`Search`]).

use crate::coding::encoded::VrFrom;
use crate::error::ExperimentError;
use crate::progress::Progress;
use crate::protocols::{Evaluation, Protocol, evaluate};
use crate::search::bayes::{BayesConfig, BayesResult};
use crate::search::dt_sweep::DtSweep;
use crate::timing::{Timing, timed};
use ndarray::Array2;
use neurotac_core::{Knn, Ranks};
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

/// The Δt sweep of the temporal coding.
#[derive(Debug, Clone, Serialize)]
pub struct DtSearch {
    /// Leave-one-out accuracy at every window.
    pub sweep: DtSweep,
    /// Δt swept over 1…`max_window_ms` ms in 1 ms steps.
    pub max_window_ms: u32,
    /// Its time.
    pub time: Timing,
}

/// The Bayesian optimisation of the spatiotemporal coding's (τ, cos θ).
#[derive(Debug, Clone, Serialize)]
pub struct BayesSearch {
    /// The result, with its convergence trace.
    pub result: BayesResult,
    /// τ searched over [`tau_min_s`, `tau_max_s`] on a grid of `tau_step_s`.
    pub tau_min_s: f64,
    /// Largest τ (s).
    pub tau_max_s: f64,
    /// τ grid step (s).
    pub tau_step_s: f64,
    /// cos θ searched over [0, 1] on a grid of `cos_step`.
    pub cos_step: f64,
    /// Distinct τ visited (Van Rossum matrix pairs computed).
    pub matrices_computed: usize,
    /// Its time.
    pub time: Timing,
}

/// The parameter search a coding ran before it was scored (what a report plots and flags).
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Search {
    /// A sweep of the temporal window Δt.
    DtSweep(DtSearch),
    /// A Bayesian optimisation of the Van Rossum (τ, cos θ).
    Bayes(BayesSearch),
}

impl Search {
    /// Its wall time.
    pub fn time(&self) -> Timing {
        match self {
            Search::DtSweep(s) => s.time,
            Search::Bayes(s) => s.time,
        }
    }
}

/// One coding's run through the pipeline.
#[derive(Debug, Clone, Serialize)]
pub struct Scored {
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
    /// The parameter search that chose the parameters, if the coding has any.
    pub search: Option<Search>,
}

/// What a coding's pipeline run works with: the set's name and labels, the settings, the
/// progress display and the ranks (`&OneProcess` for one process).
pub struct PipelineRun<'a> {
    /// Set name (for progress stages).
    pub name: &'a str,
    /// Class of each sample.
    pub labels: &'a [usize],
    /// Number of classes.
    pub n_classes: usize,
    /// The settings.
    pub config: &'a PipelineConfig,
    /// Progress display.
    pub progress: &'a dyn Progress,
    /// The ranks the distances and searches are split over.
    pub ranks: &'a dyn Ranks,
}

impl PipelineRun<'_> {
    /// The KNN head of the settings.
    pub fn knn(&self) -> Result<Knn, ExperimentError> {
        Ok(Knn::new(self.config.k)?)
    }

    /// Scores the matrix `distances` computes through leave-one-out and the seeded stratified
    /// split, timing both (under a progress stage naming the coding and its `parameters`); a
    /// class too small for the split refuses the split alone.
    pub fn score(
        &self,
        label: &str,
        parameters: String,
        search: Option<Search>,
        distances: impl FnOnce() -> Result<Array2<f64>, ExperimentError>,
    ) -> Result<Scored, ExperimentError> {
        let what = match parameters.is_empty() {
            true => label.to_lowercase(),
            false => format!("{} coding, {parameters}", label.to_lowercase()),
        };
        self.progress
            .stage(&format!("{}: {what} (LOO, 80/20 split)", self.name), 0);
        let scored = self.protocols(parameters, search, distances);
        self.progress.finish();
        scored
    }

    /// [`Self::score`] without the progress stage.
    fn protocols(
        &self,
        parameters: String,
        search: Option<Search>,
        distances: impl FnOnce() -> Result<Array2<f64>, ExperimentError>,
    ) -> Result<Scored, ExperimentError> {
        let knn = self.knn()?;
        let (result, time) = timed(|| -> Result<_, ExperimentError> {
            let d = distances()?;
            let loo = evaluate(
                d.view(),
                self.labels,
                self.n_classes,
                knn,
                Protocol::LeaveOneOut,
            )?;
            let split = evaluate(
                d.view(),
                self.labels,
                self.n_classes,
                knn,
                Protocol::Split {
                    test_fraction: self.config.test_fraction,
                    seed: self.config.split_seed,
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
        Ok(Scored {
            parameters,
            loo,
            split,
            split_refused,
            time,
            search,
        })
    }
}
