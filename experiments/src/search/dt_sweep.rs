//! Brute-force search of the temporal coding's window Δt (the paper: 1…200 ms in 1 ms steps,
//! leave-one-out KNN accuracy at each), exact, from one prefix sum per sample.
//!
//! # Why it is fast
//! With `x[b]` the pooled spike count of a sample in 1-ms bin `b` and `C[m] = Σ_{b<m} x[b]`, the
//! temporal features are `w(s) = C[s + Δ] − C[s]`, `s ∈ [0, T − Δ]` (times `1/N`, which no
//! ranking sees). Their inner product for every Δ needs no feature vector at all. Summed over
//! every window start `s ∈ ℤ` instead,
//!
//! ```text
//! Σ_s w_a(s)·w_b(s) = Σ_{k ∈ a, l ∈ b} max(0, Δ − |k − l|) = Σ_{|d| < Δ} X(d)·(Δ − |d|),   X(d) = Σ_{k ∈ a} x_b[k + d]
//! ```
//!
//! so one correlogram `X` over the lags `|d| < Δ_max` gives all windows at once, as a double
//! prefix sum over `Y(j) = X(j) + X(−j)`. `X` costs one vector add of `b`'s bins per spike of
//! `a` (bytes, 64 lanes per vector, flushed to wider sums before a lane can reach 256). The
//! windows starting before 0 or after `T − Δ` hold `C[s + Δ]` and `n − C[s]` spikes, so
//!
//! ```text
//! ⟨w_a, w_b⟩(Δ) = Σ_s w_a(s)·w_b(s) − Σ_{0 < m < Δ} (C_a[m]·C_b[m] + (n_a − C_a[T − m])·(n_b − C_b[T − m]))
//! ```
//!
//! a running sum over per-sample arrays. When a bin holds more than 255 spikes, the first sum
//! comes instead from `Q[m] = Σ_{i<m} C[i]` continued past both ends: a spike `k` adds
//! `Q_b[k + 1 + Δ] + Q_b[k + 1 − Δ] − 2·Q_b[k + 1]`, two contiguous loads for a block of Δ
//! values. The squared distance is then `‖w_a‖² + ‖w_b‖² − 2⟨w_a, w_b⟩`, an integer, computed in
//! wrapping `i32` arithmetic — exact because every step is a ring operation mod 2³² and the true
//! value is known to lie in `[0, 2³¹)` (bound checked per dataset; `i64` otherwise). Integer
//! distances rank exactly as the Euclidean distances of the features, ties included, so the KNN
//! predictions are exactly those of the feature vectors.
//!
//! Each pair's inner products, for all windows at once, come from the sample with fewer
//! spikes. Leave-one-out is fused with the distances: every pair's squared distances are
//! offered, for a block of [`LANES`] windows (one block covers the paper's 200) at once, to both
//! samples' `k` nearest (one vector comparison against the current `k`-th distances; the few
//! that pass are inserted), so no distance is stored. Rows are split into chunks that run in
//! parallel, each with its own neighbour lists; the lists of all chunks are then merged under
//! the `(distance, index)` order of [`neurotac_core::knn::TopK`], which gives the same
//! neighbours for any chunking (thread count), and voted on with its tie rules.
//!
//! Over several ranks ([`dt_sweep`]) each rank takes a block of rows balanced by pair
//! count, merges its chunks' lists, and the ranks' lists are all-gathered and merged the same
//! way: the same neighbours, so the same predictions, at any rank count.

use crate::error::ExperimentError;
use crate::protocols::Accuracy;
use lanes::Lane;
use neighbours::Neighbours;
use neurotac_core::coding::pooled_bin_counts;
use neurotac_core::knn::vote;
use neurotac_core::ranks::balanced_blocks;
use neurotac_core::{Knn, KnnError, MultiSpikeTrain, Ranks, RanksError};
use rayon::prelude::*;
use serde::Serialize;
use std::ops::Range;

mod lanes;
mod neighbours;

pub use lanes::LANES;

/// Lags per block of the byte correlogram (7 vectors of 64 bytes: `|d| < 224`).
const LAG_LANES: usize = 448;

/// Rows computed together so that each column sample's arrays are reused from cache.
const ROW_BLOCK: usize = 16;

/// Chunks of rows per thread (each with its own neighbour lists).
const CHUNKS_PER_THREAD: usize = 2;

/// Leave-one-out accuracy at every window of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DtSweep {
    /// The windows Δt (ms), increasing.
    pub windows_ms: Vec<u32>,
    /// Leave-one-out accuracy at each window.
    pub accuracy: Vec<f64>,
    /// The best window (highest accuracy; the smallest Δt among equals).
    pub best_window_ms: u32,
    /// Its accuracy, with standard deviation and Wilson interval.
    pub best: Accuracy,
}

/// One sample: its spike bins (sorted, with repeats); the counts in its first and in its last
/// `m` bins, `C[m]` and `n − C[T − m]`, for `m < Δ_max` (zero padded to whole blocks); and either
/// the bin counts as bytes shifted by `Δ_max − 1` (zero padded) for the correlogram, or, when a
/// bin holds more than a byte, `Q[m] = Σ_j x[j]·(m − 1 − j)₊` forward and reversed
/// (`Q[T + 1 − j]`), both continued past their ends as that formula does (linearly after
/// `T + 1`, 0 before 0) and long enough that every block load stays inside.
struct Prepared<L> {
    bins: Vec<u32>,
    q: Vec<L>,
    q_reversed: Vec<L>,
    lagged: Vec<u8>,
    first: Vec<L>,
    last: Vec<L>,
}

/// Shape of one sweep: duration `t`, largest window `delta_max` and, when every bin count fits a
/// byte, how many spikes a byte correlogram can add before it must be flushed.
#[derive(Debug, Clone, Copy)]
struct Shape {
    t: usize,
    delta_max: usize,
    flush_every: Option<usize>,
}

impl Shape {
    fn new(t: usize, delta_max: usize, max_bin_count: u32) -> Self {
        let flush_every = u8::try_from(max_bin_count.max(1))
            .ok()
            .map(|m| (u8::MAX / m) as usize);
        Self {
            t,
            delta_max,
            flush_every,
        }
    }

    /// Blocks of [`LANES`] windows.
    fn blocks(&self) -> usize {
        self.delta_max.div_ceil(LANES)
    }

    /// Blocks of [`LAG_LANES`] lags `d ∈ [−(Δ_max − 1), Δ_max − 1]`.
    fn lag_blocks(&self) -> usize {
        (2 * self.delta_max - 1).div_ceil(LAG_LANES)
    }
}

fn prepare<L: Lane>(bin_counts: &[u32], shape: &Shape) -> Prepared<L> {
    let (t, delta_max) = (shape.t, shape.delta_max);
    let mut bins = Vec::new();
    for (b, &c) in bin_counts.iter().enumerate() {
        bins.extend(std::iter::repeat_n(b as u32, c as usize));
    }
    let (mut q, mut q_reversed, mut lagged) = (Vec::new(), Vec::new(), Vec::new());
    if shape.flush_every.is_some() {
        // lagged[j] = x[j − (Δ_max − 1)]: the load at k covers x[k + d], |d| < Δ_max.
        lagged = vec![0u8; t + shape.lag_blocks() * LAG_LANES];
        for (b, &c) in bin_counts.iter().enumerate() {
            lagged[b + delta_max - 1] = c as u8;
        }
    } else {
        // Q[m + 1] = Q[m] + C[m], C[m + 1] = C[m] + x[m] (x = 0 from T on), in wrapping lanes.
        let len = t + 2 + delta_max + LANES;
        let (mut c, mut acc) = (L::default(), L::default());
        let mut x = bin_counts.iter().map(|&x| L::from_i64(x as i64));
        for _ in 0..len {
            q.push(acc);
            acc = acc.wadd(c);
            c = c.wadd(x.next().unwrap_or_default());
        }
        q_reversed = q[..t + 2].iter().rev().copied().collect();
        q_reversed.resize(len, L::default());
    }
    let lanes = shape.blocks() * LANES;
    let (mut first, mut last) = (vec![L::default(); lanes], vec![L::default(); lanes]);
    let (mut head, mut tail) = (0i64, 0i64);
    for m in 1..delta_max {
        head += bin_counts[m - 1] as i64;
        tail += bin_counts[t - m] as i64;
        first[m] = L::from_i64(head);
        last[m] = L::from_i64(tail);
    }
    Prepared {
        bins,
        q,
        q_reversed,
        lagged,
        first,
        last,
    }
}

/// `Σ_k (Q_b[k + 1 + Δ] + Q_b[k + 1 − Δ])` over the spikes `k` in `bins` for the block's Δ
/// values, and `Σ_k Q_b[k + 1]`: with the continued `Q`, `Σ_k Σ_l x_b[l]·max(0, Δ − |k − l|)`
/// is the first minus twice the second. Kept apart so the block accumulators stay in registers.
#[inline(never)]
fn window_sum<L: Lane>(bins: &[u32], b: &Prepared<L>, t: usize, d0: usize) -> ([L; LANES], L) {
    let mut acc = [L::default(); LANES];
    let mut centre = L::default();
    for &k in bins {
        let k = k as usize;
        let forward: &[L; LANES] = b.q[k + 2 + d0..k + 2 + d0 + LANES]
            .try_into()
            .expect("LANES values");
        let backward: &[L; LANES] = b.q_reversed[t - k + d0 + 1..t - k + d0 + 1 + LANES]
            .try_into()
            .expect("LANES values");
        for l in 0..LANES {
            acc[l] = acc[l].wadd(forward[l]).wadd(backward[l]);
        }
        centre = centre.wadd(b.q[k + 1]);
    }
    (acc, centre)
}

/// Adds the correlogram `X(d) = Σ_k x_b[k + d]` over the spikes `k` in `bins` for the lags of
/// lag block `block` to `x`, in byte lanes flushed every `flush_every` spikes (so no lane exceeds
/// 255). Kept apart so the byte accumulators stay in registers.
#[inline(never)]
fn correlogram_block<L: Lane>(
    bins: &[u32],
    lagged: &[u8],
    block: usize,
    flush_every: usize,
    x: &mut [L; LAG_LANES],
) {
    let offset = block * LAG_LANES;
    for group in bins.chunks(flush_every) {
        let mut acc = [0u8; LAG_LANES];
        for &k in group {
            let at = k as usize + offset;
            let window: &[u8; LAG_LANES] = lagged[at..at + LAG_LANES]
                .try_into()
                .expect("LAG_LANES values");
            for l in 0..LAG_LANES {
                acc[l] = acc[l].wrapping_add(window[l]);
            }
        }
        for (x, &a) in x.iter_mut().zip(&acc) {
            *x = x.wadd(L::from_i64(a as i64));
        }
    }
}

/// `⟨w_a, w_b⟩(Δ)` for `Δ = 1..=Δ_max` in `out[Δ − 1]` (`blocks · LANES` lanes, those beyond
/// `Δ_max` set to 0), from the spikes of `a` and the arrays of `b`.
///
/// First the sum over windows at every start `s ∈ ℤ`, `Σ_{k,l} x_a[k]·x_b[l]·max(0, Δ − |k − l|)`.
/// With byte bins it comes from the correlogram `X(d)` over `|d| < Δ_max`, one byte vector add
/// per spike and lag block, as a double prefix sum over `Y(j) = X(j) + X(−j)`; otherwise from
/// [`window_sum`] per block of [`LANES`] windows. The windows starting before 0 count `C[s + Δ]`
/// and those starting after `T − Δ` count `n − C[s]`, so the sum over `s ∈ [0, T − Δ]` is that
/// minus `Σ_{0 < m < Δ} (C_a[m]·C_b[m] + (n_a − C_a[T − m])·(n_b − C_b[T − m]))`.
fn inner_products<L: Lane>(
    a: &Prepared<L>,
    b: &Prepared<L>,
    shape: &Shape,
    out: &mut [L],
    lags: &mut Vec<[L; LAG_LANES]>,
) {
    let dm = shape.delta_max;
    match shape.flush_every {
        Some(flush_every) => {
            lags.resize(shape.lag_blocks(), [L::default(); LAG_LANES]);
            lags.fill([L::default(); LAG_LANES]);
            for (block, x) in lags.iter_mut().enumerate() {
                correlogram_block(&a.bins, &b.lagged, block, flush_every, x);
            }
            // Δ·Y(0) + (Δ − 1)·Y(1) + …: T(Δ + 1) = T(Δ) + Σ_{j ≤ Δ} Y(j), Y(0) = X(0).
            let x = lags.as_flattened();
            let (right, left) = (&x[dm - 1..2 * dm - 1], &x[..dm]);
            let (mut cumulative, mut total) = (L::default().wsub(right[0]), L::default());
            for ((o, &r), &l) in out.iter_mut().zip(right).zip(left.iter().rev()) {
                cumulative = cumulative.wadd(r).wadd(l);
                total = total.wadd(cumulative);
                *o = total;
            }
        }
        None => {
            for (block, out) in out.chunks_exact_mut(LANES).enumerate() {
                let (part, centre) = window_sum(&a.bins, b, shape.t, block * LANES);
                let twice = centre.wadd(centre);
                for (o, p) in out.iter_mut().zip(part) {
                    *o = p.wsub(twice);
                }
            }
        }
    }
    let mut clipped = L::default();
    for (o, (((fa, fb), la), lb)) in out
        .iter_mut()
        .zip(a.first.iter().zip(&b.first).zip(&a.last).zip(&b.last))
        .take(dm)
    {
        clipped = clipped.wadd(fa.wmul(*fb)).wadd(la.wmul(*lb));
        *o = o.wsub(clipped);
    }
    for slot in out.iter_mut().skip(dm) {
        *slot = L::default();
    }
}

/// Exact squared feature distances `N²·‖R_a − R_b‖²` for `Δ = 1..=delta_max` (for checks and
/// small problems; the sweep uses the same kernel).
pub fn window_squared_distances(
    a: &MultiSpikeTrain,
    b: &MultiSpikeTrain,
    duration_ms: u32,
    delta_max: u32,
) -> Vec<i64> {
    let counts = [
        pooled_bin_counts(a, duration_ms),
        pooled_bin_counts(b, duration_ms),
    ];
    let max_count = counts.iter().flatten().copied().max().unwrap_or(0);
    let shape = Shape::new(duration_ms as usize, delta_max as usize, max_count);
    let [pa, pb] = counts.map(|c| prepare::<i64>(&c, &shape));
    let mut lags = Vec::new();
    let mut inner = |x: &Prepared<i64>, y: &Prepared<i64>| {
        let mut out = vec![0; shape.blocks() * LANES];
        inner_products(x, y, &shape, &mut out, &mut lags);
        out
    };
    let (aa, bb, ab) = (inner(&pa, &pa), inner(&pb, &pb), inner(&pa, &pb));
    (0..delta_max as usize)
        .map(|l| aa[l] + bb[l] - 2 * ab[l])
        .collect()
}

/// Runs the sweep over `Δt = 1..=max_window_ms` ms on samples of `duration_ms` (spikes outside
/// `[0, T)` are not part of a sample), leave-one-out with `knn`.
///
/// Split over `ranks` (`&OneProcess` for one process) ([`dt_sweep_of_bins`]). Collective.
pub fn dt_sweep(
    observations: &[MultiSpikeTrain],
    labels: &[usize],
    duration_ms: u32,
    max_window_ms: u32,
    knn: Knn,
    ranks: &dyn Ranks,
) -> Result<DtSweep, ExperimentError> {
    dt_sweep_of_bins(
        &bins_of(observations, duration_ms),
        labels,
        max_window_ms,
        knn,
        ranks,
    )
}

/// [`dt_sweep`] from each sample's pooled spike count per 1-ms bin (e.g. a temporal coding
/// readout's [`bin_counts`](neurotac_core::coding::TemporalCoding::bin_counts)); all samples
/// have the same number of bins, the duration `T` in ms.
///
/// [`dt_sweep_of_bins`] split over `ranks`: the pairs of samples are split over the ranks
/// ([`leave_one_out_predictions_of_bins`]), and every rank returns the one-process sweep.
/// Collective: every rank must call it.
pub fn dt_sweep_of_bins(
    bins: &[Vec<u32>],
    labels: &[usize],
    max_window_ms: u32,
    knn: Knn,
    ranks: &dyn Ranks,
) -> Result<DtSweep, ExperimentError> {
    let predictions = leave_one_out_predictions_of_bins(bins, labels, max_window_ms, knn, ranks)?;
    let n = labels.len();
    let accuracy: Vec<f64> = predictions
        .iter()
        .map(|p| p.iter().zip(labels).filter(|(p, t)| p == t).count() as f64 / n as f64)
        .collect();
    let best = (0..accuracy.len())
        .max_by(|&x, &y| accuracy[x].total_cmp(&accuracy[y]).then(y.cmp(&x)))
        .expect("at least one window");
    Ok(DtSweep {
        windows_ms: (1..=max_window_ms).collect(),
        best_window_ms: best as u32 + 1,
        best: Accuracy::of(&predictions[best], labels),
        accuracy,
    })
}

fn bins_of(observations: &[MultiSpikeTrain], duration_ms: u32) -> Vec<Vec<u32>> {
    observations
        .par_iter()
        .map(|o| pooled_bin_counts(o, duration_ms))
        .collect()
}

/// The leave-one-out predictions of [`dt_sweep`]: entry `Δt − 1` holds one label per sample.
pub fn leave_one_out_predictions(
    observations: &[MultiSpikeTrain],
    labels: &[usize],
    duration_ms: u32,
    max_window_ms: u32,
    knn: Knn,
) -> Result<Vec<Vec<usize>>, ExperimentError> {
    leave_one_out_predictions_of_bins(
        &bins_of(observations, duration_ms),
        labels,
        max_window_ms,
        knn,
        &neurotac_core::OneProcess,
    )
}

/// [`leave_one_out_predictions`] from per-ms pooled bin counts (see [`dt_sweep_of_bins`]).
///
/// [`leave_one_out_predictions_of_bins`] split over `ranks`: each rank computes the pairs
/// `(a, b)`, `a < b`, of a block of rows `a` balanced by pair count (row `a` has `N − a − 1`),
/// for every window at once; the ranks' `k` nearest of every sample at every window are
/// all-gathered and merged in the `(distance, index)` order, so every rank returns the
/// one-process predictions. Collective: every rank must call it.
///
/// The pairs are split rather than the windows because one pair's distances at every window
/// come from one correlogram over all lags `|d| < Δ_max` (module docs): a rank given only some
/// windows would still pay for nearly all of it, while a block of pairs costs its share, and
/// only the neighbour lists (`N × Δ_max × k` entries) travel.
pub fn leave_one_out_predictions_of_bins(
    counts: &[Vec<u32>],
    labels: &[usize],
    max_window_ms: u32,
    knn: Knn,
    ranks: &dyn Ranks,
) -> Result<Vec<Vec<usize>>, ExperimentError> {
    let n = counts.len();
    if labels.len() != n {
        return Err(KnnError::Shape {
            rows: n,
            cols: n,
            labels: labels.len(),
        }
        .into());
    }
    if knn.k() > n.saturating_sub(1) {
        return Err(KnnError::KTooLarge {
            k: knn.k(),
            n_train: n.saturating_sub(1),
        }
        .into());
    }
    if u32::try_from(n).is_err() {
        // Neighbour indices are stored as u32 (u32::MAX marks an empty slot).
        return Err(ExperimentError::InvalidParameter {
            what: "samples",
            value: n as f64,
            expected: "fewer than 2³² − 1",
        });
    }
    let duration = counts.first().map_or(0, Vec::len);
    if let Some(sample) = counts.iter().position(|c| c.len() != duration) {
        return Err(ExperimentError::InvalidParameter {
            what: "bins of a sample (ms)",
            value: counts[sample].len() as f64,
            expected: "the same duration as sample 0",
        });
    }
    let duration_ms = u32::try_from(duration).unwrap_or(u32::MAX);
    if max_window_ms == 0 || max_window_ms > duration_ms {
        return Err(ExperimentError::InvalidParameter {
            what: "max_window_ms",
            value: max_window_ms as f64,
            expected: "≥ 1 and ≤ the sample duration",
        });
    }
    // Exact integer lanes: D² ≤ 2(‖w_a‖² + ‖w_b‖²) with ‖w‖² ≤ max window count · Δ · n, so the
    // wrapping ring arithmetic gives it exactly when below half the lane range.
    let bound = counts
        .iter()
        .map(|c| {
            let total: u64 = c.iter().map(|&x| x as u64).sum();
            let mut window: u64 = c[..max_window_ms as usize].iter().map(|&x| x as u64).sum();
            let mut most = window;
            for s in max_window_ms as usize..c.len() {
                window = window + c[s] as u64 - c[s - max_window_ms as usize] as u64;
                most = most.max(window);
            }
            (most as u128) * (max_window_ms as u128) * (total as u128)
        })
        .max()
        .unwrap_or(0);
    let max_count = counts.iter().flatten().copied().max().unwrap_or(0);
    let shape = Shape::new(duration_ms as usize, max_window_ms as usize, max_count);
    if 4 * bound < i32::MAX as u128 {
        Ok(sweep::<i32>(counts, labels, &shape, knn, ranks)?)
    } else if 4 * bound < i64::MAX as u128 {
        Ok(sweep::<i64>(counts, labels, &shape, knn, ranks)?)
    } else {
        Err(ExperimentError::InvalidParameter {
            what: "duration_ms",
            value: duration_ms as f64,
            expected: "duration × spikes per sample small enough for exact 64-bit window sums",
        })
    }
}

fn sweep<L: Lane>(
    counts: &[Vec<u32>],
    labels: &[usize],
    shape: &Shape,
    knn: Knn,
    ranks: &dyn Ranks,
) -> Result<Vec<Vec<usize>>, RanksError> {
    let n = counts.len();
    let lanes = shape.blocks() * LANES;
    let prepared: Vec<Prepared<L>> = counts.par_iter().map(|c| prepare(c, shape)).collect();
    let norms: Vec<Vec<L>> = prepared
        .par_iter()
        .map_init(Vec::new, |lags, p| {
            let mut out = vec![L::default(); lanes];
            inner_products(p, p, shape, &mut out, lags);
            out
        })
        .collect();
    let new_lists = || Neighbours::new(n, shape.blocks(), shape.delta_max, knn.k());
    let parts = rayon::current_num_threads() * CHUNKS_PER_THREAD;
    let lists: Vec<Neighbours<L>> = row_chunks(n, ranks.rank(), ranks.size(), parts)
        .into_par_iter()
        .map(|rows| {
            let mut lists = new_lists();
            let (mut ab, mut lags) = (vec![L::default(); lanes], Vec::new());
            for first in rows.clone().step_by(ROW_BLOCK) {
                let block = first..(first + ROW_BLOCK).min(rows.end);
                // Column b outermost so its arrays stay in cache for every row of the block.
                for b in first + 1..n {
                    for a in block.start..block.end.min(b) {
                        // ⟨w_a, w_b⟩ from the sample with fewer spikes.
                        let (sparse, dense) = if prepared[a].bins.len() <= prepared[b].bins.len() {
                            (&prepared[a], &prepared[b])
                        } else {
                            (&prepared[b], &prepared[a])
                        };
                        inner_products(sparse, dense, shape, &mut ab, &mut lags);
                        for blk in 0..shape.blocks() {
                            let at = blk * LANES;
                            let (na, nb, ab) = (&norms[a][at..], &norms[b][at..], &ab[at..]);
                            let d2: [L; LANES] =
                                std::array::from_fn(|l| na[l].wadd(nb[l]).wsub(ab[l].wadd(ab[l])));
                            lists.offer(a, blk, &d2, b);
                            lists.offer(b, blk, &d2, a);
                        }
                    }
                }
            }
            lists
        })
        .collect();
    // Merge the chunks' lists per sample and window, then the ranks'.
    let merge = |lists: &[Neighbours<L>]| {
        Neighbours::merged(lists, n, shape.blocks(), shape.delta_max, knn.k())
    };
    let mut nearest = merge(&lists);
    if ranks.size() > 1 {
        let gathered = ranks.all_gather_bytes(&nearest.to_bytes())?;
        let all = (gathered.iter().enumerate())
            .map(|(rank, bytes)| {
                let lists =
                    Neighbours::from_bytes(bytes, n, shape.blocks(), shape.delta_max, knn.k());
                lists.ok_or_else(|| RanksError::Malformed {
                    rank,
                    during: "gathering the Δt sweep's neighbour lists",
                    reason: format!(
                        "{} bytes that are not {n} samples × {} windows × {} neighbours",
                        bytes.len(),
                        shape.delta_max,
                        knn.k()
                    ),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        nearest = merge(&all);
    }
    let by_sample: Vec<Vec<usize>> = (0..n)
        .into_par_iter()
        .map(|s| {
            (0..shape.delta_max)
                .map(|lane| {
                    vote(nearest.neighbours(s, lane).map(|(_, j)| labels[j]))
                        .expect("k ≥ 1 and n > k")
                })
                .collect()
        })
        .collect();
    Ok((0..shape.delta_max)
        .map(|lane| by_sample.iter().map(|p| p[lane]).collect())
        .collect())
}

/// The rows `a` whose pairs `(a, b)`, `a < b < n`, rank `rank` of `size` computes (a block of
/// [`balanced_blocks`] by pair count, row `a` having `n − a − 1`), in at most `parts` non-empty
/// contiguous chunks with about equal numbers of pairs.
fn row_chunks(n: usize, rank: usize, size: usize, parts: usize) -> Vec<Range<usize>> {
    let pairs: Vec<f64> = (0..n).map(|a| (n - a - 1) as f64).collect();
    let mine = balanced_blocks(&pairs, size)[rank].clone();
    (balanced_blocks(&pairs[mine.clone()], parts).into_iter())
        .filter(|c| !c.is_empty())
        .map(|c| mine.start + c.start..mine.start + c.end)
        .collect()
}

#[cfg(test)]
mod tests;
