//! What LIF and Izhikevich populations share: initial conditions, the block layout that makes
//! parallel stepping deterministic, turning per-block spike masks into a [`SpikeBuffer`](neurotac_core::SpikeBuffer), and
//! the population itself, [`BlockPopulation`], generic over the per-model part ([`BlockModel`]:
//! parameters, block state, per-step constants, the fused step of one block).
//!
//! State is structure-of-arrays, cut into blocks of [`BLOCK`] neurons (each block holds its own
//! arrays). A step runs one fused update + threshold + reset loop per block, writing a 0/1 spike
//! mask; blocks run on rayon's pool when the population is large ([`PARALLEL_MIN`]) and the pool
//! has more than one thread, else in order on the caller's thread. The arithmetic of a neuron
//! never depends on the block split, so results are bit-identical at any thread count.

mod active;
mod block_population;
mod blocks;
mod checks;
mod inputs;
mod model;
mod saving;
mod settings;
mod stepping;

pub use active::{ActiveNeurons, ActiveStep};
pub use block_population::BlockPopulation;
pub use blocks::{BLOCK, BlockStep, PARALLEL_MIN, for_each_spike, unit_fraction};
pub(crate) use blocks::{DIVERGED_BIT, count_ones, take_diverged};
pub use checks::{check_param, check_representable, check_reset_and_floor};
pub use inputs::{Drive, InitialPotential};
pub use model::BlockModel;
pub(crate) use saving::precision;
pub(crate) use settings::{Fields, floor, number};
pub use stepping::{DIVERGENCE_CHECK_STEPS, Population};
