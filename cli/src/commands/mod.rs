//! The commands of the `neurotac` binary, one module each (a group of subcommands is a folder).
//! To add a command: a module with an `Args` struct (clap derive) and a
//! `run(args) -> anyhow::Result<()>`, one variant in [`Command`] and one arm in [`run`]. To add
//! a subcommand to a group (`tradeoff`, `search`), do the same inside the group's `mod.rs`.
//!
//! Imports point down: this dispatcher (and each group's `mod.rs`) names its commands, and the
//! commands name the helpers below them — [`options`] (the shared option groups and `--set`),
//! [`inputs`] (reading datasets), [`outputs`] (the overwrite rule), [`coding_parameters`],
//! [`args`] (value parsers) and [`progress`] (bars) — never the dispatcher. [`run_digest`] is
//! what MPI ranks compare before a command runs.

use clap::{Parser, Subcommand};
use neurotac_core::Ranks;

pub use run_digest::run_digest;

mod args;
mod bench;
mod classify;
mod coding_parameters;
mod convert;
mod demo;
mod devices;
mod distances;
mod export;
mod inputs;
mod neuron;
mod options;
mod outputs;
mod progress;
mod recognise;
mod record;
mod reproduce;
mod run_digest;
mod search;
mod simulate;
mod synth;
mod tradeoff;
mod transduce;
mod view;

/// neurotac: spiking neural networks for neuromorphic touch (the NeuroTac sensor).
#[derive(Debug, Parser)]
#[command(
    name = "neurotac",
    version,
    about,
    propagate_version = true,
    after_help = "Outputs: every command that writes refuses an existing output file or folder \
unless --force is given.\nCache: reproduce and simulate keep simulated datasets in \
~/.cache/neurotac ($XDG_CACHE_HOME/neurotac, or $NEUROTAC_CACHE when set); delete that \
folder to clear it."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Reproduce the NeuroTac paper: texture datasets → taxel spikes → four codings → KNN, with
    /// the paper's tables side by side and a report folder of figures.
    Reproduce(reproduce::ReproduceArgs),
    /// Run 49 taxel spike trains through 49 afferent neurons and print their spike counts.
    Demo(demo::DemoArgs),
    /// Measure throughput: neuron updates per second, or the CUBA network.
    Bench(bench::BenchArgs),
    /// Simulate one neuron under a constant current and print its spike times.
    Neuron(neuron::NeuronArgs),
    /// Write the N×N distance matrix of a spike dataset (.json, .npy or .npz by extension).
    Distances(distances::DistancesArgs),
    /// Classify a spike dataset with KNN under one coding and protocol.
    Classify(classify::ClassifyArgs),
    /// Convert a spike dataset to numpy's .npz (flat arrays), JSON or binary, by extension.
    Export(export::ExportArgs),
    /// Speed ↔ accuracy: without a subcommand, the classification accuracy of the four codings
    /// against cost per swept family (tradeoff.md); subcommands: one trade's numerical error.
    Tradeoff(tradeoff::TradeoffArgs),
    /// Parameter searches (Δt brute force, Bayesian optimisation of τ and cos θ).
    #[command(subcommand)]
    Search(search::SearchCommand),
    /// Write a seeded synthetic NeuroTac-like texture dataset.
    Synth(synth::SynthArgs),
    /// Event file → 49 taxel spike trains (BA filter, receptive fields, pooling, re-centring).
    Transduce(transduce::TransduceArgs),
    /// Event file → event file with the background-activity (and refractory) filter applied.
    Filter(transduce::FilterArgs),
    /// Find the 49 taxel centres in a short calibration recording.
    Layout(transduce::LayoutArgs),
    /// Convert an event file between AEDAT 2.0/3.1/4.0, ECD text and CSV (format from the extension).
    Convert(convert::ConvertArgs),
    /// List the DAVIS cameras attached over USB.
    Devices(devices::DevicesArgs),
    /// Record events from the first DAVIS240 attached to a file (format from the extension).
    Record(record::RecordArgs),
    /// Simulate the texture datasets (or `check` / `calibrate` the NeuroTac simulator).
    Simulate(simulate::SimulateArgs),
    /// Recognise a texture while the sensor slides (event file or live camera), a decision
    /// every pooling window; or `--eval` accuracy against time on a simulated set.
    Recognise(recognise::RecogniseArgs),
    /// A live page of the sensor on localhost — events, receptive fields, taxel rates, the
    /// spike raster, the recogniser's decisions — from a recording, the camera or the
    /// simulator; or `--snapshot` the same page to a PNG/SVG file.
    View(view::ViewArgs),
}

/// Runs the parsed command on `ranks` (one process, or the MPI ranks it was started on).
///
/// The distributed commands (`simulate`, `distances`, `classify`, `search`, `reproduce`,
/// `bench cuba`) split their work over the ranks and give the same output as one process;
/// rank 0 writes and prints. The others run on one process only.
pub fn run(cli: Cli, ranks: &dyn Ranks) -> anyhow::Result<()> {
    let single = |name: &str| -> anyhow::Result<()> {
        if ranks.size() > 1 {
            anyhow::bail!(
                "`neurotac {name}` runs on one process; it was started on {} MPI ranks \
                 (run it without mpirun, or see README \"Running on several machines\" for \
                 the commands that distribute)",
                ranks.size()
            );
        }
        Ok(())
    };
    let ran = match cli.command {
        Command::Reproduce(args) => reproduce::run(args, ranks),
        Command::Bench(args) => bench::run(args, ranks),
        Command::Distances(args) => distances::run(args, ranks),
        Command::Classify(args) => classify::run(args, ranks),
        Command::Search(command) => search::run(command, ranks),
        Command::Simulate(args) => simulate::run(args, ranks),
        Command::Demo(args) => single("demo").and_then(|()| demo::run(args)),
        Command::Neuron(args) => single("neuron").and_then(|()| neuron::run(args)),
        Command::Tradeoff(args) => single("tradeoff").and_then(|()| tradeoff::run(args)),
        Command::Synth(args) => single("synth").and_then(|()| synth::run(args)),
        Command::Export(args) => single("export").and_then(|()| export::run(args)),
        Command::Transduce(args) => {
            single("transduce").and_then(|()| transduce::run_transduce(args))
        }
        Command::Filter(args) => single("filter").and_then(|()| transduce::run_filter(args)),
        Command::Layout(args) => single("layout").and_then(|()| transduce::run_layout(args)),
        Command::Convert(args) => single("convert").and_then(|()| convert::run(args)),
        Command::Devices(args) => single("devices").and_then(|()| devices::run(args)),
        Command::Record(args) => single("record").and_then(|()| record::run(args)),
        Command::Recognise(args) => single("recognise").and_then(|()| recognise::run(args)),
        Command::View(args) => single("view").and_then(|()| view::run(args)),
    };
    ran.map_err(outputs::exists_as_refusal)
}

#[cfg(test)]
mod tests {
    use super::Cli;
    use clap::CommandFactory;

    /// clap's own checks over every command: the flags named by `requires`, `conflicts_with` and
    /// `required_unless_present` exist, and no flag is declared twice (a shared option group
    /// flattened beside a flag of the same name).
    #[test]
    fn every_command_passes_clap_checks() {
        Cli::command().debug_assert();
    }

    /// One unit per quantity: no flag of any command is named after a time unit or documented
    /// as taking bare seconds or microseconds; the time flags say how they read a value.
    #[test]
    fn no_time_flag_takes_a_bare_unit_of_its_own() {
        fn walk(cmd: &clap::Command, path: &str, bad: &mut Vec<String>, timed: &mut usize) {
            for arg in cmd
                .get_arguments()
                .filter(|a| a.get_action().takes_values())
            {
                let id = arg.get_id().as_str();
                let help = arg
                    .get_long_help()
                    .or(arg.get_help())
                    .map(|h| h.to_string())
                    .unwrap_or_default();
                let unit_named =
                    ["_ms", "_us", "_s"].iter().any(|u| id.ends_with(u)) || id == "seconds";
                const HOW: &str = "(ms, or with a unit: 20ms, 0.02s";
                let rest = help.replace(HOW, "");
                let bare_unit = [" (s)", " (s,", " (s;", " (ms)", " (ms,", " (µs)", " (µs,"]
                    .iter()
                    .any(|u| rest.contains(u));
                if unit_named || bare_unit {
                    bad.push(format!("{path} --{id}: {help}"));
                }
                *timed += help.contains(HOW) as usize;
            }
            for sub in cmd.get_subcommands() {
                walk(sub, &format!("{path} {}", sub.get_name()), bad, timed);
            }
        }
        let (mut bad, mut timed) = (Vec::new(), 0);
        walk(&Cli::command(), "neurotac", &mut bad, &mut timed);
        assert!(bad.is_empty(), "{bad:#?}");
        assert!(
            timed >= 30,
            "only {timed} time flags say how they read a value"
        );
    }
}
