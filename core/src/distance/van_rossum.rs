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
//! # Algorithm: O(n + m) per pair of samples, no `exp` per pair
//! With the markage `m_k = Σ_{l<k} e^{−(u_k − u_l)/τ}`, `⟨u,u⟩ = n + 2·Σ_k m_k`, and
//! `⟨u,v⟩ = Σ_{u_l ≤ v_j} e^{−(v_j − u_l)/τ} + Σ_{v_l < u_k} e^{−(u_k − v_l)/τ}`: a `u` spike
//! is taken before an equal `v` spike, so **every pair is counted exactly once, coincident pairs
//! with weight 1**, duplicates included. Two exact evaluations are used:
//!
//! - **centred exponentials** (fast): with `c₀` the middle of the spike-time span of the prepared
//!   samples, each spike stores `e^{∓(t − c₀)/τ}`; the sums become
//!   `Σ_j e^{−(v_j − c₀)/τ}·P_u(≤ v_j)` with `P_u` a running sum of `e^{(u_l − c₀)/τ}`, and each
//!   `P_u(≤ v_j)` is one read of a table of `u`'s prefixes over global rank cells (the
//!   `centred` submodule), so a pair costs one independent multiply-add per spike of each
//!   side, labelled line and pooled together. Used while `span/(2τ) ≤ 690`, which bounds every
//!   exponent by 690 in magnitude: nothing overflows or becomes subnormal.
//! - **decayed sums** (always stable): one merge per pair of trains with running sums `A_u`,
//!   `A_v` decayed by `e^{−Δt/τ}` with `Δt ≥ 0` between merged spikes; a `v` spike adds `A_u`, a
//!   `u` spike adds `A_v`. Only exponentials of non-positive numbers, any τ > 0 and any time
//!   offset. Used beyond the bound; tests also use it as the reference of the centred tables.
//!
//! `D²` smaller than 0 by rounding (about 10⁻¹⁵ for identical samples) is clamped to 0, as
//! pymuvr does. Every entry is computed in a fixed order from its two samples alone, so the
//! matrices are identical at any thread count.

mod centred;

use super::{check_cos, check_tau, symmetric_matrices};
use crate::error::DistanceError;
use crate::spikes::MultiSpikeTrain;
use centred::{CentredSample, Grid};
use ndarray::Array2;
use rayon::prelude::*;

/// Largest `span/(2τ)` for which the centred-exponential evaluation is used (module docs).
pub const CENTRED_EXP_LIMIT: f64 = 690.0;

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

/// `d² = ⟨u,u⟩ + ⟨v,v⟩ − 2⟨u,v⟩`, clamped at 0.
#[inline]
fn squared_from_products(self_u: f64, self_v: f64, cross: f64) -> f64 {
    (self_u + self_v - 2.0 * cross).max(0.0)
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

/// One sample prepared for the decayed-sum merges: its trains and self products.
#[derive(Debug, Clone)]
struct DecayedSample {
    trains: MultiSpikeTrain,
    pooled: Vec<f64>,
    labelled_self: f64,
    pooled_self: f64,
}

impl DecayedSample {
    fn new(trains: &MultiSpikeTrain, tau_s: f64) -> Self {
        let pooled = trains.pooled();
        Self {
            labelled_self: trains.channels().map(|c| decayed_self(c, tau_s)).sum(),
            pooled_self: decayed_self(&pooled, tau_s),
            trains: trains.clone(),
            pooled,
        }
    }
}

/// The evaluation chosen for the prepared samples (module docs).
#[derive(Debug, Clone)]
enum Evaluation {
    Centred {
        grid: Grid,
        samples: Vec<CentredSample>,
    },
    Decayed(Vec<DecayedSample>),
}

/// Samples prepared for one τ: ranks and (centred) exponentials computed once, so every pair
/// costs only its lookups or merges.
#[derive(Debug, Clone)]
pub struct PreparedVanRossum {
    tau_s: f64,
    evaluation: Evaluation,
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
        let channels = observations.first().map_or(0, MultiSpikeTrain::n_channels);
        if let Some(sample) = observations.iter().position(|o| o.n_channels() != channels) {
            return Err(DistanceError::ChannelCount {
                sample,
                expected: channels,
                got: observations[sample].n_channels(),
            });
        }
        let spikes: Vec<Vec<(u32, f64)>> = observations
            .par_iter()
            .map(MultiSpikeTrain::pooled_with_channels)
            .collect();
        let ranked = RankedTimes::of(&spikes);
        let (lo, hi) = ranked.range;
        let centre = lo / 2.0 + hi / 2.0;
        // (hi − lo) may overflow for extreme times; halves do not.
        let half_span_over_tau = (hi / 2.0 - lo / 2.0) / self.tau_s;
        let total: usize = spikes.iter().map(Vec::len).sum();
        let grid = Grid::new(
            ranked.distinct,
            channels,
            total as f64 / observations.len().max(1) as f64,
        );
        let evaluation = match grid {
            Some(grid) if allow_centred && half_span_over_tau <= CENTRED_EXP_LIMIT => {
                let inv_tau = 1.0 / self.tau_s;
                let samples = spikes
                    .par_iter()
                    .enumerate()
                    .map(|(s, spikes)| {
                        let ranks = ranked.ranks(s);
                        CentredSample::new(spikes, ranks, channels, &grid, centre, inv_tau)
                    })
                    .collect();
                Evaluation::Centred { grid, samples }
            }
            _ => Evaluation::Decayed(
                observations
                    .par_iter()
                    .map(|o| DecayedSample::new(o, self.tau_s))
                    .collect(),
            ),
        };
        Ok(PreparedVanRossum {
            tau_s: self.tau_s,
            evaluation,
        })
    }

    /// `LL²` and `SP²` for every pair of `observations` (parallel over rows).
    pub fn matrices(
        &self,
        observations: &[MultiSpikeTrain],
    ) -> Result<VanRossumMatrices, DistanceError> {
        Ok(self.prepare(observations)?.matrices())
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

/// Global ranks of the spike times of all samples (equal times share a rank).
struct RankedTimes {
    /// Ranks of every sample's spikes, concatenated in the order given.
    ranks: Vec<u64>,
    /// Where each sample's ranks start (and the end).
    offsets: Vec<usize>,
    /// Number of distinct times.
    distinct: usize,
    /// Earliest and latest time (`(0, 0)` without spikes).
    range: (f64, f64),
}

impl RankedTimes {
    /// Ranks by one sort of all times.
    fn of(samples: &[Vec<(u32, f64)>]) -> Self {
        let mut offsets = Vec::with_capacity(samples.len() + 1);
        offsets.push(0);
        for s in samples {
            offsets.push(offsets.last().copied().unwrap_or(0) + s.len());
        }
        let mut all: Vec<(f64, usize)> = samples
            .iter()
            .flatten()
            .enumerate()
            .map(|(k, &(_, t))| (t, k))
            .collect();
        all.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut ranks = vec![0u64; all.len()];
        let mut rank = 0u64;
        for (w, &(t, k)) in all.iter().enumerate() {
            if w > 0 && all[w - 1].0.total_cmp(&t).is_ne() {
                rank += 1;
            }
            ranks[k] = rank;
        }
        let range = match (all.first(), all.last()) {
            (Some(lo), Some(hi)) => (lo.0, hi.0),
            _ => (0.0, 0.0),
        };
        Self {
            distinct: if all.is_empty() { 0 } else { rank as usize + 1 },
            ranks,
            offsets,
            range,
        }
    }

    /// The ranks of sample `s`'s spikes.
    fn ranks(&self, s: usize) -> &[u64] {
        &self.ranks[self.offsets[s]..self.offsets[s + 1]]
    }
}

impl PreparedVanRossum {
    /// Kernel time constant (s).
    pub fn tau_s(&self) -> f64 {
        self.tau_s
    }

    /// Number of prepared samples.
    pub fn len(&self) -> usize {
        match &self.evaluation {
            Evaluation::Centred { samples, .. } => samples.len(),
            Evaluation::Decayed(samples) => samples.len(),
        }
    }

    /// `true` when no sample was prepared.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `true` when the centred-exponential evaluation is in use (module docs).
    pub fn is_centred(&self) -> bool {
        matches!(self.evaluation, Evaluation::Centred { .. })
    }

    /// `(LL², SP²)` between prepared samples `i` and `j` (0 for `i == j`). Panics when an index is
    /// out of range. Equal, bit for bit, to the entries of [`matrices`](Self::matrices), which
    /// is much faster for many pairs (it tabulates each sample once; a single pair walks both
    /// samples' trains instead).
    pub fn squared_parts(&self, i: usize, j: usize) -> (f64, f64) {
        if i == j {
            return (0.0, 0.0);
        }
        match &self.evaluation {
            Evaluation::Centred { grid, samples } => {
                let (a, b) = (&samples[i], &samples[j]);
                let (ll, sp) = centred::cross_pair(a, b, grid);
                (
                    squared_from_products(a.labelled_self, b.labelled_self, ll),
                    squared_from_products(a.pooled_self, b.pooled_self, sp),
                )
            }
            Evaluation::Decayed(samples) => decayed_parts(&samples[i], &samples[j], self.tau_s),
        }
    }

    /// `LL²` and `SP²` for every pair of the prepared samples (parallel over rows).
    pub fn matrices(&self) -> VanRossumMatrices {
        let [ll2, sp2] = match &self.evaluation {
            Evaluation::Centred { grid, samples } => {
                let mut halves = centred::half_product_matrices(samples, grid);
                let self_products = [
                    samples.iter().map(|s| s.labelled_self).collect::<Vec<_>>(),
                    samples.iter().map(|s| s.pooled_self).collect(),
                ];
                for (m, own) in halves.iter_mut().zip(&self_products) {
                    // ⟨a, b⟩ = (a, b) + (b, a); d² written to both.
                    for a in 0..own.len() {
                        for b in a + 1..own.len() {
                            let d2 = squared_from_products(own[a], own[b], m[[a, b]] + m[[b, a]]);
                            m[[a, b]] = d2;
                            m[[b, a]] = d2;
                        }
                    }
                }
                halves
            }
            Evaluation::Decayed(samples) => symmetric_matrices(samples.len(), |i, j| {
                let (ll, sp) = decayed_parts(&samples[i], &samples[j], self.tau_s);
                [ll, sp]
            }),
        };
        VanRossumMatrices {
            tau_s: self.tau_s,
            ll2,
            sp2,
        }
    }
}

/// `(LL², SP²)` of two samples by decayed-sum merges.
fn decayed_parts(a: &DecayedSample, b: &DecayedSample, tau_s: f64) -> (f64, f64) {
    let ll_cross: f64 = a
        .trains
        .channels()
        .zip(b.trains.channels())
        .map(|(u, v)| decayed_cross(u, v, tau_s))
        .sum();
    let sp_cross = decayed_cross(&a.pooled, &b.pooled, tau_s);
    (
        squared_from_products(a.labelled_self, b.labelled_self, ll_cross),
        squared_from_products(a.pooled_self, b.pooled_self, sp_cross),
    )
}

/// `⟨u, u⟩ = n + 2·Σ_k m_k` by the markage recursion `m_k = (1 + m_{k−1})·e^{−(u_k − u_{k−1})/τ}`.
fn decayed_self(u: &[f64], tau_s: f64) -> f64 {
    let (mut markage, mut sum) = (0.0, 0.0);
    for w in u.windows(2) {
        markage = (1.0 + markage) * (-(w[1] - w[0]) / tau_s).exp();
        sum += markage;
    }
    u.len() as f64 + 2.0 * sum
}

/// `⟨u, v⟩` of two sorted trains by one merge with decayed running sums (exponentials of
/// non-positive numbers only; `u` before `v` on equal times).
fn decayed_cross(u: &[f64], v: &[f64], tau_s: f64) -> f64 {
    let (mut i, mut j) = (0, 0);
    let (mut a_u, mut a_v) = (0.0f64, 0.0f64);
    let mut last: Option<f64> = None;
    let mut acc = 0.0;
    while i < u.len() || j < v.len() {
        let take_u = j == v.len() || (i < u.len() && u[i] <= v[j]);
        let t = if take_u { u[i] } else { v[j] };
        if let Some(last) = last {
            let decay = (-(t - last) / tau_s).exp();
            a_u *= decay;
            a_v *= decay;
        }
        last = Some(t);
        if take_u {
            acc += a_v;
            a_u += 1.0;
            i += 1;
        } else {
            acc += a_u;
            a_v += 1.0;
            j += 1;
        }
    }
    acc
}

#[cfg(test)]
mod tests;
