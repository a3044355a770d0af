//! Trials of a simulated set: their seeds ([`trial_seed`], [`camera_seed`]), the job list
//! ([`jobs_for`]) and running them in parallel ([`run_trials`], [`map_trials`]).

use super::{DatasetsError, TextureSet};
use neurotac_core::MultiSpikeTrain;
use neurotac_core::seed_hash::splitmix64;
use neurotac_sensor::sim::{
    Camera, PreparedTexture, SimParams, SimulatedTrial, Simulator, taxel_spikes,
};
use rayon::prelude::*;

/// The seed of trial `trial` of class `class` of `set` in a dataset seeded with `seed`.
pub fn trial_seed(seed: u64, set: TextureSet, class: usize, trial: usize) -> u64 {
    splitmix64(splitmix64(splitmix64(splitmix64(seed) ^ set.id()) ^ class as u64) ^ trial as u64)
}

/// The seed of the camera (fixed-pattern noise) of a dataset seeded with `seed`.
pub fn camera_seed(seed: u64) -> u64 {
    splitmix64(seed ^ 0xca3e_7a00)
}

/// One trial to simulate: its class, index and texture.
#[derive(Debug, Clone, Copy)]
pub struct TrialJob {
    /// Class (texture index).
    pub class: usize,
    /// Trial index within the class.
    pub trial: usize,
    /// Seed.
    pub seed: u64,
}

/// What a simulated trial leaves once transduced.
#[derive(Debug, Clone)]
pub struct TrialOutcome {
    /// The job.
    pub job: TrialJob,
    /// Taxel spike trains.
    pub spikes: MultiSpikeTrain,
    /// Pixel events.
    pub pixel_events: usize,
    /// Noise-labelled pixel events.
    pub noise_events: usize,
}

/// Simulates `jobs` over `textures` in parallel (one [`Simulator`] per worker) and maps each
/// trial through `f`, returning the results in job order; `progress` is called once per trial.
pub fn map_trials<T: Send>(
    params: &SimParams,
    camera: &Camera,
    textures: &[PreparedTexture],
    jobs: &[TrialJob],
    f: &(dyn Fn(&TrialJob, &SimulatedTrial) -> Result<T, DatasetsError> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<T>, DatasetsError> {
    let base = Simulator::new(*params, camera)?;
    jobs.par_iter()
        .map_init(
            || base.clone(),
            |sim, job| {
                let trial = sim.simulate_slide(&textures[job.class], job.trial, job.seed);
                let out = f(job, &trial)?;
                progress();
                Ok(out)
            },
        )
        .collect()
}

/// Simulates `jobs` and transduces every trial ([`map_trials`]); `each` sees every trial
/// first (e.g. to write its pixel events).
pub fn run_trials(
    params: &SimParams,
    camera: &Camera,
    textures: &[PreparedTexture],
    jobs: &[TrialJob],
    each: &(dyn Fn(&TrialJob, &SimulatedTrial) -> Result<(), DatasetsError> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<TrialOutcome>, DatasetsError> {
    map_trials(
        params,
        camera,
        textures,
        jobs,
        &|job, trial| {
            each(job, trial)?;
            Ok(TrialOutcome {
                job: *job,
                spikes: taxel_spikes(trial)?.spikes,
                pixel_events: trial.events.len(),
                noise_events: trial.noise_count(),
            })
        },
        progress,
    )
}

/// The jobs of `trials` slides (indices `first..first + trials`) of each class in `classes`.
pub fn jobs_for(
    set: TextureSet,
    seed: u64,
    classes: &[usize],
    first: usize,
    trials: usize,
) -> Vec<TrialJob> {
    classes
        .iter()
        .flat_map(|&class| {
            (first..first + trials).map(move |trial| TrialJob {
                class,
                trial,
                seed: trial_seed(seed, set, class, trial),
            })
        })
        .collect()
}

/// Prepares the textures of `set` (fields built in parallel).
pub fn prepare_textures(params: &SimParams, set: TextureSet) -> Vec<PreparedTexture> {
    let textures = set.textures();
    textures
        .par_iter()
        .map(|&t| PreparedTexture::new(t, params))
        .collect()
}
