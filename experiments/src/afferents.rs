//! Afferent networks: taxel spike trains → exponential synapses → one afferent neuron per taxel.
//!
//! This is the smallest network that turns the sensor's taxel spikes into the spikes of model
//! mechanoreceptor afferents (the paper's discussion proposes feeding taxel output to spiking
//! neuron models). Each taxel drives its own afferent one-to-one.
//!
//! Defaults, and why:
//! - synapse τ = 5 ms: a fast AMPA-like current, shorter than the 20 ms pooling window, so one
//!   taxel event is one brief input;
//! - the afferent itself — parameters, initial state and synaptic weight — is its model
//!   family's ([`ModelFamily::afferent`], with the reasons in the model's file): LIF weight 5
//!   (potential units), Izhikevich RS weight 20 (mV/ms), each chosen so that a lone taxel event
//!   makes exactly one afferent spike; f64, the model's default integrator;
//! - **close events summate — intended, not a bug** : an afferent is a leaky
//!   integrator, not a relay, and a real mechanoreceptor afferent fires more for denser input.
//!   Two taxel events Δ apart give the LIF afferent **3 spikes while Δ < 17 ms** and 2 beyond
//!   (the first event's synaptic current and the membrane's leftover depolarisation add to the
//!   second's, whose drive then crosses threshold twice), and the Izhikevich RS afferent 2 spikes
//!   at every Δ from 1 to 40 ms (its recovery variable absorbs the extra drive; in longer dense
//!   trains its adaptation drops spikes instead) — both tested. Pooled taxel events of
//!   neighbouring 20 ms windows can be less than 17 ms apart, so with LIF afferents a taxel that
//!   fires in consecutive windows is counted up, which is why the intensive coding differs from
//!   the direct pipeline's. `neurotac demo` (49 Poisson taxels at 20 Hz for 1 s, seed 1)
//!   measures 909 taxel spikes → 1149 LIF spikes (1.26 per taxel spike) and → 744 Izhikevich RS
//!   spikes (0.82; RS afferents start at rest, −70 mV);
//! - dt = 0.1 ms: below a tenth of both time constants.

use crate::error::ExperimentError;
use crate::neuron_setup::{NeuronKind, Precision};
use neurotac_core::graph::CROSSOVER_FILE_NAME;
use neurotac_core::{
    Connectivity, Crossovers, ExpSynapse, GraphError, InputId, MultiSpikeTrain, NetworkBuilder,
    NetworkConfig, PopulationId, ReadoutId, SpikeArrayInput, SpikeDataset, SpikeRecorder,
    SpikeSource, Stepping,
};
use neurotac_neurons::{AfferentPreset, BlockPopulation, FamilyVisitor, Integrator, ModelFamily};
use rayon::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// How long an afferent network keeps running after a sample's duration (s), so the
/// responses to the last taxel spikes (synapse τ 5 ms plus the neuron's latency) are recorded.
pub const AFFERENT_TAIL_S: f64 = 0.05;

/// Settings of an afferent network.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AfferentConfig {
    /// The afferent model, set up as its family's [`ModelFamily::afferent`] says: LIF with
    /// [`LifParams::default`](neurotac_neurons::LifParams::default) (τ_m = 10 ms, threshold 1,
    /// reset 0), exact integrator; or Izhikevich regular spiking
    /// ([`IzhikevichParams::rs`](neurotac_neurons::IzhikevichParams::rs)), Izhikevich's 2003
    /// scheme, starting at its resting point (−70 mV; an afferent without input is at rest).
    pub model: NeuronKind,
    /// Synaptic weight (jump of the synaptic current per taxel spike, in the model's input
    /// units). Default the family's ([`AfferentPreset::weight`]): 5 for LIF, 20 for Izhikevich
    /// (see the module docs).
    pub weight: f64,
    /// Synaptic time constant (s). Default 5 ms.
    pub tau_syn_s: f64,
    /// Time step (s). Default 0.1 ms.
    pub dt_s: f64,
    /// Integrator. Default the model's ([`NeuronKind::default_integrator`]: exact for LIF,
    /// Izhikevich's 2003 scheme for Izhikevich).
    pub integrator: Integrator,
    /// Arithmetic of the afferents' state. Default f64.
    pub precision: Precision,
    /// Let the readout network pick the afferents' stepping from their activity
    /// ([`afferent_stepping`]: event-driven, only afferents with input updated, while few
    /// have input) rather than step every afferent every step (clock-driven). Default `true`.
    pub automatic_stepping: bool,
}

/// A family's afferent preset without its parameters.
struct AfferentText {
    weight: f64,
    description: &'static str,
    bench_description: &'static str,
}

/// Reads a family's [`AfferentText`].
struct ReadAfferent;

impl FamilyVisitor for ReadAfferent {
    type Output = AfferentText;
    fn visit<Fam: ModelFamily>(self) -> AfferentText {
        let AfferentPreset {
            weight,
            description,
            bench_description,
            ..
        } = Fam::afferent();
        AfferentText {
            weight,
            description,
            bench_description,
        }
    }
}

impl AfferentConfig {
    /// Afferents of `model` with the documented defaults.
    pub fn of(model: NeuronKind) -> Self {
        Self {
            model,
            weight: model.visit(ReadAfferent).weight,
            tau_syn_s: 5e-3,
            dt_s: 1e-4,
            integrator: model.default_integrator(),
            precision: Precision::F64,
            automatic_stepping: true,
        }
    }

    /// The afferents as a pipeline's description names them
    /// ([`AfferentPreset::description`]: `"LIF afferents (event-driven)"`).
    pub fn description(&self) -> &'static str {
        self.model.visit(ReadAfferent).description
    }

    /// The afferents with their integrator, precision and start, as the afferent activity
    /// bench reports them ([`AfferentPreset::bench_description`]: `"LIF afferents (exact, f64)"`).
    pub fn bench_description(&self) -> &'static str {
        self.model.visit(ReadAfferent).bench_description
    }
}

/// A built afferent network and the handle of its spike recorder.
pub struct AfferentNetwork {
    /// The runnable network.
    pub network: neurotac_core::Network,
    /// The taxel input node (for [`neurotac_core::Network::replace_spike_input`]).
    pub input: neurotac_core::InputId,
    /// The afferents' spike recorder.
    pub spikes: ReadoutId<SpikeRecorder>,
    /// The taxels' spike recorder (the input as the network saw it).
    pub taxel_spikes: ReadoutId<SpikeRecorder>,
}

/// Adds one afferent per channel of `input` (`n` channels) to `builder`, each fed one-to-one
/// through an exponential synapse (`config`), and returns the afferent population.
pub fn afferent_population(
    builder: &mut NetworkBuilder,
    input: InputId,
    n: usize,
    config: AfferentConfig,
) -> Result<PopulationId, GraphError> {
    let afferents = config.model.visit(AddAfferents {
        builder,
        n,
        integrator: config.integrator,
        precision: config.precision,
    })?;
    builder.connect(
        input,
        afferents,
        Connectivity::OneToOne {
            weight: config.weight,
        },
        ExpSynapse::new(config.tau_syn_s).with_delay(0),
    )?;
    Ok(afferents)
}

/// Adds `n` afferents of a family to a network ([`afferent_population`]): its
/// [`ModelFamily::afferent`] parameters and initial potential, the configured integrator and
/// precision.
struct AddAfferents<'a> {
    builder: &'a mut NetworkBuilder,
    n: usize,
    integrator: Integrator,
    precision: Precision,
}

impl FamilyVisitor for AddAfferents<'_> {
    type Output = Result<PopulationId, GraphError>;
    fn visit<Fam: ModelFamily>(self) -> Self::Output {
        let preset = Fam::afferent();
        match self.precision {
            Precision::F64 => self.builder.add_population(
                "afferents",
                BlockPopulation::<Fam::Model<f64>>::new(self.n, preset.params)
                    .with_integrator(self.integrator)
                    .with_initial_potential(preset.initial),
            ),
            Precision::F32 => self.builder.add_population(
                "afferents",
                BlockPopulation::<Fam::Model<f32>>::new(self.n, preset.params)
                    .with_integrator(self.integrator)
                    .with_initial_potential(preset.initial),
            ),
        }
    }
}

/// The crossovers of [`afferent_stepping`], read once per process.
static CROSSOVERS: OnceLock<Crossovers> = OnceLock::new();

/// Makes [`afferent_stepping`] use the crossovers stored by `neurotac bench neurons
/// --crossover` in `cache_dir` (a command's `--cache`). Call it before the first readout
/// network is built: the crossovers are read once per process, so a later call changes
/// nothing. The stepping never changes a result, only its speed, so a crossover file that
/// cannot be used is reported in one line on stderr and the built-in crossovers are used.
pub fn use_crossovers_in(cache_dir: &Path) {
    CROSSOVERS.get_or_init(|| stored_crossovers(cache_dir));
}

/// The crossovers stored in `cache_dir`, else the built-in ones (with a warning when the file
/// exists but cannot be used).
fn stored_crossovers(cache_dir: &Path) -> Crossovers {
    Crossovers::load(&cache_dir.join(CROSSOVER_FILE_NAME))
        .unwrap_or_else(|e| {
            eprintln!("warning: {e}; using the built-in crossovers");
            None
        })
        .unwrap_or_default()
}

/// How the readout networks of `reproduce` and `online` step their afferents:
/// [`Stepping::Auto`] (each afferent population picks clock- or event-driven stepping from its
/// measured activity) with the crossovers of [`use_crossovers_in`], else those stored in the
/// default cache folder ([`default_cache_dir`](crate::datasets::simulated::default_cache_dir)),
/// else the models' built-in ones.
pub fn afferent_stepping() -> Stepping {
    let crossovers = CROSSOVERS
        .get_or_init(|| stored_crossovers(&crate::datasets::simulated::default_cache_dir()));
    Stepping::Auto(crossovers.clone())
}

/// Builds `source` (one channel per taxel) → one-to-one exponential synapses → one afferent
/// per taxel → spike recorder, clock-driven.
pub fn build_afferent_network(
    source: impl SpikeSource + 'static,
    config: AfferentConfig,
) -> Result<AfferentNetwork, GraphError> {
    let n = source.len();
    let mut b = NetworkBuilder::new();
    let input = b.add_spike_input("taxels", source)?;
    let afferents = afferent_population(&mut b, input, n, config)?;
    let spikes = b.record_spikes(afferents)?;
    let taxel_spikes = b.record_spikes(input)?;
    let network = b.build(NetworkConfig { dt_s: config.dt_s })?;
    Ok(AfferentNetwork {
        network,
        input,
        spikes,
        taxel_spikes,
    })
}

/// Runs taxel spike trains through a fresh afferent network for `duration_s` and returns the
/// afferents' spike trains.
pub fn afferent_response(
    taxels: &MultiSpikeTrain,
    duration_s: f64,
    config: AfferentConfig,
) -> Result<MultiSpikeTrain, GraphError> {
    let mut net = build_afferent_network(SpikeArrayInput::new(taxels.clone()), config)?;
    net.network.run(duration_s, &neurotac_core::OneProcess)?;
    Ok(net.network.readout(net.spikes)?.to_spike_trains())
}

/// Runs every sample of `data` through its own afferent network for `duration_s` (in
/// parallel, deterministic) and returns the afferents' spikes with the same labels, class names
/// and metadata. `progress` is called once per sample.
pub fn afferent_dataset(
    data: &SpikeDataset,
    duration_s: f64,
    config: AfferentConfig,
    progress: &(dyn Fn() + Sync),
) -> Result<SpikeDataset, ExperimentError> {
    let observations = data
        .observations()
        .par_iter()
        .map(|taxels| {
            let out = afferent_response(taxels, duration_s, config);
            progress();
            out
        })
        .collect::<Result<Vec<_>, GraphError>>()?;
    Ok(SpikeDataset::new(
        observations,
        data.labels().to_vec(),
        data.class_names().to_vec(),
        data.meta().clone(),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::menu::Menu;

    #[test]
    fn each_model_brings_its_weight_and_descriptions() {
        let lif = AfferentConfig::of(NeuronKind::Lif);
        assert_eq!((lif.weight, lif.tau_syn_s, lif.dt_s), (5.0, 5e-3, 1e-4));
        assert_eq!(lif.description(), "LIF afferents (event-driven)");
        assert_eq!(lif.bench_description(), "LIF afferents (exact, f64)");
        let rs = AfferentConfig::of(NeuronKind::Izhikevich);
        assert_eq!(rs.weight, 20.0);
        assert_eq!(rs.description(), "Izhikevich RS afferents");
    }

    /// The afferents summate, by design (module docs). Two taxel events Δ
    /// apart: LIF gives a third spike while Δ < 17 ms, Izhikevich RS two spikes at any Δ.
    #[test]
    fn close_taxel_events_summate_in_the_lif_afferent_and_not_in_the_rs_one() {
        let pair = |delta_ms: u32| {
            MultiSpikeTrain::from_channels(vec![vec![0.010, 0.010 + f64::from(delta_ms) * 1e-3]])
                .unwrap()
        };
        for delta_ms in 1..=40 {
            let lif = afferent_response(&pair(delta_ms), 0.3, AfferentConfig::of(NeuronKind::Lif))
                .unwrap();
            let rs = afferent_response(
                &pair(delta_ms),
                0.3,
                AfferentConfig::of(NeuronKind::Izhikevich),
            )
            .unwrap();
            let lif_expected = if delta_ms < 17 { 3 } else { 2 };
            assert_eq!(lif.counts(), vec![lif_expected], "LIF, Δ = {delta_ms} ms");
            assert_eq!(rs.counts(), vec![2], "RS, Δ = {delta_ms} ms");
        }
    }

    #[test]
    fn default_afferents_spike_once_per_taxel_event() {
        let taxels =
            MultiSpikeTrain::from_channels(vec![vec![0.010], vec![0.010, 0.030], vec![]]).unwrap();
        for config in NeuronKind::ALL.iter().map(|&k| AfferentConfig::of(k)) {
            let out = afferent_response(&taxels, 0.2, config).unwrap();
            assert_eq!(out.counts(), vec![1, 2, 0], "{:?}", config.model);
            // The afferent spike follows its taxel event within the 20 ms to the next one.
            let first = out.channel(0)[0];
            assert!(first > 0.010 && first < 0.030, "{:?}", config.model);
            // LIF and Izhikevich RS afferents fire within one PSP rise time.
            if [NeuronKind::Lif, NeuronKind::Izhikevich].contains(&config.model) {
                assert!(first < 0.017, "{:?}: {:?}", config.model, out.channel(0));
            }
        }
    }
}
