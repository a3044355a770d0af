//! `neurotac tradeoff …`: without a subcommand, the accuracy ↔ cost study (classification
//! accuracy of the four codings against cost, per swept family, summary `tradeoff.md`; see
//! [`study`]); the subcommands measure the numerical error of one trade alone. The trades
//! themselves live in `neurotac_cli::tradeoff`; each handler maps its flags to the trade's
//! config and prints.
//!
//! To add a trade-off: the trade in `neurotac_cli::tradeoff`, then here a module with an
//! `Args` struct (clap derive) and a `run(args) -> anyhow::Result<()>`, one variant in
//! [`TradeoffCommand`] and one arm in [`run`].

use clap::{Args, Subcommand};

mod neurons;
mod simulator;
mod study;
mod vr;

/// `neurotac tradeoff [SUBCOMMAND]`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct TradeoffArgs {
    #[command(subcommand)]
    command: Option<TradeoffCommand>,
    #[command(flatten)]
    study: study::StudyArgs,
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

/// Runs one trade-off subcommand, or the study without one.
pub fn run(args: TradeoffArgs) -> anyhow::Result<()> {
    match args.command {
        None => study::run(args.study),
        Some(TradeoffCommand::Neurons(args)) => neurons::run(args),
        Some(TradeoffCommand::Vr(args)) => vr::run(args),
        Some(TradeoffCommand::Simulator(args)) => simulator::run(args),
    }
}
