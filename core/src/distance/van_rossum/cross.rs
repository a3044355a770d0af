//! The cross products of new samples with centred prepared samples, for
//! [`PreparedVanRossum::cross_matrices`](super::PreparedVanRossum::cross_matrices).
//!
//! With `c₀` the prepared samples' centre, `e⁻_t = e^{−(t − c₀)/τ}` and `e⁺_t = e^{(t − c₀)/τ}`,
//! the product of a new train `a` with a prepared train `b` splits at every spike `t_j` of `b`:
//!
//! ```text
//! ⟨a, b⟩ = Σ_{j ∈ b} e⁻_j·P_a(≤ t_j) + e⁺_j·S_a(> t_j)
//! P_a(≤ t) = Σ_{k ∈ a, t_k ≤ t} e⁺_k        S_a(> t) = Σ_{k ∈ a, t_k > t} e⁻_k
//! ```
//!
//! (every pair once, a coincident pair with weight `e⁻·e⁺ = 1`). `P_a` and `S_a` change only at
//! `a`'s spikes, so the prepared spikes of one channel, **of all samples together in time
//! order** (the [`CrossIndex`], built once), are swept once per new sample alongside `a`'s
//! spikes; each adds `e⁻_j·P + e⁺_j·S` to its own sample's sums, labelled line (`P`, `S` of
//! `a`'s same channel) and pooled (of all of `a`'s spikes) together. That is one sequential
//! read of 16 bytes and four multiply-adds per prepared spike, with `e⁺_j = 1/e⁻_j`: no lookup
//! and no exponential. The suffixes `S_a` are summed from the end of `a`, never as differences
//! of prefixes (which would cancel). Times are compared as ranks among the prepared samples'
//! distinct times: a new spike at `t` gets the rank `#{times < t}`, so `t ≤ t_j ⟺ rank ≤ rank_j`.
//!
//! The prefixes `t < T` of the prepared samples are their spikes of rank below `#{times < T}`:
//! each channel's sweep stops there (a binary search) and counts each sample's spikes on the
//! way, and the self products of every prefix of every sample are tabulated in the index, so
//! prefixes cost no more than whole samples.

use super::centred::{CENTRED_EXP_LIMIT, CentredSample, Grid};
use crate::spikes::MultiSpikeTrain;

/// One prepared spike in a channel's sweep: its rank, its sample and `e⁻ = e^{−(t − c₀)/τ}`.
#[derive(Debug, Clone, Copy)]
struct Entry {
    rank: u32,
    sample: u32,
    e_minus: f64,
}

/// Distinct times per block of the coarse index ([`CrossIndex::rank`]).
const COARSE: usize = 64;

/// The prepared samples' spikes by channel, all samples together in time order, and the self
/// products of every sample's prefixes in time.
#[derive(Debug, Clone)]
pub(super) struct CrossIndex {
    /// Per channel, the spikes of every sample ordered by `(rank, sample)`.
    channels: Vec<Vec<Entry>>,
    /// Every [`COARSE`]-th prepared distinct time, so that ranking a time reads the large time
    /// list in one small block.
    coarse: Vec<f64>,
    /// `[Σ_n ⟨u_n, u_n⟩, ⟨∪u, ∪u⟩]` of the first `m` spikes in time order, `m = 0 ..= n`, sample
    /// after sample (sample `s` from `self_offsets[s]`).
    self_of_first: Vec<[f64; 2]>,
    self_offsets: Vec<usize>,
}

impl CrossIndex {
    /// Indexes the prepared `samples` with the sorted distinct spike `times` (one pass, then a
    /// stable sort of each channel, which merges the samples' runs and keeps equal ranks in
    /// sample order).
    pub(super) fn new(samples: &[CentredSample], grid: &Grid, times: &[f64]) -> Self {
        let n_channels = grid.channels();
        let mut counts = vec![0usize; n_channels];
        for (c, ..) in samples.iter().flat_map(|s| s.spikes(grid)) {
            counts[c] += 1;
        }
        let mut channels: Vec<Vec<Entry>> = counts.iter().map(|&n| Vec::with_capacity(n)).collect();
        let total = counts.iter().sum::<usize>() + samples.len();
        let mut self_of_first = Vec::with_capacity(total);
        let mut self_offsets = Vec::with_capacity(samples.len());
        let mut channel_prefix = vec![0.0f64; n_channels];
        for (s, sample) in samples.iter().enumerate() {
            let s = u32::try_from(s).expect("fewer than 2³² prepared samples");
            self_offsets.push(self_of_first.len());
            // ⟨u, u⟩ = n + 2·Σ_k e⁻_k·P(< k), spike by spike in time order (P over the spike's
            // channel for the labelled line, over all channels for the pool).
            channel_prefix.fill(0.0);
            let (mut pooled_prefix, mut sums) = (0.0f64, [0.0f64; 2]);
            self_of_first.push(sums);
            for (c, rank, e_minus, e_plus) in sample.spikes(grid) {
                channels[c].push(Entry {
                    rank,
                    sample: s,
                    e_minus,
                });
                let prefix = &mut channel_prefix[c];
                sums[0] += 2.0f64.mul_add(e_minus * *prefix, 1.0);
                sums[1] += 2.0f64.mul_add(e_minus * pooled_prefix, 1.0);
                *prefix += e_plus;
                pooled_prefix += e_plus;
                self_of_first.push(sums);
            }
        }
        for list in &mut channels {
            list.sort_by_key(|e| e.rank);
        }
        Self {
            channels,
            coarse: times.iter().step_by(COARSE).copied().collect(),
            self_of_first,
            self_offsets,
        }
    }

    /// `#{times < t}`, the rank of a new spike at `t` among the prepared distinct `times` (the
    /// list the index was built with): a binary search of the coarse list, then of one block.
    fn rank(&self, times: &[f64], t: f64) -> usize {
        // times[COARSE·(block − 1)] < t ≤ times[COARSE·block].
        let block = self.coarse.partition_point(|&d| d < t);
        let lo = block.saturating_sub(1) * COARSE;
        let hi = (block * COARSE).min(times.len());
        lo + times[lo..hi.max(lo)].partition_point(|&d| d < t)
    }

    /// `[Σ_n ⟨u_n, u_n⟩, ⟨∪u, ∪u⟩]` of the first `spikes` spikes (time order) of `sample`.
    pub(super) fn self_products(&self, sample: usize, spikes: usize) -> [f64; 2] {
        self.self_of_first[self.self_offsets[sample] + spikes]
    }

    /// `[Σ_n ⟨a_n, b_n⟩, ⟨∪a, ∪b⟩, m]` of the new sample `a` with each prepared sample `b`
    /// restricted to its `m` spikes of rank below `end_rank`.
    pub(super) fn cross_products(&self, a: &NewSample, end_rank: u32) -> Vec<[f64; 3]> {
        let mut sums = vec![[0.0f64; 3]; self.self_offsets.len()];
        for (c, list) in self.channels.iter().enumerate() {
            let list = &list[..list.partition_point(|e| e.rank < end_rank)];
            // `a`'s spikes counted so far (rank ≤ the current prepared spike's), and [P, S].
            let (mut k, mut next) = (0, a.ranks[0]);
            let (mut own, mut pooled) = (a.channel_start[c], a.pooled_start);
            for e in list {
                while next <= e.rank {
                    let spike = &a.spikes[k];
                    pooled = spike.pooled_after;
                    if spike.channel == c {
                        own = spike.channel_after;
                    }
                    k += 1;
                    next = a.ranks[k];
                }
                let e_plus = 1.0 / e.e_minus;
                let s = &mut sums[e.sample as usize];
                s[0] = e.e_minus.mul_add(own[0], e_plus.mul_add(own[1], s[0]));
                s[1] = e
                    .e_minus
                    .mul_add(pooled[0], e_plus.mul_add(pooled[1], s[1]));
                s[2] += 1.0;
            }
        }
        sums
    }
}

/// One spike of a new sample: its channel and the values `[P, S]` once it is counted, of its
/// channel and of the pool.
#[derive(Debug, Clone, Copy)]
struct NewSpike {
    channel: usize,
    channel_after: [f64; 2],
    pooled_after: [f64; 2],
}

/// A new sample placed among the prepared samples' times: its spikes in time order with their
/// ranks, and `[P, S]` before and after each spike (module docs).
#[derive(Debug, Clone)]
pub(super) struct NewSample {
    /// The spikes' ranks, then `u32::MAX` (above every prepared rank).
    ranks: Vec<u32>,
    spikes: Vec<NewSpike>,
    /// `[0, S(all)]` of each channel and of the pool: the values before the first spike.
    channel_start: Vec<[f64; 2]>,
    pooled_start: [f64; 2],
}

/// `true` when `|t − c₀|/τ ≤` [`CENTRED_EXP_LIMIT`]: `e^{±(t − c₀)/τ}` neither overflow nor
/// become subnormal.
fn within_limit(t: f64, centre: f64, inv_tau: f64) -> bool {
    ((t - centre) * inv_tau).abs() <= CENTRED_EXP_LIMIT
}

impl CrossIndex {
    /// Places a new sample, given as its spikes `(channel, time)` in time order, among the
    /// prepared samples with the sorted distinct spike `times`, centre `c₀` and `1/τ`: `None`
    /// when a spike lies farther than [`CENTRED_EXP_LIMIT`]`·τ` from `c₀`.
    pub(super) fn place(
        &self,
        spikes: &[(u32, f64)],
        times: &[f64],
        centre: f64,
        inv_tau: f64,
    ) -> Option<NewSample> {
        let n_channels = self.channels.len();
        let mut ranks = Vec::with_capacity(spikes.len() + 1);
        let mut exps = Vec::with_capacity(spikes.len());
        for &(_, t) in spikes {
            if !within_limit(t, centre, inv_tau) {
                return None;
            }
            // At most times.len(), below u32::MAX: the centred grid admits every rank.
            ranks.push(self.rank(times, t) as u32);
            let x = (t - centre) * inv_tau;
            exps.push(((-x).exp(), x.exp()));
        }
        ranks.push(u32::MAX);
        let mut after = vec![[[0.0f64; 2]; 2]; spikes.len()];
        // Prefixes P forwards, suffixes S backwards; [channel, pool].
        let (mut channel_sum, mut pooled_sum) = (vec![0.0f64; n_channels], 0.0f64);
        for ((slot, &(c, _)), &(_, e_plus)) in after.iter_mut().zip(spikes).zip(&exps) {
            channel_sum[c as usize] += e_plus;
            pooled_sum += e_plus;
            *slot = [[channel_sum[c as usize], 0.0], [pooled_sum, 0.0]];
        }
        channel_sum.fill(0.0);
        pooled_sum = 0.0;
        for ((slot, &(c, _)), &(e_minus, _)) in after.iter_mut().zip(spikes).zip(&exps).rev() {
            slot[0][1] = channel_sum[c as usize];
            slot[1][1] = pooled_sum;
            channel_sum[c as usize] += e_minus;
            pooled_sum += e_minus;
        }
        Some(NewSample {
            ranks,
            spikes: (spikes.iter().zip(after))
                .map(|(&(c, _), [channel_after, pooled_after])| NewSpike {
                    channel: c as usize,
                    channel_after,
                    pooled_after,
                })
                .collect(),
            channel_start: channel_sum.iter().map(|&s| [0.0, s]).collect(),
            pooled_start: [0.0, pooled_sum],
        })
    }
}

/// A centred sample's trains, from its ranks and the prepared samples' distinct `times`.
pub(super) fn prepared_trains(
    sample: &CentredSample,
    grid: &Grid,
    times: &[f64],
) -> MultiSpikeTrain {
    let spikes: Vec<(u32, f64)> = (sample.spikes(grid))
        .map(|(c, rank, _, _)| (c as u32, times[rank as usize]))
        .collect();
    MultiSpikeTrain::from_labelled_spikes(grid.channels(), &spikes)
        .expect("channels of the grid, finite prepared times")
}
