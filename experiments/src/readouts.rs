//! The main job through the framework's graph: every sample runs through one network, built
//! once per worker and reused ([`Network::replace_spike_input`] + [`Network::reset`]), whose
//! readouts are the output trains and each coding of the menu
//! ([`CodingScheme::add_readout`](crate::coding::CodingScheme::add_readout)); the pipeline
//! ([`crate::reproduce`]) classifies what the readouts hold ([`EncodedSet`]).
//!
//! ```text
//! taxel spike input ─┬───────────────────────────────┬─ IntensiveCoding    → mean count per taxel
//!   (one sample at   │  (with afferents:             ├─ SpatialCoding      → count per taxel
//!    a time)         └─ exp. synapses → afferents) ──┼─ TemporalCoding     → pooled count per 1-ms bin (every Δt)
//!                                                    ├─ SpatiotemporalCoding → trace record (trace Van Rossum)
//!                                                    └─ output trains (exact Van Rossum, online)
//! ```
//!
//! [`encode_offline`] computes the same [`EncodedSet`] with the codings' direct encoders (no
//! network); the two are identical (tested), which is what lets `reproduce` report either.

use crate::afferents::{AfferentConfig, afferent_population, afferent_stepping};
use crate::coding::scheme::SampleReader;
use crate::coding::{CodingName, ReadoutContext, sample_duration_ms};
use crate::error::ExperimentError;
use crate::menu::Menu;
use neurotac_core::coding::{SpatiotemporalCoding, duration_ms_of};
use neurotac_core::{
    InputId, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig, ReadoutId, ReadoutSource,
    SpikeArrayInput, SpikeDataset, Stepping,
};
use rayon::prelude::*;

pub use crate::coding::encoded::{EncodedSet, SetReadout, VrFrom};

/// The offline encoders' [`EncodedSet`] of `data` (no network; each coding's
/// [`CodingScheme::encode`](crate::coding::CodingScheme::encode)): the reference the graph
/// path is tested against, and the path of callers that hold a finished spike dataset.
pub fn encode_offline(data: &SpikeDataset, vr_from: VrFrom) -> Result<EncodedSet, ExperimentError> {
    let context = ReadoutContext {
        n_channels: data.n_channels(),
        duration_ms: sample_duration_ms(data, None)?,
        vr_from,
    };
    let obs = data.observations();
    let readouts = (CodingName::ALL.iter())
        .map(|c| Ok((c.key(), c.scheme().encode(obs, &context)?)))
        .collect::<Result<_, ExperimentError>>()?;
    Ok(EncodedSet {
        labels: data.labels().to_vec(),
        class_names: data.class_names().to_vec(),
        duration_ms: context.duration_ms,
        n_channels: context.n_channels,
        trains: obs.to_vec(),
        readouts,
        path: "offline encoders (no network)".into(),
        vr_from,
        neuron_updates: 0,
    })
}

/// `n` as a word up to ten ("four"), else in digits.
fn in_words(n: usize) -> String {
    const WORDS: [&str; 11] = [
        "no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    ];
    WORDS
        .get(n)
        .map_or_else(|| n.to_string(), |w| (*w).to_owned())
}

/// The network every sample of a set runs through: its output trains and every coding's
/// readout.
struct ReadoutNetwork {
    network: Network,
    input: InputId,
    /// The output trains (what every coding can read).
    trains: ReadoutId<SpatiotemporalCoding>,
    /// Each coding's reader, in menu order.
    readers: Vec<SampleReader>,
}

/// One sample's output trains, each coding's readout of it (a set of one sample) and the
/// neuron updates its run took.
type SampleReadouts = (MultiSpikeTrain, Vec<Box<dyn SetReadout>>, u64);

impl ReadoutNetwork {
    fn build(
        context: &ReadoutContext,
        afferents: Option<AfferentConfig>,
    ) -> Result<Self, ExperimentError> {
        let n_channels = context.n_channels;
        let mut b = NetworkBuilder::new();
        // Each afferent population picks clock- or event-driven stepping from its activity,
        // unless the afferents ask to be clock-driven.
        b.stepping(match afferents.is_none_or(|a| a.automatic_stepping) {
            true => afferent_stepping(),
            false => Stepping::Clock,
        });
        let input = b.add_spike_input(
            "taxels",
            SpikeArrayInput::new(MultiSpikeTrain::empty(n_channels)),
        )?;
        let source: ReadoutSource = match afferents {
            None => input.into(),
            Some(config) => afferent_population(&mut b, input, n_channels, config)?.into(),
        };
        let trains = b.add_readout(source, SpatiotemporalCoding::new(1.0)?)?;
        let readers = (CodingName::ALL.iter())
            .map(|c| c.scheme().add_readout(&mut b, source, context))
            .collect::<Result<_, _>>()?;
        let dt_s = afferents.map_or(NetworkConfig::default().dt_s, |a| a.dt_s);
        Ok(Self {
            network: b.build(NetworkConfig { dt_s })?,
            input,
            trains,
            readers,
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
        let readouts = (self.readers.iter())
            .map(|read| read(n))
            .collect::<Result<_, _>>()?;
        Ok((
            n.readout(self.trains)?.trains(),
            readouts,
            n.neuron_updates(),
        ))
    }
}

/// Runs every sample of `data` through the readout network (module docs) — taxel input, the
/// afferent layer when `afferents` is given, every coding's readout — and gathers the
/// readouts into an [`EncodedSet`]. One network per worker, built once and reset between
/// samples; each sample's readouts depend on that sample alone, so the result is the same at
/// any thread count. `progress` is called once per sample.
///
/// Without afferents each sample runs for its duration; with them for
/// [`AFFERENT_TAIL_S`](crate::afferents::AFFERENT_TAIL_S) longer, and the encoded samples
/// last that much longer too, so every coding reads the afferents' responses to the last taxel
/// spikes.
pub fn encode_through_graph(
    data: &SpikeDataset,
    afferents: Option<AfferentConfig>,
    vr_from: VrFrom,
    progress: &(dyn Fn() + Sync),
) -> Result<EncodedSet, ExperimentError> {
    let tail_ms = match afferents {
        Some(_) => (crate::afferents::AFFERENT_TAIL_S * 1e3).round() as u32,
        None => 0,
    };
    let context = ReadoutContext {
        n_channels: data.n_channels(),
        duration_ms: sample_duration_ms(data, None)? + tail_ms,
        vr_from,
    };
    let duration_ms = context.duration_ms;
    let run_s = duration_ms as f64 * 1e-3;
    let samples: Vec<SampleReadouts> = data
        .observations()
        .par_iter()
        // One network per worker, built on its first sample (a build error is that sample's).
        .map_init(
            || None,
            |slot: &mut Option<ReadoutNetwork>, sample| {
                let net = match slot {
                    Some(net) => net,
                    None => slot.insert(ReadoutNetwork::build(&context, afferents)?),
                };
                let out = net.run(sample, run_s);
                progress();
                out
            },
        )
        .collect::<Result<_, _>>()?;
    let mut trains = Vec::with_capacity(samples.len());
    // Each coding's readouts of the whole set: its readout of the first sample, the others
    // appended in order (without samples, its offline readout of none).
    let mut readouts: Vec<Box<dyn SetReadout>> = Vec::new();
    let mut neuron_updates = 0;
    for (sample_trains, sample_readouts, updates) in samples {
        trains.push(sample_trains);
        neuron_updates += updates;
        if readouts.is_empty() {
            readouts = sample_readouts;
            continue;
        }
        for (set, mut sample) in readouts.iter_mut().zip(sample_readouts) {
            if !set.append(sample.as_mut()) {
                unreachable!("a coding's reader gives the same type for every sample");
            }
        }
    }
    if readouts.is_empty() {
        readouts = (CodingName::ALL.iter())
            .map(|c| c.scheme().encode(&[], &context))
            .collect::<Result<_, _>>()?;
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
        n_channels: context.n_channels,
        trains,
        readouts: (CodingName::ALL.iter().map(|c| c.key()))
            .zip(readouts)
            .collect(),
        path: format!(
            "network: taxel input{layer} → {} coding readouts, one network reused",
            in_words(CodingName::ALL.len())
        ),
        vr_from,
        neuron_updates,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::afferents::afferent_dataset;
    use crate::coding::spatiotemporal::van_rossum_input;
    use crate::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
    use crate::menu::Menu;
    use crate::neuron_setup::NeuronKind;
    use crate::neuron_setup::Precision;
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
        assert_eq!(graph.trains, offline.trains);
        assert_eq!(graph.readouts.len(), CodingName::ALL.len());
        for ((key, g), (k, o)) in graph.readouts.iter().zip(&offline.readouts) {
            assert_eq!(key, k);
            assert!(g.same_as(o.as_ref()), "{key}: {g:?} vs {o:?}");
        }
        let matrices = |s: &EncodedSet| {
            van_rossum_input(s)
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
                    || CodingName::ALL.len() != 4
            );
            assert_eq!(
                matches!(van_rossum_input(&graph), VanRossumInput::Traces { .. }),
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
            let mut recorded = afferent_dataset(&data, run_s, config, &|| ()).unwrap();
            recorded.set_duration_s(run_s).unwrap();
            assert_same(&graph, &encode_offline(&recorded, VrFrom::Exact).unwrap());
            assert!(graph.path.contains("afferents"), "{}", graph.path);
            let means = graph.readout::<Vec<f64>>("intensive").unwrap();
            assert!(means.iter().map(|m| m[0]).sum::<f64>() > 0.0);
        }
    }

    #[test]
    fn afferent_responses_to_a_spike_at_the_end_of_a_sample_are_encoded() {
        // A taxel spike in the last ms of the sample: its afferent spike comes after the
        // sample's end, inside the tail the network runs for.
        let sample = MultiSpikeTrain::from_channels(vec![vec![0.0995], vec![0.05]]).unwrap();
        let mut data = SpikeDataset::new(
            vec![sample.clone(), sample],
            vec![0, 1],
            vec!["a".into(), "b".into()],
            Default::default(),
        )
        .unwrap();
        data.set_duration_s(0.1).unwrap();
        for config in NeuronKind::ALL.iter().map(|&k| AfferentConfig::of(k)) {
            let set = encode_through_graph(&data, Some(config), VrFrom::Exact, &|| ()).unwrap();
            let tail_ms = (crate::afferents::AFFERENT_TAIL_S * 1e3).round() as u32;
            assert_eq!(set.duration_ms, 100 + tail_ms);
            let late = set.trains[0].channel(0);
            assert!(
                late.iter().any(|&t| t > 0.1),
                "{:?}: {late:?}",
                config.model
            );
            assert!(set.neuron_updates > 0);
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
