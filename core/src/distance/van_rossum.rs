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
//! New samples against prepared ones ([`PreparedVanRossum::cross_matrices`], rectangular, with
//! prefixes in time for online use) split the same sums at the prepared spikes instead: one
//! sweep per new sample through the prepared spikes of each channel, all samples together (the
//! `cross` submodule), with the decayed sums beyond the bound.
//!
//! `D²` smaller than 0 by rounding (about 10⁻¹⁵ for identical samples) is clamped to 0, as
//! pymuvr does. Every entry is computed in a fixed order from its two samples alone, so the
//! matrices are identical at any thread count, and at any rank count when their rows are split
//! over several processes ([`PreparedVanRossum::matrices`]).

mod centred;
mod cross;
mod growing;

pub use centred::CENTRED_EXP_LIMIT;
pub use growing::{GrowingLive, GrowingVanRossum};

use super::{
    check_cos, check_tau, row_matrices, rows_on, symmetric_matrices, symmetric_matrices_on,
};
use crate::error::DistanceError;
use crate::ranks::Ranks;
use crate::spikes::MultiSpikeTrain;
use centred::{CentredSample, Grid};
use cross::{CrossIndex, NewSample, prepared_trains};
use ndarray::Array2;
use rayon::prelude::*;
use std::sync::OnceLock;

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

/// `LL²` and `SP²` of pairs of samples for one τ; any cos θ is then one elementwise
/// combination ([`squared`](Self::squared)).
///
/// Square (`N × N`, symmetric, zero diagonal) for every pair of one set
/// ([`PreparedVanRossum::matrices`]); rectangular (`n_new × n_prepared`) between new samples
/// and a prepared set ([`PreparedVanRossum::cross_matrices`]).
#[derive(Debug, Clone, PartialEq)]
pub struct VanRossumMatrices {
    /// Kernel time constant (s).
    pub tau_s: f64,
    /// Labelled-line squared distances `LL²`.
    pub ll2: Array2<f64>,
    /// Summed-population squared distances `SP²` (same shape as `ll2`).
    pub sp2: Array2<f64>,
}

/// `D²(c) = (1 − c)·LL² + c·SP²`, clamped at 0.
#[inline]
pub fn combine_squared(ll2: f64, sp2: f64, cos: f64) -> f64 {
    ((1.0 - cos) * ll2 + cos * sp2).max(0.0)
}

/// The channel count shared by every sample ([`DistanceError::ChannelCount`] names the first
/// that differs); 0 without samples.
fn common_channels(observations: &[MultiSpikeTrain]) -> Result<usize, DistanceError> {
    let channels = observations.first().map_or(0, MultiSpikeTrain::n_channels);
    match observations.iter().position(|o| o.n_channels() != channels) {
        Some(sample) => Err(DistanceError::ChannelCount {
            sample,
            expected: channels,
            got: observations[sample].n_channels(),
        }),
        None => Ok(channels),
    }
}

/// `d² = ⟨u,u⟩ + ⟨v,v⟩ − 2⟨u,v⟩`, clamped at 0.
#[inline]
fn squared_from_products(self_u: f64, self_v: f64, cross: f64) -> f64 {
    (self_u + self_v - 2.0 * cross).max(0.0)
}

impl VanRossumMatrices {
    /// `D²(c)` for every pair. Errors when `cos ∉ [0, 1]`.
    pub fn squared(&self, cos: f64) -> Result<Array2<f64>, DistanceError> {
        let mut out = Array2::zeros(self.ll2.raw_dim());
        self.squared_into(cos, &mut out)?;
        Ok(out)
    }

    /// [`squared`](Self::squared) written into `out` (reshaped to the matrices' shape when it
    /// has another), rows in parallel: the same values, without a new matrix for every cos θ
    /// (a search evaluating many cos θ at one τ). Errors when `cos ∉ [0, 1]`.
    pub fn squared_into(&self, cos: f64, out: &mut Array2<f64>) -> Result<(), DistanceError> {
        check_cos(cos)?;
        if out.dim() != self.ll2.dim() {
            *out = Array2::zeros(self.ll2.raw_dim());
        }
        let width = self.ll2.ncols().max(1);
        let combine = |o: &mut [f64], l: &[f64], s: &[f64]| {
            for ((o, &l), &s) in o.iter_mut().zip(l).zip(s) {
                *o = combine_squared(l, s, cos);
            }
        };
        let rows = (out.as_slice_mut(), self.ll2.as_slice(), self.sp2.as_slice());
        match rows {
            (Some(out), Some(ll2), Some(sp2)) if self.sp2.dim() == self.ll2.dim() => {
                (out.par_chunks_mut(width))
                    .zip(ll2.par_chunks(width).zip(sp2.par_chunks(width)))
                    .for_each(|(o, (l, s))| combine(o, l, s));
            }
            // Other memory orders (or shapes, which panic as a broadcast would).
            _ => ndarray::Zip::from(out)
                .and(&self.ll2)
                .and(&self.sp2)
                .for_each(|o, &l, &s| *o = combine_squared(l, s, cos)),
        }
        Ok(())
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
    fn new(trains: MultiSpikeTrain, tau_s: f64) -> Self {
        let pooled = trains.pooled();
        Self {
            labelled_self: trains.channels().map(|c| decayed_self(c, tau_s)).sum(),
            pooled_self: decayed_self(&pooled, tau_s),
            trains,
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
        /// The distinct spike times of all samples, sorted (rank `r` is `times[r]`).
        times: Vec<f64>,
        /// `c₀`, the middle of the spike-time span.
        centre: f64,
        /// The samples indexed for [`PreparedVanRossum::cross_matrices`] (on its first call).
        cross: OnceLock<CrossIndex>,
    },
    Decayed(Vec<DecayedSample>),
}

/// Samples prepared for one τ: ranks and (centred) exponentials computed once, so every pair
/// costs only its lookups or merges.
#[derive(Debug, Clone)]
pub struct PreparedVanRossum {
    tau_s: f64,
    /// Channels of every prepared sample (0 when there is none).
    channels: usize,
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
        let channels = common_channels(observations)?;
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
            ranked.times.len(),
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
                Evaluation::Centred {
                    grid,
                    samples,
                    times: ranked.times,
                    centre,
                    cross: OnceLock::new(),
                }
            }
            _ => Evaluation::Decayed(
                observations
                    .par_iter()
                    .map(|o| DecayedSample::new(o.clone(), self.tau_s))
                    .collect(),
            ),
        };
        Ok(PreparedVanRossum {
            tau_s: self.tau_s,
            channels,
            evaluation,
        })
    }

    /// `LL²` and `SP²` for every pair of `observations` (parallel over rows); split over
    /// `ranks` ([`PreparedVanRossum::matrices`]; every rank prepares the samples), collective;
    /// `&OneProcess` for one process.
    pub fn matrices(
        &self,
        observations: &[MultiSpikeTrain],
        ranks: &dyn Ranks,
    ) -> Result<VanRossumMatrices, DistanceError> {
        self.prepare(observations)?.matrices(ranks)
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
    /// The distinct times, sorted.
    times: Vec<f64>,
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
        let mut times = Vec::new();
        for (w, &(t, k)) in all.iter().enumerate() {
            if w > 0 && all[w - 1].0.total_cmp(&t).is_ne() {
                rank += 1;
            }
            if w == 0 || rank as usize == times.len() {
                times.push(t);
            }
            ranks[k] = rank;
        }
        let range = match (all.first(), all.last()) {
            (Some(lo), Some(hi)) => (lo.0, hi.0),
            _ => (0.0, 0.0),
        };
        Self {
            times,
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

    /// `(LL², SP²)` between prepared samples `i` and `j` (0 for `i == j`; the same for `(j, i)`).
    /// Panics when an index is out of range. Equal, bit for bit, to the entries of
    /// [`matrices`](Self::matrices), which is much faster for many pairs (it tabulates each
    /// sample once; a single pair walks both samples' trains instead).
    pub fn squared_parts(&self, i: usize, j: usize) -> (f64, f64) {
        if i == j {
            return (0.0, 0.0);
        }
        // The matrices evaluate each pair as (smaller index, larger): coincident spikes are
        // split between the two sums by that order, so the other order differs in the last bits.
        let (i, j) = (i.min(j), i.max(j));
        match &self.evaluation {
            Evaluation::Centred { grid, samples, .. } => {
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

    /// `LL²` and `SP²` between each of the samples `new` (rows) and each prepared sample
    /// (columns), `n_new × len()`, without computing any pair of prepared samples; then
    /// [`VanRossumMatrices::squared`] gives `D²(c)` for any cos θ. Each entry is the entry of the
    /// square matrices of the prepared samples followed by `new`, up to rounding (about 10⁻¹⁵
    /// of the self products `⟨u,u⟩ + ⟨v,v⟩`, where `D²` cancels for near-identical samples).
    ///
    /// With the centred evaluation (`c₀` the prepared centre, `t_k` the spikes of a new train
    /// `a`, `t_j` those of a prepared train `b`)
    ///
    /// ```text
    /// ⟨a, b⟩ = Σ_{j ∈ b} e^{−(t_j − c₀)/τ}·Σ_{t_k ≤ t_j} e^{(t_k − c₀)/τ} + e^{(t_j − c₀)/τ}·Σ_{t_k > t_j} e^{−(t_k − c₀)/τ}
    /// ```
    ///
    /// per channel for `LL²` and pooled for `SP²`: the inner sums change only at `a`'s spikes,
    /// so each new sample is one sweep through the prepared spikes of each channel, all samples
    /// together in time order, at four multiply-adds per prepared spike and no exponential. The
    /// first call indexes the prepared samples that way (once; `O(S log S)` for `S` prepared
    /// spikes, and 16 bytes per spike): call it with no new sample to do it ahead of time.
    /// About 5 ms for one sample of 49 channels × 35 spikes against 1100 such samples on one
    /// core, half that for their first half in time ([`cross_matrices_until`](Self::cross_matrices_until)).
    ///
    /// A new sample with a spike farther than [`CENTRED_EXP_LIMIT`]`·τ` from `c₀`, and every new
    /// sample when the prepared samples use the decayed sums, is compared by decayed-sum merges
    /// instead: exact and stable at any distance, but one merge per pair of trains (and, in the
    /// first case, the prepared trains rebuilt for the call). Rows run in parallel.
    ///
    /// Every new sample must have the prepared samples' channel count:
    /// [`DistanceError::ChannelCount`] names the first that differs (`sample` indexes `new`,
    /// `expected` is the prepared count); when nothing was prepared any count is accepted and
    /// the matrices have no column.
    pub fn cross_matrices(
        &self,
        new: &[MultiSpikeTrain],
    ) -> Result<VanRossumMatrices, DistanceError> {
        self.cross_matrices_until(new, f64::INFINITY)
    }

    /// [`cross_matrices`](Self::cross_matrices) between the prefixes in time of `new` and of
    /// the prepared samples: `D²(a|T, b|T)` with `u|T = {t ∈ u : t < T}`, `T = t_end_s`, the
    /// comparison of a live sample after `T` seconds with the training samples over the same
    /// elapsed time. The prepared samples are cut where they lie (a binary search per channel);
    /// nothing of them is copied or prepared again, since the index holds the self products of
    /// every prefix. `t_end_s = +∞` compares the whole samples; NaN is an
    /// [`InvalidParameter`](DistanceError::InvalidParameter).
    ///
    /// ```
    /// use neurotac_core::{MultiSpikeTrain, distance::VanRossum};
    /// let train = [
    ///     MultiSpikeTrain::from_channels(vec![vec![0.1, 0.9], vec![0.4]])?,
    ///     MultiSpikeTrain::from_channels(vec![vec![], vec![0.2, 0.3]])?,
    /// ];
    /// let prepared = VanRossum::new(0.05)?.prepare(&train)?;
    /// let live = MultiSpikeTrain::from_channels(vec![vec![0.1], vec![0.4]])?;
    /// // After 0.5 s the live sample matches the first training sample's prefix exactly.
    /// let m = prepared.cross_matrices_until(&[live], 0.5)?;
    /// let d2 = m.squared(0.4)?;
    /// assert_eq!(d2.dim(), (1, 2));
    /// assert!(d2[[0, 0]] < 1e-12 && d2[[0, 1]] > 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cross_matrices_until(
        &self,
        new: &[MultiSpikeTrain],
        t_end_s: f64,
    ) -> Result<VanRossumMatrices, DistanceError> {
        if t_end_s.is_nan() {
            return Err(DistanceError::InvalidParameter {
                what: "t_end_s",
                value: t_end_s,
                expected: "a time in seconds (not NaN)",
            });
        }
        if self.is_empty() {
            let none = Array2::zeros((new.len(), 0));
            return Ok(VanRossumMatrices {
                tau_s: self.tau_s,
                ll2: none.clone(),
                sp2: none,
            });
        }
        if let Some(sample) = new.iter().position(|o| o.n_channels() != self.channels) {
            return Err(DistanceError::ChannelCount {
                sample,
                expected: self.channels,
                got: new[sample].n_channels(),
            });
        }
        let tau_s = self.tau_s;
        let cut = |o: &MultiSpikeTrain| o.window(f64::NEG_INFINITY, t_end_s).expect("T not NaN");
        let new: Vec<DecayedSample> = (new.par_iter())
            .map(|o| DecayedSample::new(cut(o), tau_s))
            .collect();
        let decayed_row = |a: &DecayedSample, samples: &[DecayedSample]| -> Vec<[f64; 2]> {
            (samples.iter())
                .map(|b| decayed_parts_until(a, b, t_end_s, tau_s).into())
                .collect()
        };
        let [ll2, sp2] = match &self.evaluation {
            Evaluation::Decayed(samples) => {
                row_matrices(new.len(), samples.len(), |i| decayed_row(&new[i], samples))
            }
            Evaluation::Centred {
                grid,
                samples,
                times,
                centre,
                cross,
            } => {
                let index = cross.get_or_init(|| CrossIndex::new(samples, grid, times));
                let rows: Vec<Option<NewSample>> = (new.par_iter())
                    .map(|a| {
                        let spikes = a.trains.pooled_with_channels();
                        index.place(&spikes, times, *centre, 1.0 / tau_s)
                    })
                    .collect();
                // The prepared samples as decayed samples, for new samples beyond the range.
                let fallback: Vec<DecayedSample> = if rows.iter().any(Option::is_none) {
                    (samples.par_iter())
                        .map(|b| DecayedSample::new(prepared_trains(b, grid, times), tau_s))
                        .collect()
                } else {
                    Vec::new()
                };
                let end_rank = times.partition_point(|&t| t < t_end_s) as u32;
                row_matrices(new.len(), samples.len(), |i| {
                    let Some(row) = &rows[i] else {
                        return decayed_row(&new[i], &fallback);
                    };
                    let own = [new[i].labelled_self, new[i].pooled_self];
                    let cross = index.cross_products(row, end_rank);
                    (cross.iter().enumerate())
                        .map(|(b, &[ll, sp, spikes])| {
                            let other = index.self_products(b, spikes as usize);
                            [
                                squared_from_products(own[0], other[0], ll),
                                squared_from_products(own[1], other[1], sp),
                            ]
                        })
                        .collect()
                })
            }
        };
        Ok(VanRossumMatrices { tau_s, ll2, sp2 })
    }

    /// `LL²` and `SP²` for every pair of the prepared samples in this process (parallel over
    /// rows).
    fn matrices_in_one_process(&self) -> VanRossumMatrices {
        let [ll2, sp2] = match &self.evaluation {
            Evaluation::Centred { grid, samples, .. } => {
                let halves = centred::half_product_rows(samples, grid, 0..samples.len());
                centred_matrices(samples, &halves)
            }
            Evaluation::Decayed(samples) => {
                symmetric_matrices(samples.len(), decayed_pair(samples, self.tau_s))
            }
        };
        VanRossumMatrices {
            tau_s: self.tau_s,
            ll2,
            sp2,
        }
    }

    /// `LL²` and `SP²` for every pair of the prepared samples (parallel over rows).
    ///
    /// Split over `ranks` (`&OneProcess` for one process): each rank computes a contiguous block
    /// of rows (parallel within the rank), then the blocks are all-gathered, so every rank
    /// returns the one-process matrices, bit for bit, at any rank count. The centred
    /// evaluation computes whole rows of half products, so its rows are split evenly; the
    /// decayed sums compute the upper triangle, whose row `i` costs `N − i − 1` pairs, so
    /// those rows are split by [`balanced_blocks`](crate::ranks::balanced_blocks). Collective:
    /// every rank must call it, on the same prepared samples.
    ///
    /// ```
    /// use neurotac_core::{MultiSpikeTrain, distance::VanRossum, ranks::ThreadRanks};
    /// let samples: Vec<MultiSpikeTrain> = (0..5)
    ///     .map(|i| MultiSpikeTrain::from_channels(vec![vec![0.01 * i as f64], vec![0.2]]))
    ///     .collect::<Result<_, _>>()?;
    /// let prepared = VanRossum::new(0.05)?.prepare(&samples)?;
    /// let on_three = ThreadRanks::run(3, |r| prepared.matrices(r).unwrap());
    /// assert!(on_three.iter().all(|m| *m == prepared.matrices(&neurotac_core::OneProcess).unwrap()));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn matrices(&self, ranks: &dyn Ranks) -> Result<VanRossumMatrices, DistanceError> {
        if ranks.size() == 1 {
            return Ok(self.matrices_in_one_process());
        }
        let [ll2, sp2] = match &self.evaluation {
            Evaluation::Centred { grid, samples, .. } => {
                let n = samples.len();
                let halves = rows_on(ranks, &vec![2 * n; n], |rows| {
                    centred::half_product_rows(samples, grid, rows)
                })?;
                centred_matrices(samples, &halves)
            }
            Evaluation::Decayed(samples) => {
                symmetric_matrices_on(samples.len(), decayed_pair(samples, self.tau_s), ranks)?
            }
        };
        Ok(VanRossumMatrices {
            tau_s: self.tau_s,
            ll2,
            sp2,
        })
    }
}

/// `[LL², SP²]` of the centred samples from the [`half_product_rows`](centred::half_product_rows)
/// of every row: `⟨a, b⟩ = (a, b) + (b, a)`, `d²` written to both entries.
fn centred_matrices(samples: &[CentredSample], halves: &[f64]) -> [Array2<f64>; 2] {
    let n = samples.len();
    let own = [
        samples.iter().map(|s| s.labelled_self).collect::<Vec<_>>(),
        samples.iter().map(|s| s.pooled_self).collect(),
    ];
    std::array::from_fn(|m| {
        let half = |a: usize, b: usize| halves[a * 2 * n + m * n + b];
        Array2::from_shape_fn((n, n), |(i, j)| {
            let (a, b) = (i.min(j), i.max(j));
            match a == b {
                true => 0.0,
                false => squared_from_products(own[m][a], own[m][b], half(a, b) + half(b, a)),
            }
        })
    })
}

/// The decayed-sum `[LL², SP²]` of prepared samples `i` and `j`.
fn decayed_pair(
    samples: &[DecayedSample],
    tau_s: f64,
) -> impl Fn(usize, usize) -> [f64; 2] + Sync + '_ {
    move |i, j| decayed_parts(&samples[i], &samples[j], tau_s).into()
}

/// `(LL², SP²)` of two samples by decayed-sum merges.
fn decayed_parts(a: &DecayedSample, b: &DecayedSample, tau_s: f64) -> (f64, f64) {
    decayed_parts_until(a, b, f64::INFINITY, tau_s)
}

/// The spikes `t < t_end_s` of a sorted train.
fn before(u: &[f64], t_end_s: f64) -> &[f64] {
    &u[..u.partition_point(|&t| t < t_end_s)]
}

/// `(LL², SP²)` between `a` and the spikes `t < t_end_s` of `b`, by decayed-sum merges (`b`'s
/// self products are recomputed when the cut removes spikes).
fn decayed_parts_until(
    a: &DecayedSample,
    b: &DecayedSample,
    t_end_s: f64,
    tau_s: f64,
) -> (f64, f64) {
    let ll_cross: f64 = a
        .trains
        .channels()
        .zip(b.trains.channels())
        .map(|(u, v)| decayed_cross(u, before(v, t_end_s), tau_s))
        .sum();
    let b_pooled = before(&b.pooled, t_end_s);
    let sp_cross = decayed_cross(&a.pooled, b_pooled, tau_s);
    let (ll_self, sp_self) = if b_pooled.len() == b.pooled.len() {
        (b.labelled_self, b.pooled_self)
    } else {
        let channels = b.trains.channels();
        (
            channels
                .map(|v| decayed_self(before(v, t_end_s), tau_s))
                .sum(),
            decayed_self(b_pooled, tau_s),
        )
    };
    (
        squared_from_products(a.labelled_self, ll_self, ll_cross),
        squared_from_products(a.pooled_self, sp_self, sp_cross),
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
