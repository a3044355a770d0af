//! The menu of codings ([`CodingName`], one registration list, `codings!` in this file), a
//! coding with its parameters ([`Coding`]), the distance matrix of a coding
//! ([`coding_distances`]) and the sample duration the temporal coding windows
//! ([`sample_duration_ms`]). The CLI's `--coding` is [`CodingName`] itself.
//!
//! | coding | features / distance | parameters |
//! |---|---|---|
//! | intensive | mean spike count per taxel, Euclidean | — |
//! | spatial | spike count of each taxel, Euclidean | — |
//! | temporal | rolling Δt-window pooled counts in 1 ms steps over the sample, Euclidean | Δt, sample duration |
//! | spatiotemporal | multi-unit Van Rossum distance | τ, cos θ |
//!
//! Each coding is a [`CodingScheme`] in its own file — its readout in a network and offline,
//! its distances, its run through the pipeline with its parameter search, its online scorer —
//! and one line of `codings!` puts it on the menu (see CONTRIBUTING.md).

pub mod counts;
pub mod encoded;
pub mod intensive;
pub mod scheme;
pub mod spatial;
pub mod spatiotemporal;
pub mod temporal;

pub use encoded::{EncodedSet, VrFrom};
pub use scheme::{CodingParameters, CodingScheme, ReadoutContext};

use crate::error::ExperimentError;
use crate::menu::Menu;
use ndarray::Array2;
use neurotac_core::CodingError;
use neurotac_core::coding::{
    MAX_FEATURE_VALUES, check_temporal_duration_ms, duration_ms_of, whole_ms,
};
use neurotac_core::{MultiSpikeTrain, Ranks, SpikeDataset};

/// Generates [`CodingName`] from the registration list: the enum (one variant per line, in
/// menu order: the order of the paper's tables), its [`Menu`] keys (each scheme's
/// [`CodingScheme::key`]) and [`CodingName::scheme`].
macro_rules! codings {
    ($($(#[$doc:meta])* $variant:ident => $scheme:expr),+ $(,)?) => {
        /// A coding of the menu, registered with its [`CodingScheme`]. Serialised as its key
        /// (`"intensive"`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum CodingName {
            $($(#[$doc])* $variant,)+
        }

        impl CodingName {
            /// Its [`CodingScheme`].
            pub fn scheme(self) -> &'static dyn CodingScheme {
                match self {
                    $(CodingName::$variant => &$scheme,)+
                }
            }
        }

        impl Menu for CodingName {
            const WHAT: &'static str = "coding";
            const ALL: &'static [CodingName] = &[$(CodingName::$variant),+];
            fn key(self) -> &'static str {
                self.scheme().key()
            }
        }
    };
}

codings! {
    /// Mean spike count per taxel (Euclidean).
    Intensive => intensive::INTENSIVE,
    /// Spike count of each taxel (Euclidean).
    Spatial => spatial::SPATIAL,
    /// Rolling Δt-window pooled counts in 1 ms steps (Euclidean).
    Temporal => temporal::Temporal,
    /// Multi-unit Van Rossum distance at (τ, cos θ).
    Spatiotemporal => spatiotemporal::Spatiotemporal,
}

crate::menu_text!(CodingName);

impl serde::Serialize for CodingName {
    /// As its key, a unit variant (what `#[serde(rename_all = "snake_case")]` derives).
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_unit_variant("CodingName", *self as u32, self.key())
    }
}

impl CodingName {
    /// `Intensive`, `Spatial`, … ([`CodingScheme::label`]).
    pub fn label(self) -> &'static str {
        self.scheme().label()
    }
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
        self.name.scheme().describe(&self.parameters)
    }
}

/// The N × N distance matrix of `observations` under `coding` at `parameters`
/// ([`CodingScheme::distances`] of their offline readouts: Euclidean distances of the
/// features, or the exact multi-unit Van Rossum distance for the spatiotemporal coding).
///
/// Split over `ranks` (`&OneProcess` for one process): every rank computes the features (cheap), the
/// rows of the matrix are split over the ranks ([`neurotac_core::distance::euclidean_distance_matrix`],
/// [`PreparedVanRossum::matrices`](neurotac_core::distance::PreparedVanRossum::matrices))
/// and every rank returns the whole matrix, bit for bit the one-process one. Collective: every
/// rank must call it.
pub fn coding_distances(
    observations: &[MultiSpikeTrain],
    coding: CodingName,
    parameters: &CodingParameters,
    ranks: &dyn Ranks,
) -> Result<Array2<f64>, ExperimentError> {
    let needed_ms = duration_ms_of(observations)?;
    let duration_ms = parameters.duration_ms.unwrap_or(needed_ms);
    if duration_ms < needed_ms {
        return Err(ExperimentError::DurationShorterThanData {
            stated_ms: duration_ms,
            needed_ms,
        });
    }
    let context = ReadoutContext {
        n_channels: observations.first().map_or(0, |o| o.n_channels()),
        duration_ms,
        vr_from: VrFrom::Exact,
    };
    let scheme = coding.scheme();
    let set = EncodedSet {
        labels: Vec::new(),
        class_names: Vec::new(),
        duration_ms,
        n_channels: context.n_channels,
        trains: observations.to_vec(),
        readouts: vec![(scheme.key(), scheme.encode(observations, &context)?)],
        path: "offline encoders (no network)".into(),
        vr_from: VrFrom::Exact,
        neuron_updates: 0,
    };
    scheme.distances(&set, parameters, ranks)
}

/// The sample duration in whole ms that the temporal coding windows: `given_s` if given, else
/// the dataset's [`SpikeDataset::duration_s`], else one ms past the latest spike.
///
/// A stated duration (given or in the dataset) shorter than the data is an error
/// ([`ExperimentError::DurationShorterThanData`]): a spike past the end of its sample means
/// the duration or the data are wrong, and silently taking the longer one would change the
/// coding's windows without saying so. So is a duration whose per-ms counts of every sample
/// would pass the feature budget ([`MAX_FEATURE_VALUES`],
/// [`MAX_TEMPORAL_DURATION_MS`](neurotac_core::coding::MAX_TEMPORAL_DURATION_MS)).
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
    let duration_ms = match stated_ms {
        Some(stated_ms) if stated_ms < needed_ms => {
            return Err(ExperimentError::DurationShorterThanData {
                stated_ms,
                needed_ms,
            });
        }
        Some(stated_ms) => stated_ms,
        None => needed_ms,
    };
    // The temporal readout holds a count per ms of every sample.
    check_temporal_duration_ms(duration_ms)?;
    if data.len().saturating_mul(duration_ms as usize) > MAX_FEATURE_VALUES {
        return Err(CodingError::TooManyFeatures {
            samples: data.len(),
            features: duration_ms as usize,
            limit: MAX_FEATURE_VALUES,
        }
        .into());
    }
    Ok(duration_ms)
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
