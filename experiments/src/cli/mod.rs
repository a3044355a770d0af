//! The commands of the `neurotac` binary, one module each. To add a command: a module with an
//! `Args` struct (clap derive) and a `run(args) -> anyhow::Result<()>`, one variant in
//! [`Command`] and one arm in [`run`].

use clap::{Parser, Subcommand};

mod demo;

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
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Demo(args) => demo::run(args),
    }
}
