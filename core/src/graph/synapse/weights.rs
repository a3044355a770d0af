//! [`Weights`]: a projection's synapses and their weights as a user reads and writes them
//! ([`Network::weights`](crate::Network::weights),
//! [`Network::set_weights`](crate::Network::set_weights)), and the conversion of any run-time
//! wiring to explicit rows (one weight per synapse), which plasticity and written weights need.

use super::connectivity::Wiring;
use ndarray::Array2;

/// The synapses of a projection, sorted by (presynaptic, postsynaptic) index, with their
/// weights: a sparse view (`pre[s] → post[s]` with `weight[s]`), and a dense one
/// ([`dense`](Self::dense)). Postsynaptic indices are the whole population's; in a network
/// partitioned over ranks, a rank holds the synapses onto its own neurons only.
#[derive(Debug, Clone, PartialEq)]
pub struct Weights {
    /// Presynaptic neurons (channels) of the projection.
    pub n_pre: usize,
    /// Postsynaptic neurons of the projection.
    pub n_post: usize,
    /// Presynaptic index of each synapse.
    pub pre: Vec<u32>,
    /// Postsynaptic index of each synapse.
    pub post: Vec<u32>,
    /// Weight of each synapse (the jump of the synaptic current per spike).
    pub weight: Vec<f64>,
}

impl Weights {
    /// Number of synapses.
    pub fn len(&self) -> usize {
        self.weight.len()
    }

    /// `true` without synapses.
    pub fn is_empty(&self) -> bool {
        self.weight.is_empty()
    }

    /// The dense `n_pre × n_post` matrix `W[i, j]` (row = presynaptic neuron, as Brian2's
    /// `w[i, j]`); pairs without a synapse are 0, and several synapses of one pair add up.
    pub fn dense(&self) -> Array2<f64> {
        let mut w = Array2::zeros((self.n_pre, self.n_post));
        for ((&i, &j), &x) in self.pre.iter().zip(&self.post).zip(&self.weight) {
            w[(i as usize, j as usize)] += x;
        }
        w
    }
}

impl Wiring {
    /// The synapses as `(pre, local post, weight)` in CSR order (by presynaptic neuron, then
    /// as stored), for `n_pre` presynaptic and `n_post` local postsynaptic neurons.
    pub(crate) fn synapses(&self, n_pre: usize, n_post: usize) -> (Vec<u32>, Vec<u32>, Vec<f64>) {
        match self {
            Wiring::OneToOne(w) => (
                (0..n_pre as u32).collect(),
                (0..n_pre as u32).collect(),
                vec![*w; n_pre],
            ),
            Wiring::AllToAll(w) => {
                let pre = (0..n_pre as u32)
                    .flat_map(|i| std::iter::repeat_n(i, n_post))
                    .collect();
                let post = (0..n_pre).flat_map(|_| 0..n_post as u32).collect();
                (pre, post, vec![*w; n_pre * n_post])
            }
            Wiring::Csr {
                offsets,
                post,
                weight,
            } => (rows(offsets), post.clone(), weight.clone()),
            Wiring::UniformCsr {
                offsets,
                post,
                weight,
            } => (rows(offsets), post.clone(), vec![*weight; post.len()]),
        }
    }

    /// The same synapses as explicit rows with one weight per synapse ([`Wiring::Csr`]).
    pub(crate) fn explicit(&self, n_pre: usize, n_post: usize) -> Wiring {
        if let Wiring::Csr { .. } = self {
            return self.clone();
        }
        let (pre, post, weight) = self.synapses(n_pre, n_post);
        let mut offsets = vec![0usize; n_pre + 1];
        pre.iter().for_each(|&i| offsets[i as usize + 1] += 1);
        for i in 0..n_pre {
            offsets[i + 1] += offsets[i];
        }
        Wiring::Csr {
            offsets,
            post,
            weight,
        }
    }
}

/// The presynaptic neuron of each synapse of CSR rows `offsets`.
fn rows(offsets: &[usize]) -> Vec<u32> {
    (0..offsets.len().saturating_sub(1))
        .flat_map(|i| std::iter::repeat_n(i as u32, offsets[i + 1] - offsets[i]))
        .collect()
}
