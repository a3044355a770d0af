//! The coding parameters of the flags `--dt`, `--duration`, `--tau` and `--cos`, shared by the
//! commands that compute a coding's distances (`distances`, `classify`).

use super::args::Time;
use neurotac_core::SpikeDataset;
use neurotac_core::coding::whole_ms;
use neurotac_experiments::coding::{CodingParameters, sample_duration_ms};

/// The coding parameters of the flags `--dt`, `--duration`, `--tau` and `--cos`; the sample
/// duration only when a window is given (it is only read then).
pub fn coding_parameters(
    data: &SpikeDataset,
    dt: Option<Time>,
    duration: Option<Time>,
    tau: Option<Time>,
    cos: Option<f64>,
) -> anyhow::Result<CodingParameters> {
    let window_ms = dt.map(|dt| whole_ms(dt.s(), "--dt")).transpose()?;
    let duration_ms = match window_ms {
        Some(_) => Some(sample_duration_ms(data, duration.map(Time::s))?),
        None => None,
    };
    Ok(CodingParameters {
        window_ms,
        duration_ms,
        tau_s: tau.map(Time::s),
        cos,
    })
}
