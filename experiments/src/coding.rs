//! The paper's four codings by name ([`CodingName`]), the distance matrix of a coding
//! ([`coding_distances`], or [`coding_distances`] split over ranks) and the sample duration
//! the temporal coding windows ([`sample_duration_ms`]). The CLI's `--coding` is
//! [`CodingName`] itself.
//!
//! | coding | features / distance | parameters |
//! |---|---|---|
//! | intensive | mean spike count per taxel, Euclidean | — |
//! | spatial | spike count of each taxel, Euclidean | — |
//! | temporal | rolling Δt-window pooled counts in 1 ms steps over the sample, Euclidean | Δt, sample duration |
//! | spatiotemporal | multi-unit Van Rossum distance | τ, cos θ |

use crate::error::ExperimentError;
use crate::menu::Menu;
use ndarray::Array2;
use neurotac_core::coding::{
    IntensiveCoding, SpatialCoding, TemporalCoding, duration_ms_of, feature_matrix, whole_ms,
};
use neurotac_core::distance::{VanRossum, check_cos, euclidean_distance_matrix};
use neurotac_core::{MultiSpikeTrain, Ranks, SpikeDataset};
use serde::Serialize;

/// The paper's four codings, in its order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CodingName {
    /// Mean spike count per taxel (Euclidean).
    Intensive,
    /// Spike count of each taxel (Euclidean).
    Spatial,
    /// Rolling Δt-window pooled counts in 1 ms steps (Euclidean).
    Temporal,
    /// Multi-unit Van Rossum distance at (τ, cos θ).
    Spatiotemporal,
}

impl Menu for CodingName {
    const WHAT: &'static str = "coding";
    /// All four, in the paper's order (the order of its tables).
    const ALL: &'static [CodingName] = &[
        CodingName::Intensive,
        CodingName::Spatial,
        CodingName::Temporal,
        CodingName::Spatiotemporal,
    ];

    /// `intensive`, `spatial`, … (file names, CLI values).
    fn key(self) -> &'static str {
        match self {
            CodingName::Intensive => "intensive",
            CodingName::Spatial => "spatial",
            CodingName::Temporal => "temporal",
            CodingName::Spatiotemporal => "spatiotemporal",
        }
    }
}
crate::menu_text!(CodingName);

impl CodingName {
    /// `Intensive`, `Spatial`, …
    pub fn label(self) -> &'static str {
        match self {
            CodingName::Intensive => "Intensive",
            CodingName::Spatial => "Spatial",
            CodingName::Temporal => "Temporal",
            CodingName::Spatiotemporal => "Spatiotemporal",
        }
    }
}

/// The parameters of a coding; each coding reads only its own (see the module table).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CodingParameters {
    /// Temporal: the window Δt (ms).
    pub window_ms: Option<u32>,
    /// Temporal: the sample duration (ms), e.g. from [`sample_duration_ms`].
    pub duration_ms: Option<u32>,
    /// Spatiotemporal: the Van Rossum kernel time constant τ (s).
    pub tau_s: Option<f64>,
    /// Spatiotemporal: cos θ in [0, 1].
    pub cos: Option<f64>,
}

/// A coding with its parameters: what a classifier needs to encode a sample (the online
/// recogniser's `--coding`, one per evaluated timeline).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coding {
    /// Which coding.
    pub name: CodingName,
    /// Its parameters (each coding reads only its own).
    pub parameters: CodingParameters,
}

impl Coding {
    /// The intensive or spatial coding, or any coding whose parameters are set later.
    pub fn of(name: CodingName) -> Self {
        Self {
            name,
            parameters: CodingParameters::default(),
        }
    }

    /// The temporal coding with window Δt = `window_ms`.
    pub fn temporal(window_ms: u32) -> Self {
        Self {
            name: CodingName::Temporal,
            parameters: CodingParameters {
                window_ms: Some(window_ms),
                ..CodingParameters::default()
            },
        }
    }

    /// The spatiotemporal coding at kernel `tau_s` and `cos` θ.
    pub fn spatiotemporal(tau_s: f64, cos: f64) -> Self {
        Self {
            name: CodingName::Spatiotemporal,
            parameters: CodingParameters {
                tau_s: Some(tau_s),
                cos: Some(cos),
                ..CodingParameters::default()
            },
        }
    }

    /// Its parameters as a report prints them (`Δt = 159 ms`, `τ = 76 ms, cos θ = 0.40`;
    /// empty for the intensive and spatial codings).
    pub fn describe_parameters(&self) -> String {
        let p = &self.parameters;
        match self.name {
            CodingName::Intensive | CodingName::Spatial => String::new(),
            CodingName::Temporal => p
                .window_ms
                .map_or_else(String::new, |w| format!("Δt = {w} ms")),
            CodingName::Spatiotemporal => match (p.tau_s, p.cos) {
                (Some(tau_s), Some(cos)) => format!("τ = {:.0} ms, cos θ = {cos:.2}", tau_s * 1e3),
                _ => String::new(),
            },
        }
    }

    /// The temporal window Δt (ms), or the error naming it as missing.
    pub fn window_ms(&self) -> Result<u32, ExperimentError> {
        self.parameters
            .window_ms
            .ok_or_else(|| missing(self.name, "the window Δt (--dt SECONDS)"))
    }

    /// The Van Rossum `(τ, cos θ)`, or the error naming the one missing.
    pub fn tau_and_cos(&self) -> Result<(f64, f64), ExperimentError> {
        let tau_s = self
            .parameters
            .tau_s
            .ok_or_else(|| missing(self.name, "the Van Rossum τ (--tau SECONDS)"))?;
        let cos = self
            .parameters
            .cos
            .ok_or_else(|| missing(self.name, "cos θ in [0, 1] (--cos C)"))?;
        Ok((tau_s, cos))
    }
}

fn missing(coding: CodingName, what: &'static str) -> ExperimentError {
    ExperimentError::MissingParameter {
        coding: coding.key(),
        what,
    }
}

/// The N × N distance matrix of `observations` under `coding`: Euclidean distances of its
/// features, or the exact multi-unit Van Rossum distance for the spatiotemporal coding.
///
/// Split over `ranks` (`&OneProcess` for one process): every rank computes the features (cheap), the
/// rows of the matrix are split over the ranks ([`euclidean_distance_matrix`],
/// [`PreparedVanRossum::matrices`](neurotac_core::distance::PreparedVanRossum::matrices))
/// and every rank returns the whole matrix, bit for bit the one-process one. Collective: every
/// rank must call it.
pub fn coding_distances(
    observations: &[MultiSpikeTrain],
    coding: CodingName,
    parameters: &CodingParameters,
    ranks: &dyn Ranks,
) -> Result<Array2<f64>, ExperimentError> {
    let configured = Coding {
        name: coding,
        parameters: *parameters,
    };
    let features = match coding {
        CodingName::Intensive => feature_matrix(&IntensiveCoding::new(), observations)?,
        CodingName::Spatial => feature_matrix(&SpatialCoding::new(), observations)?,
        CodingName::Temporal => {
            let window_ms = configured.window_ms()?;
            let duration_ms = parameters
                .duration_ms
                .ok_or_else(|| missing(coding, "the sample duration"))?;
            feature_matrix(
                &TemporalCoding::from_ms(window_ms, duration_ms)?,
                observations,
            )?
        }
        CodingName::Spatiotemporal => {
            let (tau_s, cos) = configured.tau_and_cos()?;
            check_cos(cos)?;
            return Ok(VanRossum::new(tau_s)?
                .matrices(observations, ranks)?
                .distances(cos)?);
        }
    };
    Ok(euclidean_distance_matrix(features.view(), ranks)?)
}

/// The sample duration in whole ms that the temporal coding windows: `given_s` if given, else
/// the dataset's [`SpikeDataset::duration_s`], else one ms past the latest spike.
///
/// A stated duration (given or in the dataset) shorter than the data is an error
/// ([`ExperimentError::DurationShorterThanData`]): a spike past the end of its sample means
/// the duration or the data are wrong, and silently taking the longer one would change the
/// coding's windows without saying so.
pub fn sample_duration_ms(
    data: &SpikeDataset,
    given_s: Option<f64>,
) -> Result<u32, ExperimentError> {
    let needed_ms = duration_ms_of(data.observations())?;
    let stated_ms = match (given_s, data.duration_s()) {
        (Some(d), _) => Some(whole_ms(d, "--duration")?),
        (None, Some(d)) => Some(whole_ms(d, "meta.duration_s")?),
        (None, None) => None,
    };
    match stated_ms {
        Some(stated_ms) if stated_ms < needed_ms => Err(ExperimentError::DurationShorterThanData {
            stated_ms,
            needed_ms,
        }),
        Some(stated_ms) => Ok(stated_ms),
        None => Ok(needed_ms),
    }
}

/// Mean spikes per channel over every sample of `data` (0 without samples).
pub fn mean_spikes_per_channel(data: &SpikeDataset) -> f64 {
    let spikes: usize = data.observations().iter().map(|o| o.total_spikes()).sum();
    spikes as f64 / (data.len() * data.n_channels()).max(1) as f64
}

/// Samples per class and the mean of the intensive coding (spikes per channel) over each
/// class's samples (index = label; 0 for a class without samples).
pub fn class_means(data: &SpikeDataset) -> (Vec<usize>, Vec<f64>) {
    let intensive = data
        .observations()
        .iter()
        .map(|o| o.total_spikes() as f64 / o.n_channels().max(1) as f64);
    class_means_of(intensive, data.labels(), data.n_classes())
}

/// Samples per class and the mean of `values` (one per sample, labelled `labels`) over each of
/// `n_classes` classes (0 for a class without samples).
pub fn class_means_of(
    values: impl IntoIterator<Item = f64>,
    labels: &[usize],
    n_classes: usize,
) -> (Vec<usize>, Vec<f64>) {
    let mut samples_per_class = vec![0usize; n_classes];
    let mut means = vec![0.0; n_classes];
    for (value, &l) in values.into_iter().zip(labels) {
        samples_per_class[l] += 1;
        means[l] += value;
    }
    for (m, &n) in means.iter_mut().zip(&samples_per_class) {
        *m /= n.max(1) as f64;
    }
    (samples_per_class, means)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_samples(duration_s: Option<f64>) -> SpikeDataset {
        let a = MultiSpikeTrain::from_channels(vec![vec![0.010, 0.0205], vec![]]).unwrap();
        let b = MultiSpikeTrain::from_channels(vec![vec![0.001], vec![0.004, 0.0309]]).unwrap();
        let mut d = SpikeDataset::new(
            vec![a, b],
            vec![0, 1],
            vec!["a".into(), "b".into()],
            Default::default(),
        )
        .unwrap();
        if let Some(s) = duration_s {
            d.set_duration_s(s).unwrap();
        }
        d
    }

    #[test]
    fn duration_is_given_else_stated_else_one_ms_past_the_latest_spike() {
        // Latest spike 30.9 ms → bin 30 → 31 ms.
        assert_eq!(sample_duration_ms(&two_samples(None), None).unwrap(), 31);
        assert_eq!(
            sample_duration_ms(&two_samples(Some(0.05)), None).unwrap(),
            50
        );
        assert_eq!(
            sample_duration_ms(&two_samples(Some(0.05)), Some(0.04)).unwrap(),
            40
        );
    }

    #[test]
    fn a_duration_shorter_than_the_data_is_an_error_whoever_states_it() {
        for (stated, given) in [(None, Some(0.02)), (Some(0.02), None)] {
            let e = sample_duration_ms(&two_samples(stated), given).unwrap_err();
            assert!(
                matches!(
                    e,
                    ExperimentError::DurationShorterThanData {
                        stated_ms: 20,
                        needed_ms: 31
                    }
                ),
                "{e}"
            );
        }
        assert!(sample_duration_ms(&two_samples(None), Some(0.0305)).is_err());
    }

    #[test]
    fn distances_follow_the_coding_and_name_a_missing_parameter() {
        let d = two_samples(None);
        let obs = d.observations();
        // Intensive: mean counts 1.0 and 1.5 → distance 0.5.
        let m = coding_distances(
            obs,
            CodingName::Intensive,
            &Default::default(),
            &neurotac_core::OneProcess,
        )
        .unwrap();
        assert_eq!(m[[0, 1]], 0.5);
        // Spatial: counts (2, 0) vs (1, 2) → √5.
        let m = coding_distances(
            obs,
            CodingName::Spatial,
            &Default::default(),
            &neurotac_core::OneProcess,
        )
        .unwrap();
        assert!((m[[1, 0]] - 5f64.sqrt()).abs() < 1e-12);
        let e = coding_distances(
            obs,
            CodingName::Temporal,
            &Default::default(),
            &neurotac_core::OneProcess,
        )
        .unwrap_err();
        assert!(e.to_string().contains("--dt"), "{e}");
        let p = CodingParameters {
            window_ms: Some(10),
            duration_ms: Some(31),
            tau_s: Some(0.01),
            cos: Some(0.5),
        };
        let m =
            coding_distances(obs, CodingName::Temporal, &p, &neurotac_core::OneProcess).unwrap();
        assert!(m[[0, 1]] > 0.0 && m[[0, 0]] == 0.0);
        let m = coding_distances(
            obs,
            CodingName::Spatiotemporal,
            &p,
            &neurotac_core::OneProcess,
        )
        .unwrap();
        assert!(m[[0, 1]] > 0.0 && (m[[0, 1]] - m[[1, 0]]).abs() < 1e-12);
        let no_cos = CodingParameters { cos: None, ..p };
        let e = coding_distances(
            obs,
            CodingName::Spatiotemporal,
            &no_cos,
            &neurotac_core::OneProcess,
        )
        .unwrap_err();
        assert!(e.to_string().contains("cos θ"), "{e}");
    }

    #[test]
    fn means_count_every_sample_and_every_class() {
        let d = two_samples(None);
        assert_eq!(mean_spikes_per_channel(&d), 1.25);
        assert_eq!(class_means(&d), (vec![1, 1], vec![1.0, 1.5]));
    }
}
