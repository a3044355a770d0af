//! Identifiers of nodes, projections and readouts, and the build-time settings of a network.

use std::marker::PhantomData;

/// Identifies any node of one [`NetworkBuilder`](super::NetworkBuilder) (and of the network
/// built from it). The builder hands out typed ids — [`PopulationId`], [`InputId`],
/// [`CurrentId`] — so that a connection of the wrong roles does not compile; each converts into
/// a `NodeId` where any node will do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeId(pub(super) usize);

/// A population of neurons ([`NetworkBuilder::add_population`](super::NetworkBuilder::add_population)):
/// a projection's target, a spike emitter, state-recordable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PopulationId(pub(super) usize);

/// A spike source ([`NetworkBuilder::add_spike_input`](super::NetworkBuilder::add_spike_input)):
/// a spike emitter, replaceable between runs
/// ([`Network::replace_spike_input`](super::Network::replace_spike_input)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InputId(pub(super) usize);

/// A current source ([`NetworkBuilder::add_current_input`](super::NetworkBuilder::add_current_input)):
/// injected into populations, never connected through synapses or read out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CurrentId(pub(super) usize);

/// A node that emits spikes: the presynaptic side of a projection, or a spike readout's source.
/// Implemented by [`PopulationId`] and [`InputId`] only (sealed), so a wrong role does not
/// compile:
///
/// ```compile_fail
/// use neurotac_core::{CurrentInput, NetworkBuilder};
/// let mut b = NetworkBuilder::new();
/// let bias = b.add_current_input("bias", CurrentInput::constant(1.0)).unwrap();
/// b.record_spikes(bias); // a current emits no spikes
/// ```
///
/// ```compile_fail
/// use neurotac_core::{Connectivity, ExpSynapse, MultiSpikeTrain, NetworkBuilder, SpikeArrayInput};
/// let mut b = NetworkBuilder::new();
/// let a = b.add_spike_input("a", SpikeArrayInput::new(MultiSpikeTrain::empty(1))).unwrap();
/// let c = b.add_spike_input("c", SpikeArrayInput::new(MultiSpikeTrain::empty(1))).unwrap();
/// // A projection's target must be a population.
/// b.connect(a, c, Connectivity::OneToOne { weight: 1.0 }, ExpSynapse::new(5e-3));
/// ```
///
/// (Ids of one builder used with another are still checked when used: a role or index that
/// does not match is a [`GraphError`](crate::GraphError).)
pub trait SpikingNode: Copy + Into<NodeId> + sealed::Sealed {}
impl SpikingNode for PopulationId {}
impl SpikingNode for InputId {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::PopulationId {}
    impl Sealed for super::InputId {}
}

macro_rules! into_node {
    ($($id:ty),*) => {$(
        impl From<$id> for NodeId {
            fn from(id: $id) -> Self {
                NodeId(id.0)
            }
        }
    )*};
}
into_node!(PopulationId, InputId, CurrentId);

impl From<PopulationId> for ReadoutSource {
    fn from(id: PopulationId) -> Self {
        ReadoutSource::Node(id.into())
    }
}

impl From<InputId> for ReadoutSource {
    fn from(id: InputId) -> Self {
        ReadoutSource::Node(id.into())
    }
}

impl From<ProjectionId> for ReadoutSource {
    fn from(id: ProjectionId) -> Self {
        ReadoutSource::Projection(id)
    }
}

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
