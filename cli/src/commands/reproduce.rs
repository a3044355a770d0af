//! `neurotac reproduce`: the NeuroTac paper end to end — datasets, transduction, the four
//! codings, the Δt sweep, the Bayesian optimisation, KNN tables against the paper's, and a
//! report folder with its figures (see `neurotac_experiments::reproduce`).

use super::options::{ForceOption, SeedOption, SetsOption, ThreadsOption, help};
use super::outputs::{Output, cache_folder, check_outputs, refuse_report_over_inputs};
use super::progress::Bars;
use crate::commands::args::{self, Time};
use clap::{Args, ValueEnum};
use neurotac_cli::report::class_tables::{paper_confusion_table, phase_table, recall_table};
use neurotac_cli::report::mountings::mounting_table;
use neurotac_cli::report::tables::{
    accuracy_table, afferent_table, fitted_grids_mm, intensive_table, parameter_table,
};
use neurotac_cli::report::write_report;
use neurotac_core::Ranks;
use neurotac_experiments::afferents::AfferentConfig;
use neurotac_experiments::neuron_setup::NeuronKind;
use neurotac_experiments::neuron_setup::Precision;
use neurotac_experiments::progress::{NoProgress, Progress};
use neurotac_experiments::readouts::VrFrom;
use neurotac_experiments::reproduce::{self, ReproduceConfig, SetReport, Source};
use neurotac_experiments::threads::with_threads;
use neurotac_experiments::timing::timed;
use neurotac_sensor::sim::SimParams;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum VrFromArg {
    /// The exact distance from the spatiotemporal readout's spike trains (the paper's).
    Exact,
    /// The distance of the readout's synaptic traces sampled at --trace-dt (memory: one entry
    /// per step with a spike).
    Traces,
}

#[derive(Debug, Args)]
#[command(
    mut_args(help(
        "seed",
        "Seed of the simulated datasets, the 80/20 split and the optimisation's initial design"
    )),
    mut_args(help("threads", "Worker threads (0: all cores)")),
    mut_args(help("force", "Replace an existing report folder"))
)]
pub struct ReproduceArgs {
    #[command(flatten)]
    set: SetsOption,
    #[command(flatten)]
    seed: SeedOption,
    /// Report folder (refused if it exists, unless --force).
    #[arg(long, default_value = "neurotac-report")]
    out: PathBuf,
    #[command(flatten)]
    threads: ThreadsOption,
    /// Bayesian-optimisation evaluations (paper: 1000; --quick: 60).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    epochs: Option<usize>,
    /// Slides per texture (paper: 100 artificial, 50 natural; --quick: 10).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    trials: Option<usize>,
    /// Run on a recorded dataset instead: one folder per texture class, one event file per
    /// slide (AEDAT 2/3.1/4, ECD text or CSV); --set, --trials and --params then do not apply.
    #[arg(long)]
    dataset: Option<PathBuf>,
    #[command(flatten)]
    force: ForceOption,
    /// A first look in about a minute (once built): 10 slides per texture, 60 epochs, τ on a
    /// 10 ms grid.
    #[arg(long)]
    quick: bool,
    /// Also run the pipeline through a population of afferent neurons (one per taxel) and
    /// report accuracy and time next to the direct pipeline.
    #[arg(long, value_parser = args::menu::<NeuronKind>())]
    afferents: Option<NeuronKind>,
    /// τ grid step of the optimisation (ms, or with a unit: 20ms, 0.02s; default 5 ms,
    /// --quick 10 ms; the paper's 1 ms grid costs ≈ 5× the default).
    #[arg(value_parser = args::time_tau_step, allow_negative_numbers = true, long)]
    tau_step: Option<Time>,
    /// Where the spatiotemporal coding's Van Rossum distance comes from.
    #[arg(long, value_enum, default_value = "exact")]
    vr_from: VrFromArg,
    /// Trace step for --vr-from traces, a whole number of µs (ms, or with a unit: 20ms,
    /// 0.02s; default 0.1 ms, the network step).
    #[arg(value_parser = args::time_step, allow_negative_numbers = true, long, default_value = "0.1ms")]
    trace_dt: Time,
    /// Arithmetic of --vr-from traces.
    #[arg(long, value_parser = args::menu::<Precision>(), default_value = "f64")]
    trace_precision: Precision,
    /// Cache of simulated datasets, shared with `neurotac simulate`, and of the stepping
    /// crossovers `neurotac bench neurons --crossover` stores (default: $NEUROTAC_CACHE, else
    /// $XDG_CACHE_HOME/neurotac, else ~/.cache/neurotac; delete the folder to clear it).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Simulator parameters (JSON, see `neurotac simulate params`); default: the calibrated ones.
    #[arg(long)]
    params: Option<PathBuf>,
    /// Run each simulated set on this many mountings of its textures (the set itself, then
    /// copies with every texture mounted afresh) and report each coding's accuracy as mean ± sd
    /// over them. Each mounting costs a dataset and a pipeline run.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 1)]
    mountings: usize,
}

/// On several ranks the simulation, the distance matrices and the searches are split over them
/// ([`reproduce::run`]); every rank checks the report folder first, rank 0 alone shows progress,
/// prints and writes the report.
pub fn run(args: ReproduceArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    // The cache holds simulated sets: a recorded dataset does not need it.
    let cache = cache_folder(
        args.cache.as_deref(),
        ranks.is_root() && args.dataset.is_none(),
    );
    neurotac_experiments::afferents::use_crossovers_in(&cache);
    // The report folder replaces whatever is at --out: never a folder an input is in.
    refuse_report_over_inputs(
        &args.out,
        args.dataset.as_deref(),
        args.params.as_deref(),
        &cache,
    )?;
    check_outputs([Output::folder("--out", &args.out)], args.force.force)?;
    let mut config = match args.quick {
        true => ReproduceConfig::quick(args.seed.seed, cache),
        false => ReproduceConfig::paper(args.seed.seed, cache),
    };
    config.command = std::iter::once("neurotac".to_owned())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    if let Some(e) = args.epochs {
        config.pipeline.bayes.epochs = e;
    }
    if let Some(s) = args.tau_step {
        config.pipeline.bayes.tau_step_s = s.s();
    }
    config.trials = args.trials.or(config.trials);
    if let Some(p) = &args.params {
        config.params = SimParams::from_json_file(p)?;
    }
    config.pipeline.vr_from = match args.vr_from {
        VrFromArg::Exact => VrFrom::Exact,
        VrFromArg::Traces => VrFrom::Traces {
            trace_dt_s: args.trace_dt.s(),
            precision: args.trace_precision,
        },
    };
    config.afferents = args.afferents.map(AfferentConfig::of);
    config.mountings = args.mountings;
    let sources: Vec<Source> = match &args.dataset {
        Some(dir) => vec![Source::Recorded(dir.clone())],
        None => args
            .set
            .set
            .sets()
            .into_iter()
            .map(Source::Simulated)
            .collect(),
    };
    let bars = Bars::new();
    let progress: &dyn Progress = match ranks.is_root() {
        true => &bars,
        false => &NoProgress,
    };
    let (written, total) = timed(|| -> anyhow::Result<Option<f64>> {
        let report = with_threads(args.threads.threads, || {
            reproduce::run(&config, &sources, progress, ranks)
        })??;
        if !ranks.is_root() {
            return Ok(None);
        }
        for set in &report.sets {
            print_set(set, &fitted_grids_mm(&report, set));
        }
        bars.stage("writing the report (SVG, PNG, CSV, JSON, Markdown)", 0);
        let written = write_report(&args.out, &report, args.force.force);
        bars.finish();
        written?;
        Ok(Some(report.time.wall_s))
    });
    let Some(pipelines_s) = written? else {
        return Ok(());
    };
    println!(
        "report: {} (report.md, report.json, CSV tables, SVG and PNG figures)",
        args.out.display()
    );
    // The report states the datasets and pipelines' time (it cannot time its own writing):
    // both numbers are printed, so the terminal's total and report.md's agree.
    println!(
        "total: {total} ({pipelines_s:.1} s datasets and pipelines, as report.md states, \
         + {:.1} s printing and writing the report)",
        total.wall_s - pipelines_s
    );
    Ok(())
}

fn print_set(set: &SetReport, fitted_grids_mm: &[f64]) {
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
    let mountings = mounting_table(set);
    if !mountings.is_empty() {
        println!("{mountings}");
    }
    println!("{}", parameter_table(d));
    println!("{}", intensive_table(d, fitted_grids_mm));
    println!("{}", phase_table(set));
    println!("{}", recall_table(set));
    let confusions = paper_confusion_table(set);
    if !confusions.is_empty() {
        println!("{confusions}");
    }
    if let Some(why) = d.codings.iter().find_map(|c| c.split_refused.as_ref()) {
        println!("80/20 split refused: {why}\n");
    }
    if set.afferent.is_some() {
        println!("{}", afferent_table(set));
    }
}
