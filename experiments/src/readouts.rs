//! The main job through the framework's graph: every sample runs through one network, built
//! once per worker and reused ([`Network::replace_spike_input`] + [`Network::reset`]), whose
//! readouts are the paper's four codings; the pipeline ([`crate::reproduce`]) classifies what
//! the readouts hold ([`EncodedSet`]).
//!
//! ```text
//! taxel spike input ─┬───────────────────────────────┬─ IntensiveCoding    → mean count per taxel
//!   (one sample at   │  (with afferents:             ├─ SpatialCoding      → count per taxel
//!    a time)         └─ exp. synapses → afferents) ──┼─ TemporalCoding     → pooled count per 1-ms bin (every Δt)
//!                                                    └─ SpatiotemporalCoding → trains (exact Van Rossum)
//!                                                                             + trace record (trace Van Rossum)
//! ```
//!
//! [`encode_offline`] computes the same [`EncodedSet`] with the codings' direct encoders (no
//! network); the two are identical (tested), which is what lets `reproduce` report either.

use crate::afferents::{AfferentConfig, afferent_population};
use crate::coding::sample_duration_ms;
use crate::error::ExperimentError;
use crate::neuron_setup::Precision;
use crate::search::bayes::VanRossumInput;
use ndarray::Array2;
use neurotac_core::coding::{
    FeatureCoding, IntensiveCoding, SpatialCoding, SpatiotemporalCoding, TemporalCoding,
    TraceRecord, duration_ms_of, feature_matrix, pooled_bin_counts,
};
use neurotac_core::{
    CodingError, InputId, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig, ReadoutId,
    ReadoutSource, SpikeArrayInput, SpikeDataset,
};
use rayon::prelude::*;

/// Where the spatiotemporal coding's Van Rossum distance comes from (`--vr-from`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VrFrom {
    /// The exact distance from the readout's spike trains.
    Exact,
    /// The trace-sampled distance from the readout's synaptic trace record at `trace_dt_s`,
    /// arithmetic in `precision` ([`neurotac_core::distance::trace_sampled`]).
    Traces {
        /// Trace step (s), a whole number of µs.
        trace_dt_s: f64,
        /// `f64` or `f32`.
        precision: Precision,
    },
}

impl VrFrom {
    /// `exact` or `traces (h = 0.1 ms, f64)`.
    pub fn describe(&self) -> String {
        match self {
            VrFrom::Exact => "exact, from the readout's spike trains".into(),
            VrFrom::Traces {
                trace_dt_s,
                precision,
            } => format!(
                "from the readout's synaptic traces at {} ms, {}",
                trace_dt_s * 1e3,
                precision.name()
            ),
        }
    }
}

/// What the four coding readouts hold for every sample of a set, with its labels.
#[derive(Debug, Clone, PartialEq)]
pub struct EncodedSet {
    /// Class of each sample.
    pub labels: Vec<usize>,
    /// Class names (index = label).
    pub class_names: Vec<String>,
    /// Sample duration the temporal readout bins (ms).
    pub duration_ms: u32,
    /// Intensive readout: one row per sample, one column (mean spikes per channel).
    pub intensive: Array2<f64>,
    /// Spatial readout: one row per sample, one column per channel (spike counts).
    pub spatial: Array2<f64>,
    /// Temporal readout: pooled spike count per 1-ms bin of each sample (every window Δt's
    /// features follow, [`neurotac_core::coding::write_window_features`]).
    pub bins: Vec<Vec<u32>>,
    /// Spatiotemporal readout: each sample's spike trains.
    pub trains: Vec<MultiSpikeTrain>,
    /// Spatiotemporal readout: each sample's trace record (with [`VrFrom::Traces`]).
    pub traces: Option<Vec<TraceRecord>>,
    /// How the set was encoded (for the report): the network's path, or "offline".
    pub path: String,
    /// Van Rossum from traces or exact.
    pub vr_from: VrFrom,
}

impl EncodedSet {
    /// The Van Rossum input of the search (trains or trace records, per [`Self::vr_from`]).
    pub fn van_rossum_input(&self) -> VanRossumInput<'_> {
        match (&self.traces, self.vr_from) {
            (Some(records), VrFrom::Traces { precision, .. }) => {
                VanRossumInput::Traces { records, precision }
            }
            _ => VanRossumInput::Exact(&self.trains),
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.labels.len()
    }

    /// `true` without samples.
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// Number of classes.
    pub fn n_classes(&self) -> usize {
        self.class_names.len()
    }
}

/// The offline encoders' [`EncodedSet`] of `data` (no network): the reference the graph path
/// is tested against, and the path of callers that hold a finished spike dataset.
pub fn encode_offline(data: &SpikeDataset, vr_from: VrFrom) -> Result<EncodedSet, ExperimentError> {
    let duration_ms = sample_duration_ms(data, None)?;
    let obs = data.observations();
    let traces = match vr_from {
        VrFrom::Exact => None,
        VrFrom::Traces { trace_dt_s, .. } => Some(
            obs.par_iter()
                .map(|o| TraceRecord::of_trains(o, trace_dt_s))
                .collect::<Result<Vec<_>, CodingError>>()?,
        ),
    };
    Ok(EncodedSet {
        labels: data.labels().to_vec(),
        class_names: data.class_names().to_vec(),
        duration_ms,
        intensive: feature_matrix(&IntensiveCoding::new(), obs)?,
        spatial: feature_matrix(&SpatialCoding::new(), obs)?,
        bins: obs
            .par_iter()
            .map(|o| pooled_bin_counts(o, duration_ms))
            .collect(),
        trains: obs.to_vec(),
        traces,
        path: "offline encoders (no network)".into(),
        vr_from,
    })
}

/// The network every sample of a set runs through, and its readouts.
struct ReadoutNetwork {
    network: Network,
    input: InputId,
    intensive: ReadoutId<IntensiveCoding>,
    spatial: ReadoutId<SpatialCoding>,
    temporal: ReadoutId<TemporalCoding>,
    spatiotemporal: ReadoutId<SpatiotemporalCoding>,
}

/// One sample's readouts.
struct SampleReadouts {
    intensive: f64,
    spatial: Vec<f64>,
    bins: Vec<u32>,
    trains: MultiSpikeTrain,
    trace: Option<TraceRecord>,
}

impl ReadoutNetwork {
    fn build(
        n_channels: usize,
        duration_ms: u32,
        afferents: Option<AfferentConfig>,
        vr_from: VrFrom,
    ) -> Result<Self, ExperimentError> {
        let mut b = NetworkBuilder::new();
        // Only afferents with input (or, Izhikevich, still settling to rest) are stepped.
        b.event_driven(true);
        let input = b.add_spike_input(
            "taxels",
            SpikeArrayInput::new(MultiSpikeTrain::empty(n_channels)),
        )?;
        let source: ReadoutSource = match afferents {
            None => input.into(),
            Some(config) => afferent_population(&mut b, input, n_channels, config)?.into(),
        };
        let mut spatiotemporal = SpatiotemporalCoding::new(1.0)?;
        if let VrFrom::Traces { trace_dt_s, .. } = vr_from {
            spatiotemporal = spatiotemporal.with_trace_record(trace_dt_s)?;
        }
        let readouts = (
            b.add_readout(source, IntensiveCoding::new())?,
            b.add_readout(source, SpatialCoding::new())?,
            // The window does not matter: the pipeline reads the per-ms bins.
            b.add_readout(source, TemporalCoding::from_ms(1, duration_ms)?)?,
            b.add_readout(source, spatiotemporal)?,
        );
        let dt_s = afferents.map_or(NetworkConfig::default().dt_s, |a| a.dt_s);
        Ok(Self {
            network: b.build(NetworkConfig { dt_s })?,
            input,
            intensive: readouts.0,
            spatial: readouts.1,
            temporal: readouts.2,
            spatiotemporal: readouts.3,
        })
    }

    /// Runs `sample` from time 0 for `run_s` and returns what the readouts hold.
    fn run(
        &mut self,
        sample: &MultiSpikeTrain,
        run_s: f64,
    ) -> Result<SampleReadouts, ExperimentError> {
        self.network
            .replace_spike_input(self.input, SpikeArrayInput::new(sample.clone()))?;
        self.network.reset();
        self.network.run(run_s, &neurotac_core::OneProcess)?;
        let n = &self.network;
        let st = n.readout(self.spatiotemporal)?;
        Ok(SampleReadouts {
            intensive: n.readout(self.intensive)?.features()[0],
            spatial: n.readout(self.spatial)?.features(),
            bins: n.readout(self.temporal)?.bin_counts().to_vec(),
            trains: st.trains(),
            trace: st.trace_record().transpose()?,
        })
    }
}

/// Runs every sample of `data` through the readout network (module docs) — taxel input, the
/// afferent layer when `afferents` is given, the four coding readouts — and gathers the
/// readouts into an [`EncodedSet`]. One network per worker, built once and reset between
/// samples; each sample's readouts depend on that sample alone, so the result is the same at
/// any thread count. `progress` is called once per sample.
///
/// Without afferents each sample runs for its duration; with them for
/// [`AFFERENT_TAIL_S`](crate::afferents::AFFERENT_TAIL_S) longer, and an afferent spike after
/// the duration is an error ([`ExperimentError::DurationShorterThanData`]) as it is for any
/// dataset.
pub fn encode_through_graph(
    data: &SpikeDataset,
    afferents: Option<AfferentConfig>,
    vr_from: VrFrom,
    progress: &(dyn Fn() + Sync),
) -> Result<EncodedSet, ExperimentError> {
    let duration_ms = sample_duration_ms(data, None)?;
    let n_channels = data.n_channels();
    let run_s = duration_ms as f64 * 1e-3
        + if afferents.is_some() {
            crate::afferents::AFFERENT_TAIL_S
        } else {
            0.0
        };
    let samples: Vec<SampleReadouts> = data
        .observations()
        .par_iter()
        // One network per worker, built on its first sample (a build error is that sample's).
        .map_init(
            || None,
            |slot: &mut Option<ReadoutNetwork>, sample| {
                let net = match slot {
                    Some(net) => net,
                    None => slot.insert(ReadoutNetwork::build(
                        n_channels,
                        duration_ms,
                        afferents,
                        vr_from,
                    )?),
                };
                let out = net.run(sample, run_s);
                progress();
                out
            },
        )
        .collect::<Result<_, _>>()?;
    let n = samples.len();
    let mut intensive = Array2::zeros((n, 1));
    let mut spatial = Array2::zeros((n, n_channels));
    let (mut bins, mut trains, mut traces) = (Vec::new(), Vec::new(), Vec::new());
    for (i, s) in samples.into_iter().enumerate() {
        intensive[[i, 0]] = s.intensive;
        spatial
            .row_mut(i)
            .assign(&ndarray::ArrayView1::from(&s.spatial));
        bins.push(s.bins);
        trains.push(s.trains);
        traces.extend(s.trace);
    }
    let needed_ms = duration_ms_of(&trains)?;
    if needed_ms > duration_ms {
        return Err(ExperimentError::DurationShorterThanData {
            stated_ms: duration_ms,
            needed_ms,
        });
    }
    let layer = afferents.map_or_else(String::new, |a| {
        format!(" → exponential synapses → {}", a.description())
    });
    Ok(EncodedSet {
        labels: data.labels().to_vec(),
        class_names: data.class_names().to_vec(),
        duration_ms,
        intensive,
        spatial,
        bins,
        trains,
        traces: matches!(vr_from, VrFrom::Traces { .. }).then_some(traces),
        path: format!("network: taxel input{layer} → four coding readouts, one network reused"),
        vr_from,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::afferents::afferent_dataset;
    use crate::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
    use crate::menu::Menu;
    use crate::neuron_setup::NeuronKind;
    use crate::search::bayes::VanRossumInput;

    fn small_set() -> SpikeDataset {
        let mut data = synthetic_dataset(&SyntheticConfig {
            samples: 12,
            classes: 3,
            channels: 5,
            ..SyntheticConfig::default()
        });
        let end = data
            .observations()
            .iter()
            .filter_map(|o| o.time_range().map(|r| r.1))
            .fold(0.0, f64::max);
        // Room after the last taxel spike for the afferents' responses.
        data.set_duration_s(((end * 1e3).floor() + 100.0) * 1e-3)
            .unwrap();
        data
    }

    fn assert_same(graph: &EncodedSet, offline: &EncodedSet) {
        assert_eq!(graph.intensive, offline.intensive);
        assert_eq!(graph.spatial, offline.spatial);
        assert_eq!(graph.bins, offline.bins);
        assert_eq!(graph.trains, offline.trains);
        assert_eq!(graph.traces, offline.traces);
        let matrices = |s: &EncodedSet| {
            s.van_rossum_input()
                .matrices(0.03, &neurotac_core::OneProcess)
                .unwrap()
        };
        let (g, o) = (matrices(graph), matrices(offline));
        for (a, b) in g.ll2.iter().zip(&o.ll2).chain(g.sp2.iter().zip(&o.sp2)) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-300), "{a} vs {b}");
        }
    }

    #[test]
    fn the_graph_readouts_equal_the_offline_encoders() {
        let data = small_set();
        let traces = VrFrom::Traces {
            trace_dt_s: 1e-3,
            precision: Precision::F64,
        };
        for vr_from in [VrFrom::Exact, traces] {
            let graph = encode_through_graph(&data, None, vr_from, &|| ()).unwrap();
            assert_same(&graph, &encode_offline(&data, vr_from).unwrap());
            assert!(
                graph
                    .path
                    .starts_with("network: taxel input → four coding readouts")
            );
            assert_eq!(
                matches!(graph.van_rossum_input(), VanRossumInput::Traces { .. }),
                vr_from != VrFrom::Exact
            );
        }
    }

    #[test]
    fn with_afferents_the_readouts_watch_the_afferents_and_equal_recording_them() {
        let data = small_set();
        for config in NeuronKind::ALL.iter().map(|&k| AfferentConfig::of(k)) {
            let graph = encode_through_graph(&data, Some(config), VrFrom::Exact, &|| ()).unwrap();
            let run_s = data.duration_s().unwrap() + crate::afferents::AFFERENT_TAIL_S;
            let recorded = afferent_dataset(&data, run_s, config, &|| ()).unwrap();
            assert_same(&graph, &encode_offline(&recorded, VrFrom::Exact).unwrap());
            assert!(graph.path.contains("afferents"), "{}", graph.path);
            assert!(graph.intensive.sum() > 0.0);
        }
    }

    #[test]
    fn the_result_does_not_depend_on_the_thread_count() {
        let data = small_set();
        let run = |threads| {
            crate::threads::with_threads(threads, || {
                encode_through_graph(
                    &data,
                    Some(AfferentConfig::of(NeuronKind::Lif)),
                    VrFrom::Exact,
                    &|| (),
                )
            })
            .unwrap()
            .unwrap()
        };
        assert_eq!(run(1), run(3));
    }
}
