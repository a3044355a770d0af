//! `neurotac search …`: the paper's parameter searches.
//!
//! To add a search: a module with an `Args` struct (clap derive) and a
//! `run(args) -> anyhow::Result<()>`, one variant in [`SearchCommand`] and one arm in [`run`].

use clap::Subcommand;
use neurotac_core::Ranks;

mod dt;
mod vr;

/// The searches.
#[derive(Debug, Subcommand)]
pub enum SearchCommand {
    /// Temporal coding: leave-one-out accuracy for every window Δt = 1…200 ms (brute force).
    Dt(dt::DtArgs),
    /// Spatiotemporal coding: Bayesian optimisation of (τ, cos θ) for leave-one-out accuracy.
    Vr(vr::VrArgs),
}

/// Runs one search subcommand.
pub fn run(command: SearchCommand, ranks: &dyn Ranks) -> anyhow::Result<()> {
    match command {
        SearchCommand::Dt(args) => dt::run(args, ranks),
        SearchCommand::Vr(args) => vr::run(args, ranks),
    }
}
