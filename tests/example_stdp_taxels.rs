//! The `stdp_taxels` example's own code, run and checked: unsupervised STDP on simulated
//! taxel spikes, then the KNN head on the learned and on the fixed layer.

#[path = "../examples/stdp_taxels.rs"]
mod example;

#[test]
fn stdp_learns_on_taxel_spikes_and_the_knn_head_reads_both_layers() {
    let dir = tempfile::tempdir().unwrap();
    let o = example::run(3, &dir.path().join("cache")).unwrap();
    // Class-major slides, the first of every three trains.
    assert_eq!((o.n_train, o.n_test), (11, 22));
    let (before, after) = &o.weights;
    assert_eq!(before.len(), 49 * example::NEURONS);
    assert!(
        after.weight.iter().all(|&w| (0.0..=2.0).contains(&w)),
        "weights within the STDP bounds"
    );
    let moved = before
        .weight
        .iter()
        .zip(&after.weight)
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        moved > before.len() / 2,
        "most weights learned: {moved} of {}",
        before.len()
    );
    assert!(
        o.output_spikes.0 > 0.0 && o.output_spikes.1 > 0.0,
        "both layers spike: {:?}",
        o.output_spikes
    );
    for a in [o.learned_accuracy, o.fixed_accuracy] {
        assert!((0.0..=1.0).contains(&a));
    }
}
