//! The fused leave-one-out's neighbour lists: every sample's `k` nearest at every window.

use super::{LANES, Lane};

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
        let first = slot * self.k;
        let mut p = first + self.k - 1;
        let precedes = |dist: L, index: u32| d < dist || (d == dist && candidate < index);
        if !precedes(self.distance[p], self.index[p]) {
            return;
        }
        while p > first && precedes(self.distance[p - 1], self.index[p - 1]) {
            self.distance[p] = self.distance[p - 1];
            self.index[p] = self.index[p - 1];
            p -= 1;
        }
        self.distance[p] = d;
        self.index[p] = candidate;
        self.threshold[slot] = self.distance[first + self.k - 1];
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
