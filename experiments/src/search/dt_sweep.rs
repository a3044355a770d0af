//! Brute-force search of the temporal coding's window Δt (the paper: 1…200 ms in 1 ms steps,
//! leave-one-out KNN accuracy at each), exact, from one prefix sum per sample.
//!
//! # Why it is fast
//! With `x[b]` the pooled spike count of a sample in 1-ms bin `b`, `C[m] = Σ_{b<m} x[b]` and
//! `Q[m] = Σ_{i<m} C[i]`, the temporal features are `w(s) = C[s + Δ] − C[s]` (times `1/N`,
//! which no ranking sees). Their inner product for every Δ needs no feature vector at all:
//!
//! ```text
//! ⟨w_a, w_b⟩(Δ) = Σ_{k ∈ spikes of a} Σ_{s = lo}^{hi} (C_b[s + Δ] − C_b[s]),  lo = max(0, k − Δ + 1), hi = min(k, T − Δ)
//!              = Σ_k (Q_b[hi + Δ + 1] − Q_b[lo + Δ] − Q_b[hi + 1] + Q_b[lo])
//! ```
//!
//! and for a spike away from both ends (`Δ − 1 ≤ k ≤ T − Δ`) the term is
//! `Q_b[k + 1 + Δ] + Q_b[k + 1 − Δ] − 2·Q_b[k + 1]`: two contiguous loads per spike for a whole
//! block of Δ values (one forward in `Q_b`, one in `Q_b` reversed). The squared distance is then
//! `‖w_a‖² + ‖w_b‖² − 2⟨w_a, w_b⟩`, an integer, computed in wrapping `i32` arithmetic — exact
//! because it is a ring identity mod 2³² and the true value is known to lie in `[0, 2³¹)` (bound
//! checked per dataset; `i64` otherwise). Integer distances rank exactly as the Euclidean
//! distances of the features, ties included, so the KNN predictions are exactly those of the
//! feature vectors.
//!
//! Δ values are processed in blocks of [`LANES`]: for each block every pair's squared distances
//! are computed (rows in parallel), then leave-one-out runs for each Δ of the block (Δ values in
//! parallel), with the KNN tie rules of [`neurotac_core::knn`].

use crate::error::ExperimentError;
use crate::protocols::Accuracy;
use neurotac_core::coding::pooled_bin_counts;
use neurotac_core::knn::{TopK, vote};
use neurotac_core::{Knn, KnnError, MultiSpikeTrain};
use rayon::prelude::*;
use serde::Serialize;

/// Δ values per block (lanes of the inner loop).
pub const LANES: usize = 40;

/// Rows computed together so that each column sample's arrays are reused from cache.
const ROW_BLOCK: usize = 16;

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

/// Wrapping integer lanes (`i32` when the distances fit, `i64` otherwise).
trait Lane: Copy + Default + PartialOrd + Send + Sync + 'static {
    fn wadd(self, o: Self) -> Self;
    fn wsub(self, o: Self) -> Self;
    fn from_i64(x: i64) -> Self;
}

macro_rules! lane {
    ($($t:ty),*) => {$(
        impl Lane for $t {
            #[inline(always)]
            fn wadd(self, o: Self) -> Self { self.wrapping_add(o) }
            #[inline(always)]
            fn wsub(self, o: Self) -> Self { self.wrapping_sub(o) }
            #[inline(always)]
            fn from_i64(x: i64) -> Self { x as $t }
        }
    )*};
}
lane!(i32, i64);

/// One sample: its spike bins (sorted, with repeats) and `Q`, forward (padded with `Q[T + 1]`)
/// and reversed (padded with `Q[0] = 0`), long enough that every block load stays inside.
struct Prepared<L> {
    bins: Vec<u32>,
    q: Vec<L>,
    q_reversed: Vec<L>,
}

fn prepare<L: Lane>(bin_counts: &[u32], delta_max: usize) -> Prepared<L> {
    let t = bin_counts.len();
    let mut bins = Vec::new();
    for (b, &c) in bin_counts.iter().enumerate() {
        bins.extend(std::iter::repeat_n(b as u32, c as usize));
    }
    // C[m] for m = 0..=T, Q[m] for m = 0..=T+1 (exact in i64, then wrapped).
    let mut q = Vec::with_capacity(t + 2 + delta_max + LANES);
    let (mut c, mut acc) = (0i64, 0i64);
    q.push(L::from_i64(0));
    // Q[m + 1] = Q[m] + C[m], with C[m + 1] = C[m] + x[m].
    for x in bin_counts.iter().map(|&x| x as i64).chain([0]) {
        acc += c;
        q.push(L::from_i64(acc));
        c += x;
    }
    let mut q_reversed: Vec<L> = q.iter().rev().copied().collect();
    let (last, first) = (*q.last().expect("T + 2 ≥ 2 entries"), L::from_i64(0));
    q.resize(t + 2 + delta_max + LANES, last);
    q_reversed.resize(t + 2 + delta_max + LANES, first);
    Prepared {
        bins,
        q,
        q_reversed,
    }
}

/// `Σ_k (Q_b[k + 1 + Δ] + Q_b[k + 1 − Δ])` over interior spikes `k` for the block's Δ values,
/// and `Σ_k Q_b[k + 1]`. Kept apart so the block accumulators stay in registers.
#[inline(never)]
fn interior_sum<L: Lane>(bins: &[u32], b: &Prepared<L>, t: usize, d0: usize) -> ([L; LANES], L) {
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

/// `⟨w_a, w_b⟩(Δ)` for `Δ = d0 + 1 + l`, `l < LANES`, lanes with `Δ > delta_max` left at 0.
fn inner_block<L: Lane>(
    a: &Prepared<L>,
    b: &Prepared<L>,
    t: usize,
    d0: usize,
    delta_max: usize,
) -> [L; LANES] {
    let delta_hi = (d0 + LANES).min(delta_max);
    // Spikes whose term is the interior one for every Δ of the block.
    let lo = a.bins.partition_point(|&k| (k as usize + 1) < delta_hi);
    let hi = a
        .bins
        .partition_point(|&k| k as usize + delta_hi <= t)
        .max(lo);
    let (mut acc, centre) = interior_sum(&a.bins[lo..hi], b, t, d0);
    let twice = centre.wadd(centre);
    for a in acc.iter_mut() {
        *a = a.wsub(twice);
    }
    // Spikes near either end: the general term, branch-free over the block. With the padding
    // (forward Q by Q[T + 1], reversed Q by Q[0] = 0) the clamped indices become:
    // Q[min(k+Δ+1, T+1)] = forward, Q[max(0, k+1−Δ)] = reversed, and two selects.
    let delta0 = &b.q[d0 + 1..d0 + 1 + LANES]; // Q[Δ]
    let tail = &b.q_reversed[d0 + 1..d0 + 1 + LANES]; // Q[T + 1 − Δ]
    for &k in a.bins[..lo].iter().chain(&a.bins[hi..]) {
        let k = k as usize;
        let forward = &b.q[k + 2 + d0..k + 2 + d0 + LANES];
        let backward = &b.q_reversed[t - k + d0 + 1..t - k + d0 + 1 + LANES];
        let qk = b.q[k + 1];
        for l in 0..LANES {
            let delta = d0 + 1 + l;
            let low = if delta <= k + 1 { qk } else { delta0[l] };
            let high = if delta + k <= t { qk } else { tail[l] };
            acc[l] = acc[l]
                .wadd(forward[l])
                .wadd(backward[l])
                .wsub(low)
                .wsub(high);
        }
    }
    for slot in acc.iter_mut().skip(delta_hi.saturating_sub(d0)) {
        *slot = L::default();
    }
    acc
}

/// Exact squared feature distances `N²·‖R_a − R_b‖²` for `Δ = 1..=delta_max` (for checks and
/// small problems; the sweep uses the same kernel blockwise).
pub fn window_squared_distances(
    a: &MultiSpikeTrain,
    b: &MultiSpikeTrain,
    duration_ms: u32,
    delta_max: u32,
) -> Vec<i64> {
    let (pa, pb) = (
        prepare::<i64>(&pooled_bin_counts(a, duration_ms), delta_max as usize),
        prepare::<i64>(&pooled_bin_counts(b, duration_ms), delta_max as usize),
    );
    let (t, dm) = (duration_ms as usize, delta_max as usize);
    let mut out = Vec::with_capacity(dm);
    for d0 in (0..dm).step_by(LANES) {
        let (aa, bb, ab) = (
            inner_block(&pa, &pa, t, d0, dm),
            inner_block(&pb, &pb, t, d0, dm),
            inner_block(&pa, &pb, t, d0, dm),
        );
        for l in 0..LANES.min(dm - d0) {
            out.push(aa[l] + bb[l] - 2 * ab[l]);
        }
    }
    out
}

/// Runs the sweep over `Δt = 1..=max_window_ms` ms on samples of `duration_ms` (spikes outside
/// `[0, T)` are not part of a sample), leave-one-out with `knn`.
pub fn dt_sweep(
    observations: &[MultiSpikeTrain],
    labels: &[usize],
    duration_ms: u32,
    max_window_ms: u32,
    knn: Knn,
) -> Result<DtSweep, ExperimentError> {
    let n = observations.len();
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
    if max_window_ms == 0 || max_window_ms > duration_ms {
        return Err(ExperimentError::InvalidParameter {
            what: "max_window_ms",
            value: max_window_ms as f64,
            expected: "≥ 1 and ≤ the sample duration",
        });
    }
    let counts: Vec<Vec<u32>> = observations
        .par_iter()
        .map(|o| pooled_bin_counts(o, duration_ms))
        .collect();
    // ‖w‖² ≤ max window count · Σ_s w(s) ≤ max window count · Δ · n; D² ≤ 2(‖w_a‖² + ‖w_b‖²).
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
    if 4 * bound < i32::MAX as u128 {
        sweep::<i32>(&counts, labels, duration_ms, max_window_ms, knn)
    } else {
        sweep::<i64>(&counts, labels, duration_ms, max_window_ms, knn)
    }
}

fn sweep<L: Lane>(
    counts: &[Vec<u32>],
    labels: &[usize],
    duration_ms: u32,
    max_window_ms: u32,
    knn: Knn,
) -> Result<DtSweep, ExperimentError> {
    let n = counts.len();
    let (t, dm) = (duration_ms as usize, max_window_ms as usize);
    let prepared: Vec<Prepared<L>> = counts.par_iter().map(|c| prepare(c, dm)).collect();
    // Row a of the upper triangle holds LANES blocks of n − a − 1 squared distances.
    let mut storage: Vec<L> = vec![L::default(); LANES * n * n.saturating_sub(1) / 2];
    let mut accuracy = Vec::with_capacity(dm);
    let mut predictions: Vec<Vec<usize>> = Vec::with_capacity(dm);
    for d0 in (0..dm).step_by(LANES) {
        let norms: Vec<[L; LANES]> = prepared
            .par_iter()
            .map(|p| inner_block(p, p, t, d0, dm))
            .collect();
        let mut rows: Vec<&mut [L]> = Vec::with_capacity(n);
        let mut rest = storage.as_mut_slice();
        for a in 0..n {
            let (row, tail) = rest.split_at_mut(LANES * (n - a - 1));
            rows.push(row);
            rest = tail;
        }
        // Blocks of ROW_BLOCK rows; inside a block, column b outermost so its Q arrays stay in
        // cache while every row of the block uses them.
        let mut blocks: Vec<(usize, Vec<&mut [L]>)> = Vec::new();
        for (a, row) in rows.into_iter().enumerate() {
            if a % ROW_BLOCK == 0 {
                blocks.push((a, Vec::with_capacity(ROW_BLOCK)));
            }
            blocks.last_mut().expect("pushed above").1.push(row);
        }
        blocks.into_par_iter().for_each(|(first, mut block_rows)| {
            for b in first + 1..n {
                for (offset, row) in block_rows.iter_mut().enumerate() {
                    let a = first + offset;
                    if a >= b {
                        break;
                    }
                    let width = n - a - 1;
                    let ab = inner_block(&prepared[a], &prepared[b], t, d0, dm);
                    for l in 0..LANES {
                        row[l * width + b - a - 1] =
                            norms[a][l].wadd(norms[b][l]).wsub(ab[l].wadd(ab[l]));
                    }
                }
            }
        });
        let lanes = LANES.min(dm - d0);
        let block: Vec<Vec<usize>> = (0..lanes)
            .into_par_iter()
            .map(|l| leave_one_out_lane(&storage, n, l, labels, knn.k()))
            .collect();
        for p in block {
            let hits = p.iter().zip(labels).filter(|(p, t)| p == t).count();
            accuracy.push(hits as f64 / n as f64);
            predictions.push(p);
        }
    }
    let best = (0..dm)
        .max_by(|&x, &y| accuracy[x].total_cmp(&accuracy[y]).then(y.cmp(&x)))
        .expect("at least one window");
    Ok(DtSweep {
        windows_ms: (1..=max_window_ms).collect(),
        best_window_ms: best as u32 + 1,
        best: Accuracy::of(&predictions[best], labels),
        accuracy,
    })
}

/// Leave-one-out predictions for lane `l` of the stored block: one scan of the upper triangle,
/// each pair offered to both samples.
fn leave_one_out_lane<L: Lane>(
    storage: &[L],
    n: usize,
    l: usize,
    labels: &[usize],
    k: usize,
) -> Vec<usize> {
    let mut tops: Vec<TopK<L>> = (0..n).map(|_| TopK::new(k)).collect();
    let mut offset = 0;
    for a in 0..n {
        let width = n - a - 1;
        let row = &storage[offset + l * width..offset + (l + 1) * width];
        for (b, &d) in (a + 1..n).zip(row) {
            tops[a].offer(d, b);
            tops[b].offer(d, a);
        }
        offset += LANES * width;
    }
    tops.iter()
        .map(|t| vote(t.neighbours().iter().map(|&(_, j)| labels[j])).expect("k ≥ 1 and n > k"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic::{SyntheticConfig, synthetic_dataset};
    use neurotac_core::coding::{FeatureCoding, TemporalCoding, feature_matrix};
    use neurotac_core::distance::squared_euclidean_matrix;

    fn small() -> neurotac_core::SpikeDataset {
        synthetic_dataset(&SyntheticConfig {
            samples: 33,
            channels: 5,
            spikes_per_unit: 6.0,
            duration_s: 0.6,
            seed: 11,
            ..Default::default()
        })
    }

    #[test]
    fn kernel_distances_equal_the_feature_vectors_for_every_window() {
        let d = small();
        let obs = d.observations();
        let t = 600;
        for (a, b) in [(0, 1), (2, 30), (5, 5), (7, 12)] {
            let fast = window_squared_distances(&obs[a], &obs[b], t, 130);
            for delta in 1..=130u32 {
                let coding = TemporalCoding::from_ms(delta, t).unwrap();
                let mut ca = coding.clone();
                let mut cb = coding;
                use neurotac_core::coding::Coding;
                ca.encode(&obs[a]);
                cb.encode(&obs[b]);
                let want: f64 = ca
                    .features()
                    .iter()
                    .zip(cb.features())
                    .map(|(x, y)| ((x - y) * 5.0).round().powi(2))
                    .sum();
                assert_eq!(
                    fast[delta as usize - 1] as f64,
                    want,
                    "pair ({a},{b}) Δ={delta}"
                );
            }
        }
    }

    #[test]
    fn sweep_equals_leave_one_out_on_the_feature_matrices() {
        let d = small();
        let sweep = dt_sweep(d.observations(), d.labels(), 600, 85, Knn::default()).unwrap();
        assert_eq!(sweep.windows_ms.len(), 85);
        for delta in [1u32, 17, 40, 41, 80, 85] {
            let f = feature_matrix(
                &TemporalCoding::from_ms(delta, 600).unwrap(),
                d.observations(),
            )
            .unwrap();
            let d2 = squared_euclidean_matrix(f.view()).unwrap();
            let p = Knn::default().leave_one_out(d2.view(), d.labels()).unwrap();
            let acc = Accuracy::of(&p, d.labels()).mean;
            assert_eq!(sweep.accuracy[delta as usize - 1], acc, "Δ={delta}");
        }
        let best = sweep.accuracy.iter().cloned().fold(0.0, f64::max);
        assert_eq!(sweep.best.mean, best);
        assert_eq!(sweep.accuracy[sweep.best_window_ms as usize - 1], best);
        assert!(
            sweep.accuracy[..sweep.best_window_ms as usize - 1]
                .iter()
                .all(|&a| a < best)
        );
    }

    #[test]
    fn bad_sweeps_are_typed_errors() {
        let d = small();
        assert!(dt_sweep(d.observations(), d.labels(), 600, 601, Knn::default()).is_err());
        assert!(dt_sweep(d.observations(), d.labels(), 600, 0, Knn::default()).is_err());
        assert!(matches!(
            dt_sweep(
                &d.observations()[..3],
                &d.labels()[..3],
                600,
                10,
                Knn::default()
            ),
            Err(ExperimentError::Knn(KnnError::KTooLarge {
                k: 4,
                n_train: 2
            }))
        ));
        assert!(dt_sweep(d.observations(), &d.labels()[1..], 600, 10, Knn::default()).is_err());
    }
}
