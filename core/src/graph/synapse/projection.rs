//! [`RunningProjection`]: a projection while the network runs — its compiled [`Wiring`], delay,
//! one-step decay factor and the synaptic currents onto its (local) target neurons: spike
//! delivery, decay, the drain into a population's input and the bound on the currents.

use super::connectivity::Wiring;
use super::stdp::Plasticity;
use crate::currents::{decay_and_flush, flush};

/// A projection while running: wiring, delay, decay factor and the synaptic currents.
#[derive(Debug, Clone)]
pub(crate) struct RunningProjection {
    pub pre: usize,
    /// The target node (runtime index), `None` when pruned (kept for a trace readout).
    pub post: Option<usize>,
    pub delay: usize,
    /// The synaptic time constant τ_syn (s); `decay` is `e^(−dt/τ_syn)`.
    pub tau_s: f64,
    pub decay: f64,
    pub wiring: Wiring,
    pub current: Vec<f64>,
    /// A bound on `|current|` at every step ([`DecayingCurrents::bound`]).
    pub bound: f64,
    /// The STDP of a plastic projection (whose wiring is then [`Wiring::Csr`]).
    pub plasticity: Option<Box<Plasticity>>,
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

    /// Plasticity of the presynaptic `spikes` arriving in step `k`, after their delivery
    /// (see [`Stdp`](super::Stdp)); nothing for a fixed projection.
    #[inline]
    pub fn learn_from_pre(&mut self, spikes: &[u32], k: u64) {
        if let (
            Some(p),
            Wiring::Csr {
                offsets,
                post,
                weight,
            },
        ) = (&mut self.plasticity, &mut self.wiring)
        {
            p.on_pre(spikes, k, offsets, post, weight);
        }
    }

    /// Plasticity of the target population's `spikes` of step `k` (whole-population indices;
    /// this rank's neurons start at `first`).
    #[inline]
    pub fn learn_from_post(&mut self, spikes: &[u32], first: usize, k: u64) {
        if let (Some(p), Wiring::Csr { weight, .. }) = (&mut self.plasticity, &mut self.wiring) {
            p.on_post(spikes.iter().map(|&j| j as usize - first), k, weight);
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
        let most_onto_one = match (&self.plasticity, &self.wiring) {
            // Plastic weights move within their bounds.
            (Some(p), Wiring::Csr { post, .. }) => {
                let mut count = vec![0u32; self.current.len()];
                post.iter().for_each(|&j| count[j as usize] += 1);
                let w = p.rule.w_min.abs().max(p.rule.w_max.abs());
                count.into_iter().max().unwrap_or(0) as f64 * w
            }
            (_, wiring) => match wiring {
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
            },
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
    use crate::graph::synapse::Connectivity;
    use crate::graph::synapse::Synapse;

    #[test]
    fn decay_is_exact_and_flushes_subnormals() {
        let mut p = RunningProjection {
            pre: 0,
            post: None,
            delay: 0,
            tau_s: 10.0,
            decay: (-0.1f64).exp(),
            wiring: Wiring::OneToOne(1.0),
            current: vec![0.0; 2],
            bound: f64::INFINITY,
            plasticity: None,
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
            tau_s: tau,
            decay: (-1e-4 / tau).exp(),
            wiring: connectivity.compile(n_pre, n_post, 0..n_post),
            current: vec![0.0; n_post],
            bound: f64::INFINITY,
            plasticity: None,
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
}
