//! The commands of the `neurotac` binary, one module each. To add a command: a module with an
//! `Args` struct (clap derive) and a `run(args) -> anyhow::Result<()>`, one variant in
//! [`Command`] and one arm in [`run`].

use clap::{Parser, Subcommand};

mod bench;
mod demo;
mod neuron;
mod simulate;
mod tradeoff;

/// neurotac: spiking neural networks for neuromorphic touch (the NeuroTac sensor).
#[derive(Debug, Parser)]
#[command(name = "neurotac", version, about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run 49 taxel spike trains through 49 afferent neurons and print their spike counts.
    Demo(demo::DemoArgs),
    /// Measure throughput: neuron updates per second, or the CUBA network.
    Bench(bench::BenchArgs),
    /// Simulate one neuron under a constant current and print its spike times.
    Neuron(neuron::NeuronArgs),
    /// Speed ↔ accuracy reports (tables and SVG plots).
    Tradeoff(tradeoff::TradeoffArgs),
    /// Simulate the texture datasets (or `check` / `calibrate` the NeuroTac simulator).
    Simulate(simulate::SimulateArgs),
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Demo(args) => demo::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Neuron(args) => neuron::run(args),
        Command::Tradeoff(args) => tradeoff::run(args),
        Command::Simulate(args) => simulate::run(args),
    }
}
