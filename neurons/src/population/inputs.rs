//! What a population starts from and what drives one of its steps: the initial membrane
//! potentials ([`InitialPotential`], validated at `prepare`) and the input of one step
//! ([`Drive`]: one value for all neurons, or one per neuron).

use super::blocks::BLOCK;
use neurotac_core::ModelError;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ops::Range;

/// Initial membrane potential of each neuron.
#[derive(Debug, Clone, PartialEq)]
pub enum InitialPotential {
    /// The same value for every neuron.
    Constant(f64),
    /// Independent uniform draws in `[low, high)` from a ChaCha8 generator seeded with `seed`.
    Uniform {
        /// Lower bound (inclusive).
        low: f64,
        /// Upper bound (exclusive).
        high: f64,
        /// Seed.
        seed: u64,
    },
    /// One value per neuron.
    Values(Vec<f64>),
}

impl InitialPotential {
    /// The values of neurons `block` of a population of `n`, validated as for all `n` (finite;
    /// a list must have `n` entries); computed for the block only, each neuron's value as in
    /// the whole population (a uniform draw seeks to the block's place in the seeded stream).
    pub(crate) fn values(
        &self,
        model: &'static str,
        n: usize,
        block: Range<usize>,
    ) -> Result<Vec<f64>, ModelError> {
        let bad = |field, value, expected| ModelError::InvalidParameter {
            model,
            field,
            value,
            expected,
        };
        if block.start > block.end || block.end > n {
            return Err(bad(
                "neuron block (end)",
                block.end as f64,
                "a block of the population's neurons",
            ));
        }
        let v = match self {
            InitialPotential::Constant(v) => vec![*v; block.len()],
            InitialPotential::Uniform { low, high, seed } => {
                if !(low.is_finite() && high.is_finite() && low <= high) {
                    return Err(bad("initial potential range", *low, "finite low ≤ high"));
                }
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                // Each draw is one 64-bit output, two 32-bit words of the stream.
                rng.set_word_pos(2 * block.start as u128);
                block
                    .clone()
                    .map(|_| low + (high - low) * rng.random::<f64>())
                    .collect()
            }
            InitialPotential::Values(v) => {
                if v.len() != n {
                    return Err(bad(
                        "initial potentials (count)",
                        v.len() as f64,
                        "one value per neuron",
                    ));
                }
                // Every value is checked, not only the block's: each rank refuses the same list.
                if let Some(&x) = v.iter().find(|x| !x.is_finite()) {
                    return Err(bad("initial potential", x, "finite"));
                }
                v[block].to_vec()
            }
        };
        match v.iter().find(|x| !x.is_finite()) {
            Some(&x) => Err(bad("initial potential", x, "finite")),
            None => Ok(v),
        }
    }
}

/// The input of one step: one value for all neurons, or one per neuron.
#[derive(Debug, Clone, Copy)]
pub enum Drive<'a> {
    /// The same input for every neuron.
    Constant(f64),
    /// `input[i]` for neuron `i`.
    PerNeuron(&'a [f64]),
}

impl<'a> Drive<'a> {
    /// The part of this drive that feeds block `b`.
    #[inline]
    pub(crate) fn block(self, b: usize, len: usize) -> Drive<'a> {
        match self {
            Drive::Constant(c) => Drive::Constant(c),
            Drive::PerNeuron(x) => Drive::PerNeuron(&x[b * BLOCK..b * BLOCK + len]),
        }
    }

    /// Input for neuron `i` (block-local inside [`BlockModel::step_block`](super::BlockModel::step_block)).
    #[inline]
    pub fn at(self, i: usize) -> f64 {
        match self {
            Drive::Constant(c) => c,
            Drive::PerNeuron(x) => x[i],
        }
    }
}
