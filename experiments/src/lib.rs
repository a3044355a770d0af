//! # neurotac-experiments
//!
//! The experiments of neurotac and the `neurotac` command-line tool.
#![deny(missing_docs)]

pub mod afferents;
pub mod bench;
pub mod datasets;
pub mod neuron_setup;
pub mod neuron_tradeoff;
pub mod peers;
pub mod simulator_check;
pub mod simulator_tradeoff;
pub mod svg;
