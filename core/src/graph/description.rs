//! [`NetworkDescription`]: what a built network is — its time step, stepping, nodes (models
//! with their settings, spike and current sources) and projections (synapses with their weights
//! now, time constants, delays, plasticity) — as data: serde, JSON for the Python package's NIR
//! bridge, and the first half of a saved network ([`Network::save`]).
//! [`Network::describe`] writes it; [`NetworkBuilder::from_description`] builds from it.

use super::builder::NetworkBuilder;
use super::ids::{InputId, PopulationId};
use super::input::{CurrentInput, SourceDescription};
use super::network::Network;
use super::running::RunningKind;
use super::stepping::Stepping;
use super::synapse::{Connectivity, ExpSynapse, Stdp, Synapse, Wiring};
use crate::error::{GraphError, ModelError};
use crate::model::ModelFactory;
use crate::model_state::ModelDescription;
use serde::{Deserialize, Serialize};

/// The `format` of every description.
pub const NETWORK_FORMAT: &str = "neurotac-network";
/// The description version written; older ones (none yet) are read.
pub const NETWORK_VERSION: u32 = 1;

/// A network as data: the time step, the stepping, the nodes and the projections with their
/// weights now. As JSON:
///
/// ```json
/// {"format": "neurotac-network", "version": 1, "dt_s": 0.0001, "stepping": "clock",
///  "nodes": [{"kind": "source", "name": "taxels", "source": {"spike_array": {"trains": [[0.01, 0.02], []]}}},
///            {"kind": "population", "name": "out", "model": {"model": "lif", "size": 2, "settings": {…}}}],
///  "projections": [{"pre": "taxels", "post": "out", "tau_s": 0.005, "delay_steps": 0,
///                   "wiring": {"one_to_one": {"weight": 1.2}}, "plasticity": null}]}
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetworkDescription {
    /// Always [`NETWORK_FORMAT`].
    pub format: String,
    /// [`NETWORK_VERSION`] when written.
    pub version: u32,
    /// Time step (s) the network was built with.
    pub dt_s: f64,
    /// How its populations are stepped.
    pub stepping: Stepping,
    /// Nodes, in build order.
    pub nodes: Vec<NodeDescription>,
    /// Projections, in the order they were connected.
    pub projections: Vec<ProjectionDescription>,
}

/// One node of a [`NetworkDescription`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum NodeDescription {
    /// A population of a model.
    Population {
        /// Its name.
        name: String,
        /// Its model (made by a [`ModelFactory`]).
        model: ModelDescription,
    },
    /// A spike source.
    Source {
        /// Its name.
        name: String,
        /// What it is.
        source: SourceDescription,
    },
    /// A current source and the populations it is injected into.
    Current {
        /// Its name.
        name: String,
        /// The current.
        current: CurrentInput,
        /// The populations it feeds, by name.
        into: Vec<String>,
    },
}

impl NodeDescription {
    /// The node's name.
    pub fn name(&self) -> &str {
        match self {
            Self::Population { name, .. }
            | Self::Source { name, .. }
            | Self::Current { name, .. } => name,
        }
    }
}

/// A projection's synapses and weights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum WiringDescription {
    /// Neuron `i` → neuron `i`, one weight.
    OneToOne {
        /// The weight of every synapse.
        weight: f64,
    },
    /// Every presynaptic neuron → every postsynaptic one, one weight.
    AllToAll {
        /// The weight of every synapse.
        weight: f64,
    },
    /// Each (pre, post) pair independently with `probability`, one weight, drawn from `seed`
    /// when the network is built ([`Connectivity::Random`]). Read only: a built network
    /// describes its drawn synapses as [`Sparse`](Self::Sparse).
    Random {
        /// Connection probability in [0, 1].
        probability: f64,
        /// The weight of every synapse.
        weight: f64,
        /// Seed of the generator that draws the pairs.
        seed: u64,
    },
    /// Explicit synapses `pre[s] → post[s]` with `weight[s]`.
    Sparse {
        /// Presynaptic indices.
        pre: Vec<u32>,
        /// Postsynaptic indices.
        post: Vec<u32>,
        /// Weights.
        weight: Vec<f64>,
    },
}

/// One projection of a [`NetworkDescription`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProjectionDescription {
    /// The presynaptic node's name.
    pub pre: String,
    /// The postsynaptic population's name.
    pub post: String,
    /// Synaptic time constant τ_syn (s).
    pub tau_s: f64,
    /// Delay in steps.
    pub delay_steps: u32,
    /// Synapses and their weights now.
    pub wiring: WiringDescription,
    /// The STDP rule of a plastic projection.
    pub plasticity: Option<Stdp>,
}

impl Network {
    /// Refuses, naming `what`, on a network partitioned over ranks (each rank holds a part).
    pub(super) fn whole(&self, what: &str) -> Result<(), GraphError> {
        if self.partition.size > 1 {
            return Err(GraphError::NotSaveable {
                node: format!("rank {} of {}", self.partition.rank, self.partition.size),
                reason: format!("{what} needs the whole network; this rank holds a part of it"),
            });
        }
        Ok(())
    }

    /// This network as data ([`NetworkDescription`]): the kept nodes and projections (pruned
    /// ones are not part of it; a projection kept only for a synaptic-trace readout, whose
    /// target was pruned, neither), with the weights as they are now. Errors: a population
    /// whose model cannot be described, a source of the user's own
    /// ([`GraphError::NotSaveable`]), a network partitioned over ranks.
    pub fn describe(&self) -> Result<NetworkDescription, GraphError> {
        self.whole("describing a network")?;
        let mut nodes = Vec::new();
        for n in &self.nodes {
            nodes.push(match &n.kind {
                RunningKind::Population(m) => NodeDescription::Population {
                    name: n.name.clone(),
                    model: m.describe().ok_or_else(|| GraphError::Model {
                        population: n.name.clone(),
                        source: ModelError::NotSaveable {
                            model: m.model_name(),
                        },
                    })?,
                },
                RunningKind::Spikes(s) => NodeDescription::Source {
                    name: n.name.clone(),
                    source: s.describe().ok_or_else(|| GraphError::NotSaveable {
                        node: format!("spike source '{}'", n.name),
                        reason: "its source type has no description".into(),
                    })?,
                },
            });
        }
        for (c, current) in self.currents.iter().enumerate() {
            nodes.push(NodeDescription::Current {
                name: self.current_names[c].clone(),
                current: current.clone(),
                into: (self.nodes.iter())
                    .filter(|n| n.currents.contains(&c))
                    .map(|n| n.name.clone())
                    .collect(),
            });
        }
        let projections = (self.projections.iter())
            .filter_map(|p| p.post.map(|post| (p, post)))
            .map(|(p, post)| ProjectionDescription {
                pre: self.nodes[p.pre].name.clone(),
                post: self.nodes[post].name.clone(),
                tau_s: p.tau_s,
                delay_steps: p.delay as u32,
                wiring: match &p.wiring {
                    Wiring::OneToOne(weight) => WiringDescription::OneToOne { weight: *weight },
                    Wiring::AllToAll(weight) => WiringDescription::AllToAll { weight: *weight },
                    wiring => {
                        let (pre, post, weight) =
                            wiring.synapses(self.nodes[p.pre].size, p.current.len());
                        WiringDescription::Sparse { pre, post, weight }
                    }
                },
                plasticity: p.plasticity.as_ref().map(|pl| pl.rule),
            })
            .collect();
        Ok(NetworkDescription {
            format: NETWORK_FORMAT.into(),
            version: NETWORK_VERSION,
            dt_s: self.dt_s,
            stepping: self.stepping.clone(),
            nodes,
            projections,
        })
    }
}

impl NetworkBuilder {
    /// A builder holding the network `description` describes, its models made by `models`
    /// (`neurotac_neurons::BuiltinModels` for LIF and Izhikevich). Add readouts (find the
    /// nodes with [`population`](Self::population), [`spike_input`](Self::spike_input),
    /// [`projections`](Self::projections)) and build at the description's `dt_s`. Everything
    /// is checked as when a network is defined in code; errors: another format or a newer
    /// version, a reference to a node that does not exist ([`GraphError::Description`]), a
    /// model the factory refuses ([`GraphError::Model`]), and every error of the builder's
    /// own checks — the [limits](super::limits) on sizes and delays among them; a part the
    /// machine cannot hold is refused at build ([`GraphError::TooLarge`]).
    pub fn from_description(
        description: &NetworkDescription,
        models: &dyn ModelFactory,
    ) -> Result<NetworkBuilder, GraphError> {
        let d = description;
        if d.format != NETWORK_FORMAT {
            return Err(GraphError::Description(format!(
                "format is '{}', expected '{NETWORK_FORMAT}'",
                d.format
            )));
        }
        if d.version == 0 || d.version > NETWORK_VERSION {
            return Err(GraphError::Description(format!(
                "version {} is not one this neurotac reads (1 to {NETWORK_VERSION}; a newer neurotac wrote it?)",
                d.version
            )));
        }
        let mut b = NetworkBuilder::new();
        b.stepping(d.stepping.clone());
        for node in &d.nodes {
            match node {
                NodeDescription::Population { name, model } => {
                    let m = models.make(model).map_err(|source| GraphError::Model {
                        population: name.clone(),
                        source,
                    })?;
                    if m.len() != model.size {
                        return Err(GraphError::SizeMismatch {
                            what: format!("population '{name}' made from its description"),
                            expected: model.size,
                            got: m.len(),
                        });
                    }
                    b.add_boxed_population(name, m)?;
                }
                NodeDescription::Source { name, source } => {
                    b.add_boxed_spike_input(name, source.make(name)?)?;
                }
                NodeDescription::Current {
                    name,
                    current,
                    into,
                } => {
                    let c = b.add_current_input(name, current.clone())?;
                    for population in into {
                        let p = b.population(population).map_err(|e| described(name, e))?;
                        b.inject(c, p)?;
                    }
                }
            }
        }
        for (i, p) in d.projections.iter().enumerate() {
            let what = format!("projection {i} ('{}' → '{}')", p.pre, p.post);
            let post = b.population(&p.post).map_err(|e| described(&what, e))?;
            let connectivity = match &p.wiring {
                WiringDescription::OneToOne { weight } => {
                    Connectivity::OneToOne { weight: *weight }
                }
                WiringDescription::AllToAll { weight } => {
                    Connectivity::AllToAll { weight: *weight }
                }
                WiringDescription::Random {
                    probability,
                    weight,
                    seed,
                } => Connectivity::Random {
                    probability: *probability,
                    weight: *weight,
                    seed: *seed,
                },
                WiringDescription::Sparse { pre, post, weight } => {
                    if pre.len() != weight.len() || post.len() != weight.len() {
                        return Err(GraphError::Description(format!(
                            "{what}: {} presynaptic indices, {} postsynaptic, {} weights",
                            pre.len(),
                            post.len(),
                            weight.len()
                        )));
                    }
                    Connectivity::Sparse(
                        (0..weight.len())
                            .map(|s| Synapse {
                                pre: pre[s],
                                post: post[s],
                                weight: weight[s],
                            })
                            .collect(),
                    )
                }
            };
            let synapse = ExpSynapse::new(p.tau_s).with_delay(p.delay_steps);
            let (pre, source) = match (b.population(&p.pre), b.spike_input(&p.pre)) {
                (Ok(pre), _) => (pre.index, false),
                (_, Ok(pre)) => (pre.index, true),
                (Err(e), _) => return Err(described(&what, e)),
            };
            let brand = b.brand;
            match (source, p.plasticity) {
                (true, rule) => b.add_projection(
                    InputId { index: pre, brand },
                    post,
                    connectivity,
                    synapse,
                    rule,
                )?,
                (false, rule) => b.add_projection(
                    PopulationId { index: pre, brand },
                    post,
                    connectivity,
                    synapse,
                    rule,
                )?,
            };
        }
        Ok(b)
    }
}

/// A builder error met while reading a description, as a [`GraphError::Description`] naming
/// where.
fn described(what: &str, e: GraphError) -> GraphError {
    GraphError::Description(format!("{what}: {e}"))
}
