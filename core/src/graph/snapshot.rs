//! The state of a built network as data ([`NetworkState`]): where every part of it is — step,
//! models, spikes in the delay lines, sources' positions, synaptic currents, plastic traces,
//! stepping counts. Written by [`Network::save`](super::Network::save), put back by a build
//! of [`NetworkBuilder::load`](super::NetworkBuilder::load)'s builder.

use super::stepping::SteppingState;
use crate::model_state::ModelState;
use serde::{Deserialize, Serialize};

/// Where a network is: one entry per described node (populations and spike sources, in
/// order) and per described projection.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct NetworkState {
    /// Steps done.
    pub(super) step: u64,
    /// Neuron updates done.
    pub(super) neuron_updates: u64,
    pub(super) nodes: Vec<NodeState>,
    pub(super) projections: Vec<ProjectionState>,
}

/// One node's state.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct NodeState {
    /// A population's model state.
    pub(super) model: Option<ModelState>,
    /// A spike source's position.
    pub(super) position: Option<Vec<u64>>,
    /// The spikes of the latest steps, newest first (step − 1, step − 2, …).
    pub(super) history: Vec<(Vec<u32>, Vec<f64>)>,
    /// An event-driven or automatic population's stepping.
    pub(super) stepping: Option<SteppingState>,
}

/// One projection's state.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ProjectionState {
    /// The synaptic currents onto each target neuron.
    pub(super) current: Vec<f64>,
    /// A plastic projection's learning switch and traces.
    pub(super) plasticity: Option<TraceState>,
}

/// A plastic projection's learning switch and its traces' values and steps.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TraceState {
    pub(super) learning: bool,
    pub(super) pre: (Vec<f64>, Vec<u64>),
    pub(super) post: (Vec<f64>, Vec<u64>),
}
