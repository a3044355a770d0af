//! The coding parameters of the flags `--dt`, `--duration`, `--tau` and `--cos`, shared by the
//! commands that compute a coding's distances (`distances`, `classify`).

use super::args::Time;
use neurotac_core::SpikeDataset;
use neurotac_experiments::coding::{CodingParameters, sample_duration_ms};

/// `--duration` in seconds, refused unless a whole number of milliseconds (with the value as
/// given, before the library counts it in ms).
pub fn whole_duration_s(duration: Option<Time>) -> anyhow::Result<Option<f64>> {
    let whole = duration.map(|d| d.whole_ms("--duration")).transpose()?;
    Ok(whole.map(|ms| f64::from(ms) * 1e-3))
}

/// The coding parameters of the flags `--dt`, `--duration`, `--tau` and `--cos`; the sample
/// duration only when a window is given (it is only read then).
pub fn coding_parameters(
    data: &SpikeDataset,
    dt: Option<Time>,
    duration: Option<Time>,
    tau: Option<Time>,
    cos: Option<f64>,
) -> anyhow::Result<CodingParameters> {
    let window_ms = dt.map(|dt| dt.whole_ms("--dt")).transpose()?;
    let duration_ms = match window_ms {
        Some(_) => Some(sample_duration_ms(data, whole_duration_s(duration)?)?),
        None => None,
    };
    Ok(CodingParameters {
        window_ms,
        duration_ms,
        tau_s: tau.map(Time::s),
        cos,
    })
}
