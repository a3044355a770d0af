//! The checks of a network built over several ranks
//! ([`NetworkBuilder::build_partitioned`]): a population cut to a rank's block, and the readouts
//! that need state only one rank holds.

use super::builder::{NetworkBuilder, NodeKind};
use super::ids::ReadoutSource;
use crate::error::GraphError;
use crate::model::NeuronModel;
use std::ops::Range;

impl NetworkBuilder {
    /// `model` cut to `block` (see [`NeuronModel::restrict`]).
    pub(super) fn restricted(
        model: Box<dyn NeuronModel>,
        block: Range<usize>,
        name: &str,
    ) -> Result<Box<dyn NeuronModel>, GraphError> {
        let not_partitionable = || GraphError::ModelNotPartitionable {
            population: name.to_owned(),
            model: model.model_name(),
        };
        let part = model
            .restrict(block.clone())
            .ok_or_else(not_partitionable)?;
        if part.len() != block.len() {
            return Err(GraphError::SizeMismatch {
                what: format!("population '{name}' restricted to neurons {block:?}"),
                expected: block.len(),
                got: part.len(),
            });
        }
        Ok(part)
    }

    /// Refuses the readouts that need state only one rank holds (see
    /// [`build_partitioned`](Self::build_partitioned)).
    pub(super) fn check_partitionable_readouts(&self, size: usize) -> Result<(), GraphError> {
        for (source, r) in &self.readouts {
            let (node, reason) = match *source {
                ReadoutSource::Projection(p) => {
                    let p = &self.projections[p.index];
                    (
                        format!(
                            "projection '{}' → '{}'",
                            self.nodes[p.pre].name, self.nodes[p.post].name
                        ),
                        "it reads synaptic currents, which each rank holds only for its own neurons",
                    )
                }
                ReadoutSource::Node(n) => {
                    let n = &self.nodes[n.index];
                    if !(matches!(n.kind, NodeKind::Population(_)) && r.reads_population_state()) {
                        continue;
                    }
                    (
                        format!("population '{}'", n.name),
                        "it reads the population's state, which each rank holds only for its own neurons",
                    )
                }
            };
            return Err(GraphError::ReadoutNotPartitionable {
                node,
                ranks: size,
                reason,
            });
        }
        Ok(())
    }
}
