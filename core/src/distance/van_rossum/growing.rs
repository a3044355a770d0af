//! The multi-unit Van Rossum distance between a growing live sample and every training sample,
//! both cut at the same elapsed time `T`, updated as `T` advances: a window costs one
//! multiply-add per new spike (live or training) per training sample, not a sweep of the whole
//! prefixes.
//!
//! The sums of the module docs with centred exponentials (`E^∓ = e^{∓(t − c₀)/τ}`, `c₀` the
//! middle of the training spikes' span), walked in time order: a live spike of channel `n` at
//! `t` adds `E⁻(t)·Σ E⁺(b)` over the training spikes `b` before it (of channel `n` to `⟨·,·⟩_LL`,
//! of every channel to `⟨·,·⟩_SP`), and a training spike likewise with the live spikes before it,
//! so each pair is counted once (a coincident pair adds `E⁻·E⁺ = 1` whichever comes first).
//! Self products are running sums of `1 + 2·E⁻(t_k)·Σ_{l<k} E⁺(t_l)`. Only sums of positive terms:
//! nothing cancels until `d² = ⟨a,a⟩ + ⟨b,b⟩ − 2⟨a,b⟩`, as offline. Available while every
//! exponent stays within ±[`CENTRED_EXP_LIMIT`](super::CENTRED_EXP_LIMIT).

use super::centred::CENTRED_EXP_LIMIT;
use super::{common_channels, squared_from_products};
use crate::distance::check_tau;
use crate::error::DistanceError;
use crate::spikes::MultiSpikeTrain;

/// One sample's spikes, all channels merged in time order, with what the walk needs of each.
#[derive(Debug, Clone, Default)]
struct Spikes {
    t: Vec<f64>,
    channel: Vec<u32>,
    minus: Vec<f64>,
    plus: Vec<f64>,
    /// Self products of the first `k` spikes, per channel summed (`own_ll[k]`) and pooled
    /// (`own_sp[k]`); one more entry than spikes.
    own_ll: Vec<f64>,
    own_sp: Vec<f64>,
}

/// Running sums `Σ E⁺` of one side: per channel, and over every channel (the last entry).
type Sums = Vec<f64>;

impl Spikes {
    fn new() -> Self {
        Self {
            own_ll: vec![0.0],
            own_sp: vec![0.0],
            ..Self::default()
        }
    }

    /// Appends a spike of `channel` at `t` (not before the last), updating `sums`.
    fn push(&mut self, t: f64, channel: u32, x: f64, sums: &mut Sums) {
        let (plus, minus) = (x.exp(), (-x).exp());
        let k = self.t.len();
        let c = channel as usize;
        let all = sums.len() - 1;
        self.own_ll
            .push(self.own_ll[k] + 1.0 + 2.0 * minus * sums[c]);
        self.own_sp
            .push(self.own_sp[k] + 1.0 + 2.0 * minus * sums[all]);
        sums[c] += plus;
        sums[all] += plus;
        self.t.push(t);
        self.channel.push(channel);
        self.minus.push(minus);
        self.plus.push(plus);
    }
}

/// The training side, prepared once.
#[derive(Debug, Clone)]
pub struct GrowingVanRossum {
    tau_s: f64,
    centre: f64,
    inv_tau: f64,
    channels: usize,
    train: Vec<Spikes>,
}

/// Where the live sample stands against one training sample: training spikes walked, their
/// running sums, and the cross products so far.
#[derive(Debug, Clone)]
struct PairState {
    walked: usize,
    sums: Sums,
    cross_ll: f64,
    cross_sp: f64,
}

/// The live side and its pairs with every training sample, advanced window by window.
#[derive(Debug, Clone)]
pub struct GrowingLive {
    spikes: Spikes,
    sums: Sums,
    pairs: Vec<PairState>,
    t_end_s: f64,
}

impl GrowingVanRossum {
    /// Prepares `training` for kernel `tau_s`; `None` when its spikes span more than
    /// `2·690·τ` (the centred exponentials would overflow; use
    /// [`PreparedVanRossum::cross_matrices_until`](super::PreparedVanRossum::cross_matrices_until)).
    pub fn new(training: &[MultiSpikeTrain], tau_s: f64) -> Result<Option<Self>, DistanceError> {
        let tau_s = check_tau(tau_s)?;
        let channels = common_channels(training)?;
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
                let mut s = Spikes::new();
                let mut sums = vec![0.0; channels + 1];
                for (c, t) in merged(o) {
                    s.push(t, c, (t - centre) * inv_tau, &mut sums);
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
        let pair = PairState {
            walked: 0,
            sums: vec![0.0; self.channels + 1],
            cross_ll: 0.0,
            cross_sp: 0.0,
        };
        GrowingLive {
            spikes: Spikes::new(),
            sums: vec![0.0; self.channels + 1],
            pairs: vec![pair; self.train.len()],
            t_end_s: f64::NEG_INFINITY,
        }
    }

    /// Advances `live` to `T = t_end_s`: `new` holds, per channel, its spikes in
    /// `[previous T, T)`, sorted. Spikes out of that range or beyond the centred range, a
    /// wrong channel count or `T` going back are an
    /// [`InvalidParameter`](DistanceError::InvalidParameter) error (nothing changes).
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
        let mut window: Vec<(u32, f64)> = Vec::new();
        for (c, train) in new.iter().enumerate() {
            let mut last = live.t_end_s;
            for &t in *train {
                if !(t >= last && t < t_end_s) {
                    return Err(bad(t, "sorted, within [previous T, T)"));
                }
                if ((t - self.centre) * self.inv_tau).abs() > CENTRED_EXP_LIMIT {
                    return Err(bad(t, "within 690 τ of the training spikes' centre"));
                }
                window.push((c as u32, t));
                last = t;
            }
        }
        window.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        let first = live.spikes.t.len();
        let start_sums = live.sums.clone();
        for &(c, t) in &window {
            let x = (t - self.centre) * self.inv_tau;
            live.spikes.push(t, c, x, &mut live.sums);
        }
        live.t_end_s = t_end_s;
        let a = &live.spikes;
        let all = self.channels;
        let mut a_sums = start_sums.clone();
        for (b, pair) in self.train.iter().zip(&mut live.pairs) {
            // The two sides' spikes of this window in time order.
            let (mut i, mut j) = (first, pair.walked);
            let a_end = a.t.len();
            let mut both = false;
            loop {
                let b_next = b.t.get(j).filter(|&&t| t < t_end_s);
                let take_live = match (i < a_end, b_next) {
                    (true, Some(&tb)) => a.t[i] <= tb,
                    (true, None) => true,
                    (false, Some(_)) => false,
                    (false, None) => break,
                };
                if take_live {
                    let (c, m, p) = (a.channel[i] as usize, a.minus[i], a.plus[i]);
                    pair.cross_ll += m * pair.sums[c];
                    pair.cross_sp += m * pair.sums[all];
                    if !both {
                        a_sums.copy_from_slice(&start_sums);
                        both = true;
                    }
                    a_sums[c] += p;
                    a_sums[all] += p;
                    i += 1;
                } else {
                    let (c, m, p) = (b.channel[j] as usize, b.minus[j], b.plus[j]);
                    let sums = if both { &a_sums } else { &start_sums };
                    pair.cross_ll += m * sums[c];
                    pair.cross_sp += m * sums[all];
                    pair.sums[c] += p;
                    pair.sums[all] += p;
                    j += 1;
                }
            }
            pair.walked = j;
        }
        Ok(())
    }

    /// `(LL², SP²)` between `live` and training sample `i`, both cut at the live `T`.
    pub fn squared_parts(&self, live: &GrowingLive, i: usize) -> (f64, f64) {
        let (a, b, p) = (&live.spikes, &self.train[i], &live.pairs[i]);
        let n = a.t.len();
        (
            squared_from_products(a.own_ll[n], b.own_ll[p.walked], p.cross_ll),
            squared_from_products(a.own_sp[n], b.own_sp[p.walked], p.cross_sp),
        )
    }
}

/// Every spike of `o` as `(channel, t)`, in time order (channel order among equal times).
fn merged(o: &MultiSpikeTrain) -> Vec<(u32, f64)> {
    let mut all: Vec<(u32, f64)> = o
        .channels()
        .enumerate()
        .flat_map(|(c, train)| train.iter().map(move |&t| (c as u32, t)))
        .collect();
    all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    all
}
