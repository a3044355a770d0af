//! The decaying synaptic currents a population's projections hand to its neuron model for one
//! step: [`DecayingCurrents`] (one to `N` projections' currents with their decay factors) and
//! [`SynapticDrive`] (the one- or two-projection case
//! [`NeuronModel::step_synaptic`](crate::NeuronModel::step_synaptic) receives), with the flush
//! of tiny currents to exactly 0 ([`FLUSH_TO_ZERO`]) that every decay applies.
//!
//! The currents obey the exponential synapse of the network graph (see
//! [`graph`](crate::graph#phase-order-of-one-step)): between spikes each decays exactly by
//! `d = e^(−dt/τ_syn)` per step. This file sits below both the model contract
//! ([`NeuronModel`](crate::NeuronModel)) and the graph, which import it.

/// Magnitude below which a decaying synaptic current is set to exactly 0.
pub const FLUSH_TO_ZERO: f64 = 1e-30;

/// The synapse filter's decay of one step: `x ← x·factor`, then values below [`FLUSH_TO_ZERO`]
/// in magnitude become exactly 0 (branch-free, so it vectorises). The trace-sampled Van Rossum
/// distance ([`crate::distance::trace_sampled`]) applies the same flush to its sparse states.
#[inline]
pub(crate) fn decay_and_flush(values: &mut [f64], factor: f64) {
    values.iter_mut().for_each(|v| *v = flush(*v * factor));
}

/// `x`, or exactly 0 when `|x| <` [`FLUSH_TO_ZERO`].
#[inline(always)]
pub(crate) fn flush(x: f64) -> f64 {
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

    /// The currents `I_p` and their decay factors `d_p`, for a model's own vectorised loop,
    /// which must do what [`take`](Self::take) does for every neuron: sum in projection
    /// order, then decay and flush each current.
    pub fn parts_mut(&mut self) -> (&mut [&'a mut [f64]; N], [f64; N]) {
        (&mut self.currents, self.decays)
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

#[cfg(test)]
mod tests {
    use super::*;

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
