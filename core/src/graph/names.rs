//! Finding a builder's nodes and projections by name ([`NetworkBuilder::population`],
//! [`NetworkBuilder::spike_input`], [`NetworkBuilder::projections`],
//! [`NetworkBuilder::projection_ends`], [`NetworkBuilder::node_names`],
//! [`NetworkBuilder::node_size`]): how code that did not build a network (a loaded one, one
//! read from a description) reaches its parts.

use super::builder::NetworkBuilder;
use super::ids::{InputId, PopulationId, ProjectionId};
use crate::error::GraphError;

impl NetworkBuilder {
    /// The node named `name` and whether it is a population, a spike source or a current
    /// source ([`GraphError::UnknownName`] when there is none).
    fn named(&self, name: &str) -> Result<(usize, &'static str), GraphError> {
        self.nodes
            .iter()
            .position(|n| n.name == name)
            .map(|i| (i, self.nodes[i].kind.describe()))
            .ok_or_else(|| GraphError::UnknownName(name.to_owned()))
    }

    /// The population named `name` (e.g. in a loaded network: [`load`](Self::load)).
    pub fn population(&self, name: &str) -> Result<PopulationId, GraphError> {
        match self.named(name)? {
            (index, "population") => Ok(PopulationId {
                index,
                brand: self.brand,
            }),
            (index, _) => Err(Self::wrong_role(&self.nodes[index], "used as a population")),
        }
    }

    /// The spike source named `name`.
    pub fn spike_input(&self, name: &str) -> Result<InputId, GraphError> {
        match self.named(name)? {
            (index, "spike source") => Ok(InputId {
                index,
                brand: self.brand,
            }),
            (index, _) => Err(Self::wrong_role(
                &self.nodes[index],
                "used as a spike source",
            )),
        }
    }

    /// The names of the nodes, in the order they were added (a loaded network's: in the order
    /// of its description), e.g. to find every population and spike source of a loaded
    /// network with [`population`](Self::population) and [`spike_input`](Self::spike_input).
    pub fn node_names(&self) -> Vec<&str> {
        self.nodes.iter().map(|n| n.name.as_str()).collect()
    }

    /// The number of neurons (or channels) of the node named `name`.
    pub fn node_size(&self, name: &str) -> Result<usize, GraphError> {
        let (index, _) = self.named(name)?;
        Ok(self.nodes[index].size)
    }

    /// The presynaptic and postsynaptic node names of every projection, in the order of
    /// [`projections`](Self::projections).
    pub fn projection_ends(&self) -> Vec<(&str, &str)> {
        (self.projections.iter())
            .map(|p| {
                (
                    self.nodes[p.pre].name.as_str(),
                    self.nodes[p.post].name.as_str(),
                )
            })
            .collect()
    }

    /// Every projection, in the order they were connected (a loaded network's: in the order
    /// of its description).
    pub fn projections(&self) -> Vec<ProjectionId> {
        (0..self.projections.len())
            .map(|index| ProjectionId {
                index,
                brand: self.brand,
            })
            .collect()
    }
}
