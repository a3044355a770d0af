//! The run-time records of a built network's nodes, shared by the builder that makes them, the
//! run loop ([`Network`](super::Network)) and the spike exchange between ranks: a kept node
//! ([`RunningNode`]: its model or spike source, spike history ring and input buffer), the
//! stepping of a population that can be stepped event-driven (`EventStepping`) and a
//! readout's source by run-time index ([`RunningSource`]).

use super::input::SpikeSource;
use super::stepping::EventStepping;
use crate::model::{NeuronModel, SpikeBuffer};
use std::ops::Range;

/// A kept node's model: a spike source or a population.
pub(super) enum RunningKind {
    Spikes(Box<dyn SpikeSource>),
    Population(Box<dyn NeuronModel>),
}

/// A node kept at build, as the network runs it.
pub(super) struct RunningNode {
    pub(super) name: String,
    /// Neurons (channels) of the whole node.
    pub(super) size: usize,
    /// The neurons this rank computes (`0..size` in one process; spike sources always whole).
    pub(super) local: Range<usize>,
    pub(super) kind: RunningKind,
    /// Ring of this node's spikes, one buffer per step, long enough for its largest delay.
    pub(super) history: Vec<SpikeBuffer>,
    /// Summed input current of the local neurons (populations).
    pub(super) input: Vec<f64>,
    /// Projections targeting this node.
    pub(super) incoming: Vec<usize>,
    /// Current sources injected into this node.
    pub(super) currents: Vec<usize>,
    /// Populations that can be stepped event-driven: their mode, active neurons and activity
    /// (see [`NetworkBuilder::stepping`](super::NetworkBuilder::stepping)).
    pub(super) active: Option<EventStepping>,
}

/// What a readout watches, by run-time index: a node or a projection.
pub(super) enum RunningSource {
    Node(usize),
    Projection(usize),
}
