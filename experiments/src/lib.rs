//! # neurotac-experiments
//!
//! The NeuroTac paper's pipeline as a library: texture datasets, codings, protocols, parameter
//! searches, online recognition and the whole reproduction. Every long operation is an entry
//! point that takes a config and a [`progress::Progress`]. The `neurotac` command (crate
//! `neurotac-cli`) maps flags to these configs, draws progress bars and renders reports; nothing
//! here depends on it.
//!
//! The paper's pipeline from Rust:
//!
//! ```no_run
//! use neurotac_experiments::datasets::simulated::TextureSet;
//! use neurotac_experiments::progress::NoProgress;
//! use neurotac_experiments::reproduce::{ReproduceConfig, Source, run};
//! let config = ReproduceConfig::quick(1, std::env::temp_dir().join("neurotac-cache"));
//! let artificial = [Source::Simulated(TextureSet::Artificial)];
//! let report = run(&config, &artificial, &NoProgress, &neurotac_core::OneProcess)?;
//! println!("{}", serde_json::to_string_pretty(&report.sets[0].direct)?);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | module | what it holds |
//! |---|---|
//! | [`reproduce`] | the paper end to end: [`reproduce::run`] (sources → [`reproduce::Report`]), one set through the pipeline ([`reproduce::run_set`]), the paper's numbers |
//! | [`datasets`] | taxel spike datasets: simulated (cached, `neurotac simulate`), recorded (event-file folders), synthetic; their typed metadata |
//! | [`coding`] | the four codings by name ([`coding::CodingName`]), a coding's distance matrix, the sample duration |
//! | [`protocols`] | leave-one-out, stratified split and k-fold on a distance matrix; [`protocols::Accuracy`] (mean ± std, Wilson 95 %), [`protocols::ConfusionMatrix`] |
//! | [`search`] | the Δt brute force ([`search::dt_sweep`]) and Bayesian optimisation of (τ, cos θ) ([`search::bayes`]) |
//! | [`afferents`] | taxel → afferent networks (the `demo` command, `reproduce --afferents`) |
//! | [`transduce`] | one event file → taxel spike dataset (`neurotac transduce`), layouts (`layout`), event filtering (`filter`) |
//! | [`neuron_setup`] | the menu of neuron models ([`neuron_setup::NeuronKind`]: one registration line per model, dispatching to its `ModelFamily`); one neuron population set up by model, integrator and precision (bench, `neurotac neuron`, trade-offs) |
//! | [`song_abbott`] | Song, Miller & Abbott's STDP network (Poisson inputs → one LIF through additive STDP), its final weights compared with a peer's |
//! | [`statistics`] | the two-sample Kolmogorov–Smirnov test ([`statistics::kolmogorov_smirnov`]) |
//! | [`progress`] | the [`progress::Progress`] trait every long entry point reports to |
//! | [`threads`] | [`threads::with_threads`]: work on a pool of a chosen size |
//! | [`timing`] | wall and CPU time of a piece of work |
//! | [`menu`] | the [`menu::Menu`] trait: one enum per menu (codings, neuron models, precisions) with `FromStr` / `Display` from its keys |
//! | [`error`] | [`ExperimentError`] |
#![deny(missing_docs)]

pub mod afferents;
pub mod coding;
pub mod datasets;
pub mod error;
pub mod export;
pub mod menu;
pub mod neuron_setup;
pub mod online;
pub mod progress;
pub mod protocols;
pub mod readouts;
pub mod reproduce;
pub mod scoring;
pub mod search;
pub mod song_abbott;
pub mod statistics;
pub mod threads;
pub mod timing;
pub mod transduce;

pub use error::ExperimentError;
