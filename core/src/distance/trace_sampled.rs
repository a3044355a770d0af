//! The trace-sampled multi-unit Van Rossum distance: each channel's synaptic trace advanced at a
//! step `h` by the graph's synapse filter (decay `q = e^{−h/τ}` per step, `+1` per spike) and
//! compared sample by sample, computed from [`TraceRecord`]s in memory bounded by the number of
//! spikes.
//!
//! # Definition
//! With `f(t_k)` a trace after step `k`, the Van Rossum integral over one step is
//! `(2/τ)∫_0^h f(t_k)²·e^{−2s/τ} ds = (1 − q²)·f(t_k)²` (the trace decays exactly between
//! steps), so the sampled inner product, the tail after the last step included, is
//!
//! ```text
//! ⟨f, g⟩_h = Σ_k (1 − q²)·f(t_k)·g(t_k)
//! ```
//!
//! and `LL²`, `SP²` follow as in [`super::van_rossum`]. Between two consecutive steps `k < k'`
//! at which either trace jumps, both only decay, so that stretch sums in closed form to
//! `F·G·(1 − q^{2(k'−k)})` with `F`, `G` the states after step `k`; the stretch after the last
//! jump gives `F·G`. A pair of samples therefore costs one merge of their jump lists — no value
//! per step is ever stored or visited, at any `h`.
//!
//! `⟨f, g⟩_h` equals the exact Van Rossum product of the spike trains moved to their steps'
//! grid, so the distance is exact for spikes on the grid and its error vanishes as `h → 0`
//! (`neurotac tradeoff vr` measures it). States decayed below
//! [`FLUSH_TO_ZERO`] become 0, as in a projection. The arithmetic runs in
//! `f64` or `f32` ([`TracePrecision`]), the trade a network storing `f32` traces makes.

use super::trace_record::TraceRecord;
use super::van_rossum::VanRossumMatrices;
use super::{check_tau, symmetric_matrices_on};
use crate::currents::FLUSH_TO_ZERO;
#[cfg(test)]
use crate::error::CodingError;
use crate::error::DistanceError;
use crate::ranks::Ranks;
use crate::spikes::MultiSpikeTrain;
use rayon::prelude::*;
use std::ops::{Add, Mul};

/// The floating-point type the trace arithmetic runs in: `f64` or `f32`.
pub trait TracePrecision:
    Copy + Send + Sync + PartialOrd + Add<Output = Self> + Mul<Output = Self> + 'static
{
    /// Zero.
    const ZERO: Self;
    /// From `f64` (rounded to nearest).
    fn of(x: f64) -> Self;
    /// To `f64` (exact).
    fn f64(self) -> f64;
}

impl TracePrecision for f64 {
    const ZERO: Self = 0.0;
    fn of(x: f64) -> Self {
        x
    }
    fn f64(self) -> f64 {
        self
    }
}

impl TracePrecision for f32 {
    const ZERO: Self = 0.0;
    fn of(x: f64) -> Self {
        x as f32
    }
    fn f64(self) -> f64 {
        f64::from(self)
    }
}

/// Decay factors for gaps of `L` steps: `q^L` and `1 − q^{2L}`, tabulated up to the gap after
/// which every state has flushed to 0 (`q^L·(spikes) <` [`FLUSH_TO_ZERO`]).
struct DecayTable<R> {
    decay: Vec<R>,
    stretch: Vec<R>,
}

impl<R: TracePrecision> DecayTable<R> {
    fn new(h_over_tau: f64, max_state: f64) -> Self {
        // Past this gap even the largest state is below the flush threshold.
        let cut = ((max_state.max(1.0) / FLUSH_TO_ZERO).ln() / h_over_tau).ceil();
        let len = (cut.min(u32::MAX as f64) as usize).saturating_add(1);
        let decay = (0..len)
            .map(|l| R::of((-(l as f64) * h_over_tau).exp()))
            .collect();
        let stretch = (0..len)
            .map(|l| R::of(-(-2.0 * l as f64 * h_over_tau).exp_m1()))
            .collect();
        Self { decay, stretch }
    }

    /// `(q^L, 1 − q^{2L})` for a gap of `gap` steps; `(0, 1)` once everything has flushed.
    #[inline]
    fn get(&self, gap: u32) -> (R, R) {
        match (self.decay.get(gap as usize), self.stretch.get(gap as usize)) {
            (Some(&d), Some(&s)) => (d, s),
            _ => (R::ZERO, R::of(1.0)),
        }
    }
}

/// One trace as the states after its jumps: `(step, F_i)`.
type States<R> = Vec<(u32, R)>;

/// The states `F_i = flush(F_{i−1}·q^{gap}) + c_i` of a jump list (module docs of
/// [`crate::coding::spatiotemporal`]).
fn states<R: TracePrecision>(jumps: &[(u32, u32)], table: &DecayTable<R>) -> States<R> {
    let mut f = R::ZERO;
    let mut last = 0u32;
    jumps
        .iter()
        .map(|&(step, count)| {
            let decayed = f * table.get(step - last).0;
            let decayed = if decayed.f64().abs() < FLUSH_TO_ZERO {
                R::ZERO
            } else {
                decayed
            };
            f = decayed + R::of(f64::from(count));
            last = step;
            (step, f)
        })
        .collect()
}

/// `⟨f, g⟩_h` of two traces given as their states (module docs): one merge.
fn product<R: TracePrecision>(a: &[(u32, R)], b: &[(u32, R)], table: &DecayTable<R>) -> R {
    let (mut i, mut j) = (0, 0);
    let (mut fa, mut fb, mut acc) = (R::ZERO, R::ZERO, R::ZERO);
    let mut now = 0u32;
    while i < a.len() || j < b.len() {
        let next = match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) => x.0.min(y.0),
            (Some(x), None) => x.0,
            (None, Some(y)) => y.0,
            (None, None) => unreachable!("the loop runs while one list has entries"),
        };
        let (decay, stretch) = table.get(next - now);
        acc = acc + fa * fb * stretch;
        fa = fa * decay;
        fb = fb * decay;
        if a.get(i).is_some_and(|x| x.0 == next) {
            fa = a[i].1;
            i += 1;
        }
        if b.get(j).is_some_and(|y| y.0 == next) {
            fb = b[j].1;
            j += 1;
        }
        now = next;
    }
    acc + fa * fb
}

/// One record prepared for a τ: its channels' and pooled trace's states and self products.
struct Prepared<R> {
    channels: Vec<States<R>>,
    channel_self: Vec<R>,
    pooled: States<R>,
    pooled_self: R,
}

/// `LL²` and `SP²` of every pair of `records` for kernel time constant `tau_s`, from the traces
/// sampled at the records' step (module docs), the arithmetic in `R` (`f64` or `f32`).
///
/// All records must have the same channel count and step. Every entry is computed in a fixed
/// order from its two records alone, so the matrices are identical at any thread count.
///
/// Split over `ranks` (`&OneProcess` for one process): each rank computes a block of upper-triangle rows
/// balanced by pair count, then the blocks are all-gathered, so every rank returns the
/// one-process matrices, bit for bit. Collective: every rank must call it.
pub fn trace_matrices<R: TracePrecision>(
    records: &[TraceRecord],
    tau_s: f64,
    ranks: &dyn Ranks,
) -> Result<VanRossumMatrices, DistanceError> {
    check_tau(tau_s)?;
    let first = records.first();
    let (n_channels, step_us) = first.map_or((0, 1), |r| (r.n_channels(), r.trace_step_us()));
    for (sample, r) in records.iter().enumerate() {
        if r.n_channels() != n_channels {
            return Err(DistanceError::ChannelCount {
                sample,
                expected: n_channels,
                got: r.n_channels(),
            });
        }
        if r.trace_step_us() != step_us {
            return Err(DistanceError::InvalidParameter {
                what: "trace record step (s)",
                value: r.trace_dt_s(),
                expected: "the same step as record 0",
            });
        }
    }
    let pooled: Vec<Vec<(u32, u32)>> = records.par_iter().map(TraceRecord::pooled).collect();
    let max_state = pooled
        .iter()
        .flatten()
        .map(|&(_, c)| f64::from(c))
        .sum::<f64>()
        .max(1.0);
    let table = DecayTable::<R>::new(step_us as f64 * 1e-6 / tau_s, max_state);
    let prepared: Vec<Prepared<R>> = records
        .par_iter()
        .zip(&pooled)
        .map(|(r, pooled)| {
            let channels: Vec<States<R>> = (0..n_channels)
                .map(|c| states(r.channel(c), &table))
                .collect();
            let channel_self = channels.iter().map(|s| product(s, s, &table)).collect();
            let pooled = states(pooled, &table);
            let pooled_self = product(&pooled, &pooled, &table);
            Prepared {
                channels,
                channel_self,
                pooled,
                pooled_self,
            }
        })
        .collect();
    let squared =
        |own_a: R, own_b: R, cross: R| (own_a.f64() + own_b.f64() - 2.0 * cross.f64()).max(0.0);
    let pair = |i: usize, j: usize| {
        let (a, b) = (&prepared[i], &prepared[j]);
        let ll2 = (0..n_channels)
            .map(|c| {
                let cross = match (a.channels[c].is_empty(), b.channels[c].is_empty()) {
                    (false, false) => product(&a.channels[c], &b.channels[c], &table),
                    _ => R::ZERO,
                };
                squared(a.channel_self[c], b.channel_self[c], cross)
            })
            .sum();
        let sp2 = squared(
            a.pooled_self,
            b.pooled_self,
            product(&a.pooled, &b.pooled, &table),
        );
        [ll2, sp2]
    };
    let [ll2, sp2] = symmetric_matrices_on(records.len(), pair, ranks)?;
    Ok(VanRossumMatrices { tau_s, ll2, sp2 })
}

/// `LL²` and `SP²` of every pair of `observations` from their traces sampled at `dt_s` (a whole
/// number of µs), in `f64`: [`TraceRecord::of_trains`] then [`trace_matrices`]. Combine with
/// [`VanRossumMatrices::squared`] as for the exact ones.
pub fn trace_sampled_matrices(
    observations: &[MultiSpikeTrain],
    tau_s: f64,
    dt_s: f64,
) -> Result<VanRossumMatrices, DistanceError> {
    let records = observations
        .par_iter()
        .enumerate()
        .map(|(sample, o)| {
            TraceRecord::of_trains(o, dt_s)
                .map_err(|source| DistanceError::TraceRecord { sample, source })
        })
        .collect::<Result<Vec<_>, _>>()?;
    trace_matrices::<f64>(&records, tau_s, &crate::OneProcess)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coding::{Coding, SpatiotemporalCoding};
    use crate::distance::VanRossum;
    use crate::graph::{NetworkBuilder, NetworkConfig, SpikeArrayInput};
    use rand::{RngExt, SeedableRng};

    fn random_samples(n: usize, channels: usize, spikes: usize, seed: u64) -> Vec<MultiSpikeTrain> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                MultiSpikeTrain::from_unsorted_channels((0..channels).map(|_| {
                    (0..rng.random_range(0..=spikes))
                        .map(|_| (rng.random::<f64>() * 0.3e6).round() * 1e-6)
                        .collect::<Vec<_>>()
                }))
                .unwrap()
            })
            .collect()
    }

    /// The traces stepped one step at a time, every sample kept (the dense definition):
    /// `Σ_k (1 − q²)·f(t_k)·g(t_k)` plus the tail `f·g` after the last step.
    fn dense_product(a: &[(u32, u32)], b: &[(u32, u32)], q: f64) -> f64 {
        let end = a.iter().chain(b).map(|x| x.0).max().unwrap_or(0);
        let (mut fa, mut fb, mut acc) = (0.0f64, 0.0f64, 0.0);
        for k in 0..=end {
            fa *= q;
            fb *= q;
            fa += a.iter().find(|x| x.0 == k).map_or(0.0, |x| f64::from(x.1));
            fb += b.iter().find(|x| x.0 == k).map_or(0.0, |x| f64::from(x.1));
            if k < end {
                acc += (1.0 - q * q) * fa * fb;
            }
        }
        acc + fa * fb
    }

    #[test]
    fn the_merge_sums_the_dense_trace_samples() {
        let (tau, h) = (0.02, 1e-3);
        let obs = random_samples(4, 3, 6, 1);
        let records: Vec<TraceRecord> = obs
            .iter()
            .map(|o| TraceRecord::of_trains(o, h).unwrap())
            .collect();
        let m = trace_matrices::<f64>(&records, tau, &crate::OneProcess).unwrap();
        let q = (-h / tau).exp();
        for i in 0..4 {
            for j in 0..4 {
                if i == j {
                    continue;
                }
                let (a, b) = (&records[i], &records[j]);
                let d2 = |x: &[(u32, u32)], y: &[(u32, u32)]| {
                    dense_product(x, x, q) + dense_product(y, y, q) - 2.0 * dense_product(x, y, q)
                };
                let ll2: f64 = (0..3).map(|c| d2(a.channel(c), b.channel(c))).sum();
                let sp2 = d2(&a.pooled(), &b.pooled());
                assert!(
                    (m.ll2[[i, j]] - ll2).abs() <= 1e-12 * ll2,
                    "{} vs {ll2}",
                    m.ll2[[i, j]]
                );
                assert!(
                    (m.sp2[[i, j]] - sp2).abs() <= 1e-12 * sp2,
                    "{} vs {sp2}",
                    m.sp2[[i, j]]
                );
            }
        }
    }

    #[test]
    fn traces_are_the_exact_distance_of_spikes_moved_to_the_step_grid() {
        let (tau, h) = (0.05, 5e-3);
        let obs = random_samples(8, 4, 10, 2);
        let on_grid: Vec<MultiSpikeTrain> = obs
            .iter()
            .map(|o| {
                MultiSpikeTrain::from_channels(
                    o.channels()
                        .map(|c| c.iter().map(|&t| (t / h).floor() * h).collect::<Vec<f64>>())
                        .collect::<Vec<_>>(),
                )
                .unwrap()
            })
            .collect();
        let exact = VanRossum::new(tau)
            .unwrap()
            .matrices(&on_grid, &crate::OneProcess)
            .unwrap();
        let traces = trace_sampled_matrices(&obs, tau, h).unwrap();
        let f32_records: Vec<TraceRecord> = obs
            .iter()
            .map(|o| TraceRecord::of_trains(o, h).unwrap())
            .collect();
        let single = trace_matrices::<f32>(&f32_records, tau, &crate::OneProcess).unwrap();
        for c in [0.0, 0.4, 1.0] {
            let (e, t, s) = (
                exact.squared(c).unwrap(),
                traces.squared(c).unwrap(),
                single.squared(c).unwrap(),
            );
            for (i, (&e, (&t, &s))) in e.iter().zip(t.iter().zip(&s)).enumerate() {
                assert!((e - t).abs() <= 1e-12 * e.max(1.0), "entry {i}: {e} vs {t}");
                assert!(
                    (e - s).abs() <= 1e-4 * e.max(1.0),
                    "entry {i}, f32: {e} vs {s}"
                );
            }
        }
    }

    #[test]
    fn memory_follows_spikes_not_duration_and_the_readout_keeps_the_same_record() {
        let long = MultiSpikeTrain::from_channels(vec![vec![0.5, 999.5], vec![]]).unwrap();
        let record = TraceRecord::of_trains(&long, 1e-4).unwrap();
        // 10⁷ steps of 0.1 ms, two jumps kept.
        assert_eq!(record.channel(0), &[(5_000, 1), (9_995_000, 1)]);
        assert!(record.heap_bytes() < 256, "{}", record.heap_bytes());
        // Fed by a network at its step, the coding keeps the record `of_trains` makes.
        let sample = random_samples(1, 3, 20, 3).remove(0);
        let mut b = NetworkBuilder::new();
        let input = b
            .add_spike_input("taxels", SpikeArrayInput::new(sample.clone()))
            .unwrap();
        let coding = SpatiotemporalCoding::new(0.05)
            .unwrap()
            .with_trace_record(1e-4)
            .unwrap();
        let id = b.add_readout(input, coding).unwrap();
        let mut net = b.build(NetworkConfig { dt_s: 1e-4 }).unwrap();
        net.run(0.31, &crate::OneProcess).unwrap();
        let from_network = net.readout(id).unwrap().trace_record().unwrap().unwrap();
        assert_eq!(from_network, TraceRecord::of_trains(&sample, 1e-4).unwrap());
    }

    #[test]
    fn bad_steps_and_spikes_before_zero_are_typed_errors() {
        let s = MultiSpikeTrain::from_channels(vec![vec![0.1]]).unwrap();
        for dt in [0.0, -1e-3, f64::NAN, 1.5e-7] {
            assert!(
                matches!(
                    TraceRecord::of_trains(&s, dt),
                    Err(CodingError::InvalidParameter { .. })
                ),
                "{dt}"
            );
        }
        let early = MultiSpikeTrain::from_channels(vec![vec![-0.1, 0.2]]).unwrap();
        let e = trace_sampled_matrices(&[s.clone(), early], 0.01, 1e-3).unwrap_err();
        assert!(
            matches!(
                e,
                DistanceError::TraceRecord {
                    sample: 1,
                    source: CodingError::SpikeBeforeZero { .. }
                }
            ),
            "{e:?}"
        );
        let two = MultiSpikeTrain::from_channels(vec![vec![0.1], vec![0.2]]).unwrap();
        let early = MultiSpikeTrain::from_channels(vec![vec![0.1], vec![-0.1, 0.2]]).unwrap();
        let e = trace_sampled_matrices(&[two, early], 0.01, 1e-3).unwrap_err();
        assert!(
            matches!(
                e,
                DistanceError::TraceRecord {
                    sample: 1,
                    source: CodingError::SpikeBeforeZero { channel: 1, .. }
                }
            ),
            "{e:?}"
        );
        let mut coding = SpatiotemporalCoding::new(0.01).unwrap();
        coding.encode(&s);
        assert!(coding.trace_record().is_none());
        let other_step = TraceRecord::of_trains(&s, 2e-3).unwrap();
        let one = TraceRecord::of_trains(&s, 1e-3).unwrap();
        assert!(trace_matrices::<f64>(&[one, other_step], 0.01, &crate::OneProcess).is_err());
    }
}
