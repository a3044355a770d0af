//! # neurotac-experiments
//!
//! The experiments of neurotac and the `neurotac` command-line tool.
//!
//! | module | what it holds |
//! |---|---|
//! | [`reproduce`] | the paper end to end on one set ([`reproduce::run_set`]), its report folder and the paper's numbers (`neurotac reproduce`) |
//! | [`afferents`] | taxel → afferent networks (the `demo` command, `reproduce --afferents`) |
//! | [`protocols`] | leave-one-out, stratified split and k-fold on a distance matrix; [`protocols::Accuracy`] (mean ± std, Wilson 95 %), [`protocols::ConfusionMatrix`] |
//! | [`recorded`] | recorded texture datasets: a folder of event files per class → taxel spike dataset ([`recorded::load_recorded`]) |
//! | [`search`] | the Δt brute force ([`search::dt_sweep`]) and Bayesian optimisation of (τ, cos θ) ([`search::bayes`]) |
//! | [`synthetic`] | seeded NeuroTac-like texture datasets for benchmarks and trials |
//! | [`figures`], [`svg`], [`png`] | paper-style figures as SVG, and their PNG copies |
//! | [`timing`] | wall and CPU time of a piece of work |
//! | [`error`] | [`ExperimentError`] |
#![deny(missing_docs)]

pub mod afferents;
pub mod bench;
pub mod datasets;
pub mod error;
pub mod figures;
pub mod neuron_setup;
pub mod neuron_tradeoff;
pub mod pareto;
pub mod peers;
pub mod png;
pub mod protocols;
pub mod recorded;
pub mod reproduce;
pub mod search;
pub mod simulator_check;
pub mod simulator_tradeoff;
pub mod svg;
pub mod synthetic;
pub mod timing;
pub mod tradeoff_summary;
pub mod vr_tradeoff;

pub use error::ExperimentError;
