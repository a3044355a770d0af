//! `neurotac reproduce`: the NeuroTac paper end to end — datasets, transduction, the four
//! codings, the Δt sweep, the Bayesian optimisation, KNN tables against the paper's, and a
//! report folder with its figures (see `neurotac_experiments::reproduce`).

use anyhow::Context;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use neurotac_core::SpikeDataset;
use neurotac_experiments::afferents::{AfferentConfig, AfferentModel, afferent_dataset};
use neurotac_experiments::bench::with_threads;
use neurotac_experiments::datasets::{TextureSet, load_or_simulate_with};
use neurotac_experiments::recorded::{list_recorded, load_recorded};
use neurotac_experiments::reproduce::report::{
    AfferentRun, Report, SetReport, accuracy_table, afferent_table, check_destination,
    example_samples, parameter_table, write_report,
};
use neurotac_experiments::reproduce::{PipelineConfig, Progress, run_set};
use neurotac_experiments::timing::timed;
use neurotac_sensor::filter::MapStart;
use neurotac_sensor::sim::SimParams;
use neurotac_sensor::taxel::{TaxelLayout, TransductionConfig};
use std::path::PathBuf;
use std::sync::Mutex;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SetArg {
    /// The 11 bump grids (paper: 100 slides each; Table 1).
    Artificial,
    /// The 20 natural textures (paper: 50 slides each; Table 2).
    Natural,
    /// Both, artificial first.
    Both,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum AfferentArg {
    /// Leaky integrate-and-fire afferents (weight 5, exact integrator).
    Lif,
    /// Izhikevich regular-spiking afferents (weight 20, Izhikevich's 2003 scheme).
    Izhikevich,
}

#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Which simulated texture set(s) to run.
    #[arg(long, value_enum, default_value = "both")]
    set: SetArg,
    /// Seed of the simulated datasets, the 80/20 split and the optimisation's initial design.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Report folder (refused if it exists, unless --force).
    #[arg(long, default_value = "neurotac-report")]
    out: PathBuf,
    /// Worker threads (0: all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Bayesian-optimisation evaluations (paper: 1000; --quick: 60).
    #[arg(long)]
    epochs: Option<usize>,
    /// Slides per texture (paper: 100 artificial, 50 natural; --quick: 10).
    #[arg(long)]
    trials: Option<usize>,
    /// Run on a recorded dataset instead: one folder per texture class, one event file per
    /// slide (AEDAT 2/3.1/4, ECD text or CSV); --set, --trials and --params then do not apply.
    #[arg(long)]
    dataset: Option<PathBuf>,
    /// Replace an existing report folder.
    #[arg(long)]
    force: bool,
    /// A first look in under a minute: 10 slides per texture, 60 epochs, τ on a 10 ms grid.
    #[arg(long)]
    quick: bool,
    /// Also run the pipeline through a population of afferent neurons (one per taxel) and
    /// report accuracy and time next to the direct pipeline.
    #[arg(long, value_enum)]
    afferents: Option<AfferentArg>,
    /// τ grid step of the optimisation (s; default 0.005, --quick 0.01; the paper's 1 ms grid
    /// costs ≈ 5× the default).
    #[arg(long)]
    tau_step: Option<f64>,
    /// Cache of simulated datasets (default: $NEUROTAC_CACHE, else $XDG_CACHE_HOME/neurotac,
    /// else ~/.cache/neurotac).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Simulator parameters (JSON, see `neurotac simulate params`); default: the calibrated ones.
    #[arg(long)]
    params: Option<PathBuf>,
}

/// Progress bars on stderr (hidden when stderr is not a terminal).
struct Bars(Mutex<Option<ProgressBar>>);

impl Bars {
    fn new() -> Self {
        Self(Mutex::new(None))
    }

    fn bar(&self) -> Option<ProgressBar> {
        self.0.lock().expect("progress lock").clone()
    }
}

impl Progress for Bars {
    fn stage(&self, name: &str, total: u64) {
        let bar = if total == 0 {
            let b = ProgressBar::new_spinner();
            b.set_style(
                ProgressStyle::with_template("  {spinner} {msg} [{elapsed_precise}]")
                    .expect("valid template"),
            );
            b.enable_steady_tick(std::time::Duration::from_millis(120));
            b
        } else {
            let b = ProgressBar::new(total);
            b.set_style(
                ProgressStyle::with_template(
                    "  {msg} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
                )
                .expect("valid template"),
            );
            b
        };
        bar.set_message(name.to_owned());
        if let Some(old) = self.0.lock().expect("progress lock").replace(bar) {
            old.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(b) = self.bar() {
            b.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(b) = self.0.lock().expect("progress lock").take() {
            b.finish_and_clear();
        }
    }
}

fn default_cache() -> PathBuf {
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

/// A set to run: its name, where it comes from, and how to get it.
enum Source {
    Simulated(TextureSet),
    Recorded(PathBuf),
}

pub fn run(args: ReproduceArgs) -> anyhow::Result<()> {
    check_destination(&args.out, args.force)?;
    let command = std::iter::once("neurotac".to_owned())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let mut config = PipelineConfig::paper(args.seed);
    if args.quick {
        config.bayes.epochs = 60;
        config.bayes.tau_step_s = 0.01;
    }
    if let Some(e) = args.epochs {
        config.bayes.epochs = e;
    }
    if let Some(s) = args.tau_step {
        config.bayes.tau_step_s = s;
    }
    let trials = match (args.trials, args.quick) {
        (Some(0), _) => anyhow::bail!("--trials 0: at least one slide per texture is needed"),
        (Some(t), _) => Some(t),
        (None, true) => Some(10),
        (None, false) => None,
    };
    let sources: Vec<Source> = match &args.dataset {
        Some(dir) => vec![Source::Recorded(dir.clone())],
        None => match args.set {
            SetArg::Artificial => vec![Source::Simulated(TextureSet::Artificial)],
            SetArg::Natural => vec![Source::Simulated(TextureSet::Natural)],
            SetArg::Both => vec![
                Source::Simulated(TextureSet::Artificial),
                Source::Simulated(TextureSet::Natural),
            ],
        },
    };
    let params = match &args.params {
        Some(p) => SimParams::from_json_file(p)?,
        None => SimParams::default(),
    };
    let cache = args.cache.clone().unwrap_or_else(default_cache);
    let afferents = args.afferents.map(|a| match a {
        AfferentArg::Lif => AfferentConfig::lif(),
        AfferentArg::Izhikevich => AfferentConfig::izhikevich(),
    });
    let context = RunContext {
        trials,
        seed: args.seed,
        params,
        cache,
        config,
        afferents,
        bars: Bars::new(),
    };
    let (written, total) = timed(|| -> anyhow::Result<()> {
        let (sets, time) = timed(|| {
            with_threads(args.threads, || -> anyhow::Result<Vec<SetReport>> {
                let mut sets = Vec::new();
                for source in &sources {
                    let set = run_source(source, &context)?;
                    print_set(&set);
                    sets.push(set);
                }
                Ok(sets)
            })
        });
        let report = Report {
            command,
            version: env!("CARGO_PKG_VERSION").to_owned(),
            seed: args.seed,
            sets: sets??,
            time,
        };
        context
            .bars
            .stage("writing the report (SVG, PNG, CSV, JSON, Markdown)", 0);
        let written = write_report(&args.out, &report, args.force);
        context.bars.finish();
        Ok(written?)
    });
    written?;
    println!(
        "report: {} (report.md, report.json, CSV tables, SVG and PNG figures)",
        args.out.display()
    );
    println!("total: {total}");
    Ok(())
}

/// What every set of a run shares.
struct RunContext {
    /// Slides per texture (`None`: the paper's).
    trials: Option<usize>,
    seed: u64,
    params: SimParams,
    cache: PathBuf,
    config: PipelineConfig,
    afferents: Option<AfferentConfig>,
    bars: Bars,
}

fn run_source(source: &Source, context: &RunContext) -> anyhow::Result<SetReport> {
    let RunContext {
        trials,
        seed,
        params,
        cache,
        config,
        afferents,
        bars,
    } = context;
    let (trials, seed, afferents) = (*trials, *seed, *afferents);
    let (loaded, dataset_time) = timed(|| -> anyhow::Result<(String, String, SpikeDataset)> {
        match source {
            Source::Simulated(set) => {
                let trials = trials.unwrap_or(set.paper_trials());
                bars.stage(
                    &format!("{} set: simulating or loading", set.name()),
                    (trials * set.textures().len()) as u64,
                );
                let data =
                    load_or_simulate_with(*set, trials, seed, params, cache, &|| bars.advance(1))
                        .with_context(|| format!("building the {} dataset", set.name()))?;
                bars.finish();
                Ok((
                    set.name().to_owned(),
                    format!(
                        "simulated, {trials} slides per texture, seed {seed}, cache {}",
                        cache.display()
                    ),
                    data,
                ))
            }
            Source::Recorded(dir) => {
                let name = dir
                    .canonicalize()
                    .ok()
                    .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
                    .unwrap_or_else(|| "recorded".into());
                let files: usize = list_recorded(dir)?.iter().map(|(_, f)| f.len()).sum();
                bars.stage(&format!("{name}: transducing event files"), files as u64);
                // The paper's transduction; the BA map starts empty, so a recording's first
                // events are judged like any others whatever its time origin.
                let config = TransductionConfig {
                    ba_start: MapStart::Empty,
                    ..TransductionConfig::default()
                };
                let recorded =
                    load_recorded(dir, &TaxelLayout::neurotac_default(), config, |_, _| {
                        bars.advance(1)
                    })?;
                bars.finish();
                Ok((
                    name,
                    format!("recorded, {}", dir.display()),
                    recorded.dataset,
                ))
            }
        }
    });
    let (name, source_text, data) = loaded?;
    eprintln!(
        "{name}: {} samples, {} classes, dataset ready in {:.1} s",
        data.len(),
        data.n_classes(),
        dataset_time.wall_s
    );
    let direct = run_set(&name, &data, config, bars)
        .with_context(|| format!("running the pipeline on the {name} set"))?;
    let afferent = match afferents {
        None => None,
        Some(a) => {
            let duration_s = direct.duration_ms as f64 * 1e-3 + 0.05;
            bars.stage(&format!("{name}: afferent network"), data.len() as u64);
            let (spikes, network_time) =
                timed(|| afferent_dataset(&data, duration_s, a, &|| bars.advance(1)));
            let spikes = spikes.context("running the afferent network")?;
            bars.finish();
            let result = run_set(&name, &spikes, config, bars)
                .with_context(|| format!("running the pipeline on the {name} afferents"))?;
            Some(AfferentRun {
                model: match a.model {
                    AfferentModel::Lif => "lif".into(),
                    AfferentModel::Izhikevich => "izhikevich".into(),
                },
                weight: a.weight,
                tau_syn_s: a.tau_syn_s,
                dt_s: a.dt_s,
                network_time,
                result,
            })
        }
    };
    Ok(SetReport {
        source: source_text,
        dataset_time,
        examples: example_samples(&data),
        direct,
        afferent,
    })
}

fn print_set(set: &SetReport) {
    let d = &set.direct;
    let samples: usize = d.samples_per_class.iter().sum();
    println!(
        "\n{} set — {} classes × {} samples ({}), {:.2} spikes per taxel; pipeline {:.1} s",
        d.name,
        d.class_names.len(),
        samples,
        set.source,
        d.mean_spikes_per_taxel,
        d.time.wall_s
    );
    println!("{}", accuracy_table(set));
    println!("{}", parameter_table(d));
    if let Some(why) = d.codings.iter().find_map(|c| c.split_refused.as_ref()) {
        println!("80/20 split refused: {why}\n");
    }
    if set.afferent.is_some() {
        println!("{}", afferent_table(set));
    }
}
