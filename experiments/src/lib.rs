//! # neurotac-experiments
//!
//! The experiments of neurotac and the `neurotac` command-line tool.
#![deny(missing_docs)]

pub mod afferents;
