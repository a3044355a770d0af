//! What the cargo-fuzz targets `saved_network` and `description` (`fuzz/`) check, shared with
//! the test that replays their committed corpus on stable
//! (`neurons/tests/fuzz_corpus_replay.rs`): a saved network's bytes, or a description's JSON, read
//! with the built-in models; what reads is built and run a few steps. Any typed error is a
//! pass; a panic (or an abort) is the fuzzer's crash.

use crate::BuiltinModels;
use neurotac_core::testing::fuzz::{FUZZ_PATH, saved_network_file};
use neurotac_core::{
    NetworkBuilder, NetworkConfig, NetworkDescription, NodeDescription, OneProcess,
    SourceDescription, WiringDescription,
};
use std::path::Path;

/// Steps a network that reads is run.
const STEPS: u64 = 50;

/// The most neurons, channels, synapses or steps of delay a fuzzed network is built with: a
/// larger one is only read and checked (building it is the limits' business, tested apart).
const BUILD_AT_MOST: u64 = 100_000;

/// Reads `bytes` as a saved network file, and also as the body of one (with a valid header
/// and checksum, which a fuzzer cannot forge); each that reads is built and run.
pub fn check_saved_network_bytes(bytes: &[u8]) {
    for file in [bytes.to_vec(), saved_network_file(bytes)] {
        let path = Path::new(FUZZ_PATH);
        let Ok(description) = NetworkBuilder::saved_description(&file, path) else {
            continue;
        };
        let loaded = NetworkBuilder::from_saved_bytes(&file, path, &BuiltinModels);
        if let (Ok(b), true) = (loaded, small(&description)) {
            build_and_run(b, description.dt_s);
        }
    }
}

/// Reads `text` as a network description (JSON, as `neurotac.Network.from_description` reads
/// it); one that reads is built and run.
pub fn check_description_text(text: &[u8]) {
    let Ok(description) = serde_json::from_slice::<NetworkDescription>(text) else {
        return;
    };
    let made = NetworkBuilder::from_description(&description, &BuiltinModels);
    if let (Ok(b), true) = (made, small(&description)) {
        build_and_run(b, description.dt_s);
    }
}

/// Records every population's and source's spikes (so nothing is pruned), builds at `dt_s` and
/// runs [`STEPS`] steps: errors are typed; the spikes recorded are of neurons that exist.
fn build_and_run(mut b: NetworkBuilder, dt_s: f64) {
    let names: Vec<String> = b.node_names().into_iter().map(str::to_owned).collect();
    let mut recorders = Vec::new();
    for name in &names {
        let recorded = match (b.population(name), b.spike_input(name)) {
            (Ok(p), _) => b.record_spikes(p),
            (_, Ok(i)) => b.record_spikes(i),
            _ => continue,
        };
        if let Ok(r) = recorded {
            recorders.push(r);
        }
    }
    let Ok(mut net) = b.build(NetworkConfig { dt_s }) else {
        return;
    };
    if net.run_steps(STEPS, &OneProcess).is_err() {
        return;
    }
    for r in recorders {
        let spikes = net.readout(r).expect("a recorder of this network").spikes();
        assert!(
            spikes.iter().all(|&(_, t)| t.is_finite()),
            "a spike at a time that is not finite"
        );
    }
}

/// Whether `d` is small enough to build in a fuzzer's memory ([`BUILD_AT_MOST`]).
fn small(d: &NetworkDescription) -> bool {
    let size = |name: &str| {
        (d.nodes.iter().find(|n| n.name() == name)).map_or(0, |n| match n {
            NodeDescription::Population { model, .. } => model.size as u64,
            NodeDescription::Source { source, .. } => match source {
                SourceDescription::SpikeArray { trains } => trains.len() as u64,
                SourceDescription::Poisson { size, .. } => *size as u64,
            },
            NodeDescription::Current { current, .. } => current.len() as u64,
        })
    };
    let nodes: u64 = d.nodes.iter().map(|n| size(n.name())).sum();
    let synapses = d.projections.iter().map(|p| match &p.wiring {
        WiringDescription::AllToAll { .. } | WiringDescription::Random { .. } => {
            size(&p.pre).saturating_mul(size(&p.post))
        }
        _ => size(&p.post),
    });
    let delays = d.projections.iter().map(|p| u64::from(p.delay_steps));
    nodes <= BUILD_AT_MOST
        && synapses.chain(delays).all(|n| n <= BUILD_AT_MOST)
        && d.dt_s.is_finite()
}
