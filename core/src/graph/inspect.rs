//! Reaching into a built [`Network`]: a projection's weights ([`Network::weights`],
//! [`Network::set_weights`]), its learning switch ([`Network::set_learning`]) and a
//! population's state ([`Network::state`]).

use super::ids::{PopulationId, ProjectionId, checked_index};
use super::network::Network;
use super::running::RunningKind;
use super::synapse::{RunningProjection, Weights};
use crate::error::GraphError;

impl Network {
    /// The kept projection `id` (its run-time index), or why there is none.
    fn running_projection(&self, id: ProjectionId) -> Result<usize, GraphError> {
        let index = checked_index(id, self.brand)?;
        match self.projection_index.get(index) {
            None => Err(GraphError::UnknownProjection(index)),
            Some(None) => Err(GraphError::Pruned {
                what: format!("projection {index}"),
            }),
            Some(Some(p)) => Ok(*p),
        }
    }

    /// The synapses of projection `id` and their weights now (learned ones, for a plastic
    /// projection), sorted by presynaptic then postsynaptic index ([`Weights`]; its
    /// [`dense`](Weights::dense) is the matrix). In a network partitioned over ranks, the
    /// synapses onto this rank's neurons. Errors: an id of another builder, or a projection
    /// dropped at build ([`GraphError::Pruned`]).
    pub fn weights(&self, id: ProjectionId) -> Result<Weights, GraphError> {
        let p = &self.projections[self.running_projection(id)?];
        let first = self.post_first(p);
        let (pre, mut post, weight) = p.wiring.synapses(self.nodes[p.pre].size, p.current.len());
        post.iter_mut().for_each(|j| *j += first as u32);
        Ok(Weights {
            n_pre: self.nodes[p.pre].size,
            n_post: self.post_size(p),
            pre,
            post,
            weight,
        })
    }

    /// Sets the weights of projection `id`'s synapses: `weights` must name exactly the
    /// synapses [`weights`](Self::weights) returns, in the same order (read, change the values,
    /// write back), with finite weights — within `[w_min, w_max]` for a plastic projection.
    /// Takes effect from the next delivered spike; the synaptic currents keep their values.
    /// Errors name the first synapse that does not fit ([`GraphError::SizeMismatch`],
    /// [`GraphError::InvalidParameter`]); nothing is changed then.
    pub fn set_weights(&mut self, id: ProjectionId, weights: &Weights) -> Result<(), GraphError> {
        let index = self.running_projection(id)?;
        let now = self.weights(id)?;
        let what = format!("set_weights of projection {}", id.index);
        for (field, expected, got) in [
            ("presynaptic neurons", now.n_pre, weights.n_pre),
            ("postsynaptic neurons", now.n_post, weights.n_post),
            ("synapses", now.len(), weights.weight.len()),
            ("presynaptic indices", now.len(), weights.pre.len()),
            ("postsynaptic indices", now.len(), weights.post.len()),
        ] {
            if expected != got {
                return Err(GraphError::SizeMismatch {
                    what: format!("{what}: {field}"),
                    expected,
                    got,
                });
            }
        }
        let bounds = self.projections[index]
            .plasticity
            .as_ref()
            .map(|p| (p.rule.w_min, p.rule.w_max));
        for s in 0..now.len() {
            if (now.pre[s], now.post[s]) != (weights.pre[s], weights.post[s]) {
                return Err(GraphError::InvalidParameter {
                    what: format!(
                        "{what}: synapse {s} is {} → {}, the projection's is {} → {}",
                        weights.pre[s], weights.post[s], now.pre[s], now.post[s]
                    ),
                    value: s as f64,
                    expected: "the synapses weights() returns, in its order",
                });
            }
            let w = weights.weight[s];
            if !w.is_finite() {
                return Err(GraphError::InvalidParameter {
                    what: format!("{what}: weight of synapse {s}"),
                    value: w,
                    expected: "finite",
                });
            }
            if let Some((w_min, w_max)) = bounds.filter(|(lo, hi)| !(lo..=hi).contains(&&w)) {
                return Err(GraphError::WeightOutsideBounds {
                    what: what.clone(),
                    kind: "new",
                    synapse: s,
                    weight: w,
                    w_min,
                    w_max,
                });
            }
        }
        let p = &mut self.projections[index];
        let n_pre = self.nodes[p.pre].size;
        p.wiring = p.wiring.explicit(n_pre, p.current.len());
        if let super::synapse::Wiring::Csr { weight, .. } = &mut p.wiring {
            weight.copy_from_slice(&weights.weight);
        }
        let from_population = matches!(self.nodes[p.pre].kind, RunningKind::Population(_));
        p.bound = p.current_bound(n_pre, from_population);
        Ok(())
    }

    /// Turns learning of the plastic projection `id` on or off. Frozen (`false`), its weights
    /// stay as they are while the traces still follow the spikes, so learning can resume
    /// later as if it had watched all along. Errors: a fixed projection
    /// ([`GraphError::NotPlastic`]), a pruned one.
    pub fn set_learning(&mut self, id: ProjectionId, on: bool) -> Result<(), GraphError> {
        let index = self.running_projection(id)?;
        match &mut self.projections[index].plasticity {
            Some(p) => {
                p.learning = on;
                Ok(())
            }
            None => Err(GraphError::NotPlastic {
                projection: id.index,
            }),
        }
    }

    /// `true` while the plastic projection `id` learns (see [`set_learning`](Self::set_learning)).
    pub fn is_learning(&self, id: ProjectionId) -> Result<bool, GraphError> {
        let index = self.running_projection(id)?;
        self.projections[index]
            .plasticity
            .as_ref()
            .map(|p| p.learning)
            .ok_or(GraphError::NotPlastic {
                projection: id.index,
            })
    }

    /// The state variable `variable` (one of the model's
    /// [`variables`](crate::NeuronModel::variables), e.g. `"v"`) of every neuron of
    /// `population` this process computes, now. Event-driven neurons are current after every
    /// run (the run ends by bringing them up to date).
    pub fn state(&self, population: PopulationId, variable: &str) -> Result<Vec<f64>, GraphError> {
        let index = checked_index(population, self.brand)?;
        let node = self
            .node_index
            .get(index)
            .copied()
            .ok_or(GraphError::UnknownNode(index))?
            .ok_or_else(|| GraphError::Pruned {
                what: format!("population {index}"),
            })?;
        let n = &self.nodes[node];
        let RunningKind::Population(m) = &n.kind else {
            unreachable!("a PopulationId names a population")
        };
        let var = m
            .variables()
            .iter()
            .position(|v| *v == variable)
            .ok_or_else(|| GraphError::Model {
                population: n.name.clone(),
                source: crate::error::ModelError::UnknownVariable {
                    model: m.model_name(),
                    name: variable.to_owned(),
                    available: m.variables().join(", "),
                },
            })?;
        let neurons: Vec<u32> = (0..n.local.len() as u32).collect();
        let mut out = Vec::with_capacity(neurons.len());
        m.read_variable(var, &neurons, &mut out);
        Ok(out)
    }

    /// The first postsynaptic neuron this rank holds of projection `p`'s target.
    fn post_first(&self, p: &RunningProjection) -> usize {
        p.post.map_or(0, |post| self.nodes[post].local.start)
    }

    /// The size of projection `p`'s whole target population.
    fn post_size(&self, p: &RunningProjection) -> usize {
        p.post.map_or(p.current.len(), |post| self.nodes[post].size)
    }
}
