//! The trace-sampled multi-unit Van Rossum distance: traces advanced at the network step `dt`
//! by the graph's synapse filter and compared sample by sample (see
//! [`SpatiotemporalCoding`](crate::coding::SpatiotemporalCoding) for the features and why they
//! are exact for spikes on the step grid). It trades accuracy for nothing here — the exact
//! distance is faster — but it is what a network that only sees traces can compute, and
//! `neurotac tradeoff vr` measures its error against [`super::van_rossum`] as `dt` shrinks.

use super::euclidean::squared_euclidean_matrix;
use super::van_rossum::VanRossumMatrices;
use crate::coding::trace_features_of_dataset;
use crate::error::DistanceError;
use crate::spikes::MultiSpikeTrain;

/// `LL²` and `SP²` of every pair from traces sampled at `dt_s` over `[0, duration_s)` (plus
/// the exact tail after it). Combine with [`VanRossumMatrices::squared`] as for the exact ones.
pub fn trace_sampled_matrices(
    observations: &[MultiSpikeTrain],
    tau_s: f64,
    dt_s: f64,
    duration_s: f64,
) -> Result<VanRossumMatrices, DistanceError> {
    let (channels, pooled) = trace_features_of_dataset(observations, tau_s, dt_s, duration_s)?;
    Ok(VanRossumMatrices {
        tau_s,
        ll2: squared_euclidean_matrix(channels.view())?,
        sp2: squared_euclidean_matrix(pooled.view())?,
    })
}
