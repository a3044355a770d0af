//! The block layout of a population's state: blocks of [`BLOCK`] neurons, stepped in order or
//! on rayon's pool ([`PARALLEL_MIN`]), what one block's step returns ([`BlockStep`]), and the
//! per-block spike mask turned into a [`SpikeBuffer`] (with divergence flags and in-step
//! fractions).
//!
//! The arithmetic of a neuron never depends on the block split, so the parallel and the
//! sequential walk over the blocks give bit-identical results.

use crate::real::Real;
use neurotac_core::{SpikeBuffer, SynapticDrive};
use rayon::prelude::*;

/// Neurons per block.
pub const BLOCK: usize = 4096;

/// Smallest population stepped in parallel.
pub const PARALLEL_MIN: usize = 1 << 15;

/// What one block's step returns: its spikes, and how many of them (or of its state updates)
/// the model's divergence criterion flagged.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BlockStep {
    /// Spikes in the block.
    pub spikes: u64,
    /// Nonzero when the model's divergence criterion flagged an update of the block (see each
    /// model's docs): the flagged spikes, plus one for any non-finite update.
    pub diverged: u64,
}

impl BlockStep {
    /// One neuron's step ([`BlockModel::step_neuron`](super::BlockModel::step_neuron)) without a divergence flag: its spike.
    #[inline(always)]
    pub fn one_neuron(spiked: bool) -> BlockStep {
        BlockStep {
            spikes: u64::from(spiked),
            diverged: 0,
        }
    }

    #[inline]
    pub(crate) fn add(self, other: BlockStep) -> BlockStep {
        BlockStep {
            spikes: self.spikes + other.spikes,
            diverged: self.diverged + other.diverged,
        }
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
    f: impl Fn(usize, &mut B) -> BlockStep + Sync,
) -> BlockStep {
    if n >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
        blocks
            .par_iter_mut()
            .enumerate()
            .map(|(b, blk)| f(b, blk))
            .reduce(BlockStep::default, BlockStep::add)
    } else {
        blocks
            .iter_mut()
            .enumerate()
            .map(|(b, blk)| f(b, blk))
            .fold(BlockStep::default(), BlockStep::add)
    }
}

/// Runs `f` on every block with its part of `drive` (halving the blocks over rayon's pool
/// when `parallel`) and sums what it returns.
pub(super) fn step_blocks_synaptic<B: Send>(
    blocks: &mut [B],
    drive: SynapticDrive<'_>,
    parallel: bool,
    f: &(impl Fn(&mut B, SynapticDrive<'_>) -> BlockStep + Sync),
) -> BlockStep {
    match blocks {
        [] => BlockStep::default(),
        [block] => f(block, drive),
        _ => {
            let mid = blocks.len() / 2;
            let (left, right) = blocks.split_at_mut(mid);
            let (d_left, d_right) = drive.split_at(mid * BLOCK);
            let (a, b) = if parallel {
                rayon::join(
                    || step_blocks_synaptic(left, d_left, parallel, f),
                    || step_blocks_synaptic(right, d_right, parallel, f),
                )
            } else {
                (
                    step_blocks_synaptic(left, d_left, parallel, f),
                    step_blocks_synaptic(right, d_right, parallel, f),
                )
            };
            a.add(b)
        }
    }
}

/// Bit of a block's spike-mask byte that the fused step sets for a neuron whose update the
/// model's divergence criterion flagged; [`take_diverged`] clears it before the mask is read.
pub(crate) const DIVERGED_BIT: u8 = 2;

/// `true` when some neuron of a block's mask carries [`DIVERGED_BIT`] (one pass over the bytes).
#[inline]
pub(crate) fn has_flags(mask: &[u8]) -> bool {
    mask.iter().fold(0, |acc, &m| acc | m) & DIVERGED_BIT != 0
}

/// The number of neurons flagged with [`DIVERGED_BIT`] in a block's mask, clearing the bit so
/// the mask is 0/1 again: one pass over the mask bytes per block (a second pass, clearing,
/// only when something was flagged).
#[inline]
pub(crate) fn take_diverged(mask: &mut [u8]) -> u64 {
    if !has_flags(mask) {
        return 0;
    }
    let mut flagged = 0;
    for m in mask {
        flagged += u64::from(*m >> 1);
        *m &= 1;
    }
    flagged
}

/// The number of ones in a block's mask of 0/1 bytes (no [`DIVERGED_BIT`]s), eight bytes at a
/// time: a fused loop that counts its spikes here, after the loop, instead of in it spends one
/// vector addition per 32 neurons instead of a compare and a subtraction per vector of states.
#[inline]
pub(crate) fn count_ones(mask: &[u8]) -> u64 {
    const LOW_BYTES: u64 = 0x00ff_00ff_00ff_00ff;
    let mut total = 0;
    // Up to 255 words per sum, so that no byte lane of `acc` overflows.
    for group in mask.chunks(8 * 255) {
        let mut words = group.chunks_exact(8);
        let mut acc = 0u64;
        for word in words.by_ref() {
            acc += u64::from_ne_bytes(word.try_into().expect("8 bytes"));
        }
        // Byte lanes summed in pairs (16-bit lanes ≤ 510), then the four lanes by one multiply.
        let pairs = (acc & LOW_BYTES) + ((acc >> 8) & LOW_BYTES);
        total += pairs.wrapping_mul(0x0001_0001_0001_0001) >> 48;
        total += words.remainder().iter().map(|&m| u64::from(m)).sum::<u64>();
    }
    total
}

/// Calls `f(i)` for every `i` with `mask[i] != 0`, skipping eight silent neurons at a time.
#[inline]
pub fn for_each_spike(mask: &[u8], mut f: impl FnMut(usize)) {
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
pub(crate) fn collect_block_spikes<F: Real>(
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
pub fn unit_fraction(phi: f64) -> f64 {
    if phi.is_nan() {
        1.0
    } else {
        phi.clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_ones_counts_the_spikes_of_any_mask_length() {
        // Past 255 words a byte lane of the running sum would overflow: 5000 bytes cross it.
        for len in [0, 1, 7, 8, 9, 2040, 2041, 4096, 5000] {
            let mask: Vec<u8> = (0..len).map(|i| u8::from(i % 3 != 1)).collect();
            let ones = mask.iter().filter(|&&m| m == 1).count() as u64;
            assert_eq!(count_ones(&mask), ones, "{len}");
            assert_eq!(count_ones(&vec![1; len]), len as u64, "{len}");
        }
    }
}
