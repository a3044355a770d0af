//! The commands of the `neurotac` binary, one module each. To add a command: a module with an
//! `Args` struct (clap derive) and a `run(args) -> anyhow::Result<()>`, one variant in
//! [`Command`] and one arm in [`run`].

use clap::{Parser, Subcommand};

mod convert;
mod demo;
mod devices;
mod record;

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
    /// Convert an event file between AEDAT 2.0/3.1/4.0, ECD text and CSV (format from the extension).
    Convert(convert::ConvertArgs),
    /// List the DAVIS cameras attached over USB.
    Devices(devices::DevicesArgs),
    /// Record events from the first DAVIS240 attached to a file (format from the extension).
    Record(record::RecordArgs),
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Demo(args) => demo::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Devices(args) => devices::run(args),
        Command::Record(args) => record::run(args),
    }
}
