//! `neurotac simulate`: the simulated texture datasets, the acceptance check and the
//! calibration of the simulator (`shared/specs/simulator.md`).

use super::options::{
    ForceOption, OutOption, SeedOption, SetOption, ThreadsOption, help, required,
};
use super::outputs::{Output, cache_folder, check_outputs, refuse_nested};
use super::progress::{Bars, bar};
use crate::commands::args;
use anyhow::Context;
use clap::{Args, Subcommand, ValueEnum};
use neurotac_cli::simulator_check::{
    CheckConfig, calibrate, check_trial_count, mounting_summary, simulator_check, to_markdown,
};
use neurotac_core::Ranks;
use neurotac_core::io::{AtomicFileSet, Replace};
use neurotac_experiments::datasets::TextureSet;
use neurotac_experiments::datasets::simulated::{GenerateConfig, Generated, PixelEventFiles};
use neurotac_experiments::export::OutputFormat;
use neurotac_experiments::threads::with_threads;
use neurotac_sensor::sim::SimParams;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SimulateArgs {
    #[command(subcommand)]
    command: Option<SimulateCommand>,
    #[command(flatten)]
    generate: GenerateArgs,
}

#[derive(Debug, Subcommand)]
enum SimulateCommand {
    /// Compute the spec's 10 acceptance statistics, the onset-mechanics statistic and the protocol
    /// and specimen statistics (12–18), and print each with its bound and PASS/FAIL.
    Check(CheckArgs),
    /// Calibrate the three global parameters on the paper's three intensive means (pins' shear
    /// gain ← 0 mm 4.63, conformity gap ← 2.5 mm 9.84, lever ← 5 mm 34.73) and write the
    /// parameter file.
    Calibrate(CalibrateArgs),
    /// Print the default parameter file (JSON; every field required when read back).
    Params,
}

#[derive(Debug, Args)]
#[command(
    mut_args(required("set")),
    mut_args(help(
        "set",
        "Texture set: 11 bump grids, the 20 natural textures, or both (one file each)"
    )),
    mut_args(help("seed", "Seed of the dataset (camera and every trial)")),
    mut_args(required("out")),
    mut_args(help(
        "out",
        "Output folder: `<set>.bin` (taxel spike dataset), optionally `<set>.json` and pixel events"
    ))
)]
struct GenerateArgs {
    #[command(flatten)]
    set: SetOption,
    /// Slides per texture (default: the paper's, 100 artificial / 50 natural).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    trials: Option<usize>,
    #[command(flatten)]
    seed: SeedOption,
    #[command(flatten)]
    out: OutOption,
    /// Simulator parameter file (JSON, every field; see `neurotac simulate params`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Also write the dataset as JSON (the same as `--format json`).
    #[arg(long)]
    json: bool,
    /// Also write the dataset in these forms, comma-separated: `json` (`<set>.json`), `npz`
    /// (`<set>.npz`: flat numpy arrays `times`, `units`, `offsets`, `labels` and `meta.json`).
    /// `<set>.bin` is always written.
    #[arg(long, value_enum, value_delimiter = ',')]
    format: Vec<AlsoFormat>,
    /// Also write every trial's pixel events under `<out>/events/<class>/<trial>.<format>`.
    #[arg(long)]
    pixel_events: bool,
    /// Event-file format of --pixel-events, by extension: aedat4, aedat (2.0), aedat3, txt, csv.
    #[arg(long, default_value = "aedat4")]
    event_format: String,
    /// With --pixel-events: write CSV with a `pin` column (source pin, −1 for noise) instead.
    #[arg(long)]
    labels: bool,
    /// Cache of simulated datasets, shared with `neurotac reproduce` (default: $NEUROTAC_CACHE,
    /// else $XDG_CACHE_HOME/neurotac, else ~/.cache/neurotac; delete the folder to clear it).
    #[arg(long)]
    cache: Option<PathBuf>,
    #[command(flatten)]
    threads: ThreadsOption,
    #[command(flatten)]
    force: ForceOption,
}

/// `--format`: the forms written besides `<set>.bin`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum AlsoFormat {
    /// `<set>.json`.
    Json,
    /// `<set>.npz` (numpy).
    Npz,
}

#[derive(Debug, Args)]
#[command(mut_args(help("out", "Write `check.md` and `check.json` to this folder")))]
struct CheckArgs {
    /// Slides per grid (≥ 10 for the monotonicity statistic).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 10)]
    trials: usize,
    /// Slides of the 0, 2.5 and 5 mm grids for the variability statistic.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 20)]
    variability_trials: usize,
    /// Slides of every texture of both sets for the protocol and specimen statistics (12–18).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 5)]
    specimen_trials: usize,
    /// Mountings of the 4.5 and 5 mm grids for the spread of their count ratio.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 30)]
    mountings: usize,
    #[command(flatten)]
    seed: SeedOption,
    /// Simulator parameter file (JSON).
    #[arg(long)]
    params: Option<PathBuf>,
    #[command(flatten)]
    out: OutOption,
    #[command(flatten)]
    force: ForceOption,
    #[command(flatten)]
    threads: ThreadsOption,
}

#[derive(Debug, Args)]
#[command(
    mut_args(help("out", "Write the calibrated parameter file here (default: print it)")),
    mut_args(help("force", "Replace an existing `--out` file"))
)]
struct CalibrateArgs {
    /// Slides of the anchor grid per bisection step (each on a fresh mounting).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 20)]
    trials: usize,
    #[command(flatten)]
    seed: SeedOption,
    /// Alternations of the lever and conformity-gap fits.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 3)]
    rounds: usize,
    /// Simulator parameter file to start from (JSON).
    #[arg(long)]
    params: Option<PathBuf>,
    #[command(flatten)]
    out: OutOption,
    #[command(flatten)]
    force: ForceOption,
    #[command(flatten)]
    threads: ThreadsOption,
}

fn load_params(path: Option<&Path>) -> anyhow::Result<SimParams> {
    Ok(match path {
        Some(p) => SimParams::from_json_file(p)?,
        None => SimParams::default(),
    })
}

fn progress_bar(total: usize, what: &str) -> super::progress::Meter {
    bar(what, total as u64, "trials ")
}

pub fn run(args: SimulateArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    if args.command.is_some() && ranks.size() > 1 {
        anyhow::bail!(
            "`neurotac simulate check|calibrate|params` runs on one process; only dataset \
             generation (`neurotac simulate --set …`) splits over MPI ranks"
        );
    }
    match args.command {
        Some(SimulateCommand::Check(a)) => check(a),
        Some(SimulateCommand::Calibrate(a)) => calibrate_command(a),
        Some(SimulateCommand::Params) => {
            println!("{}", SimParams::default().to_json_string());
            Ok(())
        }
        None => generate(args.generate, ranks),
    }
}

fn generate(a: GenerateArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    let out = a.out.out.context("--out is required")?;
    let params = load_params(a.params.as_deref())?;
    let pixel_events = a.pixel_events.then(|| match a.labels {
        true => PixelEventFiles::LabelledCsv,
        false => PixelEventFiles::Format(a.event_format.clone()),
    });
    let sets = a.set.set.context("--set is required")?.sets();
    let mut also: Vec<OutputFormat> = Vec::new();
    for format in a
        .json
        .then_some(AlsoFormat::Json)
        .into_iter()
        .chain(a.format)
    {
        let format = match format {
            AlsoFormat::Json => OutputFormat::Json,
            AlsoFormat::Npz => OutputFormat::Npz,
        };
        if !also.contains(&format) {
            also.push(format);
        }
    }
    let mut outputs: Vec<PathBuf> = Vec::new();
    for set in &sets {
        for ext in std::iter::once("bin").chain(also.iter().map(|f| f.extensions()[0])) {
            outputs.push(out.join(format!("{}.{ext}", set.name())));
        }
    }
    let events = a.pixel_events.then(|| out.join("events"));
    let cache = cache_folder(a.cache.as_deref(), ranks.is_root());
    let inputs: Vec<&Path> = a
        .params
        .iter()
        .chain([&cache])
        .map(|p| p.as_path())
        .collect();
    refuse_nested(outputs.iter().chain(&events).map(|p| p.as_path()), &inputs)?;
    check_outputs(
        Output::folder_with_files("--out", &out, &outputs)
            .chain(events.iter().map(|e| Output::folder("--pixel-events", e))),
        a.force.force,
    )?;
    // Every set's files and the events folder are committed together at the end: an error or
    // an interrupted run leaves none of them (the events folder appears only complete).
    let mut files = AtomicFileSet::new(Replace::when(a.force.force));
    let mut made_sets = Vec::new();
    for set in sets {
        let config = GenerateConfig {
            set,
            trials: a.trials.unwrap_or(set.paper_trials()),
            seed: a.seed.seed,
            params,
            out: out.clone(),
            cache: cache.clone(),
            also: also.clone(),
            pixel_events: pixel_events.clone(),
        };
        let start = Instant::now();
        let bars = Bars::new();
        let made = with_threads(a.threads.threads, || {
            neurotac_experiments::datasets::simulated::generate(&config, &mut files, &bars, ranks)
        })??;
        made_sets.push((set, config.trials, made, start.elapsed().as_secs_f64()));
    }
    if !ranks.is_root() {
        return Ok(());
    }
    files
        .commit()
        .with_context(|| format!("writing the dataset files into {}", out.display()))?;
    for (set, trials, made, wall) in &made_sets {
        print_generated(*set, *trials, made, *wall, ranks.size());
    }
    Ok(())
}

/// What `neurotac simulate` says of one set it made and wrote.
fn print_generated(set: TextureSet, trials: usize, made: &Generated, wall: f64, ranks: usize) {
    let data = &made.dataset;
    let how = match made.from_cache {
        true => "loaded from the cache".to_owned(),
        false => format!("{:.1} trials/s", data.len() as f64 / wall),
    };
    let on = match ranks {
        1 => String::new(),
        k => format!(" on {k} ranks"),
    };
    println!(
        "{} set: {} textures × {} slides = {} trials in {wall:.1} s{on} ({how})",
        set.name(),
        set.textures().len(),
        trials,
        data.len(),
    );
    let stat = |key: &str| data.meta().get(key).and_then(|v| v.as_f64());
    if let (Some(pixel), Some(noise)) = (
        stat("pixel_events_per_trial"),
        stat("noise_events_per_trial"),
    ) {
        println!("pixel events per trial: {pixel:.0} (of which noise {noise:.0})");
    }
    println!("  class                   spikes/taxel (mean over slides)");
    for (name, m) in data.class_names().iter().zip(&made.class_means) {
        println!("  {name:22}  {m:8.2}");
    }
    println!("→ {}", made.binary.display());
}

fn check(a: CheckArgs) -> anyhow::Result<()> {
    if let Some(out) = &a.out.out {
        let outputs = [out.join("check.md"), out.join("check.json")];
        check_outputs(
            Output::folder_with_files("--out", out, &outputs),
            a.force.force,
        )?;
    }
    let config = CheckConfig {
        trials: a.trials.max(2),
        variability_trials: a.variability_trials,
        specimen_trials: a.specimen_trials,
        mountings: a.mountings,
        seed: a.seed.seed,
        params: load_params(a.params.as_deref())?,
        ..CheckConfig::default()
    };
    let bar = progress_bar(check_trial_count(&config)?, "check");
    let start = Instant::now();
    let report = with_threads(a.threads.threads, || {
        simulator_check(&config, &|| bar.inc(1))
    })??;
    bar.finish_and_clear();
    let markdown = to_markdown(&report);
    for s in &report.statistics {
        println!(
            "{:>2}. {:<27} {}\n    {:<27} bound: {}\n",
            s.number,
            s.name,
            s.measured,
            if s.pass { "PASS" } else { "FAIL" },
            s.bound
        );
    }
    println!(
        "spikes per taxel by grid: re-mounted slides (CV) | one mounting (CV) | signal events kept by the BA filter"
    );
    for (((d, m, sd), (_, m1, sd1)), (_, kept)) in report
        .grid_counts
        .iter()
        .zip(&report.one_mounting_counts)
        .zip(&report.signal_kept)
    {
        println!(
            "  {d:3.1} mm  {m:6.2} ± {sd:5.2} ({:4.1} %) | {m1:6.2} ± {sd1:5.2} ({:4.1} %) | {:3.0} %",
            100.0 * sd / m,
            100.0 * sd1 / m1,
            100.0 * kept
        );
    }
    println!("{}", mounting_summary(&report.specimens.mounting_ratios));
    let passed = report.statistics.iter().filter(|s| s.pass).count();
    println!(
        "{passed}/{} statistics pass ({} trials in {:.1} s)",
        report.statistics.len(),
        report.trials_simulated,
        start.elapsed().as_secs_f64()
    );
    if let Some(out) = a.out.out {
        std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
        let mut files = AtomicFileSet::new(Replace::when(a.force.force));
        let json = serde_json::to_string_pretty(&report)?;
        for (name, text) in [("check.md", markdown), ("check.json", json)] {
            let path = out.join(name);
            files
                .write(&path, text)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        files
            .commit()
            .with_context(|| format!("writing check.md and check.json into {}", out.display()))?;
    }
    Ok(())
}

fn calibrate_command(a: CalibrateArgs) -> anyhow::Result<()> {
    if let Some(out) = &a.out.out {
        check_outputs([Output::file("--out", out)], a.force.force)?;
    }
    let params = load_params(a.params.as_deref())?;
    let bar = super::progress::bar("calibrating", 0, "slides");
    let c = with_threads(a.threads.threads, || {
        calibrate(&params, a.trials, a.seed.seed, a.rounds, &|| bar.inc(1))
    })??;
    bar.finish_and_clear();
    for e in &c.entries {
        let p = e.parameter;
        println!(
            "{} = {:.4} → {:.2} spikes/taxel on the {} mm grid (target {:.2})",
            p.name, p.value, e.achieved, p.anchor_grid_mm, p.target_spikes_per_taxel
        );
    }
    println!("({} slides)", c.slides);
    let text = c.params.to_json_string();
    match a.out.out {
        Some(path) => {
            neurotac_core::io::write(&path, text, Replace::when(a.force.force))
                .with_context(|| format!("writing {}", path.display()))?;
            println!("→ {}", path.display());
        }
        None => println!("{text}"),
    }
    Ok(())
}
