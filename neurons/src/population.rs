//! What LIF and Izhikevich populations share: initial conditions, the block layout that makes
//! parallel stepping deterministic, and turning per-block spike masks into a [`SpikeBuffer`].
//!
//! State is structure-of-arrays, cut into blocks of [`BLOCK`] neurons (each block holds its own
//! arrays). A step runs one fused update + threshold + reset loop per block, writing a 0/1 spike
//! mask; blocks run on rayon's pool when the population is large ([`PARALLEL_MIN`]) and the pool
//! has more than one thread, else in order on the caller's thread. The arithmetic of a neuron
//! never depends on the block split, so results are bit-identical at any thread count.

use neurotac_core::{ModelError, NeuronModel, SpikeBuffer};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Neurons per block.
pub const BLOCK: usize = 4096;

/// Smallest population stepped in parallel.
pub const PARALLEL_MIN: usize = 1 << 15;

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
    /// The values for `n` neurons, validated (finite; a list must have `n` entries).
    pub(crate) fn values(&self, model: &'static str, n: usize) -> Result<Vec<f64>, ModelError> {
        let bad = |field, value, expected| ModelError::InvalidParameter {
            model,
            field,
            value,
            expected,
        };
        let v = match self {
            InitialPotential::Constant(v) => vec![*v; n],
            InitialPotential::Uniform { low, high, seed } => {
                if !(low.is_finite() && high.is_finite() && low <= high) {
                    return Err(bad("initial potential range", *low, "finite low ≤ high"));
                }
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                (0..n)
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
                v.clone()
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

    /// Input for neuron `i` (block-local when the drive was cut with [`block`](Self::block)).
    #[inline]
    pub(crate) fn at(self, i: usize) -> f64 {
        match self {
            Drive::Constant(c) => c,
            Drive::PerNeuron(x) => x[i],
        }
    }
}

/// What block-stepped populations (LIF, Izhikevich) share beyond [`NeuronModel`]: stepping
/// under a [`Drive`], and the checked and benchmark entry points built on it.
pub trait Population: NeuronModel {
    /// Advances every neuron one step under `drive` and returns the number of spikes, without
    /// recording indices. The population must be prepared.
    fn advance(&mut self, drive: Drive<'_>) -> u64;

    /// The time step the population is prepared for, if it is.
    fn prepared_dt(&self) -> Option<f64>;

    /// Prepares (if needed) and runs `steps` steps of `dt_s` with the same input `current` for
    /// every neuron, without recording spike indices; returns the number of spikes. This is the
    /// benchmark path; it steps exactly as a network does.
    fn run_constant(&mut self, current: f64, dt_s: f64, steps: u64) -> Result<u64, ModelError> {
        if !current.is_finite() {
            return Err(ModelError::NonFiniteInput {
                model: self.model_name(),
                neuron: 0,
                value: current,
            });
        }
        if self.prepared_dt() != Some(dt_s) {
            self.prepare(dt_s)?;
        }
        Ok((0..steps)
            .map(|_| self.advance(Drive::Constant(current)))
            .sum())
    }

    /// One network-style step with per-neuron input, rejecting input of the wrong length or
    /// with NaN/±∞ values with a typed error (the state is then untouched).
    fn step_checked(
        &mut self,
        current: &[f64],
        spikes: &mut SpikeBuffer,
    ) -> Result<(), ModelError> {
        let model = self.model_name();
        if let Some(i) = current.iter().position(|x| !x.is_finite()) {
            return Err(ModelError::NonFiniteInput {
                model,
                neuron: i,
                value: current[i],
            });
        }
        if current.len() != self.len() {
            return Err(ModelError::InvalidParameter {
                model,
                field: "input length",
                value: current.len() as f64,
                expected: "one value per neuron",
            });
        }
        spikes.clear();
        self.step(current, spikes);
        Ok(())
    }
}

/// Number of blocks for `n` neurons and the length of block `b`.
pub(crate) fn block_len(n: usize, b: usize) -> usize {
    (n - b * BLOCK).min(BLOCK)
}

pub(crate) fn n_blocks(n: usize) -> usize {
    n.div_ceil(BLOCK)
}

/// Runs `f` on every block (in parallel when worthwhile) and sums what it returns.
pub(crate) fn for_blocks<B: Send>(
    blocks: &mut [B],
    n: usize,
    f: impl Fn(usize, &mut B) -> u64 + Sync,
) -> u64 {
    if n >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
        blocks
            .par_iter_mut()
            .enumerate()
            .map(|(b, blk)| f(b, blk))
            .sum()
    } else {
        blocks
            .iter_mut()
            .enumerate()
            .map(|(b, blk)| f(b, blk))
            .sum()
    }
}

/// Calls `f(i)` for every `i` with `mask[i] != 0`, skipping eight silent neurons at a time.
#[inline]
pub(crate) fn for_each_spike(mask: &[u8], mut f: impl FnMut(usize)) {
    let mut words = mask.chunks_exact(8);
    let mut base = 0;
    for word in words.by_ref() {
        if u64::from_ne_bytes(word.try_into().expect("8 bytes")) != 0 {
            (0..8).filter(|&j| word[j] != 0).for_each(|j| f(base + j));
        }
        base += 8;
    }
    let rest = words.remainder();
    (0..rest.len())
        .filter(|&j| rest[j] != 0)
        .for_each(|j| f(base + j));
}

/// Pushes the spikes recorded in `mask` (block `b`) into `out`, with `phi` fractions when given.
#[inline]
pub(crate) fn collect_block_spikes<F: crate::Real>(
    b: usize,
    mask: &[u8],
    phi: Option<&[F]>,
    out: &mut SpikeBuffer,
) {
    let base = b * BLOCK;
    for_each_spike(mask, |i| match phi {
        Some(p) => out.push_at((base + i) as u32, unit_fraction(p[i].f64())),
        None => out.push((base + i) as u32),
    });
}

/// An in-step spike fraction limited to `[0, 1]`; NaN (a 0/0 crossing) means the end of the step.
#[inline]
pub(crate) fn unit_fraction(phi: f64) -> f64 {
    if phi.is_nan() {
        1.0
    } else {
        phi.clamp(0.0, 1.0)
    }
}

/// Validates that `x` is finite and, optionally, positive.
pub(crate) fn check_param(
    model: &'static str,
    field: &'static str,
    x: f64,
    positive: bool,
) -> Result<(), ModelError> {
    if !x.is_finite() || (positive && x <= 0.0) {
        return Err(ModelError::InvalidParameter {
            model,
            field,
            value: x,
            expected: if positive { "finite and > 0" } else { "finite" },
        });
    }
    Ok(())
}

/// Validates a time step.
pub(crate) fn check_dt(model: &'static str, dt_s: f64) -> Result<(), ModelError> {
    check_param(model, "dt_s", dt_s, true)
}
