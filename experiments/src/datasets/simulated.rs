//! The bundled texture datasets, simulated (`shared/specs/simulator.md`; the paper's data are
//! not public): the **artificial** set (11 bump grids, 0–5 mm, 100 slides each) and the
//! **natural** set (20 textures, 50 slides each), as taxel spike datasets ([`SpikeDataset`]).
//!
//! Trials run in parallel (rayon) and are deterministic: trial `i` of class `c` is simulated
//! from [`trial_seed`]`(seed, set, c, i)` by a camera drawn from [`camera_seed`]`(seed)`, never
//! from thread order, so the same seed gives a bit-identical dataset at any thread count.
//! [`load_or_simulate`] caches datasets on disk, keyed by everything that determines them.

use super::metadata::write_metadata;
use crate::coding::class_means;
use crate::export::{OutputFormat, dataset_bytes};
use crate::progress::Progress;
use crate::threads::ThreadPoolError;
use neurotac_core::{
    DatasetError, EventBuffer, MultiSpikeTrain, OneProcess, Ranks, RanksError, SpikeDataset,
};
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
pub const SIMULATED_DATASET_VERSION: u32 = 3;

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
    Threads(#[from] ThreadPoolError),
    /// The ranks sharing the simulation could not exchange their trials.
    #[error(transparent)]
    Ranks(#[from] RanksError),
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
    simulate_set_on(set, trials, seed, params, each, progress, &OneProcess)
}

/// [`simulate_set`] split over `ranks`: rank `r` of `P` simulates the jobs `r, r+P, r+2P, …`
/// of the class-major (class, trial) list — dealt round-robin, since a trial's cost grows with
/// its texture's spike count — and `each` sees only the rank's own trials. The trials are
/// all-gathered and put back in job order, so every rank returns the dataset one process makes
/// with the same seed, bit for bit (a trial depends only on its own seed). Collective: every
/// rank must call it.
pub fn simulate_set_on(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    each: &(dyn Fn(&TrialJob, &SimulatedTrial) -> Result<(), DatasetsError> + Sync),
    progress: &(dyn Fn() + Sync),
    ranks: &dyn Ranks,
) -> Result<SimulatedSet, DatasetsError> {
    if trials == 0 {
        return Err(SimulationError::ZeroTrials.into());
    }
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

/// FNV-1a 64 of the metadata's JSON text: the cache key.
fn cache_key(meta: &serde_json::Map<String, serde_json::Value>) -> u64 {
    let text = serde_json::to_string(meta).expect("metadata serialises");
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The cache folder of simulated datasets shared by `neurotac reproduce` and `neurotac
/// simulate`: `$NEUROTAC_CACHE` if set, else `$XDG_CACHE_HOME/neurotac`, else
/// `~/.cache/neurotac` (`./.neurotac-cache` without a home folder). Deleting the folder clears
/// the cache; a dataset is simulated again when next needed.
pub fn default_cache_dir() -> PathBuf {
    if let Some(p) = std::env::var_os("NEUROTAC_CACHE") {
        return p.into();
    }
    if let Some(p) = std::env::var_os("XDG_CACHE_HOME") {
        return PathBuf::from(p).join("neurotac");
    }
    match std::env::var_os("HOME") {
        Some(h) => PathBuf::from(h).join(".cache").join("neurotac"),
        None => PathBuf::from(".neurotac-cache"),
    }
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
    load_or_simulate_on(set, trials, seed, params, cache_dir, progress, &OneProcess)
}

/// [`load_or_simulate_with`] on `ranks`: every rank reads the cache, or the ranks simulate the
/// dataset together ([`simulate_set_on`]) and rank 0 stores it. Collective.
pub fn load_or_simulate_on(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
    progress: &(dyn Fn() + Sync),
    ranks: &dyn Ranks,
) -> Result<SpikeDataset, DatasetsError> {
    Ok(load_or_simulate_cached(set, trials, seed, params, cache_dir, progress, ranks)?.0)
}

/// [`load_or_simulate_with`], also saying whether the dataset came from the cache (the cache
/// file is read once).
fn load_or_simulate_cached(
    set: TextureSet,
    trials: usize,
    seed: u64,
    params: &SimParams,
    cache_dir: &Path,
    progress: &(dyn Fn() + Sync),
    ranks: &dyn Ranks,
) -> Result<(SpikeDataset, bool), DatasetsError> {
    if trials == 0 {
        return Err(SimulationError::ZeroTrials.into());
    }
    params.validate()?;
    let path = cache_path(set, trials, seed, params, cache_dir);
    // Every rank must take the same branch: they agree on whether the cache was usable.
    let cached = read_cached(&path, &dataset_meta(set, trials, seed, params));
    let usable = ranks.all_gather_bytes(&[u8::from(cached.is_some())])?;
    if let Some(cached) = cached.filter(|_| usable.iter().all(|b| b == &[1])) {
        return Ok((cached, true));
    }
    let simulated = simulate_set_on(set, trials, seed, params, &|_, _| Ok(()), progress, ranks)?;
    if ranks.is_root() {
        store(&simulated.dataset, cache_dir, &path)?;
    }
    Ok((simulated.dataset, false))
}

/// The cached dataset at `path` if it exists, decodes and carries every entry of `meta`
/// (besides them it holds the event statistics of the run).
fn read_cached(
    path: &Path,
    meta: &serde_json::Map<String, serde_json::Value>,
) -> Option<SpikeDataset> {
    let data = match SpikeDataset::load(path) {
        Ok(data) => data,
        Err(e) if path.exists() => {
            let e = neurotac_core::error_chain(&e);
            eprintln!("warning: cached dataset unusable ({e}); simulating it again");
            return None;
        }
        Err(_) => return None,
    };
    meta.iter()
        .all(|(k, v)| data.meta().get(k) == Some(v))
        .then_some(data)
}

/// Writes `dataset` to `path` (binary, checksummed) through a temporary file and a rename.
pub fn store(dataset: &SpikeDataset, dir: &Path, path: &Path) -> Result<(), DatasetsError> {
    std::fs::create_dir_all(dir).map_err(|source| DatasetsError::Io {
        path: dir.to_owned(),
        source,
    })?;
    Ok(dataset.save_binary(path)?)
}

/// How `generate` writes every trial's pixel events.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PixelEventFiles {
    /// One event file per trial in the format of this extension (`aedat4`, `aedat`, `aedat3`,
    /// `txt`, `csv`).
    Format(String),
    /// CSV with a `pin` column (source pin, −1 for noise), see [`write_events_csv`].
    LabelledCsv,
}

/// What [`generate`] simulates and writes (`neurotac simulate`).
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateConfig {
    /// The texture set.
    pub set: TextureSet,
    /// Slides per texture (≥ 1).
    pub trials: usize,
    /// Seed of the dataset.
    pub seed: u64,
    /// Simulator parameters.
    pub params: SimParams,
    /// Output folder: `<set>.bin`, optionally `<set>.json`, `<set>.npz` and
    /// `events/<class>/<trial>.<ext>`.
    pub out: PathBuf,
    /// Cache folder of simulated datasets.
    pub cache: PathBuf,
    /// Also write the dataset in these forms (JSON, numpy `.npz`; see [`crate::export`]).
    pub also: Vec<OutputFormat>,
    /// Also write every trial's pixel events (the dataset is then always simulated, and cached).
    pub pixel_events: Option<PixelEventFiles>,
}

/// What [`generate`] made.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The dataset.
    pub dataset: SpikeDataset,
    /// `true` when it was read from the cache rather than simulated.
    pub from_cache: bool,
    /// The binary dataset written (`<out>/<set>.bin`).
    pub binary: PathBuf,
    /// The other forms written ([`GenerateConfig::also`]), in that order.
    pub also: Vec<PathBuf>,
    /// Mean spikes per taxel of each class (index = label).
    pub class_means: Vec<f64>,
}

/// Simulates (or reads from the cache) the dataset of `config` and writes its files; `progress`
/// sees one stage with one step per simulated trial. Runs on the current rayon pool.
///
/// On several `ranks` the trials are split over them ([`simulate_set_on`]); each rank writes
/// its own trials' pixel-event files and rank 0 writes the datasets (and the cache), which are
/// byte-identical to a one-process run's. Collective.
pub fn generate(
    config: &GenerateConfig,
    progress: &dyn Progress,
    ranks: &dyn Ranks,
) -> Result<Generated, DatasetsError> {
    let GenerateConfig {
        set,
        trials,
        seed,
        params,
        out,
        cache,
        ..
    } = config;
    let (set, trials, seed) = (*set, *trials, *seed);
    if trials == 0 {
        return Err(SimulationError::ZeroTrials.into());
    }
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| DatasetsError::Io { path, source }
    };
    std::fs::create_dir_all(out).map_err(io(out))?;
    let cache_file = cache_path(set, trials, seed, params, cache);
    progress.stage(set.name(), (trials * set.textures().len()) as u64);
    let advance = || progress.advance(1);
    let (dataset, from_cache) = match &config.pixel_events {
        None => load_or_simulate_cached(set, trials, seed, params, cache, &advance, ranks)?,
        Some(files) => {
            let names = set.class_names();
            let dir = out.join("events");
            let each = |job: &TrialJob, trial: &SimulatedTrial| {
                let folder = dir.join(format!(
                    "{:02}-{}",
                    job.class,
                    names[job.class].replace(' ', "_")
                ));
                std::fs::create_dir_all(&folder).map_err(io(&folder))?;
                match files {
                    PixelEventFiles::LabelledCsv => {
                        let path = folder.join(format!("{:03}.csv", job.trial));
                        write_events_csv(&path, &trial.events, Some(&trial.labels))
                    }
                    PixelEventFiles::Format(ext) => {
                        let path = folder.join(format!("{:03}.{ext}", job.trial));
                        Ok(neurotac_sensor::format::write_file(&path, &trial.events)?)
                    }
                }
            };
            let simulated = simulate_set_on(set, trials, seed, params, &each, &advance, ranks)?;
            // Cache it too, so experiments find it.
            if ranks.is_root() {
                store(&simulated.dataset, cache, &cache_file)?;
            }
            (simulated.dataset, false)
        }
    };
    progress.finish();
    let binary = out.join(format!("{}.bin", set.name()));
    let root = ranks.is_root();
    if root {
        dataset.save_binary(&binary)?;
    }
    let mut also = Vec::new();
    for &format in &config.also {
        let path = out.join(format!("{}.{}", set.name(), format.extensions()[0]));
        if root {
            let bytes = dataset_bytes(&dataset, format).map_err(io(&path))?;
            neurotac_core::io::write(&path, bytes).map_err(io(&path))?;
        }
        also.push(path);
    }
    let class_means = class_means(&dataset).1;
    Ok(Generated {
        dataset,
        from_cache,
        binary,
        also,
        class_means,
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
    let mut w = neurotac_core::io::AtomicFile::create(path).map_err(io)?;
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
    w.commit().map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::threads::with_threads;

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

    /// Issue 13: simulated sets state their sample duration, and every spike lies inside it.
    #[test]
    fn simulated_sets_state_their_duration() {
        let p = short_params();
        let data = simulate_set(TextureSet::Artificial, 1, 2, &p, &|_, _| Ok(()), &|| {})
            .unwrap()
            .dataset;
        let duration_s = data.duration_s().unwrap();
        assert_eq!(duration_s, sample_duration_s(&p));
        assert!(duration_s >= p.duration_s() && duration_s < p.duration_s() + 1e-3);
        let latest = data
            .observations()
            .iter()
            .filter_map(|o| o.time_range())
            .map(|r| r.1);
        assert!(latest.fold(0.0, f64::max) < duration_s);
        assert_eq!(sample_duration_s(&SimParams::default()), 4.55);
    }
    /// Issue 13: `neurotac simulate`'s generation is a library call.
    #[test]
    fn generate_writes_the_dataset_then_reads_it_from_the_cache() {
        use crate::progress::NoProgress;
        let dir = tempfile::tempdir().unwrap();
        let config = GenerateConfig {
            set: TextureSet::Artificial,
            trials: 1,
            seed: 4,
            params: short_params(),
            out: dir.path().join("out"),
            cache: dir.path().join("cache"),
            also: vec![OutputFormat::Json, OutputFormat::Npz],
            pixel_events: None,
        };
        let first = generate(&config, &NoProgress, &OneProcess).unwrap();
        assert!(!first.from_cache);
        assert_eq!(first.binary, dir.path().join("out/artificial.bin"));
        assert_eq!(SpikeDataset::load(&first.binary).unwrap(), first.dataset);
        assert_eq!(first.also.len(), 2);
        assert!(first.also.iter().all(|p| p.is_file()));
        let npz = std::fs::read(&first.also[1]).unwrap();
        assert_eq!(
            npz,
            crate::export::dataset_npz_bytes(&first.dataset).unwrap()
        );
        assert_eq!(first.class_means.len(), 11);
        let again = generate(&config, &NoProgress, &OneProcess).unwrap();
        assert!(again.from_cache);
        assert_eq!(again.dataset, first.dataset);
        let with_events = GenerateConfig {
            pixel_events: Some(PixelEventFiles::LabelledCsv),
            ..config.clone()
        };
        let made = generate(&with_events, &NoProgress, &OneProcess).unwrap();
        assert!(!made.from_cache);
        assert!(
            dir.path()
                .join("out/events/00-grid_0.0_mm/000.csv")
                .is_file()
        );
        assert_eq!(made.dataset.observations(), first.dataset.observations());
        let zero = GenerateConfig {
            trials: 0,
            ..config
        };
        assert!(matches!(
            generate(&zero, &NoProgress, &OneProcess),
            Err(DatasetsError::Simulation(SimulationError::ZeroTrials))
        ));
    }
}
