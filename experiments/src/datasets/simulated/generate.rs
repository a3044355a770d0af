//! `neurotac simulate`: a simulated set and its files ([`generate`]), optionally every trial's
//! pixel events ([`PixelEventFiles`], [`write_events_csv`]).

use super::cache::{cache_path, load_or_simulate_cached, store, warn_about_cache_once};
use super::{DatasetsError, TextureSet, TrialJob, simulate_set};
use crate::coding::class_means;
use crate::export::{OutputFormat, dataset_bytes};
use crate::progress::Progress;
use neurotac_core::io::AtomicFileSet;
use neurotac_core::{EventBuffer, Ranks, SpikeDataset};
use neurotac_sensor::format::csv_events::CSV_HEADER;
use neurotac_sensor::sim::{EventLabel, SimParams, SimulatedTrial, check_trials};
use std::path::{Path, PathBuf};

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

/// Simulates (or reads from the cache) the dataset of `config` and writes its files into
/// `outputs`, which the caller commits (together with the files of other sets): `<set>.bin`, the
/// forms of [`GenerateConfig::also`], and the folder `events` (shared by the sets of one
/// `outputs`), which thus appears only complete. `progress` sees one stage with one step per
/// simulated trial. Runs on the current rayon pool.
///
/// On several `ranks` the trials are split over them ([`simulate_set`]); each rank writes
/// its own trials' pixel-event files into rank 0's hidden events folder, and rank 0's `outputs`
/// gets the datasets (rank 0 also stores the cache), byte-identical to a one-process run's;
/// the other ranks' `outputs` stay empty. Collective.
pub fn generate(
    config: &GenerateConfig,
    outputs: &mut AtomicFileSet,
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
    check_trials(trials, set.textures().len())?;
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
            let dir = events_folder(&out.join("events"), outputs, ranks)?;
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
                        // The simulator images the pins on a DAVIS240.
                        let sensor = neurotac_sensor::format::DAVIS240_SIZE;
                        Ok(neurotac_sensor::format::write_file(
                            &path,
                            &trial.events,
                            sensor,
                        )?)
                    }
                }
            };
            let simulated = simulate_set(set, trials, seed, params, &each, &advance, ranks)?;
            // Cache it too, so experiments find it; a cache that cannot take it (said before
            // the work by the command) does not lose the simulation.
            if ranks.is_root()
                && let Err(e) = store(&simulated.dataset, cache, &cache_file)
            {
                let e = neurotac_core::error_chain(&e);
                let warning =
                    format!("warning: the dataset could not be cached ({e}); going on without it");
                warn_about_cache_once(cache, &warning);
            }
            (simulated.dataset, false)
        }
    };
    progress.finish();
    let binary = out.join(format!("{}.bin", set.name()));
    let root = ranks.is_root();
    if root {
        outputs
            .write(&binary, dataset.to_binary())
            .map_err(io(&binary))?;
    }
    let mut also = Vec::new();
    for &format in &config.also {
        let path = out.join(format!("{}.{}", set.name(), format.extensions()[0]));
        if root {
            let bytes = dataset_bytes(&dataset, format).map_err(io(&path))?;
            outputs.write(&path, bytes).map_err(io(&path))?;
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

/// The hidden folder the pixel-event files go into: rank 0's member `target` of `outputs`,
/// its path told to every rank.
fn events_folder(
    target: &Path,
    outputs: &mut AtomicFileSet,
    ranks: &dyn Ranks,
) -> Result<PathBuf, DatasetsError> {
    let io = |source| DatasetsError::Io {
        path: target.to_owned(),
        source,
    };
    let partial = match ranks.is_root() {
        true => outputs.dir(target).map_err(io)?.to_path_buf(),
        false => PathBuf::new(),
    };
    if ranks.size() == 1 {
        return Ok(partial);
    }
    let gathered = ranks.all_gather_bytes(partial.to_string_lossy().as_bytes())?;
    Ok(PathBuf::from(
        String::from_utf8_lossy(&gathered[0]).into_owned(),
    ))
}

/// Writes pixel events as CSV (replacing an existing file) through `neurotac_core::io::csv`: a
/// header `t,x,y,on` (t in µs, `on` 1/0), one event per line; with `labels`, a fifth column
/// `pin` (source pin, −1 for noise).
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
    let file =
        neurotac_core::io::AtomicFile::create(path, neurotac_core::io::Replace::Yes).map_err(io)?;
    let mut header = CSV_HEADER.to_vec();
    if labels.is_some() {
        header.push("pin");
    }
    let mut w = neurotac_core::io::csv::writer(file, header).map_err(|e| io(e.into()))?;
    for (i, e) in events.iter().enumerate() {
        let event = (e.t.0, e.x, e.y, u8::from(e.polarity));
        match labels {
            Some(l) => {
                let pin = l[i].pin().map_or(-1, |p| p as i64);
                w.serialize((event.0, event.1, event.2, event.3, pin))
            }
            None => w.serialize(event),
        }
        .map_err(|e| io(e.into()))?;
    }
    let file = w.into_inner().map_err(|e| io(e.into_error()))?;
    file.commit().map_err(io)
}
