//! The multi-unit Van Rossum distance between a growing live sample and every training sample,
//! both cut at the same elapsed time `T`, updated as `T` advances: each window costs one
//! multiply-add per new spike per training sample, not a sweep of the whole prefixes.
//!
//! The sums of the module docs with centred exponentials (`E^∓ = e^{∓(t − c₀)/τ}`, `c₀` the
//! middle of the training spikes' span): a live spike `a` at `t` adds
//! `E⁻(t)·Σ_{b < t} E⁺(b)` to `⟨a, b⟩` and a training spike `b` at `t` adds
//! `E⁻(t)·Σ_{a ≤ t} E⁺(a)`, merged in time order (a live spike before an equal training spike, as
//! the offline sums), so each pair of spikes is counted once. Self products are running sums of
//! `1 + 2·E⁻(t_k)·Σ_{l<k} E⁺(t_l)`. Only sums of positive terms, so nothing cancels; available while
//! every exponent stays within ±[`CENTRED_EXP_LIMIT`](super::CENTRED_EXP_LIMIT) (live spikes
//! beyond it are refused, [`GrowingVanRossum::advance`]).

use super::{CENTRED_EXP_LIMIT, squared_from_products};
use crate::distance::check_tau;
use crate::error::DistanceError;
use crate::spikes::MultiSpikeTrain;

/// One unit's spikes (a channel, or all channels pooled) in time order, with `E⁻` of each,
/// the running sums of `E⁺` (`plus[k] = Σ_{l<k} E⁺_l`, one more entry than spikes) and of the
/// self products (`own[k]`, the self product of the first `k` spikes).
#[derive(Debug, Clone, Default)]
struct Unit {
    times: Vec<f64>,
    minus: Vec<f64>,
    plus: Vec<f64>,
    own: Vec<f64>,
}

impl Unit {
    fn new() -> Self {
        Self {
            plus: vec![0.0],
            own: vec![0.0],
            ..Self::default()
        }
    }

    /// Appends a spike at `t` (not before the last).
    fn push(&mut self, t: f64, centre: f64, inv_tau: f64) {
        let x = (t - centre) * inv_tau;
        let (plus, minus) = (x.exp(), (-x).exp());
        let k = self.times.len();
        self.times.push(t);
        self.minus.push(minus);
        self.own
            .push(self.own[k] + 1.0 + 2.0 * minus * self.plus[k]);
        self.plus.push(self.plus[k] + plus);
    }
}

/// The channels and the pooled unit of one sample.
#[derive(Debug, Clone)]
struct Sample {
    units: Vec<Unit>,
}

impl Sample {
    fn empty(channels: usize) -> Self {
        Self {
            units: vec![Unit::new(); channels + 1],
        }
    }
}

/// The training side, prepared once.
#[derive(Debug, Clone)]
pub struct GrowingVanRossum {
    tau_s: f64,
    centre: f64,
    inv_tau: f64,
    channels: usize,
    train: Vec<Sample>,
}

/// Where one (live, training) pair of units stands: spikes of each side merged so far and
/// their cross product.
#[derive(Debug, Clone, Copy, Default)]
struct PairState {
    live: u32,
    train: u32,
    cross: f64,
}

/// The live side and its pairs with every training sample, advanced window by window.
#[derive(Debug, Clone)]
pub struct GrowingLive {
    sample: Sample,
    pairs: Vec<PairState>,
    t_end_s: f64,
}

impl GrowingVanRossum {
    /// Prepares `training` for kernel `tau_s`; `None` when its spikes span more than
    /// `2·690·τ` (the centred exponentials would overflow; use
    /// [`PreparedVanRossum::cross_matrices_until`](super::PreparedVanRossum::cross_matrices_until)).
    pub fn new(training: &[MultiSpikeTrain], tau_s: f64) -> Result<Option<Self>, DistanceError> {
        let tau_s = check_tau(tau_s)?;
        let channels = training.first().map_or(0, MultiSpikeTrain::n_channels);
        if let Some(sample) = training.iter().position(|o| o.n_channels() != channels) {
            return Err(DistanceError::ChannelCount {
                sample,
                expected: channels,
                got: training[sample].n_channels(),
            });
        }
        let (lo, hi) = training
            .iter()
            .filter_map(MultiSpikeTrain::time_range)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (a, b)| {
                (l.min(a), h.max(b))
            });
        let centre = if lo <= hi { lo / 2.0 + hi / 2.0 } else { 0.0 };
        if lo <= hi && (hi / 2.0 - lo / 2.0) / tau_s > CENTRED_EXP_LIMIT {
            return Ok(None);
        }
        let inv_tau = 1.0 / tau_s;
        let train = training
            .iter()
            .map(|o| {
                let mut s = Sample::empty(channels);
                for (c, train) in o.channels().enumerate() {
                    for &t in train {
                        s.units[c].push(t, centre, inv_tau);
                    }
                }
                let mut pooled: Vec<f64> = o.channels().flatten().copied().collect();
                pooled.sort_by(f64::total_cmp);
                for t in pooled {
                    s.units[channels].push(t, centre, inv_tau);
                }
                s
            })
            .collect();
        Ok(Some(Self {
            tau_s,
            centre,
            inv_tau,
            channels,
            train,
        }))
    }

    /// The kernel τ (s).
    pub fn tau_s(&self) -> f64 {
        self.tau_s
    }

    /// A live sample with no spike yet, at `T = −∞`.
    pub fn live(&self) -> GrowingLive {
        GrowingLive {
            sample: Sample::empty(self.channels),
            pairs: vec![PairState::default(); self.train.len() * (self.channels + 1)],
            t_end_s: f64::NEG_INFINITY,
        }
    }

    /// Advances `live` to `T = t_end_s`: `new` holds, per channel, its spikes in
    /// `[previous T, T)`, sorted. Spikes out of that range, out of order, or beyond the centred
    /// range are an [`InvalidParameter`](DistanceError::InvalidParameter) error (nothing changes).
    pub fn advance(
        &self,
        live: &mut GrowingLive,
        new: &[&[f64]],
        t_end_s: f64,
    ) -> Result<(), DistanceError> {
        let bad = |value: f64, expected| DistanceError::InvalidParameter {
            what: "live spike time",
            value,
            expected,
        };
        if new.len() != self.channels || t_end_s.is_nan() || t_end_s < live.t_end_s {
            return Err(bad(t_end_s, "one train per channel, T not going back"));
        }
        for train in new {
            let mut last = live.t_end_s;
            for &t in *train {
                if !(t >= last && t < t_end_s) {
                    return Err(bad(t, "sorted, within [previous T, T)"));
                }
                if ((t - self.centre) * self.inv_tau).abs() > CENTRED_EXP_LIMIT {
                    return Err(bad(t, "within 690 τ of the training spikes' centre"));
                }
                last = t;
            }
        }
        let mut pooled: Vec<f64> = new.iter().flat_map(|c| c.iter().copied()).collect();
        pooled.sort_by(f64::total_cmp);
        for (c, train) in new.iter().enumerate() {
            for &t in *train {
                live.sample.units[c].push(t, self.centre, self.inv_tau);
            }
        }
        for t in pooled {
            live.sample.units[self.channels].push(t, self.centre, self.inv_tau);
        }
        live.t_end_s = t_end_s;
        let units = self.channels + 1;
        for (b, pairs) in self.train.iter().zip(live.pairs.chunks_exact_mut(units)) {
            for ((a, b), pair) in live.sample.units.iter().zip(&b.units).zip(pairs) {
                merge(a, b, pair, t_end_s);
            }
        }
        Ok(())
    }

    /// `(LL², SP²)` between `live` and training sample `i`, both cut at the live `T`.
    pub fn squared_parts(&self, live: &GrowingLive, i: usize) -> (f64, f64) {
        let units = self.channels + 1;
        let pairs = &live.pairs[i * units..(i + 1) * units];
        let own = |u: &Unit, n: u32| u.own[n as usize];
        let (mut own_a, mut own_b, mut cross) = (0.0, 0.0, 0.0);
        for ((a, b), p) in live
            .sample
            .units
            .iter()
            .zip(&self.train[i].units)
            .zip(pairs)
            .take(self.channels)
        {
            own_a += own(a, p.live);
            own_b += own(b, p.train);
            cross += p.cross;
        }
        let (a, b, p) = (
            &live.sample.units[self.channels],
            &self.train[i].units[self.channels],
            &pairs[self.channels],
        );
        (
            squared_from_products(own_a, own_b, cross),
            squared_from_products(own(a, p.live), own(b, p.train), p.cross),
        )
    }
}

/// Merges the spikes of `a` (live) and `b` (training) before `t_end` not yet in `pair`, in time
/// order (a live spike before an equal training spike).
#[inline]
fn merge(a: &Unit, b: &Unit, pair: &mut PairState, t_end: f64) {
    let (mut i, mut j) = (pair.live as usize, pair.train as usize);
    let mut cross = pair.cross;
    loop {
        let b_next = b.times.get(j).filter(|&&t| t < t_end);
        match (a.times.get(i), b_next) {
            (Some(ta), Some(tb)) if ta <= tb => {
                cross += a.minus[i] * b.plus[j];
                i += 1;
            }
            (Some(_), None) => {
                cross += a.minus[i] * b.plus[j];
                i += 1;
            }
            (_, Some(_)) => {
                cross += b.minus[j] * a.plus[i];
                j += 1;
            }
            (None, None) => break,
        }
    }
    *pair = PairState {
        live: i as u32,
        train: j as u32,
        cross,
    };
}
