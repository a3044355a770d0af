//! Input nodes: spike sources ([`SpikeSource`]: [`SpikeArrayInput`], [`PoissonInput`]) and
//! current sources ([`CurrentInput`]).

use crate::error::GraphError;
use crate::model::SpikeBuffer;
use crate::spikes::MultiSpikeTrain;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A node that emits spikes every step (taxel spike arrays, Poisson generators, user sources).
pub trait SpikeSource: Send {
    /// Number of channels.
    fn len(&self) -> usize;

    /// `true` for a source without channels.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Precomputes what depends on the time step; called once at build for needed sources.
    fn prepare(&mut self, dt_s: f64) -> Result<(), GraphError>;

    /// Rewinds to step 0 (as right after `prepare`).
    fn reset(&mut self);

    /// Pushes the spikes of step `step` (covering `[step·dt, (step+1)·dt)`) into `out`.
    fn emit(&mut self, step: u64, out: &mut SpikeBuffer);

    /// What this source is, for saving or describing its network
    /// ([`Network::save`](crate::Network::save)); `None` (the default): it cannot be saved.
    fn describe(&self) -> Option<SourceDescription> {
        None
    }

    /// Where this prepared source is in its stream beyond what the step number tells (a
    /// random generator's position), for saving mid-run; `None` (the default) when it cannot
    /// be saved.
    fn position(&self) -> Option<Vec<u64>> {
        None
    }

    /// Continues this prepared source (made from its description) from `position` as of step
    /// `step`, so that it emits what the saved one would have. The default refuses.
    fn seek(&mut self, step: u64, position: &[u64]) -> Result<(), GraphError> {
        let _ = (step, position);
        Err(GraphError::NotSaveable {
            node: "a spike source".into(),
            reason: "it has no saved position".into(),
        })
    }
}

/// What a built-in spike source is: enough to make it anew ([`SourceDescription::make`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SourceDescription {
    /// A [`SpikeArrayInput`]: spike times (s) per channel.
    SpikeArray {
        /// One train per channel, ascending times.
        trains: Vec<Vec<f64>>,
    },
    /// A [`PoissonInput`].
    Poisson {
        /// Channels.
        size: usize,
        /// Rate of every channel (Hz).
        rate_hz: f64,
        /// Seed of its generator.
        seed: u64,
    },
}

impl SourceDescription {
    /// The source described (unprepared). Spike trains that are not valid (a time not finite,
    /// out of order) are a [`GraphError::Description`] naming `node`.
    pub fn make(&self, node: &str) -> Result<Box<dyn SpikeSource>, GraphError> {
        Ok(match self {
            SourceDescription::SpikeArray { trains } => Box::new(SpikeArrayInput::new(
                MultiSpikeTrain::from_channels(trains.clone())
                    .map_err(|e| GraphError::Description(format!("spike source '{node}': {e}")))?,
            )),
            SourceDescription::Poisson {
                size,
                rate_hz,
                seed,
            } => Box::new(PoissonInput::new(*size, *rate_hz, *seed)),
        })
    }
}

/// Tolerance on `t/dt` when assigning a spike time to a step: 0.3 s / 0.1 s evaluates to
/// 2.9999999999999996 and must land in step 3.
const STEP_EPS: f64 = 1e-9;

/// Replays recorded spike trains (e.g. the 49 taxel trains of one slide) into the network.
///
/// A spike at time `t` is emitted in step `k = ⌊t/dt + 10⁻⁹⌋`, with in-step fraction
/// `(t − k·dt)/dt`; spikes at negative times are never emitted.
#[derive(Debug, Clone)]
pub struct SpikeArrayInput {
    trains: MultiSpikeTrain,
    /// `(step, channel, fraction)` in emission order, built by `prepare`.
    schedule: Vec<(u64, u32, f64)>,
    cursor: usize,
}

impl SpikeArrayInput {
    /// A source replaying `trains` (one channel per output neuron).
    pub fn new(trains: MultiSpikeTrain) -> Self {
        Self {
            trains,
            schedule: Vec::new(),
            cursor: 0,
        }
    }

    /// The trains being replayed.
    pub fn trains(&self) -> &MultiSpikeTrain {
        &self.trains
    }
}

impl SpikeSource for SpikeArrayInput {
    fn len(&self) -> usize {
        self.trains.n_channels()
    }

    fn prepare(&mut self, dt_s: f64) -> Result<(), GraphError> {
        self.schedule.clear();
        for (c, t) in self.trains.pooled_with_channels() {
            if t < 0.0 {
                continue;
            }
            let k = (t / dt_s + STEP_EPS).floor();
            let phi = ((t - k * dt_s) / dt_s).clamp(0.0, 1.0);
            self.schedule.push((k as u64, c, phi));
        }
        self.cursor = 0;
        Ok(())
    }

    fn reset(&mut self) {
        self.cursor = 0;
    }

    fn describe(&self) -> Option<SourceDescription> {
        Some(SourceDescription::SpikeArray {
            trains: (0..self.trains.n_channels())
                .map(|c| self.trains.channel(c).to_vec())
                .collect(),
        })
    }

    fn position(&self) -> Option<Vec<u64>> {
        Some(Vec::new())
    }

    /// The position is the step's: the first spike scheduled at or after `step`.
    fn seek(&mut self, step: u64, _position: &[u64]) -> Result<(), GraphError> {
        self.cursor = self.schedule.partition_point(|&(k, _, _)| k < step);
        Ok(())
    }

    fn emit(&mut self, step: u64, out: &mut SpikeBuffer) {
        // Skip anything scheduled before `step` (e.g. when a run starts late); emit this step's.
        while let Some(&(k, c, phi)) = self.schedule.get(self.cursor) {
            if k > step {
                break;
            }
            if k == step {
                out.push_at(c, phi);
            }
            self.cursor += 1;
        }
    }
}

/// Independent Poisson spike generators, one per channel, at `rate_hz` each.
///
/// Each step, each channel spikes with probability `p = rate·dt` (a Bernoulli approximation of
/// a Poisson process, exact as `dt → 0`; `rate·dt ≤ 1` is required). Spikes are stamped at the
/// start of the step. The stream is a pure function of `seed` (ChaCha8), so runs repeat bit for
/// bit.
///
/// Rather than one draw per channel and step, each channel draws its gap to its next spike: the
/// number of silent steps before a success of independent Bernoulli(`p`) trials is geometric,
/// `P(g) = (1 − p)^g·p`, drawn as `g = ⌊ln u / ln(1 − p)⌋` from one uniform `u ∈ (0, 1]`. The
/// spikes have the same law as per-step draws at the cost of one draw per spike (1000 inputs at
/// 15 Hz and dt = 0.1 ms: 1.5 draws per step instead of 1000). Channels draw their first gaps
/// in channel order at the start, then one gap per spike, in the order the spikes are emitted
/// (by step, then channel).
#[derive(Debug, Clone)]
pub struct PoissonInput {
    n: usize,
    rate_hz: f64,
    seed: u64,
    /// `ln(1 − p)` (−∞ for `p = 1`; 0 for `p = 0`, when no channel ever spikes).
    ln_q: f64,
    /// Each channel's next spike step, earliest first (ties by channel).
    next: BinaryHeap<Reverse<(u64, u32)>>,
    rng: ChaCha8Rng,
}

impl PoissonInput {
    /// `n` channels firing at `rate_hz`, drawn from the generator seeded with `seed`.
    pub fn new(n: usize, rate_hz: f64, seed: u64) -> Self {
        Self {
            n,
            rate_hz,
            seed,
            ln_q: 0.0,
            next: BinaryHeap::new(),
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    /// A saved position of `len` numbers where `2 + channels` were expected.
    fn misfit(channels: usize, len: usize) -> GraphError {
        GraphError::Description(format!(
            "a Poisson source's position is {} numbers, the saved one has {len}",
            2 + channels
        ))
    }

    /// The silent steps before a channel's next spike (geometric; see the type docs).
    fn gap(&mut self) -> u64 {
        let u = 1.0 - self.rng.random::<f64>();
        // ln u ≤ 0 and ln(1 − p) < 0 (−∞ for p = 1: gap 0): a ratio ≥ 0, cast saturating.
        (u.ln() / self.ln_q).floor() as u64
    }
}

impl SpikeSource for PoissonInput {
    fn len(&self) -> usize {
        self.n
    }

    fn prepare(&mut self, dt_s: f64) -> Result<(), GraphError> {
        let p = self.rate_hz * dt_s;
        if !(self.rate_hz.is_finite() && self.rate_hz >= 0.0 && p <= 1.0) {
            return Err(GraphError::InvalidParameter {
                what: "PoissonInput rate_hz".into(),
                value: self.rate_hz,
                expected: "finite, ≥ 0 and ≤ 1/dt",
            });
        }
        self.ln_q = (-p).ln_1p();
        // A silent source (rate 0) holds no channel.
        self.next = BinaryHeap::with_capacity(if self.ln_q < 0.0 { self.n } else { 0 });
        self.reset();
        Ok(())
    }

    fn reset(&mut self) {
        self.rng = ChaCha8Rng::seed_from_u64(self.seed);
        self.next.clear();
        if self.ln_q < 0.0 {
            for i in 0..self.n as u32 {
                let first = self.gap();
                self.next.push(Reverse((first, i)));
            }
        }
    }

    fn describe(&self) -> Option<SourceDescription> {
        Some(SourceDescription::Poisson {
            size: self.n,
            rate_hz: self.rate_hz,
            seed: self.seed,
        })
    }

    /// The generator's word position (128 bits, as two `u64`, low first), then each channel's
    /// next spike step, by channel (none when the rate is 0).
    fn position(&self) -> Option<Vec<u64>> {
        let w = self.rng.get_word_pos();
        let mut next = vec![0u64; self.next.len()];
        for &Reverse((k, i)) in &self.next {
            next[i as usize] = k;
        }
        Some(
            [w as u64, (w >> 64) as u64]
                .into_iter()
                .chain(next)
                .collect(),
        )
    }

    fn seek(&mut self, _step: u64, position: &[u64]) -> Result<(), GraphError> {
        let channels = if self.ln_q < 0.0 { self.n } else { 0 };
        let [low, high, next @ ..] = position else {
            return Err(Self::misfit(channels, position.len()));
        };
        if next.len() != channels {
            return Err(Self::misfit(channels, position.len()));
        }
        self.rng = ChaCha8Rng::seed_from_u64(self.seed);
        self.rng
            .set_word_pos(u128::from(*low) | (u128::from(*high) << 64));
        self.next.clear();
        self.next.extend(
            next.iter()
                .enumerate()
                .map(|(i, &k)| Reverse((k, i as u32))),
        );
        Ok(())
    }

    fn emit(&mut self, step: u64, out: &mut SpikeBuffer) {
        // Channels due at `step` (or, if steps were skipped, before it) leave the heap's top
        // in channel order; each spikes if due now and draws its next gap.
        while let Some(&Reverse((k, i))) = self.next.peek() {
            if k > step {
                break;
            }
            if k == step {
                out.push_at(i, 0.0);
            }
            let next = step.saturating_add(1).saturating_add(self.gap());
            if let Some(mut top) = self.next.peek_mut() {
                *top = Reverse((next, i));
            }
        }
    }
}

/// A current injected directly into a population (no synapse), in the model's input units.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CurrentInput {
    /// A constant current per neuron (one value is broadcast to every neuron).
    Constant {
        /// Amplitudes, one per neuron or a single one.
        amplitude: Vec<f64>,
    },
    /// A piecewise-constant current shared by all neurons: 0 until the first change, then the
    /// amplitude of the latest change whose time `≤ t_k` (the step's start time).
    Steps {
        /// Number of neurons it feeds (1 = broadcast).
        size: usize,
        /// `(time_s, amplitude)` changes, sorted by time.
        changes: Vec<(f64, f64)>,
    },
}

impl CurrentInput {
    /// A constant `amplitude` for any population (broadcast).
    pub fn constant(amplitude: f64) -> Self {
        CurrentInput::Constant {
            amplitude: vec![amplitude],
        }
    }

    /// Number of neurons this source defines (1 means broadcast).
    pub fn len(&self) -> usize {
        match self {
            CurrentInput::Constant { amplitude } => amplitude.len(),
            CurrentInput::Steps { size, .. } => *size,
        }
    }

    /// `true` when the source defines no neuron.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub(crate) fn validate(&self, name: &str) -> Result<(), GraphError> {
        let bad = |value: f64, expected| GraphError::InvalidParameter {
            what: format!("current input '{name}'"),
            value,
            expected,
        };
        match self {
            CurrentInput::Constant { amplitude } => {
                if let Some(&a) = amplitude.iter().find(|a| !a.is_finite()) {
                    return Err(bad(a, "finite amplitudes"));
                }
            }
            CurrentInput::Steps { changes, .. } => {
                let mut last = f64::NEG_INFINITY;
                for &(t, a) in changes {
                    if !t.is_finite() || t < last {
                        return Err(bad(t, "finite change times in increasing order"));
                    }
                    if !a.is_finite() {
                        return Err(bad(a, "finite amplitudes"));
                    }
                    last = t;
                }
            }
        }
        Ok(())
    }

    /// The part of this source that feeds the neurons `block` of its populations (a rank's
    /// block): per-neuron amplitudes are cut to the block, broadcast values stay as they are.
    pub(crate) fn restrict(&self, block: std::ops::Range<usize>) -> CurrentInput {
        match self {
            CurrentInput::Constant { amplitude } if amplitude.len() > 1 => CurrentInput::Constant {
                amplitude: amplitude[block].to_vec(),
            },
            other => other.clone(),
        }
    }

    /// Adds this source's current at step start time `t_s` into `out` (one entry per neuron).
    pub(crate) fn add_into(&self, t_s: f64, out: &mut [f64]) {
        match self {
            CurrentInput::Constant { amplitude } if amplitude.len() == 1 => {
                let a = amplitude[0];
                out.iter_mut().for_each(|o| *o += a);
            }
            CurrentInput::Constant { amplitude } => {
                out.iter_mut().zip(amplitude).for_each(|(o, a)| *o += a);
            }
            CurrentInput::Steps { changes, .. } => {
                let k = changes.partition_point(|&(tc, _)| tc <= t_s + STEP_EPS * 1e-3);
                if k > 0 {
                    let a = changes[k - 1].1;
                    out.iter_mut().for_each(|o| *o += a);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spike_array_lands_each_spike_in_the_step_that_contains_it() {
        let trains = MultiSpikeTrain::from_channels(vec![vec![0.0, 0.3], vec![0.25, 0.3]]).unwrap();
        let mut src = SpikeArrayInput::new(trains);
        src.prepare(0.1).unwrap();
        let mut seen = Vec::new();
        for k in 0..5 {
            let mut b = SpikeBuffer::new();
            src.emit(k, &mut b);
            for (&i, &phi) in b.indices().iter().zip(b.fractions()) {
                seen.push((k, i, (phi * 1e6).round() / 1e6));
            }
        }
        assert_eq!(
            seen,
            vec![(0, 0, 0.0), (2, 1, 0.5), (3, 0, 0.0), (3, 1, 0.0)]
        );
    }

    #[test]
    fn poisson_gaps_have_the_law_of_one_bernoulli_draw_per_channel_and_step() {
        // p = 0.2 per step over 2000 channels × 500 steps: a channel spikes in a step with
        // probability p, and in two steps in a row with probability p² (independent steps),
        // within 5 σ.
        let (n, p, steps) = (2000usize, 0.2, 500u64);
        let mut src = PoissonInput::new(n, p / 1e-3, 9);
        src.prepare(1e-3).unwrap();
        let mut previous = vec![false; n];
        let (mut spikes, mut pairs) = (0u64, 0u64);
        for k in 0..steps {
            let mut b = SpikeBuffer::new();
            src.emit(k, &mut b);
            assert!(b.indices().windows(2).all(|w| w[0] < w[1]), "by channel");
            let mut now = vec![false; n];
            for &i in b.indices() {
                now[i as usize] = true;
                pairs += u64::from(previous[i as usize]);
            }
            spikes += b.indices().len() as u64;
            previous = now;
        }
        let within = |count: u64, trials: f64, q: f64| {
            (count as f64 / trials - q).abs() < 5.0 * (q * (1.0 - q) / trials).sqrt()
        };
        let trials = (n as u64 * steps) as f64;
        assert!(within(spikes, trials, p), "{spikes}");
        assert!(within(pairs, trials - n as f64, p * p), "{pairs}");
        // p = 1 spikes every channel every step; p = 0 never.
        for (rate_hz, each) in [(1000.0, 3), (0.0, 0)] {
            let mut src = PoissonInput::new(3, rate_hz, 1);
            src.prepare(1e-3).unwrap();
            for k in 0..10 {
                let mut b = SpikeBuffer::new();
                src.emit(k, &mut b);
                assert_eq!(b.indices().len(), each, "rate {rate_hz}, step {k}");
            }
        }
    }

    #[test]
    fn poisson_continues_from_its_saved_position_and_restarts_on_reset() {
        let steps = |src: &mut PoissonInput, range: std::ops::Range<u64>| {
            range
                .flat_map(|k| {
                    let mut b = SpikeBuffer::new();
                    src.emit(k, &mut b);
                    b.indices().iter().map(|&i| (k, i)).collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()
        };
        let mut whole = PoissonInput::new(50, 200.0, 4);
        whole.prepare(1e-3).unwrap();
        let first = steps(&mut whole, 0..100);
        let position = whole.position().unwrap();
        let rest = steps(&mut whole, 100..300);
        let mut resumed = PoissonInput::new(50, 200.0, 4);
        resumed.prepare(1e-3).unwrap();
        resumed.seek(100, &position).unwrap();
        assert_eq!(steps(&mut resumed, 100..300), rest);
        assert!(resumed.seek(100, &position[..3]).is_err());
        whole.reset();
        assert_eq!(steps(&mut whole, 0..100), first);
    }

    #[test]
    fn poisson_is_seeded_and_has_the_asked_rate() {
        let run = |seed| {
            let mut src = PoissonInput::new(100, 50.0, seed);
            src.prepare(1e-3).unwrap();
            let mut total = Vec::new();
            for k in 0..1000 {
                let mut b = SpikeBuffer::new();
                src.emit(k, &mut b);
                total.extend_from_slice(b.indices());
            }
            total
        };
        let (a, b, c) = (run(7), run(7), run(8));
        assert_eq!(a, b);
        assert_ne!(a, c);
        // 100 channels × 1 s × 50 Hz = 5000 expected; 5 σ ≈ 350.
        assert!((a.len() as f64 - 5000.0).abs() < 350.0, "{}", a.len());
        assert!(PoissonInput::new(1, 2000.0, 0).prepare(1e-3).is_err());
        assert!(PoissonInput::new(1, f64::NAN, 0).prepare(1e-3).is_err());
    }

    #[test]
    fn step_current_switches_at_its_change_times() {
        let c = CurrentInput::Steps {
            size: 1,
            changes: vec![(0.1, 2.0), (0.2, -1.0)],
        };
        let at = |t| {
            let mut o = [0.0];
            c.add_into(t, &mut o);
            o[0]
        };
        assert_eq!(
            (at(0.0), at(0.1), at(0.15), at(0.2), at(5.0)),
            (0.0, 2.0, 2.0, -1.0, -1.0)
        );
        assert!(CurrentInput::constant(f64::INFINITY).validate("x").is_err());
        let unsorted = CurrentInput::Steps {
            size: 1,
            changes: vec![(0.2, 1.0), (0.1, 1.0)],
        };
        assert!(unsorted.validate("x").is_err());
    }
}
