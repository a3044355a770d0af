//! `neurotac bench neurons|cuba|stdp`: throughput on the cases Brian2 is measured on.

mod peer_runs;
mod stdp;

use super::options::{SeedOption, ThreadsOption, help};
use super::outputs::{Output, check_outputs};
use crate::commands::args::{self, Time};
use clap::{Args, Subcommand};
use neurotac_cli::bench::{
    ActivityBench, ActivityBenchResult, CubaConfig, afferent_activity, afferent_crossover, cuba,
    cuba_spikes, neuron_throughput,
};
use neurotac_cli::ceiling::{Ceiling, CeilingFractions};
use neurotac_cli::peers::{PeerResult, brian2_method, brian2_precision};
use neurotac_core::graph::CROSSOVER_FILE_NAME;
use neurotac_core::{Crossovers, Ranks};
use neurotac_experiments::afferents::AfferentConfig;
use neurotac_experiments::datasets::simulated::default_cache_dir;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision};
use neurotac_experiments::threads::with_threads;
use neurotac_neurons::Integrator;
use peer_runs::{PeerCase, add_peer, fastest_interleaved, print};
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    what: BenchCommand,
}

#[derive(Debug, Subcommand)]
enum BenchCommand {
    /// Neuron updates per second of N uncoupled neurons under constant input.
    Neurons(NeuronsArgs),
    /// The CUBA network: 4000 LIF, 80/20 exc/inh, 2 % connectivity, exponential synapses.
    Cuba(CubaArgs),
    /// Song, Miller & Abbott (2000) Fig. 1: Poisson inputs onto one LIF neuron through
    /// additive STDP; final weights, output rate, and with --brian2 the same network in
    /// Brian2 (weights compared by a two-sample KS test, speed ratio).
    Stdp(stdp::StdpArgs),
}

#[derive(Debug, Args)]
struct NeuronsArgs {
    /// Model: LIF (I = 1.04, τ = 10 ms) or Izhikevich RS (I = 10).
    #[arg(long, value_parser = args::menu::<NeuronKind>(), default_value = "lif")]
    model: NeuronKind,
    /// Number of neurons.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 100_000)]
    n: usize,
    /// Simulated duration (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "1s")]
    duration: Time,
    /// Time step (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_step, allow_negative_numbers = true, long, default_value = "0.1ms")]
    dt: Time,
    /// Floating-point precision.
    #[arg(long, value_parser = args::menu::<Precision>(), default_value = "f32")]
    precision: Precision,
    /// Integrator (default: exact for LIF, izhikevich2003 for Izhikevich).
    #[arg(long)]
    integrator: Option<Integrator>,
    /// Instead: the afferent pipeline (N taxels → exponential synapses → N afferents of
    /// --model: LIF exact, or Izhikevich RS from rest; f64, one thread) with this fraction of
    /// the taxels firing (Poisson, --rate), clock-driven, event-driven and automatic (each
    /// population picks its mode from its measured activity and the crossover stored in the
    /// cache, else its model's built-in one): wall times, ratios, the mode chosen, identical
    /// spikes (--precision and --integrator do not apply).
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long)]
    activity: Option<f64>,
    /// Instead: measures the crossover of --model's afferents, the measured activity at which
    /// clock- and event-driven stepping cost the same (sweeps the taxel activity 0.001…1 as
    /// --activity does), and stores it in the cache's stepping-crossovers.json, which
    /// automatic stepping then uses.
    #[arg(long, conflicts_with = "activity")]
    crossover: bool,
    /// Folder of the stored crossovers with --activity and --crossover (default:
    /// $NEUROTAC_CACHE, else $XDG_CACHE_HOME/neurotac, else ~/.cache/neurotac).
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
    /// Firing rate of the active taxels with --activity (Hz).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 20.0)]
    rate: f64,
    #[command(flatten)]
    run: RunOptions,
}

/// Options shared by every benchmark.
#[derive(Debug, Args)]
struct RunOptions {
    #[command(flatten)]
    threads: ThreadsOption,
    /// Also run the same case in Brian2 (C++ standalone) with this Python, at the same precision
    /// with the same integration method, and report the ratio (refused for an integrator
    /// Brian2 does not have).
    #[arg(long, value_name = "PYTHON")]
    brian2: Option<PathBuf>,
    /// Runs of each side (neurotac and, with --brian2, the peer, interleaved); the fastest of
    /// each is reported, since a shared machine's noise only ever adds time.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 5)]
    repeats: usize,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, Args)]
#[command(mut_args(help("seed", "Seed of the connectivity and initial potentials")))]
struct CubaArgs {
    /// Simulated duration (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "1s")]
    duration: Time,
    /// Time step (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_step, allow_negative_numbers = true, long, default_value = "0.1ms")]
    dt: Time,
    #[command(flatten)]
    seed: SeedOption,
    /// Neurons (80 % excitatory, 20 % inhibitory; Brian2's benchmark: 4000).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 4000)]
    neurons: usize,
    /// Connection probability.
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long, default_value_t = 0.02)]
    probability: f64,
    #[command(flatten)]
    run: RunOptions,
}

/// `bench cuba` splits its populations over the ranks (spikes exchanged every one-step epoch);
/// `bench neurons` runs on one process.
pub fn run(args: BenchArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    match args.what {
        BenchCommand::Neurons(_) if ranks.size() > 1 => anyhow::bail!(
            "`neurotac bench neurons` runs on one process; under mpirun only `bench cuba` splits \
             its network over the ranks"
        ),
        BenchCommand::Neurons(a) => neurons(a),
        BenchCommand::Cuba(a) => cuba_network(a, ranks),
        BenchCommand::Stdp(_) if ranks.size() > 1 => anyhow::bail!(
            "`neurotac bench stdp` runs one neuron on one process; run it without mpirun"
        ),
        BenchCommand::Stdp(a) => stdp::run(a),
    }
}

fn neurons(a: NeuronsArgs) -> anyhow::Result<()> {
    if a.crossover {
        return crossover_bench(&a);
    }
    if let Some(activity) = a.activity {
        return activity_bench(&a, activity);
    }
    let integrator = a.integrator.unwrap_or(a.model.default_integrator());
    // Like for like or not at all: refused before anything runs.
    let method = match &a.run.brian2 {
        Some(_) => Some(brian2_method(a.model, integrator)?),
        None => None,
    };
    let threads = with_threads(a.run.threads.threads, rayon::current_num_threads)?;
    let case = a
        .run
        .brian2
        .as_deref()
        .zip(method)
        .map(|(python, method)| PeerCase {
            python,
            args: vec![
                "neurons".into(),
                a.model.name().into(),
                a.n.to_string(),
                a.duration.s().to_string(),
                a.dt.s().to_string(),
                threads.to_string(),
                brian2_precision(a.precision).into(),
                method.into(),
            ],
            precision: brian2_precision(a.precision),
            method,
        });
    let setup = NeuronSetup {
        integrator,
        ..NeuronSetup::benchmark(a.model, a.precision)
    };
    let cost = setup.update_cost();
    // The ceilings are measured after every run and the highest counts, as the fastest run
    // does: one measurement can fall into a moment when the core is busy with something else.
    // Each byte of state is read once and written once per step.
    let working_set = a.n * cost.bytes as usize / 2;
    let mut ceiling: Option<Ceiling> = None;
    let run = || {
        let r = neuron_throughput(
            a.model,
            a.n,
            a.duration.s(),
            a.dt.s(),
            a.precision,
            Some(integrator),
            threads,
        )?;
        let now = Ceiling::measure(a.precision, working_set);
        ceiling = Some(ceiling.map_or(now, |c| c.max(now)));
        Ok(r)
    };
    let (r, peer) =
        fastest_interleaved::<_, PeerResult>(a.run.repeats, run, |r| r.wall_s, case.as_ref())?;
    let ceiling = ceiling.expect("at least one run");
    let mut report = serde_json::to_value(&r)?;
    if let (Some(peer), Some(case)) = (&peer, &case) {
        add_peer(&mut report, peer, case, r.wall_s, r.updates);
    }
    let limit = LoopCeiling {
        fractions: ceiling.fractions(r.updates_per_s_per_thread, cost.flops, cost.bytes),
        flops_per_update: cost.flops,
        bytes_per_update: cost.bytes,
        ceiling,
    };
    report["ceiling"] = serde_json::to_value(&limit)?;
    let line = format!(
        "{} {} {} n={} dt={} s: {:.3e} updates/s ({:.3e} per thread, {} threads), {} spikes, {:.3} s wall\n{}",
        r.model.name(),
        r.integrator,
        r.precision.name(),
        r.n,
        r.dt_s,
        r.updates_per_s,
        r.updates_per_s_per_thread,
        r.threads,
        r.spikes,
        r.wall_s,
        limit.describe(a.precision)
    );
    print(&report, a.run.json, line);
    Ok(())
}

/// How close a throughput is to this core's ceilings ([`Ceiling`]) for the work of one update.
#[derive(serde::Serialize)]
struct LoopCeiling {
    #[serde(flatten)]
    ceiling: Ceiling,
    /// Floating-point operations per update ([`UpdateCost`](neurotac_neurons::UpdateCost)).
    flops_per_update: u32,
    /// Bytes of state read and written per update.
    bytes_per_update: u32,
    #[serde(flatten)]
    fractions: CeilingFractions,
}

impl LoopCeiling {
    /// One line: both shares, with the numbers they divide.
    fn describe(&self, precision: Precision) -> String {
        let LoopCeiling {
            ceiling: c,
            fractions: f,
            ..
        } = self;
        format!(
            "per thread: {:.0} % of this core's {} FMA peak ({:.3} Gflop/s, {} kernel) for {} \
             flops per update; {:.0} % of its read-modify-write bandwidth over {:.2} MB ({:.1} \
             GB/s) for {} bytes per update",
            100.0 * f.of_peak_flops,
            precision.name(),
            c.peak_flops_per_s / 1e9,
            c.peak_kernel,
            self.flops_per_update,
            100.0 * f.of_bandwidth,
            c.working_set_bytes as f64 / 1e6,
            c.bandwidth_bytes_per_s / 1e9,
            self.bytes_per_update
        )
    }
}

fn cuba_network(a: CubaArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    if a.run.brian2.is_some() && ranks.size() > 1 {
        anyhow::bail!("--brian2 compares one process with Brian2: run it without mpirun");
    }
    let n_exc = a.neurons * 4 / 5;
    let config = CubaConfig {
        duration_s: a.duration.s(),
        dt_s: a.dt.s(),
        seed: a.seed.seed,
        n_exc,
        n_inh: a.neurons - n_exc,
        probability: a.probability,
    };
    let threads = with_threads(a.run.threads.threads, rayon::current_num_threads)?;
    // neurotac's CUBA: f64, v exact with the synaptic currents held over each step and the
    // currents decayed exactly, which is Brian2's exponential_euler on these equations.
    let (precision, method) = ("float64", Integrator::ExponentialEuler.name());
    let case = a.run.brian2.as_deref().map(|python| PeerCase {
        python,
        args: vec![
            "cuba".into(),
            a.duration.s().to_string(),
            a.dt.s().to_string(),
            threads.to_string(),
            precision.into(),
            method.into(),
            a.neurons.to_string(),
            a.probability.to_string(),
        ],
        precision,
        method,
    });
    // The first run keeps its spikes (for the checksum); every run counts for the fastest.
    let mut spikes = None;
    let run = || {
        with_threads(threads, || {
            if spikes.is_none() {
                let (r, s) = cuba_spikes(config, ranks)?;
                spikes = Some(s);
                Ok(r)
            } else {
                cuba(config, ranks)
            }
        })?
        .map_err(anyhow::Error::from)
    };
    let (r, peer) =
        fastest_interleaved::<_, PeerResult>(a.run.repeats, run, |r| r.run_s, case.as_ref())?;
    let spikes = spikes.expect("the first run keeps its spikes");
    if !ranks.is_root() {
        return Ok(());
    }
    let mut report = serde_json::to_value(&r)?;
    report["threads"] = json!(threads);
    report["precision"] = json!(Precision::F64);
    report["method"] = json!(method);
    report["spike_checksum"] = json!(format!("{:016x}", spikes.checksum()));
    if let (Some(peer), Some(case)) = (&peer, &case) {
        add_peer(&mut report, peer, case, r.run_s, r.duration_s);
    }
    let mut line = format!(
        "CUBA (f64, {method}): {} neurons, {} synapses, {} s simulated in {:.4} s ({:.4} s per simulated second, {} threads; build {:.3} s), {} spikes ({:.1} Hz)",
        r.neurons,
        r.synapses,
        r.duration_s,
        r.run_s,
        r.wall_s,
        threads,
        r.build_s,
        r.spikes,
        r.rate_hz
    );
    if r.ranks > 1 {
        line += &format!(
            "\non {} ranks ({} threads each): spike exchange {:.4} s of rank 0's run ({:.1} %, {} exchanges of {} step(s)); spike checksum {:016x}",
            r.ranks,
            threads,
            r.exchange_s,
            100.0 * r.exchange_s / r.run_s,
            r.exchanges,
            (r.duration_s / r.exchanges.max(1) as f64 / a.dt.s()).round(),
            spikes.checksum()
        );
    }
    print(&report, a.run.json, line);
    Ok(())
}

/// The refusals shared by `--activity` and `--crossover` (they run the afferent pipeline with
/// its own integrators and have no Brian2 counterpart), and the crossover file they use.
fn activity_setup(a: &NeuronsArgs, flag: &str) -> anyhow::Result<PathBuf> {
    if a.integrator.is_some() {
        let own: Vec<String> = NeuronKind::ALL
            .iter()
            .map(|k| format!("{} {}", k.label(), k.default_integrator()))
            .collect();
        anyhow::bail!(
            "{flag} runs the afferent pipeline with its own integrators ({}): drop --integrator",
            own.join(", ")
        );
    }
    if a.run.brian2.is_some() {
        anyhow::bail!("{flag} has no Brian2 counterpart; drop --brian2");
    }
    let cache = a.cache.clone().unwrap_or_else(default_cache_dir);
    Ok(cache.join(CROSSOVER_FILE_NAME))
}

/// The pipeline bench's settings from the flags, with the crossovers stored in `file` (none
/// when it does not exist; a file that cannot be used is an error naming it).
fn activity_bench_settings(a: &NeuronsArgs, file: &Path) -> anyhow::Result<ActivityBench> {
    Ok(ActivityBench {
        config: AfferentConfig::of(a.model),
        n: a.n,
        rate_hz: a.rate,
        duration_s: a.duration.s(),
        dt_s: a.dt.s(),
        seed: 1,
        repeats: a.run.repeats,
        crossovers: Crossovers::load(file)?.unwrap_or_default(),
    })
}

/// `bench neurons --activity F`: the afferent pipeline clock-driven, event-driven and
/// automatic.
fn activity_bench(a: &NeuronsArgs, activity: f64) -> anyhow::Result<()> {
    let file = activity_setup(a, "--activity")?;
    let bench = activity_bench_settings(a, &file)?;
    let (config, crossovers) = (bench.config, &bench.crossovers);
    let r = afferent_activity(&bench, activity)?;
    if a.run.json {
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    println!(
        "afferent pipeline: {} taxels ({:.1} % firing at {} Hz) → {} {}, {} steps of {} s, one thread",
        r.n,
        100.0 * r.active_fraction,
        r.rate_hz,
        r.n,
        config.bench_description(),
        r.steps,
        r.dt_s
    );
    let faster = r.clock_driven.wall_s.min(r.event_driven.wall_s);
    for (name, run) in [
        ("clock-driven", r.clock_driven),
        ("event-driven", r.event_driven),
        ("automatic", r.automatic),
    ] {
        println!(
            "  {name:12}  {:8.4} s wall ({:.2}× the faster fixed mode)  {:>14} neuron updates  effective {:.3e} neuron-steps/s  {} spikes",
            run.wall_s,
            run.wall_s / faster,
            run.updates,
            run.effective_updates_per_s,
            run.spikes
        );
    }
    let s = &r.automatic_stepping;
    println!(
        "automatic: ended {} after {} switches, activity {:.4} (crossover {:.4}{})",
        s.mode,
        s.switches,
        s.activity.unwrap_or(0.0),
        s.crossover.unwrap_or(f64::NAN),
        if crossovers.get(s.model).is_some() {
            format!(", stored in {}", file.display())
        } else {
            ", built-in".to_owned()
        }
    );
    println!(
        "event-driven is {:.1}× faster; spikes {}",
        r.speedup,
        if r.identical_spikes {
            "identical"
        } else {
            "DIFFER"
        }
    );
    Ok(())
}

/// One row of the activity table: taxel activity, measured activity, wall times, ratios, mode.
fn activity_row(p: &ActivityBenchResult) -> String {
    let faster = p.clock_driven.wall_s.min(p.event_driven.wall_s);
    format!(
        "  {:>8.3}  {:>9.4}  {:>9.4}  {:>9.4}  {:>9.4}  {:>7.2}  {:>6.2}  {:<13} {}",
        p.active_fraction,
        p.measured_activity,
        p.clock_driven.wall_s,
        p.event_driven.wall_s,
        p.automatic.wall_s,
        p.speedup,
        p.automatic.wall_s / faster,
        p.automatic_stepping.mode.to_string(),
        if p.identical_spikes {
            "identical"
        } else {
            "DIFFER"
        }
    )
}

/// `bench neurons --crossover`: sweeps the activity, finds the crossover, stores it.
fn crossover_bench(a: &NeuronsArgs) -> anyhow::Result<()> {
    let file = activity_setup(a, "--crossover")?;
    // The crossovers are stored in the cache (replacing the file): checked before the sweep.
    check_outputs([Output::file("--cache", &file)], true)?;
    let bench = activity_bench_settings(a, &file)?;
    let r = afferent_crossover(&bench)?;
    let (config, mut crossovers) = (bench.config, bench.crossovers);
    crossovers.set(r.model, r.crossover)?;
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir).map_err(|e| {
            anyhow::anyhow!("cannot create the cache folder {}: {e}", dir.display())
        })?;
    }
    crossovers.save(&file)?;
    if a.run.json {
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    println!(
        "afferent pipeline: {} taxels at {} Hz → {} {}, {} s of {} s steps, one thread",
        a.n,
        a.rate,
        a.n,
        config.bench_description(),
        a.duration.s(),
        a.dt.s()
    );
    println!(
        "  {:>8}  {:>9}  {:>9}  {:>9}  {:>9}  {:>7}  {:>6}  {:<13} spikes",
        "taxels", "activity", "clock s", "event s", "auto s", "clk/evt", "auto/best", "auto mode"
    );
    for p in &r.points {
        println!("{}", activity_row(p));
    }
    println!(
        "crossover of {}: activity {:.4} (stored in {})",
        r.model,
        r.crossover,
        file.display()
    );
    Ok(())
}
