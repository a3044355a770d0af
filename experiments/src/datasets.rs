//! The bundled texture datasets, simulated (`shared/specs/simulator.md`; the paper's data are
//! not public): the **artificial** set (11 bump grids, 0–5 mm, 100 slides each) and the
//! **natural** set (20 textures, 50 slides each), as taxel spike datasets ([`SpikeDataset`]).
//!
//! Trials run in parallel (rayon) and are deterministic: trial `i` of class `c` is simulated
//! from [`trial_seed`]`(seed, set, c, i)` by a camera drawn from [`camera_seed`]`(seed)`, never
//! from thread order, so the same seed gives a bit-identical dataset at any thread count.
//! [`load_or_simulate`] caches datasets on disk, keyed by everything that determines them.

use crate::bench::BenchError;
use neurotac_core::{DatasetError, EventBuffer, MultiSpikeTrain, SpikeDataset};
use neurotac_sensor::sim::{
    Camera, EventLabel, GRID_SIZES_MM, NATURAL_TEXTURES, PreparedTexture, SimParams,
    SimulatedTrial, SimulationError, Simulator, Texture, paper_transduction, taxel_spikes,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Version of the simulated-dataset format and generator; bump it whenever the simulator's
/// output for given parameters changes, so stale caches are not reused.
pub const SIMULATED_DATASET_VERSION: u32 = 2;

/// Dataset generation that cannot proceed.
#[derive(Debug, thiserror::Error)]
pub enum DatasetsError {
    /// The simulator rejected its set-up.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// Pixel events could not be transduced or filtered.
    #[error(transparent)]
    Transduction(#[from] neurotac_sensor::error::TransductionError),
    /// A dataset could not be built, read or written.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// An event file could not be written.
    #[error(transparent)]
    Format(#[from] neurotac_sensor::FormatError),
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The thread pool could not start.
    #[error(transparent)]
    Threads(#[from] BenchError),
}

/// Which texture set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TextureSet {
    /// 11 bump grids, d = 0 … 5 mm in 0.5 mm steps (paper: 100 slides each).
    Artificial,
    /// The 20 natural textures of the paper's Table II (paper: 50 slides each).
    Natural,
}

impl TextureSet {
    /// The textures, in class order.
    pub fn textures(self) -> Vec<Texture> {
        match self {
            TextureSet::Artificial => GRID_SIZES_MM
                .iter()
                .map(|&d| Texture::Grid { size_mm: d })
                .collect(),
            TextureSet::Natural => NATURAL_TEXTURES.iter().map(Texture::Natural).collect(),
        }
    }

    /// Class names (index = label).
    pub fn class_names(self) -> Vec<String> {
        self.textures().iter().map(Texture::name).collect()
    }

    /// Slides per texture in the paper.
    pub fn paper_trials(self) -> usize {
        match self {
            TextureSet::Artificial => 100,
            TextureSet::Natural => 50,
        }
    }

    /// `artificial` or `natural`.
    pub fn name(self) -> &'static str {
        match self {
            TextureSet::Artificial => "artificial",
            TextureSet::Natural => "natural",
        }
    }

    fn id(self) -> u64 {
        match self {
            TextureSet::Artificial => 1,
            TextureSet::Natural => 2,
        }
    }
}

/// SplitMix64 finaliser.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of trial `trial` of class `class` of `set` in a dataset seeded with `seed`.
pub fn trial_seed(seed: u64, set: TextureSet, class: usize, trial: usize) -> u64 {
    mix(mix(mix(mix(seed) ^ set.id()) ^ class as u64) ^ trial as u64)
}

/// The seed of the camera (fixed-pattern noise) of a dataset seeded with `seed`.
pub fn camera_seed(seed: u64) -> u64 {
    mix(seed ^ 0xca3e_7a00)
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
pub fn simulate_set(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    each: &(dyn Fn(&TrialJob, &SimulatedTrial) -> Result<(), DatasetsError> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<SimulatedSet, DatasetsError> {
    if trials == 0 {
        return Err(SimulationError::ZeroTrials.into());
    }
    params.validate()?;
    let textures = prepare_textures(params, set);
    let camera = Camera::new(params, camera_seed(seed));
    let classes: Vec<usize> = (0..textures.len()).collect();
    let jobs = jobs_for(set, seed, &classes, 0, trials);
    let outcomes = run_trials(params, &camera, &textures, &jobs, each, progress)?;
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

/// Everything that determines a simulated dataset, as stored in its metadata (a simulated
/// dataset's metadata adds `pixel_events_per_trial` and `noise_events_per_trial`).
fn dataset_meta(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
) -> serde_json::Map<String, serde_json::Value> {
    let t = paper_transduction();
    let json = serde_json::json!({
        "generator": "neurotac-sim",
        "version": SIMULATED_DATASET_VERSION,
        "set": set,
        "trials_per_texture": trials,
        "seed": seed,
        "params": params,
        "transduction": {
            "ba_window_us": t.ba_window_us,
            "rf_radius_px": t.rf_radius_px,
            "pool_window_us": t.pool_window_us,
            "recentre_gain": t.recentre_gain,
            "max_shift_px": t.max_shift_px,
            "origin_us": t.origin_us,
        },
    });
    match json {
        serde_json::Value::Object(map) => map,
        _ => unreachable!("a JSON object literal"),
    }
}

/// FNV-1a 64 of the metadata's JSON text: the cache key.
fn cache_key(meta: &serde_json::Map<String, serde_json::Value>) -> u64 {
    let text = serde_json::to_string(meta).expect("metadata serialises");
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The cache file of a dataset in `cache_dir`.
pub fn cache_path(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
) -> PathBuf {
    let key = cache_key(&dataset_meta(set, trials, seed, params));
    cache_dir.join(format!(
        "{}-v{SIMULATED_DATASET_VERSION}-n{trials}-s{seed}-{key:016x}.bin",
        set.name()
    ))
}

/// The dataset of `set` with `trials` slides per texture, simulated from `seed` with `params`:
/// read from `cache_dir` when a dataset with exactly the same metadata (version, set, trials,
/// seed, parameters, transduction) is there, else simulated in parallel and stored (binary
/// [`SpikeDataset`], written atomically).
pub fn load_or_simulate(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
) -> Result<SpikeDataset, DatasetsError> {
    load_or_simulate_with(set, trials, seed, params, cache_dir, &|| {})
}

/// [`load_or_simulate`] with a progress callback (once per simulated trial).
pub fn load_or_simulate_with(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
    progress: &(dyn Fn() + Sync),
) -> Result<SpikeDataset, DatasetsError> {
    if trials == 0 {
        return Err(SimulationError::ZeroTrials.into());
    }
    params.validate()?;
    let path = cache_path(set, trials, seed, params, cache_dir);
    if let Some(cached) = read_cached(&path, &dataset_meta(set, trials, seed, params)) {
        return Ok(cached);
    }
    let simulated = simulate_set(set, trials, seed, params, &|_, _| Ok(()), progress)?;
    store(&simulated.dataset, cache_dir, &path)?;
    Ok(simulated.dataset)
}

/// The cached dataset at `path` if it exists, decodes and carries every entry of `meta`
/// (besides them it holds the event statistics of the run).
fn read_cached(
    path: &Path,
    meta: &serde_json::Map<String, serde_json::Value>,
) -> Option<SpikeDataset> {
    let data = SpikeDataset::load(path).ok()?;
    meta.iter()
        .all(|(k, v)| data.meta().get(k) == Some(v))
        .then_some(data)
}

/// Writes `dataset` to `path` (binary) through a temporary file and a rename.
pub fn store(dataset: &SpikeDataset, dir: &Path, path: &Path) -> Result<(), DatasetsError> {
    std::fs::create_dir_all(dir).map_err(|source| DatasetsError::Io {
        path: dir.to_owned(),
        source,
    })?;
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    dataset.save_binary(&tmp)?;
    std::fs::rename(&tmp, path).map_err(|source| DatasetsError::Io {
        path: path.to_owned(),
        source,
    })
}

/// Writes pixel events as CSV: a header `t,x,y,on` (t in µs, `on` 1/0), one event per line;
/// with `labels`, a fifth column `pin` (source pin, −1 for noise).
///
/// This is the simulator's own minimal writer; the event-file formats of the DAVIS stack
/// supersede it.
pub fn write_events_csv(
    path: &Path,
    events: &EventBuffer,
    labels: Option<&[EventLabel]>,
) -> Result<(), DatasetsError> {
    let io = |source| DatasetsError::Io {
        path: path.to_owned(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut w = std::io::BufWriter::new(file);
    let header = if labels.is_some() {
        "t,x,y,on,pin\n"
    } else {
        "t,x,y,on\n"
    };
    w.write_all(header.as_bytes()).map_err(io)?;
    for (i, e) in events.iter().enumerate() {
        match labels {
            Some(l) => {
                let pin = l[i].pin().map_or(-1, |p| p as i64);
                writeln!(
                    w,
                    "{},{},{},{},{pin}",
                    e.t.0,
                    e.x,
                    e.y,
                    u8::from(e.polarity)
                )
            }
            None => writeln!(w, "{},{},{},{}", e.t.0, e.x, e.y, u8::from(e.polarity)),
        }
        .map_err(io)?;
    }
    w.flush().map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::with_threads;

    fn short_params() -> SimParams {
        let mut p = SimParams::default();
        p.kinematics.distance_mm = 6.0;
        p.kinematics.rest_before_s = 0.05;
        p.kinematics.rest_after_s = 0.05;
        p
    }

    #[test]
    fn same_seed_is_bit_identical_at_any_thread_count_and_another_seed_differs() {
        let p = short_params();
        let run = |threads, seed| {
            with_threads(threads, || {
                simulate_set(TextureSet::Artificial, 2, seed, &p, &|_, _| Ok(()), &|| {})
            })
            .unwrap()
            .unwrap()
            .dataset
        };
        let one = run(1, 5);
        let two = run(2, 5);
        assert_eq!(one.to_binary(), two.to_binary());
        assert_eq!(one.len(), 22);
        assert_eq!(one.labels()[21], 10);
        assert_ne!(run(2, 6).to_binary(), one.to_binary());
    }

    #[test]
    fn zero_trials_is_an_error() {
        let p = short_params();
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(
            load_or_simulate(TextureSet::Natural, 0, 1, &p, dir.path()),
            Err(DatasetsError::Simulation(SimulationError::ZeroTrials))
        ));
    }

    #[test]
    fn cache_is_reused_and_keyed_by_the_parameters() {
        let p = short_params();
        let dir = tempfile::tempdir().unwrap();
        let first = load_or_simulate(TextureSet::Artificial, 1, 3, &p, dir.path()).unwrap();
        let path = cache_path(TextureSet::Artificial, 1, 3, &p, dir.path());
        assert!(path.exists());
        // A cached file is what is returned: replace it by a one-trial dataset with the same
        // metadata and read that back.
        let fake = SpikeDataset::new(
            first.observations()[..1].to_vec(),
            vec![0],
            first.class_names().to_vec(),
            first.meta().clone(),
        )
        .unwrap();
        store(&fake, dir.path(), &path).unwrap();
        let again = load_or_simulate(TextureSet::Artificial, 1, 3, &p, dir.path()).unwrap();
        assert_eq!(again, fake);
        let mut spoiled = first.clone();
        spoiled.meta_mut().insert("seed".into(), 999.into());
        let mut other = p;
        other.pixel.threshold_on = 0.21;
        assert_ne!(
            cache_path(TextureSet::Artificial, 1, 3, &other, dir.path()),
            path
        );
        // A file whose metadata does not match (hash collision, edits) is not trusted.
        store(&spoiled, dir.path(), &path).unwrap();
        let regenerated = load_or_simulate(TextureSet::Artificial, 1, 3, &p, dir.path()).unwrap();
        assert_eq!(regenerated, first);
    }

    #[test]
    fn events_csv_has_a_header_and_labels() {
        let p = short_params();
        let camera = Camera::new(&p, 1);
        let mut sim = Simulator::new(p, &camera).unwrap();
        let tex = sim.prepare(Texture::grid(5.0).unwrap());
        let trial = sim.simulate(&tex, 9);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("e.csv");
        write_events_csv(&path, &trial.events, Some(&trial.labels)).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("t,x,y,on,pin"));
        assert_eq!(lines.count(), trial.events.len());
        assert!(text.contains(",-1\n"));
    }
}
