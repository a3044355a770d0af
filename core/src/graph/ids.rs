//! Identifiers of nodes, projections and readouts, and the build-time settings of a network.
//!
//! Every id carries the *brand* of the [`NetworkBuilder`](super::NetworkBuilder) that handed it
//! out: a number drawn once per builder from a process-wide counter, kept by the
//! [`Network`](super::Network) it builds. A builder or network refuses an id of another brand
//! with a [`GraphError::ForeignId`] (never wiring, or reading, whatever has the same index
//! there).

use crate::error::GraphError;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicU64, Ordering};

/// The next brand a new builder takes (0 is never handed out).
static NEXT_BRAND: AtomicU64 = AtomicU64::new(1);

/// A brand no builder has taken before, for a new builder.
pub(super) fn fresh_brand() -> u64 {
    NEXT_BRAND.fetch_add(1, Ordering::Relaxed)
}

/// `id`'s index when it carries `brand` (the builder's, or the network's); else a
/// [`GraphError::ForeignId`] naming the id's kind and both brands.
pub(super) fn checked_index(id: impl Branded, brand: u64) -> Result<usize, GraphError> {
    if id.brand() == brand {
        Ok(id.index())
    } else {
        Err(GraphError::ForeignId {
            kind: id.kind(),
            id_brand: id.brand(),
            builder_brand: brand,
        })
    }
}

/// Identifies any node of one [`NetworkBuilder`](super::NetworkBuilder) (and of the network
/// built from it). The builder hands out typed ids — [`PopulationId`], [`InputId`],
/// [`CurrentId`] — so that a connection of the wrong roles does not compile; each converts into
/// a `NodeId` where any node will do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeId {
    pub(super) index: usize,
    pub(super) brand: u64,
}

/// A population of neurons ([`NetworkBuilder::add_population`](super::NetworkBuilder::add_population)):
/// a projection's target, a spike emitter, state-recordable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PopulationId {
    pub(super) index: usize,
    pub(super) brand: u64,
}

/// A spike source ([`NetworkBuilder::add_spike_input`](super::NetworkBuilder::add_spike_input)):
/// a spike emitter, replaceable between runs
/// ([`Network::replace_spike_input`](super::Network::replace_spike_input)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InputId {
    pub(super) index: usize,
    pub(super) brand: u64,
}

/// A current source ([`NetworkBuilder::add_current_input`](super::NetworkBuilder::add_current_input)):
/// injected into populations, never connected through synapses or read out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CurrentId {
    pub(super) index: usize,
    pub(super) brand: u64,
}

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
/// (An id of one builder used with another builder, or with the network built from another, is
/// refused when used: a [`GraphError::ForeignId`].)
pub trait SpikingNode: Copy + Into<NodeId> + Branded + sealed::Sealed {}
impl SpikingNode for PopulationId {}
impl SpikingNode for InputId {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::PopulationId {}
    impl Sealed for super::InputId {}
}

pub(super) use branded::Branded;

mod branded {
    /// An id that carries the brand of the builder that handed it out (every id type).
    pub trait Branded: Copy {
        /// What the id names, for a [`GraphError::ForeignId`](crate::GraphError::ForeignId).
        fn kind(&self) -> &'static str;
        /// The brand of the builder that handed it out.
        fn brand(&self) -> u64;
        /// Its index among that builder's items of its kind.
        fn index(&self) -> usize;
    }
}

macro_rules! branded {
    ($($id:ty => $kind:literal),* $(,)?) => {$(
        impl Branded for $id {
            fn kind(&self) -> &'static str {
                $kind
            }
            fn brand(&self) -> u64 {
                self.brand
            }
            fn index(&self) -> usize {
                self.index
            }
        }
    )*};
}
branded!(
    NodeId => "node",
    PopulationId => "population",
    InputId => "spike input",
    CurrentId => "current input",
    ProjectionId => "projection",
);

impl<T> Branded for ReadoutId<T> {
    fn kind(&self) -> &'static str {
        "readout"
    }
    fn brand(&self) -> u64 {
        self.brand
    }
    fn index(&self) -> usize {
        self.index
    }
}

macro_rules! into_node {
    ($($id:ty),*) => {$(
        impl From<$id> for NodeId {
            fn from(id: $id) -> Self {
                NodeId {
                    index: id.index,
                    brand: id.brand,
                }
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
pub struct ProjectionId {
    pub(super) index: usize,
    pub(super) brand: u64,
}

/// Identifies a readout of type `T`; [`Network::readout`](super::Network::readout) returns it typed.
#[derive(Debug)]
pub struct ReadoutId<T> {
    pub(super) index: usize,
    pub(super) brand: u64,
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
