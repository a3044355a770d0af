//! A small network defined in Rust code: 49 taxel spike trains → exponential synapses → 49 LIF
//! afferents → spike recorder. Prints each afferent's spike count.
//!
//! Run with `cargo run --release --example taxel_afferents`.

use neurotac::core::{
    Connectivity, ExpSynapse, GraphError, MultiSpikeTrain, NetworkBuilder, NetworkConfig,
    SpikeArrayInput,
};
use neurotac::neurons::{Integrator, Lif, LifParams};

/// Taxel `c` fires regularly at `5 + c/2` Hz from t = 0 until 50 ms before the end (a stand-in
/// for the sensor's output; the margin lets the last input's afferent spike happen in the run).
pub fn taxel_trains(duration_s: f64) -> MultiSpikeTrain {
    let channels = (0..49).map(|c| {
        let period = 1.0 / (5.0 + c as f64 / 2.0);
        (0..)
            .map(|k| k as f64 * period)
            .take_while(|&t| t < duration_s - 0.05)
            .collect::<Vec<f64>>()
    });
    MultiSpikeTrain::from_channels(channels).expect("regular trains are sorted and finite")
}

/// Builds and runs the network; returns (taxel spike counts, afferent spike counts).
pub fn run(duration_s: f64) -> Result<(Vec<usize>, Vec<usize>), GraphError> {
    let taxels = taxel_trains(duration_s);
    let mut b = NetworkBuilder::new();
    let input = b.add_spike_input("taxels", SpikeArrayInput::new(taxels.clone()))?;
    // LIF afferents: τ_m = 10 ms, threshold 1, reset 0, integrated exactly.
    let afferents = b.add_population(
        "afferents",
        Lif::<f64>::new(49, LifParams::default()).with_integrator(Integrator::Exact),
    )?;
    // One exponential current synapse per taxel: τ = 5 ms, weight 5, delivered in the same step.
    // Its PSP peaks at 1.25× threshold, so a lone taxel spike makes one afferent spike (spikes
    // closer than ≈ 10 ms interact; see neurotac_experiments::afferents).
    b.connect(
        input,
        afferents,
        Connectivity::OneToOne { weight: 5.0 },
        ExpSynapse::new(5e-3).with_delay(0),
    )?;
    let recorder = b.record_spikes(afferents)?;
    let mut net = b.build(NetworkConfig { dt_s: 1e-4 })?;
    net.run(duration_s, &neurotac_core::OneProcess)?;
    Ok((taxels.counts(), net.readout(recorder)?.counts()))
}

#[allow(dead_code)]
fn main() -> Result<(), GraphError> {
    let (taxel_counts, afferent_counts) = run(2.0)?;
    println!("taxel → afferent spike counts over 2 s");
    for (i, (t, a)) in taxel_counts.iter().zip(&afferent_counts).enumerate() {
        println!("  taxel {i:2}: {t:3} → afferent {a:3}");
    }
    println!(
        "total: {} → {}",
        taxel_counts.iter().sum::<usize>(),
        afferent_counts.iter().sum::<usize>()
    );
    Ok(())
}
