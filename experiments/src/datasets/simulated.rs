//! The bundled texture datasets, simulated (`shared/specs/simulator.md`; the paper's data are
//! not public): the **artificial** set (11 bump grids, 0–5 mm, 100 slides each) and the
//! **natural** set (20 textures, 50 slides each), as taxel spike datasets ([`SpikeDataset`]).
//!
//! Trials run in parallel (rayon) and are deterministic: trial `i` of class `c` is simulated
//! from [`trial_seed`]`(seed, set, c, i)` by a camera drawn from [`camera_seed`]`(seed)`, never
//! from thread order, so the same seed gives a bit-identical dataset at any thread count.
//! [`load_or_simulate`] caches datasets on disk, keyed by everything that determines them.
//!
//! | file | what it holds |
//! |---|---|
//! | this one | [`simulate_set`]: every trial of a set, split over ranks, as one dataset |
//! | `trials.rs` | trial seeds, the job list, running jobs in parallel |
//! | `cache.rs` | the on-disk cache: [`cache_path`], [`load_or_simulate`], [`store`] |
//! | `generate.rs` | `neurotac simulate`: [`generate`] and pixel-event files |

mod cache;
mod generate;
#[cfg(test)]
mod tests;
mod trials;

pub use super::error::DatasetsError;
pub use super::texture_set::TextureSet;
pub use cache::{cache_path, default_cache_dir, load_or_simulate, store, warn_about_cache_once};
pub use generate::{GenerateConfig, Generated, PixelEventFiles, generate, write_events_csv};
pub use trials::{
    TrialJob, TrialOutcome, camera_seed, jobs_for, map_trials, prepare_textures, run_trials,
    trial_seed,
};

use super::metadata::write_metadata;
use neurotac_core::{Ranks, RanksError, SpikeDataset};
use neurotac_sensor::sim::{Camera, SimParams, SimulatedTrial, check_trials, paper_transduction};
use std::path::PathBuf;

/// Version of the simulated-dataset format and generator; bump it whenever the simulator's
/// output for given parameters changes, so stale caches are not reused.
pub const SIMULATED_DATASET_VERSION: u32 = 4;

/// A simulated dataset and its event statistics.
#[derive(Debug, Clone)]
pub struct SimulatedSet {
    /// The taxel spike dataset (labels = class index, observations in class-major order).
    pub dataset: SpikeDataset,
    /// Mean pixel events per trial.
    pub mean_pixel_events: f64,
    /// Mean noise-labelled pixel events per trial.
    pub mean_noise_events: f64,
}

/// Simulates `trials` slides of every texture of `set` (see the module docs). `each` sees
/// every simulated trial; `progress` is called once per trial.
///
/// On one process (`&OneProcess`) every trial runs here. Split over `ranks`, rank `r` of `P`
/// simulates the jobs `r, r+P, r+2P, …`
/// of the class-major (class, trial) list — dealt round-robin, since a trial's cost grows with
/// its texture's spike count — and `each` sees only the rank's own trials. The trials are
/// all-gathered and put back in job order, so every rank returns the dataset one process makes
/// with the same seed, bit for bit (a trial depends only on its own seed). Collective: every
/// rank must call it.
pub fn simulate_set(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    each: &(dyn Fn(&TrialJob, &SimulatedTrial) -> Result<(), DatasetsError> + Sync),
    progress: &(dyn Fn() + Sync),
    ranks: &dyn Ranks,
) -> Result<SimulatedSet, DatasetsError> {
    check_trials(trials, set.textures().len())?;
    params.validate()?;
    let textures = prepare_textures(params, set);
    let camera = Camera::new(params, camera_seed(seed));
    let classes: Vec<usize> = (0..textures.len()).collect();
    let jobs = jobs_for(set, seed, &classes, 0, trials);
    let mine: Vec<TrialJob> = jobs
        .iter()
        .copied()
        .skip(ranks.rank())
        .step_by(ranks.size())
        .collect();
    let outcomes = run_trials(params, &camera, &textures, &mine, each, progress)?;
    let outcomes = gather_outcomes(outcomes, set, ranks)?;
    let n = outcomes.len() as f64;
    let mean_pixel_events = outcomes.iter().map(|o| o.pixel_events as f64).sum::<f64>() / n;
    let mean_noise_events = outcomes.iter().map(|o| o.noise_events as f64).sum::<f64>() / n;
    let labels = outcomes.iter().map(|o| o.job.class).collect();
    let observations = outcomes.into_iter().map(|o| o.spikes).collect();
    let mut meta = dataset_meta(set, trials, seed, params);
    meta.insert("pixel_events_per_trial".into(), mean_pixel_events.into());
    meta.insert("noise_events_per_trial".into(), mean_noise_events.into());
    let dataset = SpikeDataset::new(observations, labels, set.class_names(), meta)?;
    Ok(SimulatedSet {
        dataset,
        mean_pixel_events,
        mean_noise_events,
    })
}

/// Every rank's trial outcomes, in job order (class, then trial). A rank's trials travel as a
/// binary spike dataset (the checksummed format of the cache) whose metadata carries the jobs
/// and event counts.
fn gather_outcomes(
    local: Vec<TrialOutcome>,
    set: TextureSet,
    ranks: &dyn Ranks,
) -> Result<Vec<TrialOutcome>, DatasetsError> {
    if ranks.size() == 1 {
        return Ok(local);
    }
    let column = |f: &dyn Fn(&TrialOutcome) -> u64| -> serde_json::Value {
        local.iter().map(f).collect::<Vec<u64>>().into()
    };
    let mut meta = serde_json::Map::new();
    meta.insert("class".into(), column(&|o| o.job.class as u64));
    meta.insert("trial".into(), column(&|o| o.job.trial as u64));
    meta.insert("seed".into(), column(&|o| o.job.seed));
    meta.insert("pixel_events".into(), column(&|o| o.pixel_events as u64));
    meta.insert("noise_events".into(), column(&|o| o.noise_events as u64));
    let labels = local.iter().map(|o| o.job.class).collect();
    let observations = local.into_iter().map(|o| o.spikes).collect();
    let block = SpikeDataset::new(observations, labels, set.class_names(), meta)?;
    let mut all = Vec::new();
    for (rank, bytes) in ranks
        .all_gather_bytes(&block.to_binary())?
        .into_iter()
        .enumerate()
    {
        let name = PathBuf::from(format!("<trials of rank {rank}>"));
        let block = SpikeDataset::from_binary(&bytes, &name)?;
        let column = |key: &'static str| -> Result<Vec<u64>, DatasetsError> {
            let values = block.meta().get(key).and_then(|v| v.as_array());
            let values: Option<Vec<u64>> = values
                .map(|a| a.iter().map(serde_json::Value::as_u64).collect())
                .unwrap_or(None);
            match values {
                Some(v) if v.len() == block.len() => Ok(v),
                _ => Err(RanksError::Malformed {
                    rank,
                    during: "gathering simulated trials",
                    reason: format!("metadata field '{key}' is not one integer per trial"),
                }
                .into()),
            }
        };
        let (class, trial, seed) = (column("class")?, column("trial")?, column("seed")?);
        let (pixel, noise) = (column("pixel_events")?, column("noise_events")?);
        for (i, spikes) in block.observations().iter().enumerate() {
            all.push(TrialOutcome {
                job: TrialJob {
                    class: class[i] as usize,
                    trial: trial[i] as usize,
                    seed: seed[i],
                },
                spikes: spikes.clone(),
                pixel_events: pixel[i] as usize,
                noise_events: noise[i] as usize,
            });
        }
    }
    all.sort_by_key(|o| (o.job.class, o.job.trial));
    Ok(all)
}

/// Everything that determines a simulated dataset, as stored in its metadata, with the typed
/// fields of [`super::metadata`] (`duration_s`, `transduction`); a simulated dataset's metadata
/// adds `pixel_events_per_trial` and `noise_events_per_trial`.
fn dataset_meta(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
) -> serde_json::Map<String, serde_json::Value> {
    let json = serde_json::json!({
        "generator": "neurotac-sim",
        "version": SIMULATED_DATASET_VERSION,
        "set": set,
        "trials_per_texture": trials,
        "seed": seed,
        "params": params,
    });
    let serde_json::Value::Object(mut meta) = json else {
        unreachable!("a JSON object literal")
    };
    write_metadata(
        &mut meta,
        &paper_transduction(),
        Some(sample_duration_s(params)),
    );
    meta
}

/// The length of every simulated sample (s): the trial's (rest, slide, rest), rounded up to a
/// whole ms as the temporal coding's bins need; every spike lies before it.
pub fn sample_duration_s(params: &SimParams) -> f64 {
    let ms = params.duration_s() * 1e3;
    // A duration already whole up to rounding (4.55 s = 4550.000000000001 ms) stays as it is.
    (ms - 1e-6).ceil() / 1e3
}
