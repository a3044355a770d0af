//! The CUBA network and the afferent pipeline partitioned over 1, 2 and 3 ranks (threads of
//! this process, [`ThreadRanks`]) give every rank exactly the spikes of one process.

use neurotac_cli::bench::{CubaConfig, activity_taxels, afferent_network, cuba, cuba_spikes};
use neurotac_core::OneProcess;
use neurotac_core::Stepping;
use neurotac_core::ranks::ThreadRanks;
use neurotac_experiments::afferents::AfferentConfig;
use neurotac_experiments::neuron_setup::NeuronKind;

#[test]
fn cuba_spikes_as_in_one_process_on_1_2_and_3_ranks() {
    let config = CubaConfig {
        duration_s: 0.05,
        ..CubaConfig::default()
    };
    let (one, spikes) = cuba_spikes(config, &OneProcess).unwrap();
    assert!(
        spikes.excitatory.len() > 1000 && spikes.inhibitory.len() > 200,
        "{one:?}: CUBA must be active"
    );
    assert_eq!((one.ranks, one.exchanges, one.exchange_s), (1, 0, 0.0));
    let plain = cuba(config, &neurotac_core::OneProcess).unwrap();
    assert_eq!((plain.spikes, plain.synapses), (one.spikes, one.synapses));
    for size in 1..=3 {
        let per_rank = ThreadRanks::run(size, |ranks| cuba_spikes(config, ranks).unwrap());
        for (rank, (result, got)) in per_rank.into_iter().enumerate() {
            assert!(
                got == spikes,
                "{size} ranks, rank {rank}: {} + {} spikes, one process {} + {}",
                got.excitatory.len(),
                got.inhibitory.len(),
                spikes.excitatory.len(),
                spikes.inhibitory.len()
            );
            assert_eq!(
                (result.spikes, result.synapses, result.ranks),
                (one.spikes, one.synapses, size)
            );
            // One exchange per step: CUBA's delay is one step.
            let exchanges = if size == 1 { 0 } else { 500 };
            assert_eq!(result.exchanges, exchanges);
        }
    }
}

#[test]
fn the_afferent_pipeline_spikes_as_in_one_process_on_1_2_and_3_ranks() {
    let (duration_s, dt_s) = (0.5, 1e-4);
    let taxels = activity_taxels(49, 0.6, 40.0, duration_s, 3);
    // The two models whose afferents are event-driven (an idle neuron is skipped).
    for config in [NeuronKind::Lif, NeuronKind::Izhikevich].map(AfferentConfig::of) {
        // Each rank of an automatic network decides for its own block.
        for (mode, stepping) in [
            ("clock-driven", Stepping::Clock),
            ("event-driven", Stepping::Event),
            ("automatic", Stepping::auto()),
        ] {
            let stepping = || stepping.clone();
            let (mut net, id) = afferent_network(
                &taxels,
                config,
                dt_s,
                stepping(),
                &neurotac_core::OneProcess,
            )
            .unwrap();
            net.run(duration_s, &neurotac_core::OneProcess).unwrap();
            let one = net.readout(id).unwrap().spikes().to_vec();
            assert!(one.len() > 100, "{} spikes", one.len());
            for size in 1..=3 {
                let per_rank = ThreadRanks::run(size, |ranks| {
                    let (mut net, id) =
                        afferent_network(&taxels, config, dt_s, stepping(), ranks).unwrap();
                    net.run(duration_s, ranks).unwrap();
                    let active = !net.event_driven_populations().is_empty();
                    (net.readout(id).unwrap().spikes().to_vec(), active)
                });
                for (rank, (got, active)) in per_rank.into_iter().enumerate() {
                    assert!(
                        got == one,
                        "{config:?}, {mode}, {size} ranks, rank {rank}: {} spikes, one process {}",
                        got.len(),
                        one.len()
                    );
                    if stepping() != Stepping::auto() {
                        assert_eq!(active, stepping() == Stepping::Event, "{mode}");
                    }
                }
            }
        }
    }
}
