//! Identifiers of nodes, projections and readouts, and the build-time settings of a network.

use std::marker::PhantomData;

/// Identifies a node of one [`NetworkBuilder`](super::NetworkBuilder) (and of the network built from it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeId(pub(super) usize);

/// Identifies a projection of one [`NetworkBuilder`](super::NetworkBuilder).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ProjectionId(pub(super) usize);

/// Identifies a readout of type `T`; [`Network::readout`](super::Network::readout) returns it typed.
#[derive(Debug)]
pub struct ReadoutId<T> {
    pub(super) index: usize,
    pub(super) _type: PhantomData<fn() -> T>,
}

impl<T> Clone for ReadoutId<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for ReadoutId<T> {}

/// What a readout watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadoutSource {
    /// A population or spike source.
    Node(NodeId),
    /// A projection (its synaptic currents).
    Projection(ProjectionId),
}

/// Simulation settings fixed at build time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetworkConfig {
    /// Time step in seconds (> 0). Default 10⁻⁴ s (0.1 ms).
    pub dt_s: f64,
}

impl Default for NetworkConfig {
    fn default() -> Self {
        Self { dt_s: 1e-4 }
    }
}
