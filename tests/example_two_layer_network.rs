//! The `two_layer_network` example's own code, run and checked.

#[path = "../examples/two_layer_network.rs"]
mod example;

#[test]
fn the_two_layer_network_classifies_its_three_classes_from_traces() {
    let example::Outcome {
        labels,
        records,
        weights: [w_lif, w_rs],
        predicted,
    } = example::run().unwrap();
    assert_eq!(labels.len(), 3 * example::PER_CLASS);
    // LIF (τ_m 10 ms, τ_syn 5 ms): the PSP peaks at w/4, so one spike needs w ≈ 4 (threshold
    // 1); the step-wise input makes it slightly more.
    assert!((w_lif / 1.25 - 4.0).abs() < 0.1, "{w_lif}");
    assert!(w_rs > 0.0);
    // Every RS neuron fired (its trace jumped), and the traces tell the classes apart.
    assert!(
        records
            .iter()
            .all(|r| (0..r.n_channels()).all(|c| !r.channel(c).is_empty()))
    );
    let correct = predicted
        .iter()
        .zip(&labels)
        .filter(|(p, l)| p == l)
        .count();
    assert_eq!(correct, labels.len(), "{predicted:?}");
}
