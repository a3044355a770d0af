//! Recorded texture datasets: a folder of event files, one sub-folder per texture class,
//! transduced into a taxel [`SpikeDataset`] ([`load_recorded`]).
//!
//! ```text
//! textures/            the dataset folder
//!   cotton/            class `cotton` (classes sorted by folder name → labels 0, 1, …)
//!     trial01.aedat4   one event file per trial (files sorted by name)
//!     trial02.csv
//!     README.txt       ← read as ECD text: keep notes out of class folders or name them .md
//!   denim/
//!     …
//! ```
//!
//! An event file is a file whose extension the sensor crate knows ([`Format::from_extension`]:
//! `.aedat`, `.aedat2`, `.aedat3`, `.aedat4`, `.txt`, `.csv`); its format is then detected from
//! its first bytes, so any AEDAT 2.0/3.1/4.0, ECD text or CSV file is read. Hidden entries
//! (names starting with `.`), files of other extensions (`.json`, `.md`, no extension) and
//! nested folders are skipped, and so are loose files next to the class folders.
//!
//! Each file runs through its own [`Transducer`] (the paper's settings with
//! [`TransductionConfig::default`]: BA filter 5 ms, receptive fields of 6 px diameter (radius 3 px), 20 ms pooling,
//! re-centring), files in parallel (rayon); the result is in file order whatever the thread
//! count. Spike times are seconds since each recording's first event.
//!
//! Sensor size: files state it in their format's way (AEDAT 4.0 `sizeX`/`sizeY`, the camera an
//! AEDAT 2.0 or 3.1 header names, a `# sensor WIDTHxHEIGHT` first line in ECD text and CSV; see
//! [`EventReader::sensor_size`]); every stated size must be the same and equal to the
//! transduction's sensor (`config.width × config.height`). A file that states none: its events
//! must lie inside the transduction's sensor.
//!
//! ```no_run
//! use neurotac_experiments::datasets::recorded::load_recorded;
//! use neurotac_sensor::taxel::{TaxelLayout, TransductionConfig};
//! let recorded = load_recorded(
//!     "textures".as_ref(),
//!     &TaxelLayout::neurotac_default(),
//!     TransductionConfig::default(),
//!     |done, total| eprintln!("{done}/{total}"),
//! )?;
//! println!("{} trials of {} classes", recorded.dataset.len(), recorded.dataset.n_classes());
//! # Ok::<(), neurotac_experiments::datasets::recorded::RecordedError>(())
//! ```

use super::metadata::write_metadata;
use neurotac_core::{DatasetError, EventBuffer, MultiSpikeTrain, SpikeDataset};
use neurotac_sensor::format::{EventReader, Format, open_reader};
use neurotac_sensor::taxel::{TaxelLayout, Transducer, TransductionConfig, TransductionCounts};
use neurotac_sensor::{FormatError, TransductionError};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Why a recorded dataset could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum RecordedError {
    /// The dataset folder does not exist.
    #[error("dataset folder {path} does not exist")]
    Missing {
        /// The folder given.
        path: PathBuf,
    },
    /// The dataset path is not a folder.
    #[error("{path} is not a folder (expected a folder with one sub-folder per texture class)")]
    NotAFolder {
        /// The path given.
        path: PathBuf,
    },
    /// A folder could not be listed.
    #[error("cannot list {path}")]
    List {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The dataset folder holds no class sub-folder.
    #[error("no class sub-folders in {path} (expected one sub-folder of event files per texture)")]
    NoClasses {
        /// The dataset folder.
        path: PathBuf,
    },
    /// Only one class: nothing to classify.
    #[error("only one class (`{class}`) in {path}: a texture dataset needs at least 2")]
    TooFewClasses {
        /// The dataset folder.
        path: PathBuf,
        /// The one class found.
        class: String,
    },
    /// No class folder holds an event file.
    #[error(
        "no event files in any class folder of {path} (expected .aedat, .aedat2, .aedat3, .aedat4, .txt or .csv)"
    )]
    NoEventFiles {
        /// The dataset folder.
        path: PathBuf,
    },
    /// A class folder holds no event file.
    #[error("no event files in {path} (expected .aedat, .aedat2, .aedat3, .aedat4, .txt or .csv)")]
    EmptyClass {
        /// The class folder.
        path: PathBuf,
    },
    /// An event file could not be read (missing permissions, unknown content, corrupt data).
    #[error("reading the event file {path}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What the reader found (boxed: format errors are large).
        source: Box<FormatError>,
    },
    /// An event file holds no event.
    #[error("no events in {path}")]
    NoEvents {
        /// The file.
        path: PathBuf,
    },
    /// The events of a file could not be transduced (e.g. time going backwards).
    #[error("transducing {path}")]
    Transduction {
        /// The file.
        path: PathBuf,
        /// What the transducer refused.
        source: TransductionError,
    },
    /// The transduction settings or the layout are invalid.
    #[error("invalid transduction settings")]
    Config(#[source] TransductionError),
    /// Two files state different sensor sizes.
    #[error(
        "{first} is a {}×{} recording but {other} is {}×{}: every file of a dataset must come from one sensor",
        first_size.0, first_size.1, other_size.0, other_size.1
    )]
    MixedSensorSizes {
        /// The first file stating a size.
        first: PathBuf,
        /// Its size (width, height).
        first_size: (u16, u16),
        /// The first file stating another size.
        other: PathBuf,
        /// That size (width, height).
        other_size: (u16, u16),
    },
    /// The files' stated sensor size is not the transduction's.
    #[error(
        "{path} is a {}×{} recording; the transduction expects a {}×{} sensor",
        size.0, size.1, expected.0, expected.1
    )]
    SensorSizeMismatch {
        /// The first file stating the size.
        path: PathBuf,
        /// Its size (width, height).
        size: (u16, u16),
        /// The transduction's sensor (width, height).
        expected: (u16, u16),
    },
    /// A file without a stated size has events outside the transduction's sensor.
    #[error(
        "{path} has events outside the {}×{} sensor (largest x = {max_x}, y = {max_y}; {dropped} events beyond 240×180 dropped by the reader)",
        sensor.0, sensor.1
    )]
    EventsOutsideSensor {
        /// The file.
        path: PathBuf,
        /// Largest column seen.
        max_x: u16,
        /// Largest row seen.
        max_y: u16,
        /// Events the reader dropped for lying outside 240 × 180.
        dropped: u64,
        /// The transduction's sensor (width, height).
        sensor: (u16, u16),
    },
    /// The spike dataset could not be assembled.
    #[error("assembling the spike dataset")]
    Dataset(#[from] DatasetError),
}

/// What one event file gave.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedFile {
    /// The file.
    pub path: PathBuf,
    /// Its class (index into the dataset's class names).
    pub label: usize,
    /// Pixel events read.
    pub events: u64,
    /// Sensor size `(width, height)` the file states (AEDAT); `None` for text files.
    pub sensor_size: Option<(u16, u16)>,
    /// `(largest x + 1, largest y + 1)` over the events read (`(0, 0)` without events).
    pub extent: (u16, u16),
    /// Time from the first to the last event (µs).
    pub span_us: i64,
    /// What each transduction stage passed.
    pub counts: TransductionCounts,
}

/// A transduced recorded dataset.
#[derive(Debug, Clone)]
pub struct RecordedDataset {
    /// One observation per file (49 taxel spike trains with the default layout), labels and
    /// class names; `meta` holds `source`, the transduction settings and `duration_s` (whole
    /// ms: one ms past the last event of the longest recording), see [`super::metadata`].
    pub dataset: SpikeDataset,
    /// Per file, in dataset order.
    pub files: Vec<RecordedFile>,
}

/// The class folders (sorted by name) and, for each, its event files (sorted by name).
pub fn list_recorded(dir: &Path) -> Result<Vec<(String, Vec<PathBuf>)>, RecordedError> {
    if !dir.exists() {
        return Err(RecordedError::Missing {
            path: dir.to_path_buf(),
        });
    }
    if !dir.is_dir() {
        return Err(RecordedError::NotAFolder {
            path: dir.to_path_buf(),
        });
    }
    let classes = entries(dir, |p| p.is_dir())?;
    match classes.as_slice() {
        [] => {
            return Err(RecordedError::NoClasses {
                path: dir.to_path_buf(),
            });
        }
        [only] => {
            return Err(RecordedError::TooFewClasses {
                path: dir.to_path_buf(),
                class: name_of(only),
            });
        }
        _ => {}
    }
    let listed: Vec<(String, Vec<PathBuf>)> = classes
        .iter()
        .map(|class| {
            let files = entries(class, |p| p.is_file() && Format::from_extension(p).is_ok())?;
            Ok((name_of(class), files))
        })
        .collect::<Result<_, RecordedError>>()?;
    if listed.iter().all(|(_, files)| files.is_empty()) {
        return Err(RecordedError::NoEventFiles {
            path: dir.to_path_buf(),
        });
    }
    if let Some((class, _)) = classes.iter().zip(&listed).find(|(_, l)| l.1.is_empty()) {
        return Err(RecordedError::EmptyClass {
            path: class.clone(),
        });
    }
    Ok(listed)
}

/// The non-hidden entries of a recorded dataset folder that [`list_recorded`] does not read,
/// sorted: files beside the class folders, and in each class folder the sub-folders and the
/// files whose extension is not an event format (`notes.md`, `slide.bag`, …). `reproduce
/// --dataset` lists them so that nothing is skipped without a word.
pub fn skipped_entries(dir: &Path) -> Result<Vec<PathBuf>, RecordedError> {
    let mut skipped = entries(dir, |p| !p.is_dir())?;
    for class in entries(dir, |p| p.is_dir())? {
        skipped.extend(entries(&class, |p| {
            !(p.is_file() && Format::from_extension(p).is_ok())
        })?);
    }
    skipped.sort();
    Ok(skipped)
}

/// The non-hidden entries of `dir` that `keep` accepts, sorted by name.
fn entries(dir: &Path, keep: impl Fn(&Path) -> bool) -> Result<Vec<PathBuf>, RecordedError> {
    let list_error = |source| RecordedError::List {
        path: dir.to_path_buf(),
        source,
    };
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(list_error)? {
        let path = entry.map_err(list_error)?.path();
        let hidden = path
            .file_name()
            .is_some_and(|n| n.as_encoded_bytes().starts_with(b"."));
        if !hidden && keep(&path) {
            out.push(path);
        }
    }
    out.sort_by(|a, b| a.file_name().cmp(&b.file_name()));
    Ok(out)
}

fn name_of(path: &Path) -> String {
    path.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

/// One file's result: its info, and its spike trains unless its stated size is not the
/// transduction's (then it is not transduced; [`check_sizes`] reports it).
type Transduced = (RecordedFile, Option<MultiSpikeTrain>);

/// Reads and transduces one file.
fn transduce_file(
    path: &Path,
    label: usize,
    layout: &TaxelLayout,
    config: TransductionConfig,
) -> Result<Transduced, RecordedError> {
    let read_error = |source| RecordedError::Read {
        path: path.to_path_buf(),
        source: Box::new(source),
    };
    let mut reader = open_reader(path).map_err(read_error)?;
    let sensor = (config.width, config.height);
    let sensor_size = reader.sensor_size();
    let mut file = RecordedFile {
        path: path.to_path_buf(),
        label,
        events: 0,
        sensor_size,
        extent: (0, 0),
        span_us: 0,
        counts: TransductionCounts::default(),
    };
    if sensor_size.is_some_and(|s| s != sensor) {
        return Ok((file, None));
    }
    let mut transducer = Transducer::new(layout, config).map_err(RecordedError::Config)?;
    let (mut first_t, mut last_t) = (None, 0i64);
    let pushed = push_all(reader.as_mut(), &mut transducer, |chunk, reader| {
        let max_x = chunk.x.iter().copied().max().unwrap_or(0);
        let max_y = chunk.y.iter().copied().max().unwrap_or(0);
        file.extent = (
            file.extent.0.max(max_x.saturating_add(1)),
            file.extent.1.max(max_y.saturating_add(1)),
        );
        if file.extent.0 > sensor.0 || file.extent.1 > sensor.1 {
            return Err(outside(&file, reader.stats().out_of_range, sensor));
        }
        first_t.get_or_insert(chunk.t[0]);
        last_t = *chunk.t.last().unwrap_or(&last_t);
        Ok(())
    });
    match pushed {
        Ok(_) => {}
        Err(PushError::Read(source)) => return Err(read_error(source)),
        Err(PushError::Transduction(source)) => {
            return Err(RecordedError::Transduction {
                path: path.to_path_buf(),
                source,
            });
        }
        Err(PushError::Stopped(e)) => return Err(e),
    }
    let stats = reader.stats();
    if sensor_size.is_none() && stats.out_of_range > 0 {
        return Err(outside(&file, stats.out_of_range, sensor));
    }
    file.events = stats.events;
    if file.events == 0 {
        return Err(RecordedError::NoEvents {
            path: path.to_path_buf(),
        });
    }
    file.span_us = first_t.map_or(0, |t0| last_t - t0);
    file.counts = transducer.counts();
    Ok((file, Some(transducer.spike_trains())))
}

/// Why [`push_all`] stopped.
#[derive(Debug)]
pub enum PushError<E> {
    /// The reader failed.
    Read(FormatError),
    /// The transducer refused a chunk.
    Transduction(TransductionError),
    /// `inspect` stopped the loop.
    Stopped(E),
}

/// The read → push loop of a transduction: reads `reader` chunk by chunk, shows each chunk to
/// `inspect` (which may stop the loop with its own error), pushes it through `transducer`, and
/// finishes the transducer at the end of the file. Returns the time spent inside the transducer
/// alone (reading and decoding excluded).
pub fn push_all<E>(
    reader: &mut dyn EventReader,
    transducer: &mut Transducer,
    mut inspect: impl FnMut(&EventBuffer, &dyn EventReader) -> Result<(), E>,
) -> Result<Duration, PushError<E>> {
    let mut chunk = EventBuffer::new();
    let mut transducing = Duration::ZERO;
    while reader.read_chunk(&mut chunk).map_err(PushError::Read)? > 0 {
        inspect(&chunk, &*reader).map_err(PushError::Stopped)?;
        let start = Instant::now();
        transducer.push(&chunk).map_err(PushError::Transduction)?;
        transducing += start.elapsed();
        chunk.clear();
    }
    let start = Instant::now();
    transducer.finish();
    Ok(transducing + start.elapsed())
}

fn outside(file: &RecordedFile, dropped: u64, sensor: (u16, u16)) -> RecordedError {
    RecordedError::EventsOutsideSensor {
        path: file.path.clone(),
        max_x: file.extent.0.saturating_sub(1),
        max_y: file.extent.1.saturating_sub(1),
        dropped,
        sensor,
    }
}

/// Every stated size must be one and the transduction's.
fn check_sizes(files: &[RecordedFile], sensor: (u16, u16)) -> Result<(), RecordedError> {
    let mut stated = files.iter().filter_map(|f| f.sensor_size.map(|s| (f, s)));
    let Some((first, first_size)) = stated.next() else {
        return Ok(());
    };
    if let Some((other, other_size)) = stated.find(|&(_, s)| s != first_size) {
        return Err(RecordedError::MixedSensorSizes {
            first: first.path.clone(),
            first_size,
            other: other.path.clone(),
            other_size,
        });
    }
    if first_size != sensor {
        return Err(RecordedError::SensorSizeMismatch {
            path: first.path.clone(),
            size: first_size,
            expected: sensor,
        });
    }
    Ok(())
}

/// Loads the recorded dataset in `dir` (see the module docs): lists it, transduces every file
/// with `layout` and `config` in parallel, calling `progress(done, total)` after each file, and
/// checks the sensor sizes. The first failing file in dataset order is reported.
pub fn load_recorded(
    dir: &Path,
    layout: &TaxelLayout,
    config: TransductionConfig,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<RecordedDataset, RecordedError> {
    Transducer::new(layout, config).map_err(RecordedError::Config)?;
    let listed = list_recorded(dir)?;
    let jobs: Vec<(usize, &PathBuf)> = listed
        .iter()
        .enumerate()
        .flat_map(|(label, (_, files))| files.iter().map(move |f| (label, f)))
        .collect();
    let total = jobs.len();
    let done = AtomicUsize::new(0);
    let results: Vec<Result<Transduced, RecordedError>> = jobs
        .par_iter()
        .map(|&(label, path)| {
            let result = transduce_file(path, label, layout, config);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            result
        })
        .collect();
    let results: Vec<Transduced> = results.into_iter().collect::<Result<_, _>>()?;
    let (files, trains): (Vec<RecordedFile>, Vec<Option<MultiSpikeTrain>>) =
        results.into_iter().unzip();
    check_sizes(&files, (config.width, config.height))?;
    // After `check_sizes`, every file was transduced.
    let observations: Vec<MultiSpikeTrain> = trains.into_iter().flatten().collect();
    let longest_us = files.iter().map(|f| f.span_us).max().unwrap_or(0);
    let mut meta = serde_json::Map::new();
    meta.insert("source".into(), dir.display().to_string().into());
    // One ms past the ms bin of the latest event: no spike (a mean event time) lies beyond.
    let duration_s = neurotac_core::time::us_to_s((longest_us / 1000 + 1) * 1000);
    write_metadata(&mut meta, &config, Some(duration_s));
    let labels = files.iter().map(|f| f.label).collect();
    let names = listed.into_iter().map(|(name, _)| name).collect();
    let dataset = SpikeDataset::new(observations, labels, names, meta)?;
    Ok(RecordedDataset { dataset, files })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skipped_entries_names_every_file_that_is_not_read() {
        let dir = tempfile::tempdir().unwrap();
        for class in ["a", "b"] {
            std::fs::create_dir(dir.path().join(class)).unwrap();
            std::fs::write(dir.path().join(class).join("0.csv"), "").unwrap();
        }
        std::fs::write(dir.path().join("README.md"), "").unwrap();
        std::fs::write(dir.path().join("a/notes.md"), "").unwrap();
        std::fs::write(dir.path().join("b/.hidden"), "").unwrap();
        std::fs::create_dir(dir.path().join("b/extra")).unwrap();
        let skipped = skipped_entries(dir.path()).unwrap();
        let names: Vec<String> = skipped
            .iter()
            .map(|p| {
                let rel = p.strip_prefix(dir.path()).unwrap();
                rel.to_string_lossy().into_owned()
            })
            .collect();
        assert_eq!(names, ["README.md", "a/notes.md", "b/extra"]);
    }
}
