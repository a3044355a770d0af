//! # neurotac-experiments
//!
//! The experiments of neurotac and the `neurotac` command-line tool. Every command is a library
//! entry point here that takes a config and a [`progress::Progress`]; the CLI (`src/cli/`, one
//! module per command) only maps flags to configs, draws progress bars and prints.
//!
//! The paper's pipeline from Rust:
//!
//! ```no_run
//! use neurotac_experiments::datasets::simulated::TextureSet;
//! use neurotac_experiments::progress::NoProgress;
//! use neurotac_experiments::reproduce::{ReproduceConfig, Source, run};
//! let config = ReproduceConfig::quick(1, std::env::temp_dir().join("neurotac-cache"));
//! let report = run(&config, &[Source::Simulated(TextureSet::Artificial)], &NoProgress)?;
//! neurotac_experiments::report::write_report("neurotac-report".as_ref(), &report, true)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | module | what it holds |
//! |---|---|
//! | [`reproduce`] | the paper end to end: [`reproduce::run`] (sources → [`reproduce::Report`]), one set through the pipeline ([`reproduce::run_set`]), the paper's numbers |
//! | [`report`] | a reproduction's report folder: Markdown tables, CSV, figures (SVG, PNG), atomic folder writing |
//! | [`datasets`] | taxel spike datasets: simulated (cached, `neurotac simulate`), recorded (event-file folders), synthetic; their typed metadata |
//! | [`coding`] | the four codings by name ([`coding::CodingName`]), a coding's distance matrix, the sample duration |
//! | [`protocols`] | leave-one-out, stratified split and k-fold on a distance matrix; [`protocols::Accuracy`] (mean ± std, Wilson 95 %), [`protocols::ConfusionMatrix`] |
//! | [`search`] | the Δt brute force ([`search::dt_sweep`]) and Bayesian optimisation of (τ, cos θ) ([`search::bayes`]) |
//! | [`afferents`] | taxel → afferent networks (the `demo` command, `reproduce --afferents`) |
//! | [`tradeoff`] | speed ↔ accuracy trade-offs (neurons, Van Rossum, simulator), their shared table and writers, the summary page |
//! | [`transduce`] | one event file → taxel spike dataset (`neurotac transduce`), layouts (`layout`), event filtering (`filter`) |
//! | [`bench`](mod@bench) | throughput benchmarks (neuron updates/s, the CUBA network) |
//! | [`neuron_setup`] | one neuron population set up by model, integrator and precision (bench, `neurotac neuron`, trade-offs) |
//! | [`peers`] | same-run comparisons against peer simulators (Brian2), as ratios |
//! | [`simulator_check`] | the simulator's acceptance statistics and calibration (`neurotac simulate check`, `calibrate`) |
//! | [`progress`] | the [`progress::Progress`] trait every long entry point reports to |
//! | [`threads`] | [`threads::with_threads`]: work on a pool of a chosen size |
//! | [`timing`] | wall and CPU time of a piece of work |
//! | [`error`] | [`ExperimentError`] |
#![deny(missing_docs)]

pub mod afferents;
pub mod bench;
pub mod coding;
pub mod datasets;
pub mod error;
pub mod export;
pub mod neuron_setup;
pub mod online;
pub mod peers;
pub mod progress;
pub mod protocols;
pub mod readouts;
pub mod report;
pub mod reproduce;
pub mod search;
pub mod simulator_check;
pub mod threads;
pub mod timing;
pub mod tradeoff;
pub mod transduce;

pub use error::ExperimentError;
