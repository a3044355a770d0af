//! Projections: connectivity plus exponential current synapses.
//!
//! Each projection keeps one synaptic current per target neuron,
//!
//! ```text
//! τ_syn · dI/dt = −I        between spikes (advanced exactly: I ← I·e^(−dt/τ_syn))
//! I ← I + w                 when a presynaptic spike arrives (delay d steps after emission)
//! ```
//!
//! and the target population receives the sum of its projections' currents at the start of the
//! step, held constant over the step. Currents below 10⁻³⁰ in magnitude are flushed to zero so a long silence never
//! leaves subnormal numbers in the loop (they are 10–100× slower on x86).

use crate::error::GraphError;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ops::Range;

/// Magnitude below which a decaying synaptic current is set to exactly 0.
pub const FLUSH_TO_ZERO: f64 = 1e-30;

/// The synapse filter's decay of one step: `x ← x·factor`, then values below [`FLUSH_TO_ZERO`]
/// in magnitude become exactly 0 (branch-free, so it vectorises). The trace-sampled Van Rossum
/// distance ([`crate::distance::trace_sampled`]) applies the same flush to its sparse states.
#[inline]
fn decay_and_flush(values: &mut [f64], factor: f64) {
    values.iter_mut().for_each(|v| *v = flush(*v * factor));
}

/// `x`, or exactly 0 when `|x| <` [`FLUSH_TO_ZERO`].
#[inline(always)]
pub(super) fn flush(x: f64) -> f64 {
    if x.abs() < FLUSH_TO_ZERO { 0.0 } else { x }
}

/// The synaptic currents `I_p` of the projections feeding a population, borrowed for one
/// clock-driven step ([`SynapticDrive`]), with their one-step decay factors `d_p = e^(−dt/τ_p)`.
///
/// [`take`](Self::take)`(i)` is neuron `i`'s input, `x_i = I_0[i] + I_1[i] + …` (summed in
/// projection order), and leaves each current decayed as a projection decays it,
/// `I_p[i] ← I_p[i]·d_p`, flushed to 0 below [`FLUSH_TO_ZERO`]: the network's drain and the
/// model's update in one loop, so the input never goes through memory.
#[derive(Debug)]
pub struct DecayingCurrents<'a, const N: usize> {
    currents: [&'a mut [f64]; N],
    decays: [f64; N],
    bound: f64,
}

impl<'a, const N: usize> DecayingCurrents<'a, N> {
    /// The currents `currents[p]` (one value per neuron, all of one length) decaying by
    /// `decays[p]` per step, whose sum never exceeds `bound` in magnitude (`f64::INFINITY` when
    /// nothing is known; the network proves a finite bound at build, see
    /// [`bound`](Self::bound)). `None` when the lengths differ or `N = 0`.
    pub fn new(currents: [&'a mut [f64]; N], decays: [f64; N], bound: f64) -> Option<Self> {
        let n = currents.first()?.len();
        currents.iter().all(|c| c.len() == n).then_some(Self {
            currents,
            decays,
            bound,
        })
    }

    /// Neurons.
    pub fn len(&self) -> usize {
        self.currents[0].len()
    }

    /// `true` when there are no neurons.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A bound on `|x_i|` for every input [`take`](Self::take) returns. The network's is
    /// `Σ_p 4·W_p/(1 − d_p)`, where `W_p` is the largest sum of `|w|` onto one neuron of
    /// projection `p`: a presynaptic population spikes at most once per neuron per step, so
    /// `|I_p| ≤ W_p·(1 + d_p + d_p² + …)`, and the factor 4 covers rounding. It is infinite
    /// for a projection from a spike input (which may repeat a channel within a step) or with
    /// `1 − d_p < 2⁻⁴⁰`.
    pub fn bound(&self) -> f64 {
        self.bound
    }

    /// Neuron `i`'s input `Σ_p I_p[i]`; then every `I_p[i]` decays by one step (flushed below
    /// [`FLUSH_TO_ZERO`]). Panics when `i ≥ len()`; a loop over `0..len()` has its bounds
    /// checks removed.
    #[inline(always)]
    pub fn take(&mut self, i: usize) -> f64 {
        let mut x = self.currents[0][i];
        self.currents[0][i] = flush(x * self.decays[0]);
        for p in 1..N {
            let c = self.currents[p][i];
            x += c;
            self.currents[p][i] = flush(c * self.decays[p]);
        }
        x
    }

    /// Writes every neuron's input into `out` (`out[i] =` [`take`](Self::take)`(i)`).
    pub fn drain_into(&mut self, out: &mut [f64]) {
        let n = self.len().min(out.len());
        for (i, x) in out[..n].iter_mut().enumerate() {
            *x = self.take(i);
        }
    }

    /// The first `mid` neurons and the rest (`mid ≤ len()`).
    pub fn split_at(self, mid: usize) -> (Self, Self) {
        let Self {
            currents,
            decays,
            bound,
        } = self;
        let mut left = currents.map(|c| c.split_at_mut(mid));
        let right = std::array::from_fn(|p| std::mem::take(&mut left[p].1));
        (
            Self {
                currents: left.map(|(l, _)| l),
                decays,
                bound,
            },
            Self {
                currents: right,
                decays,
                bound,
            },
        )
    }
}

/// The input of one clock-driven step of a population fed only by the exponential synapses of
/// one or two projections (as in CUBA: an excitatory and an inhibitory one), given to
/// [`NeuronModel::step_synaptic`](crate::NeuronModel::step_synaptic) so that a model can sum
/// and decay the currents inside its own update loop.
#[derive(Debug)]
pub enum SynapticDrive<'a> {
    /// One projection.
    One(DecayingCurrents<'a, 1>),
    /// Two projections, summed as `I_0 + I_1`.
    Two(DecayingCurrents<'a, 2>),
}

impl SynapticDrive<'_> {
    /// Neurons.
    pub fn len(&self) -> usize {
        match self {
            SynapticDrive::One(c) => c.len(),
            SynapticDrive::Two(c) => c.len(),
        }
    }

    /// `true` when there are no neurons.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bound on the inputs' magnitude ([`DecayingCurrents::bound`]).
    pub fn bound(&self) -> f64 {
        match self {
            SynapticDrive::One(c) => c.bound(),
            SynapticDrive::Two(c) => c.bound(),
        }
    }

    /// Writes every neuron's input into `out` and decays the currents
    /// ([`DecayingCurrents::drain_into`]): the unfused step.
    pub fn drain_into(self, out: &mut [f64]) {
        match self {
            SynapticDrive::One(mut c) => c.drain_into(out),
            SynapticDrive::Two(mut c) => c.drain_into(out),
        }
    }

    /// The first `mid` neurons and the rest (`mid ≤ len()`).
    pub fn split_at(self, mid: usize) -> (Self, Self) {
        match self {
            SynapticDrive::One(c) => {
                let (a, b) = c.split_at(mid);
                (SynapticDrive::One(a), SynapticDrive::One(b))
            }
            SynapticDrive::Two(c) => {
                let (a, b) = c.split_at(mid);
                (SynapticDrive::Two(a), SynapticDrive::Two(b))
            }
        }
    }
}

/// Exponential current synapse parameters shared by all synapses of a projection: each
/// presynaptic spike adds its weight `w` to the synaptic current, which decays as
/// `I(t) = w·e^{−t/τ_syn}` and enters the target model's input (weights are in the model's input
/// units; [`one_spike_weight`](super::one_spike_weight) finds the weight at which one spike makes
/// a neuron fire).
///
/// **Delay rule:** `delay_steps ≥ 1` from a population, `≥ 0` from a spike input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExpSynapse {
    /// Decay time constant τ_syn in seconds (> 0).
    pub tau_s: f64,
    /// Transmission delay in whole steps. 0 is allowed from input nodes only; from a
    /// population it must be ≥ 1, since a population's spikes of step k exist only after its
    /// own integration in step k (the delay rule, checked by
    /// [`NetworkBuilder::connect`](super::NetworkBuilder::connect)).
    pub delay_steps: u32,
}

impl ExpSynapse {
    /// A synapse with time constant `tau_s` and a one-step delay.
    pub fn new(tau_s: f64) -> Self {
        Self {
            tau_s,
            delay_steps: 1,
        }
    }

    /// The same synapse with another delay.
    pub fn with_delay(self, delay_steps: u32) -> Self {
        Self {
            delay_steps,
            ..self
        }
    }
}

/// One explicit synapse: presynaptic index, postsynaptic index, weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Synapse {
    /// Presynaptic neuron (channel) index.
    pub pre: u32,
    /// Postsynaptic neuron index.
    pub post: u32,
    /// Weight: the jump of the synaptic current per spike.
    pub weight: f64,
}

/// Which neurons a projection connects, and with what weights.
#[derive(Debug, Clone, PartialEq)]
pub enum Connectivity {
    /// Neuron `i` → neuron `i`; both sides must have the same size.
    OneToOne {
        /// Weight of every synapse.
        weight: f64,
    },
    /// Every presynaptic neuron → every postsynaptic neuron.
    AllToAll {
        /// Weight of every synapse.
        weight: f64,
    },
    /// Each (pre, post) pair independently with `probability`, drawn from `seed` at build time
    /// (self-pairs included, as in Brian2's `connect(p=…)`).
    Random {
        /// Connection probability in [0, 1].
        probability: f64,
        /// Weight of every synapse.
        weight: f64,
        /// Seed of the ChaCha8 generator that draws the pairs.
        seed: u64,
    },
    /// An explicit list of synapses.
    Sparse(Vec<Synapse>),
}

/// Compressed connectivity used while running.
#[derive(Debug, Clone)]
pub(crate) enum Wiring {
    OneToOne(f64),
    AllToAll(f64),
    /// CSR by presynaptic neuron.
    Csr {
        offsets: Vec<usize>,
        post: Vec<u32>,
        weight: Vec<f64>,
    },
    /// CSR by presynaptic neuron, one weight for all (random connectivity): a spike's row is
    /// only its targets, a third of the memory a row with weights reads.
    UniformCsr {
        offsets: Vec<usize>,
        post: Vec<u32>,
        weight: f64,
    },
}

fn check_weight(what: &str, w: f64) -> Result<(), GraphError> {
    if w.is_finite() {
        Ok(())
    } else {
        Err(GraphError::InvalidParameter {
            what: format!("{what} weight"),
            value: w,
            expected: "finite",
        })
    }
}

impl Connectivity {
    /// Checks this connectivity against the sizes of both sides (done at `connect`).
    pub(crate) fn validate(
        &self,
        what: &str,
        n_pre: usize,
        n_post: usize,
    ) -> Result<(), GraphError> {
        match self {
            Connectivity::OneToOne { weight } => {
                check_weight(what, *weight)?;
                if n_pre != n_post {
                    return Err(GraphError::SizeMismatch {
                        what: format!("{what}: one-to-one needs equal sizes; postsynaptic size"),
                        expected: n_pre,
                        got: n_post,
                    });
                }
            }
            Connectivity::AllToAll { weight } => check_weight(what, *weight)?,
            Connectivity::Random {
                probability,
                weight,
                ..
            } => {
                check_weight(what, *weight)?;
                if !(0.0..=1.0).contains(probability) {
                    return Err(GraphError::InvalidParameter {
                        what: format!("{what} probability"),
                        value: *probability,
                        expected: "in [0, 1]",
                    });
                }
            }
            Connectivity::Sparse(list) => {
                for (index, s) in list.iter().enumerate() {
                    check_weight(what, s.weight)?;
                    for (side, neuron, size) in [("pre", s.pre, n_pre), ("post", s.post, n_post)] {
                        if neuron as usize >= size {
                            return Err(GraphError::IndexOutOfRange {
                                what: format!("{what} ({side})"),
                                index,
                                neuron: neuron as usize,
                                size,
                            });
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Compiles into run-time wiring (random pairs are drawn here, only for needed projections),
    /// keeping only the synapses onto the postsynaptic neurons `post_block`, renumbered from
    /// `post_block.start` (the whole `0..n_post` in one process). The synapses kept are exactly
    /// those of the whole projection: random pairs are drawn from the same stream whatever the
    /// block, and the others skipped (so every rank walks the whole stream, and keeps in memory
    /// only its own block's synapses).
    pub(crate) fn compile(&self, n_pre: usize, n_post: usize, post_block: Range<usize>) -> Wiring {
        let whole = post_block == (0..n_post);
        // Row offsets from per-row counts (`counts[i + 1]` = synapses of row i).
        let offsets = |mut counts: Vec<usize>| {
            for i in 0..n_pre {
                counts[i + 1] += counts[i];
            }
            counts
        };
        let local = |j: usize| {
            post_block
                .contains(&j)
                .then(|| (j - post_block.start) as u32)
        };
        match self {
            Connectivity::OneToOne { weight } if whole => Wiring::OneToOne(*weight),
            Connectivity::AllToAll { weight } => Wiring::AllToAll(*weight),
            Connectivity::OneToOne { weight } => {
                let mut counts = vec![0usize; n_pre + 1];
                post_block.clone().for_each(|i| counts[i + 1] = 1);
                Wiring::UniformCsr {
                    offsets: offsets(counts),
                    post: (0..post_block.len() as u32).collect(),
                    weight: *weight,
                }
            }
            Connectivity::Sparse(list) => {
                let mut list: Vec<(u32, u32, f64)> = list
                    .iter()
                    .filter_map(|s| local(s.post as usize).map(|j| (s.pre, j, s.weight)))
                    .collect();
                list.sort_by_key(|s| (s.0, s.1));
                let mut counts = vec![0usize; n_pre + 1];
                list.iter().for_each(|s| counts[s.0 as usize + 1] += 1);
                Wiring::Csr {
                    offsets: offsets(counts),
                    post: list.iter().map(|s| s.1).collect(),
                    weight: list.iter().map(|s| s.2).collect(),
                }
            }
            Connectivity::Random {
                probability,
                weight,
                seed,
            } => {
                // Pairs are drawn in (pre, post) order, so rows come out sorted.
                let mut counts = vec![0usize; n_pre + 1];
                let expected = n_pre as f64 * post_block.len() as f64 * probability.clamp(0.0, 1.0);
                // Room for the expected count plus 6 σ: one allocation, no doubling.
                let mut post =
                    Vec::with_capacity((expected + 6.0 * expected.sqrt() + 16.0) as usize);
                let mut keep = |i: usize, j: usize| {
                    if let Some(j) = local(j) {
                        counts[i + 1] += 1;
                        post.push(j);
                    }
                };
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                let total = n_pre * n_post;
                if *probability >= 1.0 {
                    (0..n_pre).for_each(|i| (0..n_post).for_each(|j| keep(i, j)));
                } else if *probability > 0.0 {
                    // Geometric skipping: the gap to the next chosen pair is Geometric(p). The
                    // pair `k` is `(i, j) = (k / n_post, k % n_post)`, followed incrementally
                    // (a division only when a gap crosses a row's end).
                    let log_q = (1.0 - probability).ln();
                    let (mut k, mut i, mut j) = (0usize, 0usize, 0usize);
                    loop {
                        let u: f64 = rng.random::<f64>();
                        let gap = ((1.0 - u).ln() / log_q).floor();
                        if gap >= (total - k) as f64 {
                            break;
                        }
                        k += gap as usize;
                        j += gap as usize;
                        if j >= n_post {
                            i += j / n_post;
                            j %= n_post;
                        }
                        keep(i, j);
                        k += 1;
                        j += 1;
                    }
                }
                Wiring::UniformCsr {
                    offsets: offsets(counts),
                    post,
                    weight: *weight,
                }
            }
        }
    }
}

/// A projection while running: wiring, delay, decay factor and the synaptic currents.
#[derive(Debug, Clone)]
pub(crate) struct RunningProjection {
    pub pre: usize,
    /// The target node (runtime index), `None` when pruned (kept for a trace readout).
    pub post: Option<usize>,
    pub delay: usize,
    pub decay: f64,
    pub wiring: Wiring,
    pub current: Vec<f64>,
    /// A bound on `|current|` at every step ([`DecayingCurrents::bound`]).
    pub bound: f64,
}

impl RunningProjection {
    /// Decays every synaptic current by one step, flushing tiny values to 0 (branch-free).
    #[inline]
    pub fn decay(&mut self) {
        decay_and_flush(&mut self.current, self.decay);
    }

    /// Adds this projection's currents to `input` (or writes them, when `first`), then decays
    /// them by one step — one pass instead of two.
    #[inline]
    pub fn drain_into(&mut self, input: &mut [f64], first: bool) {
        let d = self.decay;
        if first {
            for (x, c) in input.iter_mut().zip(self.current.iter_mut()) {
                *x = *c;
                *c = flush(*c * d);
            }
        } else {
            for (x, c) in input.iter_mut().zip(self.current.iter_mut()) {
                *x += *c;
                *c = flush(*c * d);
            }
        }
    }

    /// Adds the weights of the presynaptic neurons `spikes` to their targets' currents.
    #[inline]
    pub fn deliver(&mut self, spikes: &[u32]) {
        match &self.wiring {
            Wiring::OneToOne(w) => {
                for &i in spikes {
                    self.current[i as usize] += w;
                }
            }
            Wiring::AllToAll(w) => {
                let total = w * spikes.len() as f64;
                if !spikes.is_empty() {
                    self.current.iter_mut().for_each(|c| *c += total);
                }
            }
            Wiring::Csr {
                offsets,
                post,
                weight,
            } => {
                for &i in spikes {
                    let (a, b) = (offsets[i as usize], offsets[i as usize + 1]);
                    for (&j, &w) in post[a..b].iter().zip(&weight[a..b]) {
                        self.current[j as usize] += w;
                    }
                }
            }
            Wiring::UniformCsr {
                offsets,
                post,
                weight,
            } => {
                for &i in spikes {
                    for &j in &post[offsets[i as usize]..offsets[i as usize + 1]] {
                        self.current[j as usize] += weight;
                    }
                }
            }
        }
    }

    /// Calls `f` with every target neuron the presynaptic `spikes` reach (with repeats).
    #[inline]
    pub fn for_each_target(&self, spikes: &[u32], mut f: impl FnMut(u32)) {
        match &self.wiring {
            Wiring::OneToOne(_) => spikes.iter().for_each(|&i| f(i)),
            Wiring::AllToAll(_) => {
                if !spikes.is_empty() {
                    (0..self.current.len() as u32).for_each(f);
                }
            }
            Wiring::Csr { offsets, post, .. } | Wiring::UniformCsr { offsets, post, .. } => {
                for &i in spikes {
                    let (a, b) = (offsets[i as usize], offsets[i as usize + 1]);
                    post[a..b].iter().for_each(|&j| f(j));
                }
            }
        }
    }

    /// The bound on this projection's currents ([`DecayingCurrents::bound`]): `4·W/(1 − d)`
    /// with `W` the largest sum of `|w|` onto one target, when each presynaptic neuron spikes
    /// at most once per step (`once_per_step`: the source is a population); else infinite.
    pub fn current_bound(&self, n_pre: usize, once_per_step: bool) -> f64 {
        let leak = 1.0 - self.decay;
        if !once_per_step || leak < (-40f64).exp2() {
            return f64::INFINITY;
        }
        let most_onto_one = match &self.wiring {
            Wiring::OneToOne(w) => w.abs(),
            Wiring::AllToAll(w) => n_pre as f64 * w.abs(),
            Wiring::Csr { post, weight, .. } => {
                let mut sum = vec![0.0f64; self.current.len()];
                post.iter()
                    .zip(weight)
                    .for_each(|(&j, w)| sum[j as usize] += w.abs());
                sum.into_iter().fold(0.0, f64::max)
            }
            Wiring::UniformCsr { post, weight, .. } => {
                let mut count = vec![0u32; self.current.len()];
                post.iter().for_each(|&j| count[j as usize] += 1);
                count.into_iter().max().unwrap_or(0) as f64 * weight.abs()
            }
        };
        4.0 * most_onto_one / leak
    }

    /// Number of synapses.
    pub fn n_synapses(&self, n_pre: usize) -> usize {
        match &self.wiring {
            Wiring::OneToOne(_) => n_pre,
            Wiring::AllToAll(_) => n_pre * self.current.len(),
            Wiring::Csr { post, .. } | Wiring::UniformCsr { post, .. } => post.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_connectivity_has_the_asked_density_and_is_seeded() {
        let c = Connectivity::Random {
            probability: 0.02,
            weight: 1.0,
            seed: 3,
        };
        let count = |w: &Wiring| match w {
            Wiring::Csr { post, .. } | Wiring::UniformCsr { post, .. } => post.len(),
            _ => unreachable!(),
        };
        let (a, b) = (
            c.compile(1000, 1000, 0..1000),
            c.compile(1000, 1000, 0..1000),
        );
        let n = count(&a);
        // 20 000 expected, σ ≈ 140.
        assert!((n as f64 - 20_000.0).abs() < 700.0, "{n}");
        assert_eq!(n, count(&b));
        let other = Connectivity::Random {
            probability: 0.02,
            weight: 1.0,
            seed: 4,
        };
        assert_ne!(
            format!("{:?}", other.compile(1000, 1000, 0..1000)),
            format!("{a:?}")
        );
        let none = Connectivity::Random {
            probability: 0.0,
            weight: 1.0,
            seed: 0,
        };
        assert_eq!(count(&none.compile(10, 10, 0..10)), 0);
        let all = Connectivity::Random {
            probability: 1.0,
            weight: 1.0,
            seed: 0,
        };
        assert_eq!(count(&all.compile(10, 7, 0..7)), 70);
    }

    /// Row `i` of a wiring as `(global post, weight)` in delivery order.
    fn rows(w: &Wiring, n_pre: usize, block: Range<usize>) -> Vec<Vec<(usize, f64)>> {
        (0..n_pre)
            .map(|i| match w {
                Wiring::OneToOne(x) => vec![(i, *x)],
                Wiring::AllToAll(x) => block.clone().map(|j| (j, *x)).collect(),
                Wiring::Csr {
                    offsets,
                    post,
                    weight,
                } => (offsets[i]..offsets[i + 1])
                    .map(|s| (block.start + post[s] as usize, weight[s]))
                    .collect(),
                Wiring::UniformCsr {
                    offsets,
                    post,
                    weight,
                } => (offsets[i]..offsets[i + 1])
                    .map(|s| (block.start + post[s] as usize, *weight))
                    .collect(),
            })
            .collect()
    }

    /// The random pairs as first written (`(k / n_post, k % n_post)` for each drawn `k`): the
    /// connectivity of every network built before must not change.
    fn reference_pairs(
        probability: f64,
        seed: u64,
        n_pre: usize,
        n_post: usize,
    ) -> Vec<(usize, f64)> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (total, log_q) = (n_pre * n_post, (1.0 - probability).ln());
        let (mut k, mut out) = (0usize, Vec::new());
        loop {
            let u: f64 = rng.random::<f64>();
            let gap = ((1.0 - u).ln() / log_q).floor();
            if gap >= (total - k) as f64 {
                break;
            }
            k += gap as usize;
            out.push((k / n_post, k % n_post));
            k += 1;
        }
        out.into_iter()
            .map(|(i, j)| (i * n_post + j, 0.5))
            .collect()
    }

    #[test]
    fn random_pairs_are_those_drawn_before() {
        for (probability, n_pre, n_post) in
            [(0.02, 300, 400), (0.3, 17, 5), (0.001, 50, 30), (0.9, 3, 1)]
        {
            let c = Connectivity::Random {
                probability,
                weight: 0.5,
                seed: 9,
            };
            let got: Vec<(usize, f64)> =
                rows(&c.compile(n_pre, n_post, 0..n_post), n_pre, 0..n_post)
                    .into_iter()
                    .enumerate()
                    .flat_map(|(i, row)| row.into_iter().map(move |(j, w)| (i * n_post + j, w)))
                    .collect();
            assert_eq!(got, reference_pairs(probability, 9, n_pre, n_post));
        }
    }

    #[test]
    fn blocks_of_postsynaptic_neurons_keep_exactly_their_synapses() {
        let (n_pre, n_post) = (40, 13);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let sparse = (0..200)
            .map(|k| Synapse {
                pre: rng.random_range(0..n_pre as u32),
                post: rng.random_range(0..n_post as u32),
                weight: k as f64,
            })
            .collect();
        for c in [
            Connectivity::Random {
                probability: 0.3,
                weight: 0.5,
                seed: 7,
            },
            Connectivity::Random {
                probability: 1.0,
                weight: 0.5,
                seed: 7,
            },
            Connectivity::Sparse(sparse),
            Connectivity::AllToAll { weight: 2.0 },
        ] {
            let whole = rows(&c.compile(n_pre, n_post, 0..n_post), n_pre, 0..n_post);
            assert!(whole.iter().map(Vec::len).sum::<usize>() > 100);
            for size in 1..=15 {
                let mut joined = vec![Vec::new(); n_pre];
                for rank in 0..size {
                    let block = crate::ranks::even_block(n_post, rank, size);
                    let part = rows(&c.compile(n_pre, n_post, block.clone()), n_pre, block);
                    joined.iter_mut().zip(part).for_each(|(j, p)| j.extend(p));
                }
                assert_eq!(joined, whole, "{c:?} over {size} ranks");
            }
        }
        let one = Connectivity::OneToOne { weight: 3.0 };
        let whole = rows(&one.compile(n_post, n_post, 0..n_post), n_post, 0..n_post);
        let mut joined = vec![Vec::new(); n_post];
        for rank in 0..4 {
            let block = crate::ranks::even_block(n_post, rank, 4);
            let part = rows(&one.compile(n_post, n_post, block.clone()), n_post, block);
            joined.iter_mut().zip(part).for_each(|(j, p)| j.extend(p));
        }
        assert_eq!(joined, whole);
    }

    #[test]
    fn decay_is_exact_and_flushes_subnormals() {
        let mut p = RunningProjection {
            pre: 0,
            post: None,
            delay: 0,
            decay: (-0.1f64).exp(),
            wiring: Wiring::OneToOne(1.0),
            current: vec![0.0; 2],
            bound: f64::INFINITY,
        };
        p.deliver(&[1]);
        for _ in 0..10 {
            p.decay();
        }
        assert!((p.current[1] - (-1.0f64).exp()).abs() < 1e-15);
        for _ in 0..1000 {
            p.decay();
        }
        assert_eq!(
            p.current[1], 0.0,
            "decayed current must flush to exact zero"
        );
    }

    fn projection(
        connectivity: &Connectivity,
        n_pre: usize,
        n_post: usize,
        tau: f64,
    ) -> RunningProjection {
        RunningProjection {
            pre: 0,
            post: Some(1),
            delay: 1,
            decay: (-1e-4 / tau).exp(),
            wiring: connectivity.compile(n_pre, n_post, 0..n_post),
            current: vec![0.0; n_post],
            bound: f64::INFINITY,
        }
    }

    /// The largest |current| of `p` over 2000 steps in which each of its `n_pre` presynaptic
    /// neurons spikes every step.
    fn largest_current_when_every_neuron_spikes(p: &mut RunningProjection, n_pre: usize) -> f64 {
        let everyone: Vec<u32> = (0..n_pre as u32).collect();
        let mut largest = 0.0f64;
        for _ in 0..2000 {
            p.deliver(&everyone);
            largest = p.current.iter().fold(largest, |m, c| m.max(c.abs()));
            p.decay();
        }
        largest
    }

    #[test]
    fn the_current_bound_holds_when_every_neuron_spikes_every_step() {
        // The worst case the bound covers: each presynaptic neuron spikes at every step. The
        // largest current then tends to W/(1 − d) = bound/4 from below.
        let (n_pre, n_post) = (50, 40);
        let sparse = Connectivity::Sparse(vec![
            Synapse {
                pre: 0,
                post: 3,
                weight: -2.5,
            },
            Synapse {
                pre: 7,
                post: 3,
                weight: 1.0,
            },
            Synapse {
                pre: 7,
                post: 9,
                weight: 4.0,
            },
        ]);
        for (c, w_max) in [
            (Connectivity::AllToAll { weight: -0.5 }, 25.0),
            (Connectivity::OneToOne { weight: 3.0 }, 3.0),
            (sparse, 4.0),
        ] {
            let n_pre = if matches!(c, Connectivity::OneToOne { .. }) {
                n_post
            } else {
                n_pre
            };
            let mut p = projection(&c, n_pre, n_post, 5e-3);
            let bound = p.current_bound(n_pre, true);
            assert!(
                (bound - 4.0 * w_max / (1.0 - p.decay)).abs() < 1e-9 * bound,
                "{c:?}"
            );
            let largest = largest_current_when_every_neuron_spikes(&mut p, n_pre);
            assert!(
                largest <= bound / 4.0 * (1.0 + 1e-12),
                "{c:?}: {largest} vs {bound}"
            );
            assert!(largest > 0.99 * bound / 4.0, "{c:?}: the bound is tight");
        }
        let random = Connectivity::Random {
            probability: 0.1,
            weight: 1.5,
            seed: 3,
        };
        let mut p = projection(&random, 500, 400, 5e-3);
        let bound = p.current_bound(500, true);
        let largest = largest_current_when_every_neuron_spikes(&mut p, 500);
        assert!(largest <= bound / 4.0 * (1.0 + 1e-12) && largest > 0.99 * bound / 4.0);
    }

    #[test]
    fn no_bound_from_spike_inputs_or_without_leak() {
        let c = Connectivity::AllToAll { weight: 1.0 };
        assert_eq!(
            projection(&c, 3, 3, 5e-3).current_bound(3, false),
            f64::INFINITY
        );
        // τ = 10⁹ s at dt = 0.1 ms: 1 − d ≈ 10⁻¹³ < 2⁻⁴⁰.
        assert_eq!(
            projection(&c, 3, 3, 1e9).current_bound(3, true),
            f64::INFINITY
        );
    }

    #[test]
    fn decaying_currents_sum_decay_and_split_as_the_drain() {
        let mut a = vec![1.0, -2.0, 1e-31, 0.5, 3.0];
        let mut b = vec![0.25, 2.0, 0.0, -1e-29, 7.0];
        let (da, db) = (0.9, 0.5);
        let expected_input: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + y).collect();
        let expected_a: Vec<f64> = a.iter().map(|&x| flush(x * da)).collect();
        let expected_b: Vec<f64> = b.iter().map(|&x| flush(x * db)).collect();
        let drive = DecayingCurrents::new([&mut a[..], &mut b[..]], [da, db], 7.0).unwrap();
        assert_eq!((drive.len(), drive.bound()), (5, 7.0));
        let (mut left, right) = drive.split_at(2);
        let (mut one, mut rest) = right.split_at(1);
        assert_eq!((left.len(), one.len(), rest.len()), (2, 1, 2));
        let mut input = vec![0.0; 5];
        left.drain_into(&mut input[..2]);
        input[2] = one.take(0);
        rest.drain_into(&mut input[3..]);
        assert_eq!(input, expected_input);
        assert_eq!((a, b), (expected_a, expected_b));
        assert!(DecayingCurrents::new([&mut [1.0][..], &mut [][..]], [1.0, 1.0], 0.0).is_none());
    }
}
