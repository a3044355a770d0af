//! The spike exchange of a network partitioned over ranks: one rank's spikes of an epoch packed
//! into bytes, and every rank's unpacked into the spike histories (see
//! [`Network::run_steps`](super::Network::run_steps)).
//!
//! A message is a status byte (0, or 1 when the rank's populations diverged), then, for every
//! exchanged population in node order: the spike count of each step of the epoch (`u32`), a
//! flag byte (1 when fractions follow), the spikes' global indices of all the epoch's steps
//! (`u32`), and, when flagged, their in-step fractions (`f64`); all little-endian. Fractions
//! are sent only when one of the population's spikes in the epoch has `φ ≠ 1`.

use super::running::RunningNode;
use crate::error::GraphError;
use crate::model::SpikeBuffer;
use std::ops::Range;

/// The history slot of step `k` of node `n`.
fn slot(n: &RunningNode, k: u64) -> usize {
    (k % n.history.len() as u64) as usize
}

/// Writes this rank's message for the epoch `steps` into `out` (cleared first).
pub(super) fn pack_epoch(
    nodes: &[RunningNode],
    exchanged: &[usize],
    steps: Range<u64>,
    diverged: bool,
    out: &mut Vec<u8>,
) {
    out.clear();
    out.push(u8::from(diverged));
    for &i in exchanged {
        let n = &nodes[i];
        let buffers = || steps.clone().map(|k| &n.history[slot(n, k)]);
        for b in buffers() {
            out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        }
        let fractional = buffers().any(|b| b.fractions().iter().any(|&phi| phi != 1.0));
        out.push(u8::from(fractional));
        for b in buffers() {
            b.indices()
                .iter()
                .for_each(|i| out.extend_from_slice(&i.to_le_bytes()));
        }
        if fractional {
            for b in buffers() {
                b.fractions()
                    .iter()
                    .for_each(|phi| out.extend_from_slice(&phi.to_le_bytes()));
            }
        }
    }
}

/// A cursor over one rank's message.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: Option<usize>) -> Result<&'a [u8], String> {
        let end = n
            .and_then(|n| self.at.checked_add(n))
            .filter(|&end| end <= self.bytes.len())
            .ok_or_else(|| format!("cut short at byte {}", self.at))?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    fn byte(&mut self) -> Result<u8, String> {
        Ok(self.take(Some(1))?[0])
    }
}

fn u32_at(bytes: &[u8], j: usize) -> u32 {
    u32::from_le_bytes(bytes[4 * j..4 * j + 4].try_into().expect("4 bytes"))
}

fn f64_at(bytes: &[u8], j: usize) -> f64 {
    f64::from_le_bytes(bytes[8 * j..8 * j + 8].try_into().expect("8 bytes"))
}

/// Refills the history slots of the epoch `steps` of every exchanged node with the spikes of
/// every rank's message (`blocks`, in rank order). A rank that reports a divergence is a
/// [`GraphError::PeerDiverged`]; a malformed message a [`GraphError::Exchange`].
pub(super) fn unpack_epoch(
    nodes: &mut [RunningNode],
    exchanged: &[usize],
    steps: Range<u64>,
    blocks: &[Vec<u8>],
) -> Result<(), GraphError> {
    let step = steps.end;
    if let Some(rank) = blocks.iter().position(|b| b.first() == Some(&1)) {
        return Err(GraphError::PeerDiverged { rank, step });
    }
    for &i in exchanged {
        let n = &mut nodes[i];
        for k in steps.clone() {
            let s = slot(n, k);
            n.history[s].clear();
        }
    }
    let n_steps = (steps.end - steps.start) as usize;
    for (rank, block) in blocks.iter().enumerate() {
        unpack_block(nodes, exchanged, steps.clone(), n_steps, block).map_err(|reason| {
            GraphError::Exchange {
                step,
                reason: format!("rank {rank} sent a malformed message: {reason}"),
            }
        })?;
    }
    Ok(())
}

/// Appends one rank's spikes (`block`) to the history slots of `steps`.
fn unpack_block(
    nodes: &mut [RunningNode],
    exchanged: &[usize],
    steps: Range<u64>,
    n_steps: usize,
    block: &[u8],
) -> Result<(), String> {
    let mut r = Reader {
        bytes: block,
        at: 0,
    };
    if r.byte()? != 0 {
        return Err("unknown status byte".into());
    }
    for &i in exchanged {
        let n = &mut nodes[i];
        let counts = r.take(n_steps.checked_mul(4))?;
        let total = (0..n_steps)
            .map(|s| u32_at(counts, s) as usize)
            .sum::<usize>();
        let fractions = match r.byte()? {
            0 => None,
            1 => Some(()),
            flag => return Err(format!("fraction flag {flag} (expected 0 or 1)")),
        };
        let indices = r.take(total.checked_mul(4))?;
        let fractions = match fractions {
            Some(()) => Some(r.take(total.checked_mul(8))?),
            None => None,
        };
        let mut j = 0;
        for (s, k) in steps.clone().enumerate() {
            let slot = slot(n, k);
            let buffer: &mut SpikeBuffer = &mut n.history[slot];
            for _ in 0..u32_at(counts, s) {
                let index = u32_at(indices, j);
                if index as usize >= n.size {
                    return Err(format!(
                        "neuron {index} of '{}', which has {}",
                        n.name, n.size
                    ));
                }
                match fractions {
                    Some(f) => buffer.push_at(index, f64_at(f, j)),
                    None => buffer.push(index),
                }
                j += 1;
            }
        }
    }
    if r.at != block.len() {
        return Err(format!("{} bytes left over", block.len() - r.at));
    }
    Ok(())
}
