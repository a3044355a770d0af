//! A projection that learns, frozen, saved and loaded again: 1000 Poisson inputs at 15 Hz →
//! additive STDP (Song, Miller & Abbott 2000) → one LIF neuron, run for 10 s; the learned
//! weights are frozen, the network saved mid-run and loaded to continue bit for bit.
//!
//! Run with `cargo run --release --example stdp_save_load`.

use neurotac::core::{
    Connectivity, ExpSynapse, NetworkBuilder, NetworkConfig, OneProcess, PoissonInput, Stdp,
    Weights,
};
use neurotac::neurons::{BuiltinModels, Lif, LifParams};
use std::error::Error;
use std::path::Path;

/// The weights before and after learning, the loaded network's, and the output spikes.
pub type Learned = (Weights, Weights, Weights, usize);

/// Learns for `duration_s`, saves the network to `path` and loads it again.
pub fn run(duration_s: f64, path: &Path) -> Result<Learned, Box<dyn Error>> {
    let mut b = NetworkBuilder::new();
    let inputs = b.add_spike_input("inputs", PoissonInput::new(1000, 15.0, 1))?;
    let neuron = b.add_population("neuron", Lif::<f64>::new(1, LifParams::default()))?;
    // additive STDP: τ₊ = τ₋ = 20 ms, a₊ = 0.01·w_max, a₋ = 0.0105·w_max, weights in [0, w_max]
    let w_max = 0.6;
    let stdp = Stdp::additive(0.020, 0.020, 0.01 * w_max, 0.0105 * w_max, w_max);
    let synapses = b.connect_plastic(
        inputs,
        neuron,
        Connectivity::AllToAll { weight: 0.3 },
        ExpSynapse::new(5e-3),
        stdp,
    )?;
    let spikes = b.record_spikes(neuron)?;
    let mut net = b.build(NetworkConfig { dt_s: 1e-4 })?;
    let initial = net.weights(synapses)?;
    net.run(duration_s, &OneProcess)?;
    let learned = net.weights(synapses)?; // sparse (pre, post, weight) lists; .dense() is the matrix
    net.set_learning(synapses, false)?; // frozen for evaluation
    net.save(path)?; // versioned, checksummed, bit-exact
    let mut again = NetworkBuilder::load(path, &BuiltinModels)?; // add readouts, build, run on
    // Ids are per builder: the loaded network's own, found by name.
    let plastic = again.projections()[0];
    again.record_spikes(again.population("neuron")?)?;
    let loaded = again.build(NetworkConfig { dt_s: 1e-4 })?;
    let output_spikes = net.readout(spikes)?.spikes().len();
    Ok((initial, learned, loaded.weights(plastic)?, output_spikes))
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn Error>> {
    let path = std::env::temp_dir().join("neurotac-stdp-example.ntnet");
    let (initial, learned, loaded, output_spikes) = run(10.0, &path)?;
    let near = |w: &Weights, x: f64| w.weight.iter().filter(|&&v| (v - x).abs() < 0.06).count();
    println!(
        "{output_spikes} output spikes; weights near 0: {} → {}; near w_max: {} → {}; loaded = learned: {}",
        near(&initial, 0.0),
        near(&learned, 0.0),
        near(&initial, 0.6),
        near(&learned, 0.6),
        loaded == learned
    );
    std::fs::remove_file(&path)?;
    Ok(())
}
