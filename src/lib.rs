//! # neurotac
//!
//! Spiking neural networks for neuromorphic touch. This facade re-exports the workspace crates:
//!
//! | module | crate | what it holds |
//! |---|---|---|
//! | [`core`] | `neurotac-core` | time, spikes, events, datasets, the network graph, readouts, codings, distances, KNN |
//! | [`neurons`] | `neurotac-neurons` | LIF and Izhikevich populations, integrators |
//! | [`sensor`] | `neurotac-sensor` | the DAVIS240 camera, event files, transduction, the simulator |
//! | [`experiments`] | `neurotac-experiments` | texture experiments, protocols, parameter searches, reports |
//! | [`view`] | `neurotac-view` | the live view of a stream: frames, their SVG drawing, the player and the page's server |
//!
//! Data flows one way: sensor → core graph → readouts → experiments. See `examples/` for
//! networks defined in Rust code.
#![deny(missing_docs)]

pub use neurotac_core as core;
pub use neurotac_experiments as experiments;
pub use neurotac_neurons as neurons;
pub use neurotac_sensor as sensor;
pub use neurotac_view as view;
