//! `neurotac bench neurons|cuba`: throughput on the cases Brian2 is measured on.

use super::options::{SeedOption, ThreadsOption, help};
use crate::commands::args;
use clap::{Args, Subcommand};
use neurotac_cli::bench::{CubaConfig, afferent_activity, cuba, cuba_spikes, neuron_throughput};
use neurotac_cli::peers::run_brian2;
use neurotac_core::Ranks;
use neurotac_experiments::afferents::AfferentConfig;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::neuron_setup::{NeuronKind, Precision};
use neurotac_neurons::Integrator;
use serde_json::{Value, json};
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
}

#[derive(Debug, Args)]
struct NeuronsArgs {
    /// Model: LIF (I = 1.04, τ = 10 ms) or Izhikevich RS (I = 10).
    #[arg(long, value_parser = args::menu::<NeuronKind>(), default_value = "lif")]
    model: NeuronKind,
    /// Number of neurons.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 100_000)]
    n: usize,
    /// Simulated duration (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1.0)]
    duration: f64,
    /// Time step (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1e-4)]
    dt: f64,
    /// Floating-point precision.
    #[arg(long, value_parser = args::menu::<Precision>(), default_value = "f32")]
    precision: Precision,
    /// Integrator (default: exact for LIF, izhikevich2003 for Izhikevich).
    #[arg(long)]
    integrator: Option<Integrator>,
    /// Instead: the afferent pipeline (N taxels → exponential synapses → N afferents of
    /// --model: LIF exact, or Izhikevich RS from rest; f64, one thread) with this fraction of
    /// the taxels firing (Poisson, --rate), clock-driven against event-driven: effective
    /// throughput, speed-up, identical spikes (--precision and --integrator do not apply).
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long)]
    activity: Option<f64>,
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
    /// Also run the same case in Brian2 (C++ standalone) with this Python and report the ratio.
    #[arg(long, value_name = "PYTHON")]
    brian2: Option<PathBuf>,
    /// Runs of each side (neurotac and, with --brian2, the peer); the fastest of each is
    /// reported, since a shared machine's noise only ever adds time.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 3)]
    repeats: usize,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, Args)]
#[command(mut_args(help("seed", "Seed of the connectivity and initial potentials")))]
struct CubaArgs {
    /// Simulated duration (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1.0)]
    duration: f64,
    /// Time step (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1e-4)]
    dt: f64,
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

/// Adds the peer's numbers and `speedup = peer time / our time` to `report`.
fn compare(
    report: &mut Value,
    python: &Path,
    peer_args: Vec<String>,
    our_wall_s: f64,
    work: f64,
    repeats: usize,
) -> anyhow::Result<()> {
    let mut peer = run_brian2(python, &peer_args)?;
    for _ in 1..repeats {
        let again = run_brian2(python, &peer_args)?;
        if again.run_s < peer.run_s {
            peer = again;
        }
    }
    report["peer"] = json!(peer.peer);
    report["peer_wall_s"] = json!(peer.run_s);
    report["peer_spikes"] = json!(peer.spikes);
    report["peer_per_s"] = json!(work / peer.run_s);
    report["speedup"] = json!(peer.run_s / our_wall_s);
    Ok(())
}

fn print(report: &Value, json: bool, line: String) {
    if json {
        println!("{report}");
        return;
    }
    println!("{line}");
    if let Some(peer) = report["peer"].as_str() {
        println!(
            "{peer}: {:.4} s wall, {} spikes → neurotac is {:.2}× faster",
            report["peer_wall_s"].as_f64().unwrap_or(f64::NAN),
            report["peer_spikes"],
            report["speedup"].as_f64().unwrap_or(f64::NAN)
        );
    }
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
    }
}

fn neurons(a: NeuronsArgs) -> anyhow::Result<()> {
    if let Some(activity) = a.activity {
        return activity_bench(&a, activity);
    }
    for (flag, value) in [("duration", a.duration), ("dt", a.dt)] {
        super::neuron::check_precision(flag, value, a.precision)?;
    }
    let run = || {
        neuron_throughput(
            a.model,
            a.n,
            a.duration,
            a.dt,
            a.precision,
            a.integrator,
            a.run.threads.threads,
        )
    };
    let mut r = run()?;
    for _ in 1..a.run.repeats {
        let again = run()?;
        if again.wall_s < r.wall_s {
            r = again;
        }
    }
    let mut report = serde_json::to_value(&r)?;
    if let Some(python) = &a.run.brian2 {
        let peer_args = ["neurons", r.model.name()].map(String::from).into_iter();
        let peer_args = peer_args.chain([
            a.n.to_string(),
            a.duration.to_string(),
            a.dt.to_string(),
            r.threads.to_string(),
        ]);
        compare(
            &mut report,
            python,
            peer_args.collect(),
            r.wall_s,
            r.updates,
            a.run.repeats,
        )?;
    }
    let line = format!(
        "{} {} {} n={} dt={} s: {:.3e} updates/s ({:.3e} per thread, {} threads), {} spikes, {:.3} s wall",
        r.model.name(),
        r.integrator,
        r.precision.name(),
        r.n,
        r.dt_s,
        r.updates_per_s,
        r.updates_per_s_per_thread,
        r.threads,
        r.spikes,
        r.wall_s
    );
    print(&report, a.run.json, line);
    Ok(())
}

fn cuba_network(a: CubaArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    if a.run.brian2.is_some() && ranks.size() > 1 {
        anyhow::bail!("--brian2 compares one process with Brian2: run it without mpirun");
    }
    let n_exc = a.neurons * 4 / 5;
    let config = CubaConfig {
        duration_s: a.duration,
        dt_s: a.dt,
        seed: a.seed.seed,
        n_exc,
        n_inh: a.neurons - n_exc,
        probability: a.probability,
    };
    let (r, spikes, threads) =
        neurotac_experiments::threads::with_threads(a.run.threads.threads, || {
            let (mut best, spikes) = cuba_spikes(config, ranks)?;
            for _ in 1..a.run.repeats {
                let again = cuba(config, ranks)?;
                if again.run_s < best.run_s {
                    best = again;
                }
            }
            Ok::<_, neurotac_cli::bench::BenchError>((best, spikes, rayon::current_num_threads()))
        })??;
    if !ranks.is_root() {
        return Ok(());
    }
    let mut report = serde_json::to_value(&r)?;
    report["threads"] = json!(threads);
    report["spike_checksum"] = json!(format!("{:016x}", spikes.checksum()));
    if let Some(python) = &a.run.brian2 {
        let peer_args = vec![
            "cuba".into(),
            a.duration.to_string(),
            a.dt.to_string(),
            threads.to_string(),
        ];
        compare(
            &mut report,
            python,
            peer_args,
            r.run_s,
            r.duration_s,
            a.run.repeats,
        )?;
    }
    let mut line = format!(
        "CUBA: {} neurons, {} synapses, {} s simulated in {:.4} s ({:.4} s per simulated second, {} threads; build {:.3} s), {} spikes ({:.1} Hz)",
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
            (r.duration_s / r.exchanges.max(1) as f64 / a.dt).round(),
            spikes.checksum()
        );
    }
    print(&report, a.run.json, line);
    Ok(())
}

/// `bench neurons --activity F`: the afferent pipeline clock-driven against event-driven.
fn activity_bench(a: &NeuronsArgs, activity: f64) -> anyhow::Result<()> {
    if a.integrator.is_some() {
        let own: Vec<String> = NeuronKind::ALL
            .iter()
            .map(|k| format!("{} {}", k.label(), k.default_integrator()))
            .collect();
        anyhow::bail!(
            "--activity runs the afferent pipeline with its own integrators ({}): drop --integrator",
            own.join(", ")
        );
    }
    if a.run.brian2.is_some() {
        anyhow::bail!("--activity has no Brian2 counterpart; drop --brian2");
    }
    let config = AfferentConfig::of(a.model);
    let afferents = config.bench_description();
    let r = afferent_activity(config, a.n, activity, a.rate, a.duration, a.dt, 1)?;
    if a.run.json {
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    println!(
        "afferent pipeline: {} taxels ({:.1} % firing at {} Hz) → {} {afferents}, {} steps of {} s, one thread",
        r.n,
        100.0 * r.active_fraction,
        r.rate_hz,
        r.n,
        r.steps,
        r.dt_s
    );
    for (name, run) in [
        ("clock-driven", r.clock_driven),
        ("event-driven", r.event_driven),
    ] {
        println!(
            "  {name:12}  {:8.4} s wall  {:>14} neuron updates  effective {:.3e} neuron-steps/s  {} spikes",
            run.wall_s, run.updates, run.effective_updates_per_s, run.spikes
        );
    }
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
