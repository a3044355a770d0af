//! The exact multi-unit Van Rossum distance (Houghton & Sen 2008) in pymuvr's normalisation,
//! computed from spike times with the markage recursion (Houghton & Kreuz 2012).
//!
//! # Definition
//! Channel `n` of a sample is filtered into `f_n(t) = Σ_i H(t − t_n^i)·e^{−(t − t_n^i)/τ}`;
//! unit `n` gets a unit vector `e_n` with `e_n·e_m = c = cos θ` for `n ≠ m`, and
//!
//! ```text
//! D²(U, V) = (2/τ)·∫ |Σ_n e_n (f_{u_n}(t) − f_{v_n}(t))|² dt
//!          = (1 − c)·LL² + c·SP²
//! LL² = Σ_n d²(u_n, v_n)                     (labelled line, c = 0)
//! SP² = d²(∪_n u_n, ∪_n v_n)                 (summed population, c = 1; pooled trains keep duplicates)
//! d²(u, v) = ⟨u,u⟩ + ⟨v,v⟩ − 2⟨u,v⟩,   ⟨u,v⟩ = Σ_k Σ_l e^{−|u_k − v_l|/τ}
//! ```
//!
//! The factor `2/τ` makes one spike against an empty train `D = 1` (pymuvr and elephant; Van
//! Rossum 2001 uses `1/τ`, so `D = √2·D_vR2001`). Only `t/τ` enters, so τ is in the unit of the
//! spike times (seconds). Because `C = (1 − c)·I + c·11ᵀ`, computing `LL²` and `SP²` once for a
//! τ makes every `c ∈ [0, 1]` free ([`VanRossumMatrices::squared`]).
//!
//! Limits: `τ → ∞` gives `(1 − c)·Σ_n Δn_n² + c·(Σ_n Δn_n)²` (spike-count differences: spatial
//! coding at `c = 0`, 49 × intensive at `c = 1`); `τ → 0` gives the number of spikes that have no
//! coincident partner, since `⟨u,v⟩` then counts coincident pairs.
//!
//! # Algorithm: one merge per pair of trains, O(n + m)
//! With the markage `m_k = Σ_{l<k} e^{−(u_k − u_l)/τ}`, `⟨u,u⟩ = n + 2·Σ_k m_k`, and
//! `⟨u,v⟩ = Σ_{u_l ≤ v_j} e^{−(v_j − u_l)/τ} + Σ_{v_l < u_k} e^{−(u_k − v_l)/τ}`: one merge of the
//! two sorted trains in which a `u` spike is taken before an equal `v` spike, so **every pair is
//! counted exactly once, coincident pairs with weight 1**, duplicates included. Two exact
//! evaluations of the merge are used:
//!
//! - **centred exponentials** (fast): with `c₀` the middle of the spike-time span of the prepared
//!   samples, each spike stores `e⁻ = e^{−(t − c₀)/τ}` and `P`, the sum of `e^{(t_l − c₀)/τ}` over
//!   the earlier spikes of its train, so a merge step is one multiply-add and no `exp`. Used
//!   while `span/(2τ) ≤ 690`, which bounds every exponent by 690 in magnitude: nothing
//!   overflows or becomes subnormal.
//! - **decayed sums** (always stable): running sums `A_u`, `A_v` decayed by `e^{−Δt/τ}` with
//!   `Δt ≥ 0` between merged spikes; a `v` spike adds `A_u`, a `u` spike adds `A_v`. Only
//!   exponentials of non-positive numbers, any τ > 0 and any time offset. Used beyond the bound.
//!
//! The labelled-line merges of all channels run as one merge over channel-major keys
//! `(channel, rank of t)` with an end-of-channel marker per channel, so each pair of samples costs
//! two branch-free merges (labelled line and pooled), interleaved for instruction-level
//! parallelism. `D²` smaller than 0 by rounding (about 10⁻¹⁵ for identical samples) is clamped
//! to 0, as pymuvr does.

use super::{check_cos, check_tau, symmetric_matrices};
use crate::error::DistanceError;
use crate::spikes::MultiSpikeTrain;
use ndarray::Array2;
use rayon::prelude::*;

/// Largest `span/(2τ)` for which the centred-exponential evaluation is used (module docs).
pub const CENTRED_EXP_LIMIT: f64 = 690.0;

/// Rank field of an end-of-channel marker key (larger than any spike's rank).
const MARKER_RANK: u64 = u32::MAX as u64;

/// Multi-unit Van Rossum distance with kernel time constant `tau_s`.
///
/// ```
/// use neurotac_core::{MultiSpikeTrain, distance::VanRossum};
/// let one = MultiSpikeTrain::from_channels(vec![vec![0.5], vec![]])?;
/// let empty = MultiSpikeTrain::empty(2);
/// let vr = VanRossum::new(0.076)?;
/// assert!((vr.distance(&one, &empty, 0.4)? - 1.0).abs() < 1e-12); // one spike vs none
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VanRossum {
    tau_s: f64,
}

/// `LL²` and `SP²` of every pair of samples for one τ; any cos θ is then one elementwise
/// combination ([`squared`](Self::squared)).
#[derive(Debug, Clone, PartialEq)]
pub struct VanRossumMatrices {
    /// Kernel time constant (s).
    pub tau_s: f64,
    /// Labelled-line squared distances `LL²` (N × N, symmetric, zero diagonal).
    pub ll2: Array2<f64>,
    /// Summed-population squared distances `SP²` (N × N, symmetric, zero diagonal).
    pub sp2: Array2<f64>,
}

/// `D²(c) = (1 − c)·LL² + c·SP²`, clamped at 0.
#[inline]
pub fn combine_squared(ll2: f64, sp2: f64, cos: f64) -> f64 {
    ((1.0 - cos) * ll2 + cos * sp2).max(0.0)
}

impl VanRossumMatrices {
    /// `D²(c)` for every pair. Errors when `cos ∉ [0, 1]`.
    pub fn squared(&self, cos: f64) -> Result<Array2<f64>, DistanceError> {
        check_cos(cos)?;
        let mut out = self.ll2.clone();
        out.zip_mut_with(&self.sp2, |l, &s| *l = combine_squared(*l, s, cos));
        Ok(out)
    }

    /// `D(c) = √D²(c)` for every pair (pymuvr's `square_distance_matrix`).
    pub fn distances(&self, cos: f64) -> Result<Array2<f64>, DistanceError> {
        Ok(self.squared(cos)?.mapv_into(f64::sqrt))
    }
}

/// One merge entry. A merge step reads all three fields of one entry per side, so they sit
/// together (one cache line, one bounds check) rather than in three arrays.
#[derive(Debug, Clone, Copy, Default)]
struct Entry {
    /// `(channel << 32) | rank(t)`; end-of-channel markers have rank [`MARKER_RANK`].
    key: u64,
    /// Centred: `e^{−(t − c₀)/τ}` (0 for markers). Decayed: `t` (unused for markers).
    x: f64,
    /// Centred: sum of `e^{(t_l − c₀)/τ}` over the earlier spikes of the same channel.
    p: f64,
}

/// Keyed spike entries of one sample for one merge (labelled line or pooled), ending with a
/// sentinel key `u64::MAX`.
#[derive(Debug, Clone, Default)]
struct MergeArrays {
    entries: Vec<Entry>,
    /// `⟨u,u⟩` summed over the channels of this merge.
    self_product: f64,
}

impl MergeArrays {
    /// Number of entries without the sentinel.
    fn len(&self) -> usize {
        self.entries.len() - 1
    }
}

#[derive(Debug, Clone, Default)]
struct PreparedSample {
    labelled: MergeArrays,
    pooled: MergeArrays,
    /// Index in `labelled` where channel `P/2` starts and in `pooled` of the first spike at or
    /// after the middle rank: each merge runs as two independent halves (the prefixes `P` are
    /// global, so a half can start anywhere), four chains per pair for instruction-level
    /// parallelism.
    labelled_split: usize,
    pooled_split: usize,
}

/// Samples prepared for one τ: ranks, keys and (centred) exponentials computed once, so every
/// pair costs only the two merges.
#[derive(Debug, Clone)]
pub struct PreparedVanRossum {
    tau_s: f64,
    centred: bool,
    samples: Vec<PreparedSample>,
}

impl VanRossum {
    /// Kernel time constant `tau_s` in seconds (finite and > 0).
    pub fn new(tau_s: f64) -> Result<Self, DistanceError> {
        Ok(Self {
            tau_s: check_tau(tau_s)?,
        })
    }

    /// The kernel time constant (s).
    pub fn tau_s(&self) -> f64 {
        self.tau_s
    }

    /// Prepares `observations` (all with the same channel count; [`DistanceError::ChannelCount`]
    /// names the first that differs). Trains are sorted and finite by construction of
    /// [`MultiSpikeTrain`].
    pub fn prepare(
        &self,
        observations: &[MultiSpikeTrain],
    ) -> Result<PreparedVanRossum, DistanceError> {
        self.prepare_with(observations, true)
    }

    /// [`prepare`](Self::prepare), with the centred evaluation allowed or not (tests compare both).
    pub(crate) fn prepare_with(
        &self,
        observations: &[MultiSpikeTrain],
        allow_centred: bool,
    ) -> Result<PreparedVanRossum, DistanceError> {
        let expected = observations.first().map_or(0, MultiSpikeTrain::n_channels);
        if let Some(sample) = observations.iter().position(|o| o.n_channels() != expected) {
            return Err(DistanceError::ChannelCount {
                sample,
                expected,
                got: observations[sample].n_channels(),
            });
        }
        // Global ranks of the distinct spike times: exact integer keys for the merges.
        let mut distinct: Vec<f64> = observations
            .iter()
            .flat_map(|o| o.flat_times().iter().copied())
            .collect();
        distinct.par_sort_unstable_by(f64::total_cmp);
        distinct.dedup_by(|a, b| a.total_cmp(b).is_eq());
        let (lo, hi) = match (distinct.first(), distinct.last()) {
            (Some(&lo), Some(&hi)) => (lo, hi),
            _ => (0.0, 0.0),
        };
        let centre = lo / 2.0 + hi / 2.0;
        // (hi − lo) may overflow for extreme times; halves do not.
        let half_span_over_tau = (hi / 2.0 - lo / 2.0) / self.tau_s;
        let centred = allow_centred && half_span_over_tau <= CENTRED_EXP_LIMIT;
        let rank = |t: f64| distinct.partition_point(|&d| d.total_cmp(&t).is_lt()) as u64;
        let middle_rank = (distinct.len() / 2) as u64;
        let samples = observations
            .par_iter()
            .map(|o| {
                let channels: Vec<&[f64]> = o.channels().collect();
                let pooled = o.pooled();
                let labelled = self.merge_arrays(&channels, centred, centre, &rank);
                let pooled = self.merge_arrays(&[&pooled], centred, centre, &rank);
                let middle_channel = ((channels.len() / 2) as u64) << 32;
                PreparedSample {
                    labelled_split: labelled.entries.partition_point(|e| e.key < middle_channel),
                    pooled_split: pooled.entries.partition_point(|e| e.key < middle_rank),
                    labelled,
                    pooled,
                }
            })
            .collect();
        Ok(PreparedVanRossum {
            tau_s: self.tau_s,
            centred,
            samples,
        })
    }

    /// Keys and exponentials of `trains` (channel `c` = position in the slice) for one merge.
    fn merge_arrays(
        &self,
        trains: &[&[f64]],
        centred: bool,
        centre: f64,
        rank: &(impl Fn(f64) -> u64 + Sync),
    ) -> MergeArrays {
        let total: usize = trains.iter().map(|t| t.len()).sum();
        let mut m = MergeArrays {
            entries: Vec::with_capacity(total + trains.len() + 1),
            self_product: 0.0,
        };
        let inv_tau = 1.0 / self.tau_s;
        for (c, times) in trains.iter().enumerate() {
            let high = (c as u64) << 32;
            let mut prefix = 0.0;
            let mut markage_sum = 0.0;
            let mut markage = 0.0;
            for (k, &t) in times.iter().enumerate() {
                let key = high | rank(t);
                if centred {
                    let e_minus = (-(t - centre) * inv_tau).exp();
                    m.entries.push(Entry {
                        key,
                        x: e_minus,
                        p: prefix,
                    });
                    markage_sum += e_minus * prefix;
                    prefix += ((t - centre) * inv_tau).exp();
                } else {
                    m.entries.push(Entry { key, x: t, p: 0.0 });
                    if k > 0 {
                        markage = (1.0 + markage) * (-(t - times[k - 1]) * inv_tau).exp();
                        markage_sum += markage;
                    }
                }
            }
            m.self_product += times.len() as f64 + 2.0 * markage_sum;
            m.entries.push(Entry {
                key: high | MARKER_RANK,
                x: 0.0,
                p: prefix,
            });
        }
        m.entries.push(Entry {
            key: u64::MAX,
            x: 0.0,
            p: 0.0,
        });
        m
    }

    /// `LL²` and `SP²` for every pair of `observations` (parallel over rows).
    pub fn matrices(
        &self,
        observations: &[MultiSpikeTrain],
    ) -> Result<VanRossumMatrices, DistanceError> {
        let prepared = self.prepare(observations)?;
        let [ll2, sp2] = symmetric_matrices(observations.len(), |i, j| {
            let (ll, sp) = prepared.squared_parts(i, j);
            [ll, sp]
        });
        Ok(VanRossumMatrices {
            tau_s: self.tau_s,
            ll2,
            sp2,
        })
    }

    /// `D²(c)` between two samples with the same channel count.
    pub fn squared_distance(
        &self,
        u: &MultiSpikeTrain,
        v: &MultiSpikeTrain,
        cos: f64,
    ) -> Result<f64, DistanceError> {
        check_cos(cos)?;
        let prepared = self.prepare(&[u.clone(), v.clone()])?;
        let (ll, sp) = prepared.squared_parts(0, 1);
        Ok(combine_squared(ll, sp, cos))
    }

    /// `D(c)` between two samples with the same channel count.
    pub fn distance(
        &self,
        u: &MultiSpikeTrain,
        v: &MultiSpikeTrain,
        cos: f64,
    ) -> Result<f64, DistanceError> {
        Ok(self.squared_distance(u, v, cos)?.sqrt())
    }
}

impl PreparedVanRossum {
    /// Kernel time constant (s).
    pub fn tau_s(&self) -> f64 {
        self.tau_s
    }

    /// Number of prepared samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// `true` when no sample was prepared.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// `true` when the centred-exponential evaluation is in use (module docs).
    pub fn is_centred(&self) -> bool {
        self.centred
    }

    /// `(LL², SP²)` between prepared samples `i` and `j` (0 for `i == j`). Panics when an index is
    /// out of range.
    pub fn squared_parts(&self, i: usize, j: usize) -> (f64, f64) {
        if i == j {
            return (0.0, 0.0);
        }
        let (a, b) = (&self.samples[i], &self.samples[j]);
        let (ll_cross, sp_cross) = if self.centred {
            centred_cross_pair(a, b)
        } else {
            (
                decayed_cross(&a.labelled, &b.labelled, self.tau_s),
                decayed_cross(&a.pooled, &b.pooled, self.tau_s),
            )
        };
        let ll = a.labelled.self_product + b.labelled.self_product - 2.0 * ll_cross;
        let sp = a.pooled.self_product + b.pooled.self_product - 2.0 * sp_cross;
        (ll.max(0.0), sp.max(0.0))
    }
}

/// One branch-free step of a centred merge: take the smaller key (`u` on ties), add its `e⁻`
/// times the other side's prefix `P` at the merge position.
#[inline(always)]
fn centred_step(u: &[Entry], v: &[Entry], i: &mut usize, j: &mut usize, acc: &mut f64) {
    let (a, b) = (&u[*i], &v[*j]);
    let take_u = a.key <= b.key;
    let (taken, other) = if take_u { (a, b) } else { (b, a) };
    *acc += taken.x * other.p;
    *i += take_u as usize;
    *j += (!take_u) as usize;
}

/// `(Σ_n ⟨u_n, v_n⟩, ⟨∪u, ∪v⟩)`: both merges, each in two halves, as four interleaved chains.
fn centred_cross_pair(a: &PreparedSample, b: &PreparedSample) -> (f64, f64) {
    let (ll_u, ll_v) = (&a.labelled.entries[..], &b.labelled.entries[..]);
    let (sp_u, sp_v) = (&a.pooled.entries[..], &b.pooled.entries[..]);
    let len = |e: &[Entry]| e.len() - 1;
    // (start i, start j, steps) of each chain.
    let chains = [
        (0, 0, a.labelled_split + b.labelled_split),
        (
            a.labelled_split,
            b.labelled_split,
            len(ll_u) - a.labelled_split + len(ll_v) - b.labelled_split,
        ),
        (0, 0, a.pooled_split + b.pooled_split),
        (
            a.pooled_split,
            b.pooled_split,
            len(sp_u) - a.pooled_split + len(sp_v) - b.pooled_split,
        ),
    ];
    let [
        (mut i0, mut j0, n0),
        (mut i1, mut j1, n1),
        (mut i2, mut j2, n2),
        (mut i3, mut j3, n3),
    ] = chains;
    let mut acc = [0.0f64; 4];
    let common = n0.min(n1).min(n2).min(n3);
    for _ in 0..common {
        centred_step(ll_u, ll_v, &mut i0, &mut j0, &mut acc[0]);
        centred_step(ll_u, ll_v, &mut i1, &mut j1, &mut acc[1]);
        centred_step(sp_u, sp_v, &mut i2, &mut j2, &mut acc[2]);
        centred_step(sp_u, sp_v, &mut i3, &mut j3, &mut acc[3]);
    }
    for _ in common..n0 {
        centred_step(ll_u, ll_v, &mut i0, &mut j0, &mut acc[0]);
    }
    for _ in common..n1 {
        centred_step(ll_u, ll_v, &mut i1, &mut j1, &mut acc[1]);
    }
    for _ in common..n2 {
        centred_step(sp_u, sp_v, &mut i2, &mut j2, &mut acc[2]);
    }
    for _ in common..n3 {
        centred_step(sp_u, sp_v, &mut i3, &mut j3, &mut acc[3]);
    }
    (acc[0] + acc[1], acc[2] + acc[3])
}

/// `Σ_n ⟨u_n, v_n⟩` by decayed running sums (exponentials of non-positive numbers only).
fn decayed_cross(u: &MergeArrays, v: &MergeArrays, tau_s: f64) -> f64 {
    let (mut i, mut j) = (0, 0);
    let (mut a_u, mut a_v, mut last) = (0.0f64, 0.0f64, f64::NAN);
    let mut acc = 0.0;
    for _ in 0..u.len() + v.len() {
        let (a, b) = (&u.entries[i], &v.entries[j]);
        let take_u = a.key <= b.key;
        let (key, t) = if take_u { (a.key, a.x) } else { (b.key, b.x) };
        if take_u {
            i += 1;
        } else {
            j += 1;
        }
        if key & MARKER_RANK == MARKER_RANK {
            // End of a channel: nothing carries over to the next one.
            (a_u, a_v, last) = (0.0, 0.0, f64::NAN);
            continue;
        }
        if !last.is_nan() {
            let decay = (-(t - last) / tau_s).exp();
            a_u *= decay;
            a_v *= decay;
        }
        last = t;
        if take_u {
            acc += a_v;
            a_u += 1.0;
        } else {
            acc += a_u;
            a_v += 1.0;
        }
    }
    acc
}

#[cfg(test)]
mod tests;
