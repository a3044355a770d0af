//! A whole reproduction ([`run`]): each [`Source`] → taxel spike dataset → [`run_set`] (and the
//! afferent variant when asked) → one [`Report`], ready for the report folder (`neurotac_cli::report::write_report`).

use super::confusions::{LooAnalysis, loo_analysis};
use super::paper;
use super::phases::Phases;
use super::{PipelineConfig, SetResult, run_encoded};
use crate::afferents::AfferentConfig;
use crate::coding::CodingName;
use crate::datasets::recorded::{RecordedError, list_recorded, load_recorded, skipped_entries};
use crate::datasets::simulated::{DatasetsError, TextureSet, load_or_simulate};
use crate::error::ExperimentError;
use crate::progress::Progress;
use crate::readouts::{EncodedSet, encode_through_graph};
use crate::timing::{Timing, timed};
use neurotac_core::{MultiSpikeTrain, Ranks, SpikeDataset};
use neurotac_sensor::filter::MapStart;
use neurotac_sensor::sim::{CalibratedParameter, SimParams, check_trials};
use neurotac_sensor::taxel::{TaxelLayout, TransductionConfig};
use serde::Serialize;
use std::path::PathBuf;

/// A set to run: the bundled simulated texture set, or a recorded dataset folder (one
/// sub-folder of event files per class, see [`crate::datasets::recorded`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// A simulated set ([`crate::datasets::simulated`]), read from the cache when there.
    Simulated(TextureSet),
    /// A recorded dataset folder.
    Recorded(PathBuf),
}

/// Everything a reproduction needs besides its sources.
#[derive(Debug, Clone, PartialEq)]
pub struct ReproduceConfig {
    /// The pipeline (KNN, Δt sweep, Bayesian optimisation, split).
    pub pipeline: PipelineConfig,
    /// Seed of the simulated datasets (the pipeline's seeds are in `pipeline`).
    pub seed: u64,
    /// Slides per texture of the simulated sets; `None`: the paper's (100 / 50).
    pub trials: Option<usize>,
    /// Simulator parameters.
    pub params: SimParams,
    /// Cache folder of simulated datasets.
    pub cache: PathBuf,
    /// Also run every set through afferent neurons.
    pub afferents: Option<AfferentConfig>,
    /// `true` for a reduced run ([`ReproduceConfig::quick`]): its tables are not comparable
    /// with the paper's.
    pub quick: bool,
    /// Mountings each simulated set is run on (≥ 1): the set as simulated (mounting 0) and
    /// `mountings − 1` copies with every texture mounted afresh (`kinematics.mounting`), each
    /// through the pipeline, so every coding's accuracy comes with its spread over mountings.
    pub mountings: usize,
    /// The command line recorded in the report (e.g. `neurotac reproduce --quick`).
    pub command: String,
}

impl ReproduceConfig {
    /// The paper's protocol ([`PipelineConfig::paper`]) on the paper's slide counts, simulated
    /// datasets cached in `cache`.
    pub fn paper(seed: u64, cache: PathBuf) -> Self {
        Self {
            pipeline: PipelineConfig::paper(seed),
            seed,
            trials: None,
            params: SimParams::default(),
            cache,
            afferents: None,
            quick: false,
            mountings: 1,
            command: String::new(),
        }
    }

    /// A first look in under a minute: 10 slides per texture, 60 epochs, τ on a 10 ms grid.
    pub fn quick(seed: u64, cache: PathBuf) -> Self {
        let mut c = Self::paper(seed, cache);
        c.pipeline.bayes.epochs = 60;
        c.pipeline.bayes.tau_step_s = 0.01;
        c.trials = Some(10);
        c.quick = true;
        c
    }
}

/// Why a reproduction stopped.
#[derive(Debug, thiserror::Error)]
pub enum ReproduceError {
    /// A simulated dataset could not be built.
    #[error("building the {set} dataset")]
    Simulated {
        /// The set.
        set: &'static str,
        /// Why.
        source: DatasetsError,
    },
    /// A recorded dataset could not be loaded.
    #[error(transparent)]
    Recorded(#[from] RecordedError),
    /// The pipeline failed on a set.
    #[error("running the pipeline on the {name} {what}")]
    Pipeline {
        /// The set.
        name: String,
        /// `set` or `afferents`.
        what: &'static str,
        /// Why (boxed: experiment errors are large).
        source: Box<ExperimentError>,
    },
    /// The readout network (with or without afferents) failed.
    #[error("running the readout network")]
    Afferents(#[source] Box<ExperimentError>),
    /// The pipeline's settings are refused before any dataset is built.
    #[error("the pipeline's settings")]
    Settings(#[source] Box<ExperimentError>),
    /// No mounting to run a simulated set on.
    #[error("a simulated set runs on at least one mounting (mountings = 0)")]
    NoMountings,
}

/// The afferent-network variant of one set.
#[derive(Debug, Clone, Serialize)]
pub struct AfferentRun {
    /// `lif` or `izhikevich`.
    pub model: String,
    /// Synaptic weight, synaptic τ (s) and step (s) used.
    pub weight: f64,
    /// Synaptic time constant (s).
    pub tau_syn_s: f64,
    /// Network time step (s).
    pub dt_s: f64,
    /// Time to run every sample through the network (taxel input → afferents → coding
    /// readouts).
    pub network_time: Timing,
    /// The pipeline on the afferents' spikes.
    pub result: SetResult,
}

/// One set: where its data came from, the direct pipeline, and the afferent variant if run.
#[derive(Debug, Clone, Serialize)]
pub struct SetReport {
    /// `simulated (…)` or the recorded dataset's folder.
    pub source: String,
    /// Time to build or load the taxel spike dataset.
    pub dataset_time: Timing,
    /// Time to run every sample through the readout network (taxel input → coding readouts).
    pub readout_time: Timing,
    /// Taxel spikes → codings (the paper's pipeline).
    pub direct: SetResult,
    /// The share of the taxel spikes in each slide phase, per class (simulated sets only).
    pub phases: Phases,
    /// The direct pipeline's leave-one-out predictions class by class: recall, and the
    /// confusions the paper names.
    pub loo_analysis: LooAnalysis,
    /// Taxel spikes → afferent neurons → codings.
    pub afferent: Option<AfferentRun>,
    /// The set on each mounting ([`ReproduceConfig::mountings`]; the first is `direct`);
    /// empty for one mounting or a recorded set.
    pub mountings: Vec<MountingRun>,
    /// A reduced run ([`ReproduceConfig::quick`]): its tables are not comparable with the
    /// paper's.
    pub quick: bool,
    /// One sample of each class shown in the spike-train figure: `(class name, sample)`.
    #[serde(skip)]
    pub examples: Vec<(String, MultiSpikeTrain)>,
}

/// A simulated set on one mounting through the pipeline: where the rig put each texture (its
/// lateral offset, phase and specimen friction) changed, nothing else.
#[derive(Debug, Clone, Serialize)]
pub struct MountingRun {
    /// The mounting (`kinematics.mounting`; 0 is the set as simulated).
    pub mounting: u64,
    /// Mean spikes per taxel.
    pub mean_spikes_per_taxel: f64,
    /// Each coding's leave-one-out accuracy (a fraction) and chosen parameters, in the menu's
    /// order.
    pub codings: Vec<(CodingName, f64, String)>,
}

impl MountingRun {
    fn of(mounting: u64, result: &SetResult) -> Self {
        Self {
            mounting,
            mean_spikes_per_taxel: result.mean_spikes_per_taxel,
            codings: result
                .codings
                .iter()
                .map(|c| (c.coding, c.loo.accuracy.mean, c.parameters.clone()))
                .collect(),
        }
    }
}

/// A whole run.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// The command line.
    pub command: String,
    /// neurotac's version.
    pub version: String,
    /// Seed of the datasets, the split and the search.
    pub seed: u64,
    /// The sets, in run order.
    pub sets: Vec<SetReport>,
    /// The simulator's calibrated parameters ([`SimParams::calibrated_parameters`]) when a set
    /// is simulated, else empty: the only numbers fitted to the paper, each to one of its
    /// three intensive means. Every accuracy, confusion matrix and chosen Δt / τ / cos θ is a
    /// held-out prediction.
    pub calibration: Vec<CalibratedParameter>,
    /// Wall and CPU time of the datasets and pipelines (writing the report not included).
    pub time: Timing,
}

/// Runs the paper's pipeline on every source in order (on the current rayon pool) and gathers
/// the report. `progress` sees every long stage, and one note per dataset ready.
///
/// Split over `ranks` (`&OneProcess` for one process): the simulated datasets
/// ([`load_or_simulate`]), the distance matrices and the searches
/// ([`run_encoded`](super::run_encoded)) are computed by all ranks together, and every
/// rank returns the one-process report (timings aside). The readout and afferent networks
/// and the transduction of recorded datasets run on every rank alike. Nothing is written but
/// the dataset cache, by rank 0. Collective: every rank must call it.
pub fn run(
    config: &ReproduceConfig,
    sources: &[Source],
    progress: &dyn Progress,
    ranks: &dyn Ranks,
) -> Result<Report, ReproduceError> {
    // Slide counts and searches the settings cannot hold are refused before any dataset is
    // simulated.
    for source in sources {
        if let (Source::Simulated(set), Some(trials)) = (source, config.trials) {
            check_trials(trials, set.textures().len()).map_err(|e| ReproduceError::Simulated {
                set: set.name(),
                source: e.into(),
            })?;
        }
    }
    crate::search::bayes::check(&config.pipeline.bayes)
        .map_err(|e| ReproduceError::Settings(Box::new(e)))?;
    if config.mountings == 0 {
        return Err(ReproduceError::NoMountings);
    }
    let (sets, time) = timed(|| {
        sources
            .iter()
            .map(|source| run_source(source, config, progress, ranks))
            .collect::<Result<Vec<_>, _>>()
    });
    Ok(Report {
        command: config.command.clone(),
        version: env!("CARGO_PKG_VERSION").to_owned(),
        seed: config.seed,
        sets: sets?,
        calibration: match sources.iter().any(|s| matches!(s, Source::Simulated(_))) {
            true => config.params.calibrated_parameters().to_vec(),
            false => Vec::new(),
        },
        time,
    })
}

/// The taxel spike dataset of `source` as [`run`] builds it (simulated sets from the cache
/// or simulated, recorded folders transduced), its name, how it was made and its slide phases.
/// Collective: every rank must call it.
pub fn load_source(
    source: &Source,
    config: &ReproduceConfig,
    progress: &dyn Progress,
    ranks: &dyn Ranks,
) -> Result<(String, String, SpikeDataset, Phases), ReproduceError> {
    match source {
        Source::Simulated(set) => {
            let trials = config.trials.unwrap_or(set.paper_trials());
            progress.stage(
                &format!("{} set: simulating or loading", set.name()),
                (trials * set.textures().len()) as u64,
            );
            let (seed, cache) = (config.seed, &config.cache);
            let advance = || progress.advance(1);
            let data = load_or_simulate(*set, trials, seed, &config.params, cache, &advance, ranks)
                .map_err(|source| ReproduceError::Simulated {
                    set: set.name(),
                    source,
                })?;
            progress.finish();
            let how = format!(
                "simulated, {trials} slides per texture, seed {seed}, cache {}",
                cache.display()
            );
            let phases = Phases::of_simulated(&data, &config.params);
            Ok((set.name().to_owned(), how, data, phases))
        }
        Source::Recorded(dir) => {
            let name = dir
                .canonicalize()
                .ok()
                .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
                .unwrap_or_else(|| "recorded".into());
            let files: usize = list_recorded(dir)?.iter().map(|(_, f)| f.len()).sum();
            let skipped = skipped_entries(dir)?;
            if !skipped.is_empty() {
                let shown: Vec<String> = skipped
                    .iter()
                    .take(20)
                    .map(|p| p.strip_prefix(dir).unwrap_or(p).display().to_string())
                    .collect();
                let more = match skipped.len().saturating_sub(shown.len()) {
                    0 => String::new(),
                    n => format!(", and {n} more"),
                };
                progress.note(&format!(
                    "{name}: skipped {} entries that are not event files in a class folder \
                     (read: .aedat .aedat3 .aedat4 .txt .csv): {}{more}",
                    skipped.len(),
                    shown.join(", ")
                ));
            }
            progress.stage(&format!("{name}: transducing event files"), files as u64);
            // The paper's transduction; the BA map starts empty, so a recording's first
            // events are judged like any others whatever its time origin.
            let transduction = TransductionConfig {
                ba_start: MapStart::Empty,
                ..TransductionConfig::default()
            };
            let layout = TaxelLayout::neurotac_default();
            let recorded = load_recorded(dir, &layout, transduction, |_, _| progress.advance(1))?;
            progress.finish();
            Ok((
                name,
                format!("recorded, {}", dir.display()),
                recorded.dataset,
                Phases::recorded(),
            ))
        }
    }
}

/// One source through the pipeline (and the afferent variant when asked).
fn run_source(
    source: &Source,
    config: &ReproduceConfig,
    progress: &dyn Progress,
    ranks: &dyn Ranks,
) -> Result<SetReport, ReproduceError> {
    let (loaded, dataset_time) = timed(|| load_source(source, config, progress, ranks));
    let (name, source_text, data, phases) = loaded?;
    progress.note(&format!(
        "{name}: {} samples, {} classes, dataset ready in {:.1} s",
        data.len(),
        data.n_classes(),
        dataset_time.wall_s
    ));
    let vr_from = config.pipeline.vr_from;
    let through_graph = |afferents: Option<AfferentConfig>, what: &str| {
        progress.stage(
            &format!("{name}: {what} network (taxel input → coding readouts)"),
            data.len() as u64,
        );
        let out = timed(|| {
            encode_through_graph(&data, afferents, vr_from, &|| progress.advance(1))
                .map_err(|e| ReproduceError::Afferents(Box::new(e)))
        });
        progress.finish();
        out
    };
    let pipeline = |set: &EncodedSet, what: &'static str| {
        run_encoded(&name, set, &config.pipeline, progress, ranks).map_err(|source| {
            ReproduceError::Pipeline {
                name: name.clone(),
                what,
                source: Box::new(source),
            }
        })
    };
    let (encoded, readout_time) = through_graph(None, "readout");
    let direct = pipeline(&(encoded?), "set")?;
    let mut mountings = Vec::new();
    if config.mountings > 1 && matches!(source, Source::Simulated(_)) {
        mountings.push(MountingRun::of(0, &direct));
        for mounting in 1..config.mountings as u64 {
            let mut remounted = config.clone();
            remounted.params.kinematics.mounting = mounting;
            let (_, _, data, _) = load_source(source, &remounted, progress, ranks)?;
            progress.stage(
                &format!("{name}: mounting {mounting} network (taxel input → coding readouts)"),
                data.len() as u64,
            );
            let encoded = encode_through_graph(&data, None, vr_from, &|| progress.advance(1))
                .map_err(|e| ReproduceError::Afferents(Box::new(e)))?;
            progress.finish();
            let name = format!("{name} (mounting {mounting})");
            let result = run_encoded(&name, &encoded, &config.pipeline, progress, ranks).map_err(
                |source| ReproduceError::Pipeline {
                    name: name.clone(),
                    what: "set",
                    source: Box::new(source),
                },
            )?;
            mountings.push(MountingRun::of(mounting, &result));
        }
    }
    let afferent = match config.afferents {
        None => None,
        Some(a) => {
            let (encoded, network_time) = through_graph(Some(a), "afferent");
            Some(AfferentRun {
                model: a.model.to_string(),
                weight: a.weight,
                tau_syn_s: a.tau_syn_s,
                dt_s: a.dt_s,
                network_time,
                result: pipeline(&encoded?, "afferents")?,
            })
        }
    };
    Ok(SetReport {
        source: source_text,
        dataset_time,
        readout_time,
        examples: example_samples(&data),
        phases,
        loo_analysis: loo_analysis(&direct),
        direct,
        afferent,
        mountings,
        quick: config.quick,
    })
}

/// The samples to draw in the spike-train figure: the first sample of the 0, 2.5 and 5 mm
/// grids when the set has them (the paper's figure), else of the first, middle and last class.
pub fn example_samples(data: &SpikeDataset) -> Vec<(String, MultiSpikeTrain)> {
    let names = data.class_names();
    let wanted: Vec<usize> = {
        let grids: Vec<usize> = paper::INTENSIVE_MEANS
            .iter()
            .filter_map(|&(mm, _)| names.iter().position(|n| *n == paper::grid_name(mm)))
            .collect();
        if grids.len() == 3 {
            grids
        } else {
            let n = data.n_classes();
            let mut v = vec![0, n / 2, n.saturating_sub(1)];
            v.dedup();
            v
        }
    };
    wanted
        .into_iter()
        .filter_map(|c| {
            let i = data.labels().iter().position(|&l| l == c)?;
            Some((names[c].clone(), data.observations()[i].clone()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
    use crate::progress::NoProgress;
    use neurotac_sensor::sim::SimulationError;

    /// A recorded-style folder is not needed to test the assembly: a missing folder is a
    /// typed error, and a slide count outside the budget is refused before any work.
    #[test]
    fn bad_sources_and_slide_counts_are_typed_errors() {
        let dir = tempfile::tempdir().unwrap();
        let mut config = ReproduceConfig::quick(1, dir.path().join("cache"));
        let missing = Source::Recorded(dir.path().join("nope"));
        assert!(matches!(
            run(&config, &[missing], &NoProgress, &neurotac_core::OneProcess),
            Err(ReproduceError::Recorded(RecordedError::Missing { .. }))
        ));
        // Zero slides, or more than the trial budget, are refused before anything is simulated.
        let simulated = [Source::Simulated(TextureSet::Artificial)];
        for (trials, expected) in [
            (0, SimulationError::ZeroTrials),
            (
                10usize.pow(15),
                SimulationError::TooManyTrials {
                    trials: 10usize.pow(15),
                    textures: 11,
                    limit: neurotac_sensor::sim::MAX_TRIALS,
                },
            ),
        ] {
            config.trials = Some(trials);
            match run(&config, &simulated, &NoProgress, &neurotac_core::OneProcess) {
                Err(ReproduceError::Simulated {
                    source: DatasetsError::Simulation(e),
                    ..
                }) => assert_eq!(e.to_string(), expected.to_string()),
                other => panic!("{trials}: {other:?}"),
            }
        }
    }

    #[test]
    fn quick_is_the_paper_protocol_reduced() {
        let paper = ReproduceConfig::paper(3, "c".into());
        let quick = ReproduceConfig::quick(3, "c".into());
        assert_eq!((paper.trials, paper.pipeline.bayes.epochs), (None, 1000));
        assert_eq!((quick.trials, quick.pipeline.bayes.epochs), (Some(10), 60));
        assert!(quick.quick && !paper.quick);
        assert_eq!(quick.pipeline.k, paper.pipeline.k);
    }

    #[test]
    fn examples_are_the_papers_grids_or_first_middle_last() {
        let data = synthetic_dataset(&SyntheticConfig {
            samples: 10,
            classes: 5,
            channels: 2,
            ..SyntheticConfig::default()
        });
        let names: Vec<String> = example_samples(&data).into_iter().map(|e| e.0).collect();
        assert_eq!(names, ["texture 0", "texture 2", "texture 4"]);
    }
}
