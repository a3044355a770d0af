//! Parameter searches of the paper: the temporal coding's window Δt by brute force
//! ([`dt_sweep`]) and the spatiotemporal coding's (τ, cos θ) by Bayesian optimisation
//! ([`bayes`]).

pub mod bayes;
pub mod dt_sweep;
