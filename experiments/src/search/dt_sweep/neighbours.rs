//! The fused leave-one-out's neighbour lists: every sample's `k` nearest at every window.

use super::lanes::{LANES, Lane};
use rayon::prelude::*;

/// The `k` nearest seen so far of every sample at every window, ordered by `(distance, index)`
/// as [`TopK`](neurotac_core::knn::TopK), in flat arrays: slot `(sample, lane)` holds `k` entries, unfilled ones
/// `(L::MAX, u32::MAX)`. `threshold` is each slot's `k`-th distance, the bound a candidate must
/// not exceed (`L::MIN` for the padding lanes beyond the last window, which take nothing).
pub(super) struct Neighbours<L> {
    k: usize,
    lanes: usize,
    distance: Vec<L>,
    index: Vec<u32>,
    threshold: Vec<L>,
}

impl<L: Lane> Neighbours<L> {
    pub(super) fn new(n: usize, blocks: usize, windows: usize, k: usize) -> Self {
        let lanes = blocks * LANES;
        let slots = n * lanes;
        Self {
            k,
            lanes,
            distance: vec![L::MAX; slots * k],
            index: vec![u32::MAX; slots * k],
            threshold: (0..slots)
                .map(|s| if s % lanes < windows { L::MAX } else { L::MIN })
                .collect(),
        }
    }

    /// Offers `candidate` at the distances `d2` of block `blk` to `sample`'s lists.
    #[inline(always)]
    pub(super) fn offer(&mut self, sample: usize, blk: usize, d2: &[L; LANES], candidate: usize) {
        let base = sample * self.lanes + blk * LANES;
        let threshold: &[L; LANES] = self.threshold[base..base + LANES]
            .try_into()
            .expect("LANES slots");
        let mut any = false;
        for l in 0..LANES {
            any |= d2[l] <= threshold[l];
        }
        if any {
            self.insert_block(base, d2, candidate as u32);
        }
    }

    #[inline(never)]
    fn insert_block(&mut self, base: usize, d2: &[L; LANES], candidate: u32) {
        for (l, &d) in d2.iter().enumerate() {
            if d <= self.threshold[base + l] {
                self.insert(base + l, d, candidate);
            }
        }
    }

    /// Inserts `(d, candidate)` into slot `slot` when it precedes the slot's `k`-th entry.
    fn insert(&mut self, slot: usize, d: L, candidate: u32) {
        let entries = slot * self.k..(slot + 1) * self.k;
        self.threshold[slot] = insert_sorted(
            &mut self.distance[entries.clone()],
            &mut self.index[entries],
            d,
            candidate,
        );
    }

    /// The `k` nearest of every slot among all of `lists` (each of shape `(n, blocks, windows,
    /// k)`, which the result has too): the lists' entries are inserted in turn, in the
    /// `(distance, index)` order, so the result does not depend on how candidates were split
    /// between the lists. Samples in parallel.
    pub(super) fn merged(
        lists: &[Self],
        n: usize,
        blocks: usize,
        windows: usize,
        k: usize,
    ) -> Self {
        let mut out = Self::new(n, blocks, windows, k);
        let lanes = out.lanes;
        (out.distance.par_chunks_mut(lanes * k))
            .zip(out.index.par_chunks_mut(lanes * k))
            .zip(out.threshold.par_chunks_mut(lanes))
            .enumerate()
            .for_each(|(sample, ((distance, index), threshold))| {
                for (lane, threshold) in threshold.iter_mut().enumerate().take(windows) {
                    let entries = lane * k..(lane + 1) * k;
                    for (d, j) in lists.iter().flat_map(|l| l.neighbours(sample, lane)) {
                        *threshold = insert_sorted(
                            &mut distance[entries.clone()],
                            &mut index[entries.clone()],
                            d,
                            j as u32,
                        );
                    }
                }
            });
        out
    }

    /// The lists as bytes, to send to other ranks: every distance as a little-endian `i64`, then
    /// every index as a little-endian `u32`.
    pub(super) fn to_bytes(&self) -> Vec<u8> {
        let distances = self.distance.iter().flat_map(|d| d.to_i64().to_le_bytes());
        let indices = self.index.iter().flat_map(|i| i.to_le_bytes());
        distances.chain(indices).collect()
    }

    /// Lists of shape `(n, blocks, windows, k)` from [`to_bytes`](Self::to_bytes); `None` when
    /// the length does not match the shape or an index is not a sample's (nor empty).
    pub(super) fn from_bytes(
        bytes: &[u8],
        n: usize,
        blocks: usize,
        windows: usize,
        k: usize,
    ) -> Option<Self> {
        let mut out = Self::new(n, blocks, windows, k);
        let entries = out.distance.len();
        if bytes.len() != entries * 12 {
            return None;
        }
        let (distances, indices) = bytes.split_at(entries * 8);
        for (d, b) in out.distance.iter_mut().zip(distances.chunks_exact(8)) {
            *d = L::from_i64(i64::from_le_bytes(b.try_into().ok()?));
        }
        for (i, b) in out.index.iter_mut().zip(indices.chunks_exact(4)) {
            *i = u32::from_le_bytes(b.try_into().ok()?);
            if *i != u32::MAX && *i as usize >= n {
                return None;
            }
        }
        for (slot, threshold) in out.threshold.iter_mut().enumerate() {
            if slot % out.lanes < windows {
                *threshold = out.distance[(slot + 1) * k - 1];
            }
        }
        Some(out)
    }

    /// The filled entries of `(sample, lane)` as `(distance, index)`.
    pub(super) fn neighbours(
        &self,
        sample: usize,
        lane: usize,
    ) -> impl Iterator<Item = (L, usize)> + '_ {
        let first = (sample * self.lanes + lane) * self.k;
        (first..first + self.k)
            .filter(|&e| self.index[e] != u32::MAX)
            .map(|e| (self.distance[e], self.index[e] as usize))
    }
}

/// Inserts `(d, candidate)` into the `k` entries `distance`, `index` (sorted by `(distance,
/// index)`) when it precedes the last, which drops out; returns the `k`-th distance after.
fn insert_sorted<L: Lane>(distance: &mut [L], index: &mut [u32], d: L, candidate: u32) -> L {
    let last = distance.len() - 1;
    let precedes = |dist: L, at: u32| d < dist || (d == dist && candidate < at);
    if precedes(distance[last], index[last]) {
        let mut p = last;
        while p > 0 && precedes(distance[p - 1], index[p - 1]) {
            distance[p] = distance[p - 1];
            index[p] = index[p - 1];
            p -= 1;
        }
        distance[p] = d;
        index[p] = candidate;
    }
    distance[last]
}
