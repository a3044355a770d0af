//! The `stdp_save_load` example's own code, run and checked (the guide's STDP tutorial shows
//! it).

#[path = "../examples/stdp_save_load.rs"]
mod example;

#[test]
fn a_plastic_projection_learns_freezes_and_loads_with_its_learned_weights() {
    let dir = tempfile::tempdir().unwrap();
    let (initial, learned, loaded, output_spikes) =
        example::run(2.0, &dir.path().join("trained.ntnet")).unwrap();
    assert!(output_spikes > 0);
    assert_eq!(initial.len(), 1000);
    assert_ne!(learned.weight, initial.weight, "STDP moved the weights");
    assert!(learned.weight.iter().all(|&w| (0.0..=0.6).contains(&w)));
    assert_eq!(loaded, learned);
}
