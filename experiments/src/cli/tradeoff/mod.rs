//! `neurotac tradeoff …`: speed ↔ accuracy reports, one subcommand per trade.
//!
//! To add a trade-off: a module with an `Args` struct (clap derive) and a
//! `run(args) -> anyhow::Result<()>`, one variant in [`TradeoffCommand`] and one arm in [`run`].

use clap::Subcommand;

mod neurons;
mod simulator;
mod vr;

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

/// Runs one trade-off subcommand.
pub fn run(command: TradeoffCommand) -> anyhow::Result<()> {
    match command {
        TradeoffCommand::Neurons(args) => neurons::run(args),
        TradeoffCommand::Vr(args) => vr::run(args),
        TradeoffCommand::Simulator(args) => simulator::run(args),
    }
}
