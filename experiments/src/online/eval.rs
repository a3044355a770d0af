//! `neurotac recognise --eval`: how early a texture can be told. Trains on an 80/20 stratified
//! split of a simulated set, re-simulates the held-out slides (each slide is a pure function of
//! its seed, so its pixel events are those of the dataset's sample) and replays their pixel
//! events through the online path ([`super::Recogniser`]) with every coding: accuracy against
//! the time since the slide start, when each coding first reaches 90 % of its final accuracy,
//! and the decision latency.

use super::{
    Decision, LatencyPercentiles, OnlineClassifier, OnlineTraining, Recogniser, latency_percentiles,
};
use crate::coding::Coding;
use crate::datasets::simulated::{
    DatasetsError, TextureSet, TrialJob, camera_seed, load_or_simulate, map_trials,
    prepare_textures, trial_seed,
};
use crate::error::ExperimentError;
use crate::menu::Menu;
use crate::protocols::stratified_split;
use neurotac_core::{EventBuffer, OneProcess, SpikeDataset};
use neurotac_sensor::sim::{Camera, SimParams, paper_transduction};
use std::path::Path;

/// Settings of an online evaluation.
#[derive(Debug, Clone)]
pub struct OnlineEvalConfig {
    /// The texture set.
    pub set: TextureSet,
    /// Slides per texture.
    pub trials: usize,
    /// Seed of the dataset (and of the split).
    pub seed: u64,
    /// Simulator parameters.
    pub params: SimParams,
    /// The codings to evaluate, with their parameters.
    pub codings: Vec<Coding>,
    /// Neighbours.
    pub k: usize,
    /// Windows a decision must hold to count as stable.
    pub stable_windows: usize,
    /// Held-out fraction (0.2).
    pub test_fraction: f64,
}

/// One coding's online result.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CodingTimeline {
    /// The coding's name.
    pub coding: &'static str,
    /// Its parameters, for the report.
    pub parameters: String,
    /// Accuracy (fraction) of the decisions after each window, in window order.
    pub accuracy: Vec<f64>,
    /// Accuracy of the final decisions (whole slides).
    pub final_accuracy: f64,
    /// The first elapsed time (s) at which the accuracy reaches 90 % of the final one.
    pub t90_s: Option<f64>,
    /// Decision latency over every window of every slide.
    pub latency: LatencyPercentiles,
    /// Held-out slides replayed per second of wall time, relative to real time (the
    /// slide's duration over the replay's wall time, mean over slides).
    pub replay_speed: f64,
}

/// What [`evaluate_online`] measured.
#[derive(Debug, Clone, serde::Serialize)]
pub struct OnlineEval {
    /// The set's name.
    pub set: &'static str,
    /// Training and held-out slides.
    pub n_train: usize,
    /// Held-out slides.
    pub n_test: usize,
    /// Neighbours of every coding's KNN (the `k` the classifiers used).
    pub k: usize,
    /// End of each window (s since the slide start).
    pub window_end_s: Vec<f64>,
    /// One timeline per coding.
    pub codings: Vec<CodingTimeline>,
}

/// One held-out slide replayed with one coding: its window decisions, its final decision and
/// the replay's wall time.
struct SlideRun {
    decisions: Vec<Decision>,
    last: Decision,
    wall_s: f64,
}

/// Runs the evaluation (module docs); `cache_dir` holds simulated datasets, `progress` is
/// called once per held-out slide.
pub fn evaluate_online(
    config: &OnlineEvalConfig,
    cache_dir: &Path,
    progress: &(dyn Fn() + Sync),
) -> Result<OnlineEval, ExperimentError> {
    let sim_error = |e: DatasetsError| ExperimentError::Datasets(Box::new(e));
    let data = load_or_simulate(
        config.set,
        config.trials,
        config.seed,
        &config.params,
        cache_dir,
        &|| {},
        &OneProcess,
    )
    .map_err(sim_error)?;
    let labels = data.labels();
    let (train, test) = stratified_split(labels, config.test_fraction, config.seed)?;
    let training = OnlineTraining::new(&subset(&data, &train)?, None)?;
    let classifiers = (config.codings.iter())
        .map(|&coding| OnlineClassifier::new(&training, coding, config.k))
        .collect::<Result<Vec<_>, _>>()?;
    // Samples are class-major, `trials` per class: sample i is trial i mod trials.
    let jobs: Vec<TrialJob> = test
        .iter()
        .map(|&i| {
            let (class, trial) = (labels[i], i % config.trials);
            TrialJob {
                class,
                trial,
                seed: trial_seed(config.seed, config.set, class, trial),
            }
        })
        .collect();
    let textures = prepare_textures(&config.params, config.set);
    let camera = Camera::new(&config.params, camera_seed(config.seed));
    let runs = map_trials(
        &config.params,
        &camera,
        &textures,
        &jobs,
        &|_, trial| {
            Ok(classifiers
                .iter()
                .map(|c| replay_slide(c, config.stable_windows, &trial.events))
                .collect::<Result<Vec<SlideRun>, ExperimentError>>())
        },
        progress,
    )
    .map_err(sim_error)?
    .into_iter()
    .collect::<Result<Vec<Vec<SlideRun>>, ExperimentError>>()?;
    let duration_s = training.duration_ms() as f64 * 1e-3;
    // Every slide has the same windows (the training duration).
    let window_end_s: Vec<f64> = (runs.first().and_then(|r| r.first()))
        .map(|r| r.decisions.iter().map(|d| d.t_s).collect())
        .unwrap_or_default();
    let windows = window_end_s.len();
    let truth: Vec<usize> = jobs.iter().map(|j| j.class).collect();
    let codings = config
        .codings
        .iter()
        .enumerate()
        .map(|(c, coding)| {
            let slides = || runs.iter().map(move |r| &r[c]);
            let hits = |pick: &dyn Fn(&SlideRun) -> Option<usize>| {
                slides()
                    .zip(&truth)
                    .filter(|(r, t)| pick(r) == Some(**t))
                    .count() as f64
                    / truth.len().max(1) as f64
            };
            let accuracy: Vec<f64> = (0..windows)
                .map(|w| hits(&|r| r.decisions.get(w).map(|d| d.class)))
                .collect();
            let final_accuracy = hits(&|r| Some(r.last.class));
            let t90_s = accuracy
                .iter()
                .zip(&window_end_s)
                .find(|(a, _)| **a >= 0.9 * final_accuracy)
                .map(|(_, &t)| t);
            let all: Vec<Decision> = slides().flat_map(|r| r.decisions.clone()).collect();
            let latency = latency_percentiles(&all).unwrap_or_default();
            let replay_speed =
                slides().map(|r| duration_s / r.wall_s).sum::<f64>() / truth.len().max(1) as f64;
            CodingTimeline {
                coding: coding.name.key(),
                parameters: coding.describe_parameters(),
                accuracy,
                final_accuracy,
                t90_s,
                latency,
                replay_speed,
            }
        })
        .collect();
    Ok(OnlineEval {
        set: config.set.name(),
        n_train: train.len(),
        n_test: test.len(),
        k: config.k,
        window_end_s,
        codings,
    })
}

/// Replays one slide's pixel events (in chunks of 4096, as a reader delivers them).
fn replay_slide(
    classifier: &OnlineClassifier<'_>,
    stable_windows: usize,
    events: &EventBuffer,
) -> Result<SlideRun, ExperimentError> {
    let start = std::time::Instant::now();
    let mut r = Recogniser::new(classifier, paper_transduction(), stable_windows)?;
    let mut chunk = EventBuffer::new();
    for first in (0..events.len()).step_by(4096) {
        chunk.clear();
        for j in first..(first + 4096).min(events.len()) {
            chunk.push(events.get(j).expect("in range"));
        }
        r.push(&chunk)?;
        if r.is_done() {
            break;
        }
    }
    let last = r.finish()?;
    Ok(SlideRun {
        decisions: r.decisions().to_vec(),
        last,
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// The samples `idx` of `data`, in that order (labels, class names and metadata kept).
pub fn subset(data: &SpikeDataset, idx: &[usize]) -> Result<SpikeDataset, ExperimentError> {
    Ok(SpikeDataset::new(
        idx.iter()
            .map(|&i| data.observations()[i].clone())
            .collect(),
        idx.iter().map(|&i| data.labels()[i]).collect(),
        data.class_names().to_vec(),
        data.meta().clone(),
    )?)
}
