//! A two-layer network written from the docs alone: taxel spike input → LIF layer →
//! Izhikevich layer → synaptic-trace readout → Van Rossum distances → KNN, on a small
//! synthetic three-class "texture" set.
//!
//! - weights come from [`one_spike_weight`] (the weight at which one input spike makes the
//!   target neuron fire), times a margin — no guessing in undocumented units;
//! - the ids are typed: `connect(input, lif, …)` takes an `InputId` or `PopulationId` as source
//!   and only a `PopulationId` as target, so a wrong connection does not compile;
//! - the delay rule: from an input, delay 0 is allowed; from a population, at least one step;
//! - the network is built once and reused for every sample ([`Network::replace_spike_input`] +
//!   [`Network::reset`]);
//! - the readout's [`TraceRecord`]s go straight to [`trace_matrices`] (Van Rossum `LL²`/`SP²`)
//!   and the matrices to [`Knn`]; `ndarray` comes re-exported from `neurotac::core`.
//!
//! Run with `cargo run --release --example two_layer_network`.

use neurotac::core::coding::{SpatiotemporalCoding, TraceRecord};
use neurotac::core::distance::trace_matrices;
use neurotac::core::ndarray::Array2;
use neurotac::core::{
    Connectivity, ExpSynapse, Knn, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig,
    SpikeArrayInput, one_spike_weight,
};
use neurotac::neurons::{Integrator, Izhikevich, IzhikevichParams, Lif, LifParams};

/// Taxels of the toy sensor.
pub const TAXELS: usize = 16;
/// Samples per class.
pub const PER_CLASS: usize = 8;
/// Network step (s).
pub const DT_S: f64 = 1e-4;
/// Length of a sample (s).
pub const DURATION_S: f64 = 1.0;

/// Sample `trial` of class `class`: every taxel fires regularly, class `c` at `(10 + 8c)` Hz
/// with a class-specific phase per taxel and a small per-trial jitter, deterministic.
pub fn sample(class: usize, trial: usize) -> MultiSpikeTrain {
    let period = 1.0 / (10.0 + 8.0 * class as f64);
    let channels = (0..TAXELS).map(|taxel| {
        let phase = period * ((taxel * (class + 1)) % 7) as f64 / 7.0;
        let jitter = 1e-3 * ((trial * 7 + taxel * 3) % 5) as f64;
        (0..)
            .map(|k| phase + jitter + k as f64 * period)
            .take_while(|&t| t < DURATION_S - 0.1)
            .collect::<Vec<f64>>()
    });
    MultiSpikeTrain::from_channels(channels).expect("regular trains are sorted and finite")
}

/// What [`run`] returns.
pub struct Outcome {
    /// Class of each sample.
    pub labels: Vec<usize>,
    /// The readout's trace record of each sample (the Izhikevich layer's spikes as traces).
    pub records: Vec<TraceRecord>,
    /// The weights input → LIF and LIF → Izhikevich.
    pub weights: [f64; 2],
    /// Leave-one-out KNN predictions at (τ, cos θ) = (20 ms, 0.5).
    pub predicted: Vec<usize>,
}

/// Builds the network once and runs every sample through it.
pub fn run() -> Result<Outcome, Box<dyn std::error::Error>> {
    let synapse = ExpSynapse::new(5e-3);
    let lif = || Lif::<f64>::new(1, LifParams::default()).with_integrator(Integrator::Exact);
    let rs = || Izhikevich::<f64>::new(1, IzhikevichParams::rs());
    // 25 % above the weight at which one spike makes the neuron fire.
    let w_lif = 1.25 * one_spike_weight(lif, synapse.with_delay(0), DT_S)?;
    let w_rs = 1.25 * one_spike_weight(rs, synapse, DT_S)?;

    let mut b = NetworkBuilder::new();
    let input = b.add_spike_input(
        "taxels",
        SpikeArrayInput::new(MultiSpikeTrain::empty(TAXELS)),
    )?;
    let layer1 = b.add_population(
        "lif",
        Lif::<f64>::new(TAXELS, LifParams::default()).with_integrator(Integrator::Exact),
    )?;
    let layer2 = b.add_population("rs", Izhikevich::<f64>::new(TAXELS, IzhikevichParams::rs()))?;
    b.connect(
        input,
        layer1,
        Connectivity::OneToOne { weight: w_lif },
        synapse.with_delay(0),
    )?;
    b.connect(
        layer1,
        layer2,
        Connectivity::OneToOne { weight: w_rs },
        synapse,
    )?;
    let traces = SpatiotemporalCoding::new(0.02)?.with_trace_record(DT_S)?;
    let readout = b.add_readout(layer2, traces)?;
    let mut net: Network = b.build(NetworkConfig { dt_s: DT_S })?;

    let (mut labels, mut records) = (Vec::new(), Vec::new());
    for class in 0..3 {
        for trial in 0..PER_CLASS {
            net.replace_spike_input(input, SpikeArrayInput::new(sample(class, trial)))?;
            net.reset();
            net.run(DURATION_S, &neurotac_core::OneProcess)?;
            records.push(net.readout(readout)?.trace_record().expect("traces on")?);
            labels.push(class);
        }
    }
    let d2: Array2<f64> =
        trace_matrices::<f64>(&records, 0.02, &neurotac_core::OneProcess)?.squared(0.5)?;
    let predicted = Knn::new(3)?.leave_one_out(d2.view(), &labels)?;
    Ok(Outcome {
        labels,
        records,
        weights: [w_lif, w_rs],
        predicted,
    })
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Outcome {
        labels,
        records,
        weights: [w_lif, w_rs],
        predicted,
    } = run()?;
    let correct = predicted
        .iter()
        .zip(&labels)
        .filter(|(p, l)| p == l)
        .count();
    let jumps: usize = records
        .iter()
        .map(|r| {
            (0..r.n_channels())
                .map(|c| r.channel(c).len())
                .sum::<usize>()
        })
        .sum();
    println!("weights: input → LIF {w_lif:.3}, LIF → RS {w_rs:.3} (1.25 × one-spike weight)");
    println!(
        "{} samples, {jumps} trace jumps kept ({} bytes in all)",
        labels.len(),
        records.iter().map(TraceRecord::heap_bytes).sum::<usize>()
    );
    println!(
        "leave-one-out KNN (k = 3) on the RS layer's traces: {correct}/{} correct",
        labels.len()
    );
    Ok(())
}
