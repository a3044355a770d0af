//! Connectivity: which neurons a projection connects and with what weights ([`Connectivity`],
//! [`Synapse`]), checked at `connect` and compiled at build into the run-time [`Wiring`]
//! (CSR rows by presynaptic neuron, random pairs drawn from a seeded stream), keeping only the
//! synapses onto one rank's block of postsynaptic neurons.

use crate::error::GraphError;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ops::Range;

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

    /// Checks that every weight lies in `[w_min, w_max]` (a plastic projection's bounds).
    pub(crate) fn check_weights_within(
        &self,
        what: &str,
        w_min: f64,
        w_max: f64,
    ) -> Result<(), GraphError> {
        let outside = |w: f64| !(w_min..=w_max).contains(&w);
        let bad = match self {
            Connectivity::OneToOne { weight }
            | Connectivity::AllToAll { weight }
            | Connectivity::Random { weight, .. } => outside(*weight).then_some((0, *weight)),
            Connectivity::Sparse(list) => {
                (list.iter().map(|s| s.weight).enumerate()).find(|&(_, w)| outside(w))
            }
        };
        match bad {
            Some((synapse, weight)) => Err(GraphError::WeightOutsideBounds {
                what: what.to_owned(),
                kind: "initial",
                synapse,
                weight,
                w_min,
                w_max,
            }),
            None => Ok(()),
        }
    }

    /// The most synapses onto `n_post` targets from `n_pre` sources this connectivity can
    /// hold (all pairs for all-to-all and random ones, saturating).
    pub(crate) fn max_synapses(&self, n_pre: usize, n_post: usize) -> u64 {
        match self {
            Connectivity::OneToOne { .. } => n_post as u64,
            Connectivity::AllToAll { .. } | Connectivity::Random { .. } => {
                (n_pre as u64).saturating_mul(n_post as u64)
            }
            Connectivity::Sparse(list) => list.len() as u64,
        }
    }

    /// The synapses a fixed projection of this connectivity stores one by one (none for
    /// one-to-one and all-to-all, which keep one weight; random ones: their expected number
    /// and a margin).
    pub(crate) fn stored_synapses(&self, n_pre: usize, n_post: usize) -> u64 {
        match self {
            Connectivity::OneToOne { .. } | Connectivity::AllToAll { .. } => 0,
            Connectivity::Random { probability, .. } => {
                let pairs = self.max_synapses(n_pre, n_post) as f64;
                (pairs * probability * 1.1) as u64
            }
            Connectivity::Sparse(list) => list.len() as u64,
        }
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
}
