//! `neurotac tradeoff …`: speed ↔ accuracy reports, one subcommand per trade; without a
//! subcommand, every trade and one summary page (`tradeoff.md`, see [`all`]).
//!
//! To add a trade-off: a module with an `Args` struct (clap derive), a `report` function that
//! measures and writes the trade's files (called by both paths) and a
//! `run(args) -> anyhow::Result<()>`, one variant in [`TradeoffCommand`], one arm in [`run`], and
//! a section in `neurotac_experiments::tradeoff_summary`.

use anyhow::Context;
use clap::{Args, Subcommand};
use std::path::Path;

mod all;
mod neurons;
mod simulator;
mod vr;

/// `neurotac tradeoff [SUBCOMMAND]`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct TradeoffArgs {
    #[command(subcommand)]
    command: Option<TradeoffCommand>,
    #[command(flatten)]
    all: all::AllArgs,
}

/// The trade-offs.
#[derive(Debug, Subcommand)]
pub enum TradeoffCommand {
    /// Neuron simulation: model × integrator × dt × precision × spike stamping.
    Neurons(neurons::NeuronsArgs),
    /// Trace-sampled vs exact multi-unit Van Rossum: relative error and time against dt.
    Vr(vr::VrArgs),
    /// NeuroTac simulator: pixel-model step tolerance vs event timing and trials/s.
    Simulator(simulator::SimulatorArgs),
}

/// Runs one trade-off subcommand, or all of them without one.
pub fn run(args: TradeoffArgs) -> anyhow::Result<()> {
    match args.command {
        None => all::run(args.all),
        Some(TradeoffCommand::Neurons(args)) => neurons::run(args),
        Some(TradeoffCommand::Vr(args)) => vr::run(args),
        Some(TradeoffCommand::Simulator(args)) => simulator::run(args),
    }
}

/// Creates `dir` and writes each `(file name, text)` into it.
fn write_files(dir: &Path, files: &[(&str, String)]) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (name, text) in files {
        let path = dir.join(name);
        neurotac_core::io::write(&path, text)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}
