//! `neurotac tradeoff [--quick] [--set artificial|natural|both] [--dataset DIR] [--families …]`:
//! the accuracy ↔ cost study (`neurotac_cli::tradeoff::study`). Builds `reproduce`'s
//! configuration from the same flags, loads each set as `reproduce` does, studies every family
//! and writes `tradeoff.md` and one folder per set and family.

use crate::commands::args;
use crate::commands::options::{
    ForceOption, SeedOption, SetArg, ThreadsOption, TradeoffOutOption, help,
};
use crate::commands::outputs::{Output, cache_folder, check_outputs, refuse_report_over_inputs};
use crate::commands::progress::Bars;
use anyhow::Context;
use clap::{Args, ValueEnum};
use neurotac_cli::tradeoff::study::report::{study_files, write_study};
use neurotac_cli::tradeoff::study::{Family, SimulatedSource, StudyConfig, study_set};
use neurotac_core::io::{AtomicFileSet, Replace};
use neurotac_experiments::neuron_setup::NeuronKind;
use neurotac_experiments::progress::Progress;
use neurotac_experiments::reproduce::{ReproduceConfig, Source, load_source};
use neurotac_experiments::threads::with_threads;
use neurotac_sensor::sim::SimParams;
use std::path::PathBuf;

/// A family of settings to sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum FamilyArg {
    /// Van Rossum distance: exact vs synaptic traces (trace step × f64/f32).
    Vr,
    /// The afferent layer (--afferents): integrator × dt × precision, event- vs clock-driven.
    Afferents,
    /// The transduction's pooling and BA windows around the paper's (simulated sets only:
    /// re-simulates the set once).
    Transduction,
    /// The simulator's pixel step tolerance, mechanics step and shear ODE step (simulated
    /// sets only: re-simulates the set once per setting).
    Simulator,
}

#[derive(Debug, Args)]
#[command(mut_args(help(
    "out",
    "Output folder (created if needed): tradeoff.md and one sub-folder per set and family"
)))]
pub struct StudyArgs {
    #[command(flatten)]
    out: TradeoffOutOption,
    /// Fewer settings, 10 slides per texture and `reproduce --quick`'s search (about two
    /// minutes on two cores; wide intervals).
    #[arg(long)]
    quick: bool,
    #[command(flatten)]
    force: ForceOption,
    /// Which simulated texture set(s) to study.
    #[arg(
        long,
        value_enum,
        default_value = "artificial",
        conflicts_with = "dataset"
    )]
    set: SetArg,
    /// Study a recorded dataset instead: one folder per texture class, one event file per slide.
    #[arg(long)]
    dataset: Option<PathBuf>,
    /// The families to sweep, comma-separated (default: all four with --set, vr,afferents with
    /// --dataset).
    #[arg(long, value_enum, value_delimiter = ',')]
    families: Option<Vec<FamilyArg>>,
    /// The afferent model of the afferent family.
    #[arg(long, value_parser = args::menu::<NeuronKind>(), default_value = "lif")]
    afferents: NeuronKind,
    #[command(flatten)]
    seed: SeedOption,
    /// Slides per texture (default: the paper's 100 / 50; --quick: 10).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    trials: Option<usize>,
    /// Bayesian-optimisation evaluations of the reference (paper: 1000; --quick: 60).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    epochs: Option<usize>,
    /// Cache of simulated datasets, shared with `neurotac simulate` and `reproduce`.
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Simulator parameters (JSON, see `neurotac simulate params`).
    #[arg(long)]
    params: Option<PathBuf>,
    #[command(flatten)]
    threads: ThreadsOption,
}

pub fn run(args: StudyArgs) -> anyhow::Result<()> {
    // The cache holds simulated sets: a recorded dataset does not need it.
    let cache = cache_folder(args.cache.as_deref(), args.dataset.is_none());
    neurotac_experiments::afferents::use_crossovers_in(&cache);
    refuse_report_over_inputs(
        &args.out.out,
        args.dataset.as_deref(),
        args.params.as_deref(),
        &cache,
    )?;
    // The summary is always written: refused before any work (every file once the sets'
    // names are known).
    let summary_path = args.out.out.join("tradeoff.md");
    check_outputs(
        [
            Output::into_folder("--out", &args.out.out),
            Output::file("--out", &summary_path),
        ],
        args.force.force,
    )?;
    let mut config = match args.quick {
        true => ReproduceConfig::quick(args.seed.seed, cache),
        false => ReproduceConfig::paper(args.seed.seed, cache),
    };
    if let Some(e) = args.epochs {
        config.pipeline.bayes.epochs = e;
    }
    config.trials = args.trials.or(config.trials);
    if let Some(p) = &args.params {
        config.params = SimParams::from_json_file(p)?;
    }
    let sources: Vec<Source> = match &args.dataset {
        Some(dir) => vec![Source::Recorded(dir.clone())],
        None => args.set.sets().into_iter().map(Source::Simulated).collect(),
    };
    let mut families = Vec::new();
    let asked = match (&args.families, &args.dataset) {
        (Some(f), _) => f.clone(),
        (None, Some(_)) => vec![FamilyArg::Vr, FamilyArg::Afferents],
        (None, None) => FamilyArg::value_variants().to_vec(),
    };
    for f in &asked {
        let family = match f {
            FamilyArg::Vr => Family::VanRossum,
            FamilyArg::Afferents => Family::Afferents(args.afferents),
            FamilyArg::Transduction => Family::Transduction,
            FamilyArg::Simulator => Family::Simulator,
        };
        if !families.contains(&family) {
            families.push(family);
        }
    }
    if args.dataset.is_some()
        && (families.contains(&Family::Transduction) || families.contains(&Family::Simulator))
    {
        anyhow::bail!(
            "the transduction and simulator families re-simulate their set: they need --set, not --dataset (choose --families vr,afferents)"
        );
    }
    let study = StudyConfig {
        pipeline: config.pipeline,
        families,
        quick: args.quick,
    };
    let bars = Bars::new();
    let start = std::time::Instant::now();
    let sets = with_threads(args.threads.threads, || -> anyhow::Result<_> {
        let mut sets = Vec::new();
        for source in &sources {
            let (name, how, data, _) =
                load_source(source, &config, &bars, &neurotac_core::OneProcess)?;
            bars.note(&format!("{name}: {} samples ({how})", data.len()));
            // The set's outputs are checked before its study.
            let stems: Vec<String> = study.families.iter().map(|f| f.stem()).collect();
            let files = study_files(&args.out.out, std::slice::from_ref(&name), &stems);
            check_outputs(Output::files("--out", &files), args.force.force)?;
            let simulated = match source {
                Source::Simulated(set) => Some(SimulatedSource {
                    set: *set,
                    trials: config.trials.unwrap_or(set.paper_trials()),
                    seed: config.seed,
                    params: config.params,
                }),
                Source::Recorded(_) => None,
            };
            sets.push(study_set(&name, &data, simulated.as_ref(), &study, &bars)?);
        }
        Ok(sets)
    })??;
    let seconds = start.elapsed().as_secs_f64();
    let command = std::iter::once("neurotac".to_owned())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let header = format!(
        "Made by `{command}` in {seconds:.0} s on {} threads (seed {}, {} slides per texture for simulated sets).",
        if args.threads.threads == 0 {
            std::thread::available_parallelism().map_or(1, |n| n.get())
        } else {
            args.threads.threads
        },
        args.seed.seed,
        config
            .trials
            .map_or_else(|| "the paper's".to_owned(), |t| t.to_string())
    );
    let mut files = AtomicFileSet::new(Replace::when(args.force.force));
    let summary = write_study(&mut files, &args.out.out, &header, args.quick, &sets)?;
    files.commit().context("writing the study's files")?;
    println!("{summary}");
    println!(
        "wrote {} in {seconds:.1} s",
        args.out.out.join("tradeoff.md").display()
    );
    Ok(())
}
