//! Unsupervised learning on taxel spikes: the simulated artificial texture set (bump grids
//! 0–5 mm) → 49 taxel spike trains → a plastic all-to-all projection (additive STDP, Song,
//! Miller & Abbott 2000) → a layer of LIF neurons that inhibit each other → spike counts → the
//! KNN head. The layer learns on the training slides without labels; then learning is frozen
//! and every slide's output counts are classified, the test slides against the training
//! slides. The same network with its initial (random, fixed) weights is the baseline.
//!
//! A demonstration, reported as it comes: nothing here is tuned toward an accuracy.
//!
//! Run with `cargo run --release --example stdp_taxels`.

use ndarray::Array2;
use neurotac::core::{
    Connectivity, ExpSynapse, InputId, Knn, MultiSpikeTrain, Network, NetworkBuilder,
    NetworkConfig, OneProcess, ProjectionId, ReadoutId, SpikeArrayInput, SpikeDataset,
    SpikeRecorder, Stdp, Synapse, Weights,
};
use neurotac::experiments::datasets::simulated::{TextureSet, load_or_simulate, sample_duration_s};
use neurotac::neurons::{Lif, LifParams};
use neurotac::sensor::sim::SimParams;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::error::Error;
use std::path::Path;

/// Neurons of the learning layer.
pub const NEURONS: usize = 16;
/// Time step (s).
const DT: f64 = 1e-4;
/// Upper bound of the plastic weights: about half the weight at which one taxel spike makes a
/// neuron fire (`one_spike_weight` ≈ 4 for this LIF and synapse), so a neuron fires on a few
/// coincident taxel spikes.
const W_MAX: f64 = 2.0;

/// What the example measured.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Training and test slides.
    pub n_train: usize,
    /// Test slides.
    pub n_test: usize,
    /// Test accuracy of the KNN head on the learned layer's spike counts.
    pub learned_accuracy: f64,
    /// Test accuracy on the same layer with its initial, fixed weights.
    pub fixed_accuracy: f64,
    /// Mean output spikes per slide, learned and fixed.
    pub output_spikes: (f64, f64),
    /// The plastic weights before and after learning.
    pub weights: (Weights, Weights),
}

/// The built network and the ids the example uses.
struct Layer {
    net: Network,
    taxels: InputId,
    plastic: ProjectionId,
    spikes: ReadoutId<SpikeRecorder>,
}

/// The network: taxels → plastic projection (initial weights uniform in `[0, W_MAX]` from
/// `seed`) → `NEURONS` LIF neurons with all-to-all inhibition (one step of delay).
fn network(seed: u64) -> Result<Layer, Box<dyn Error>> {
    let mut b = NetworkBuilder::new();
    let empty = MultiSpikeTrain::from_channels(vec![Vec::new(); 49])?;
    let taxels = b.add_spike_input("taxels", SpikeArrayInput::new(empty))?;
    let layer = b.add_population("layer", Lif::<f64>::new(NEURONS, LifParams::default()))?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let initial = (0..49u32)
        .flat_map(|pre| (0..NEURONS as u32).map(move |post| (pre, post)))
        .map(|(pre, post)| Synapse {
            pre,
            post,
            weight: W_MAX * rng.random::<f64>(),
        })
        .collect();
    let stdp = Stdp::additive(0.02, 0.02, 0.02 * W_MAX, 0.021 * W_MAX, W_MAX);
    let plastic = b.connect_plastic(
        taxels,
        layer,
        Connectivity::Sparse(initial),
        ExpSynapse::new(5e-3).with_delay(0),
        stdp,
    )?;
    b.connect(
        layer,
        layer,
        Connectivity::AllToAll { weight: -3.0 },
        ExpSynapse::new(5e-3),
    )?;
    let spikes = b.record_spikes(layer)?;
    Ok(Layer {
        net: b.build(NetworkConfig { dt_s: DT })?,
        taxels,
        plastic,
        spikes,
    })
}

/// Runs slide `i` of `data` through the layer from time 0; its output spike counts.
fn counts(
    layer: &mut Layer,
    data: &SpikeDataset,
    i: usize,
    duration_s: f64,
) -> Result<Vec<f64>, Box<dyn Error>> {
    let net = &mut layer.net;
    net.replace_spike_input(
        layer.taxels,
        SpikeArrayInput::new(data.observations()[i].clone()),
    )?;
    net.reset();
    net.run(duration_s, &OneProcess)?;
    Ok(net
        .readout(layer.spikes)?
        .counts()
        .into_iter()
        .map(|c| c as f64)
        .collect())
}

/// KNN (k = 1… the head's k) accuracy on the test slides from the training slides' features.
fn knn_accuracy(
    features: &[Vec<f64>],
    labels: &[usize],
    train: &[usize],
    test: &[usize],
) -> Result<f64, Box<dyn Error>> {
    let mut d = Array2::zeros((test.len(), train.len()));
    for (a, &i) in test.iter().enumerate() {
        for (b, &j) in train.iter().enumerate() {
            d[(a, b)] = features[i]
                .iter()
                .zip(&features[j])
                .map(|(x, y)| (x - y).powi(2))
                .sum::<f64>()
                .sqrt();
        }
    }
    let train_labels: Vec<usize> = train.iter().map(|&j| labels[j]).collect();
    let predicted = Knn::new(1)?.fit(&train_labels)?.predict(d.view())?;
    let right = predicted
        .iter()
        .zip(test)
        .filter(|(p, t)| **p == labels[**t])
        .count();
    Ok(right as f64 / test.len() as f64)
}

/// The example on `trials` slides per texture (the first half of each texture's slides
/// train, the rest test), the simulated set cached in `cache`.
pub fn run(trials: usize, cache: &Path) -> Result<Outcome, Box<dyn Error>> {
    let params = SimParams::default();
    let data = load_or_simulate(
        TextureSet::Artificial,
        trials,
        1,
        &params,
        cache,
        &|| {},
        &OneProcess,
    )?;
    let duration_s = sample_duration_s(&params);
    let labels = data.labels().to_vec();
    // Class-major order: slide t of a texture trains when t < trials / 2.
    let (train, test): (Vec<usize>, Vec<usize>) =
        (0..data.len()).partition(|&i| i % trials < trials / 2);

    let mut layer = network(7)?;
    let before = layer.net.weights(layer.plastic)?;
    for &i in &train {
        counts(&mut layer, &data, i, duration_s)?;
    }
    layer.net.set_learning(layer.plastic, false)?;
    let after = layer.net.weights(layer.plastic)?;
    let all_counts = |layer: &mut Layer| {
        (0..data.len())
            .map(|i| counts(layer, &data, i, duration_s))
            .collect::<Result<Vec<_>, _>>()
    };
    let learned = all_counts(&mut layer)?;
    let mut fixed_layer = network(7)?;
    fixed_layer.net.set_learning(fixed_layer.plastic, false)?;
    let fixed = all_counts(&mut fixed_layer)?;

    let mean_spikes =
        |f: &[Vec<f64>]| f.iter().map(|c| c.iter().sum::<f64>()).sum::<f64>() / f.len() as f64;
    Ok(Outcome {
        n_train: train.len(),
        n_test: test.len(),
        learned_accuracy: knn_accuracy(&learned, &labels, &train, &test)?,
        fixed_accuracy: knn_accuracy(&fixed, &labels, &train, &test)?,
        output_spikes: (mean_spikes(&learned), mean_spikes(&fixed)),
        weights: (before, after),
    })
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn Error>> {
    let trials = 10;
    let cache = neurotac::experiments::datasets::simulated::default_cache_dir();
    let o = run(trials, &cache)?;
    let (before, after) = &o.weights;
    let near = |w: &Weights, x: f64| {
        w.weight
            .iter()
            .filter(|&&v| (v - x).abs() < 0.1 * W_MAX)
            .count()
    };
    println!(
        "artificial set: 11 textures × {trials} slides; {} train (unlabelled STDP), {} test",
        o.n_train, o.n_test
    );
    println!(
        "plastic weights (49 × {NEURONS}): near 0 {} → {}, near w_max {} → {}",
        near(before, 0.0),
        near(after, 0.0),
        near(before, W_MAX),
        near(after, W_MAX)
    );
    println!(
        "output spikes per slide: learned {:.1}, fixed {:.1}",
        o.output_spikes.0, o.output_spikes.1
    );
    println!(
        "KNN (k = 1) test accuracy: learned {:.1} %, fixed initial weights {:.1} % (chance 9.1 %)",
        100.0 * o.learned_accuracy,
        100.0 * o.fixed_accuracy
    );
    Ok(())
}
