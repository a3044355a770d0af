//! The `taxel_afferents` example's own code, run and checked.

#[path = "../examples/taxel_afferents.rs"]
mod example;

#[test]
fn each_taxel_spike_makes_exactly_one_afferent_spike() {
    let (taxels, afferents) = example::run(2.0).unwrap();
    assert_eq!(taxels.len(), 49);
    // Regular trains at 5 + c/2 Hz on [0, 1.95 s): 10 spikes at 5 Hz, 57 at 29 Hz.
    assert_eq!((taxels[0], taxels[48]), (10, 57));
    assert!(taxels.windows(2).all(|w| w[0] <= w[1]));
    // The synapse was chosen so one taxel spike (≥ 34 ms apart here) drives one afferent spike.
    assert_eq!(afferents, taxels);
}
