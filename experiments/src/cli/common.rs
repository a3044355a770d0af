//! Helpers shared by the commands: loading a dataset, the sample duration, codings and their
//! distance matrices, and CPU/wall timing (re-exported from the library's `bench`).

use anyhow::{Context, bail};
use clap::ValueEnum;
use ndarray::Array2;
use neurotac_core::SpikeDataset;
use neurotac_core::coding::{
    IntensiveCoding, SpatialCoding, TemporalCoding, duration_ms_of, feature_matrix, whole_ms,
};
use neurotac_core::distance::{VanRossum, euclidean_distance_matrix};
use std::path::Path;

pub use neurotac_experiments::timing::timed;

/// The paper's four codings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CodingArg {
    /// Mean spike count per taxel (Euclidean).
    Intensive,
    /// Spike count per taxel (Euclidean).
    Spatial,
    /// Rolling Δt-window pooled counts in 1 ms steps (Euclidean).
    Temporal,
    /// Multi-unit Van Rossum distance (τ, cos θ).
    Spatiotemporal,
}

pub fn load(path: &Path) -> anyhow::Result<SpikeDataset> {
    // The dataset error names file, sample and field; its source chain would repeat it.
    SpikeDataset::load(path)
        .map_err(|e| anyhow::anyhow!("reading the spike dataset {}: {e}", path.display()))
}

/// The sample duration in whole ms: `--duration` if given, else `meta.duration_s`, else one bin
/// past the latest spike. Errors when spikes lie beyond it or before 0.
pub fn duration_ms(data: &SpikeDataset, duration_s: Option<f64>) -> anyhow::Result<u32> {
    let needed = duration_ms_of(data.observations())?;
    let given = match duration_s {
        Some(d) => Some(whole_ms(d, "--duration")?),
        None => match data.meta().get("duration_s").and_then(|v| v.as_f64()) {
            Some(d) => Some(whole_ms(d, "meta.duration_s")?),
            None => None,
        },
    };
    match given {
        Some(ms) if ms < needed => bail!(
            "sample duration {} ms is shorter than the data, whose latest spike needs {} ms",
            ms,
            needed
        ),
        Some(ms) => Ok(ms),
        None => Ok(needed),
    }
}

/// Euclidean distances of a feature coding.
pub fn feature_distances(
    data: &SpikeDataset,
    coding: CodingArg,
    dt_s: Option<f64>,
    duration_s: Option<f64>,
) -> anyhow::Result<Array2<f64>> {
    let obs = data.observations();
    let features = match coding {
        CodingArg::Intensive => feature_matrix(&IntensiveCoding::new(), obs)?,
        CodingArg::Spatial => feature_matrix(&SpatialCoding::new(), obs)?,
        CodingArg::Temporal => {
            let dt = dt_s.context("the temporal coding needs --dt SECONDS (the window Δt)")?;
            let coding =
                TemporalCoding::from_ms(whole_ms(dt, "--dt")?, duration_ms(data, duration_s)?)?;
            feature_matrix(&coding, obs)?
        }
        CodingArg::Spatiotemporal => {
            bail!("the spatiotemporal coding uses the Van Rossum distance")
        }
    };
    Ok(euclidean_distance_matrix(features.view())?)
}

/// Van Rossum distances at (τ, cos θ).
pub fn van_rossum_distances(
    data: &SpikeDataset,
    tau_s: Option<f64>,
    cos: Option<f64>,
) -> anyhow::Result<Array2<f64>> {
    let tau = tau_s.context("the Van Rossum distance needs --tau SECONDS")?;
    let cos = cos.context("the Van Rossum distance needs --cos C (cos θ in [0, 1])")?;
    neurotac_core::distance::check_cos(cos)?;
    Ok(VanRossum::new(tau)?
        .matrices(data.observations())?
        .distances(cos)?)
}

/// Mean spikes per channel over the dataset.
pub fn mean_spikes_per_unit(data: &SpikeDataset) -> f64 {
    let spikes: usize = data.observations().iter().map(|o| o.total_spikes()).sum();
    let units = data.len() * data.n_channels();
    if units == 0 {
        0.0
    } else {
        spikes as f64 / units as f64
    }
}
