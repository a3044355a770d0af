//! `neurotac tradeoff …`: speed ↔ accuracy reports, one subcommand per trade.

use clap::{Args, Subcommand};

mod neurons;
mod simulator;

#[derive(Debug, Args)]
pub struct TradeoffArgs {
    #[command(subcommand)]
    what: TradeoffCommand,
}

#[derive(Debug, Subcommand)]
enum TradeoffCommand {
    /// Neuron simulation: model × integrator × dt × precision × spike stamping.
    Neurons(neurons::NeuronsArgs),
    /// NeuroTac simulator: pixel-model step tolerance vs event timing and trials/s.
    Simulator(simulator::SimulatorArgs),
}

pub fn run(args: TradeoffArgs) -> anyhow::Result<()> {
    match args.what {
        TradeoffCommand::Neurons(a) => neurons::run(a),
        TradeoffCommand::Simulator(a) => simulator::run(a),
    }
}
