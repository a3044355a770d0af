//! Saved networks ([`Network::save`], [`NetworkBuilder::load`]) and descriptions
//! ([`Network::describe`], [`NetworkBuilder::from_description`]) with a small saveable model:
//! a loaded network continues exactly as the uninterrupted one, and a damaged or foreign file
//! is a typed error naming it, never a different network.

use neurotac_core::{
    Connectivity, CurrentInput, ExpSynapse, GraphError, ModelDescription, ModelError, ModelFactory,
    ModelState, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig, NetworkDescription,
    NetworkFileError, NeuronModel, OneProcess, PoissonInput, PopulationId, ProjectionId, ReadoutId,
    SpikeArrayInput, SpikeBuffer, SpikeRecorder, Stdp,
};
use std::path::Path;

const DT: f64 = 1e-4;

/// A leaky integrator `v ← v·e^(−dt/τ) + input`, a spike and reset to 0 at `v ≥ 1`.
struct Leaky {
    n: usize,
    tau_s: f64,
    decay: f64,
    v: Vec<f64>,
}

impl Leaky {
    fn new(n: usize, tau_s: f64) -> Self {
        Self {
            n,
            tau_s,
            decay: 0.0,
            v: Vec::new(),
        }
    }
}

impl NeuronModel for Leaky {
    fn model_name(&self) -> &'static str {
        "leaky"
    }
    fn len(&self) -> usize {
        self.n
    }
    fn variables(&self) -> &'static [&'static str] {
        &["v"]
    }
    fn prepare(&mut self, dt_s: f64) -> Result<(), ModelError> {
        self.decay = (-dt_s / self.tau_s).exp();
        self.v = vec![0.0; self.n];
        Ok(())
    }
    fn reset(&mut self) {
        self.v.iter_mut().for_each(|v| *v = 0.0);
    }
    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer) {
        for (i, (v, &x)) in self.v.iter_mut().zip(current).enumerate() {
            *v = *v * self.decay + x;
            if *v >= 1.0 {
                *v = 0.0;
                spikes.push(i as u32);
            }
        }
    }
    fn read_variable(&self, _var: usize, neurons: &[u32], out: &mut Vec<f64>) {
        out.extend(neurons.iter().map(|&i| self.v[i as usize]));
    }
    fn describe(&self) -> Option<ModelDescription> {
        Some(ModelDescription {
            model: "leaky".into(),
            size: self.n,
            settings: serde_json::json!({ "tau_s": self.tau_s }),
        })
    }
    fn save_state(&self) -> Option<ModelState> {
        Some(ModelState {
            arrays: vec![("v".into(), self.v.clone())],
            ..ModelState::default()
        })
    }
    fn restore_state(&mut self, state: &ModelState) -> Result<(), ModelError> {
        let v = state.array("leaky", "v", self.n)?;
        self.v.copy_from_slice(v);
        Ok(())
    }
}

struct LeakyFactory;

impl ModelFactory for LeakyFactory {
    fn make(&self, d: &ModelDescription) -> Result<Box<dyn NeuronModel>, ModelError> {
        let tau = d.settings["tau_s"].as_f64();
        match (d.model.as_str(), tau) {
            ("leaky", Some(tau)) => Ok(Box::new(Leaky::new(d.size, tau))),
            _ => Err(ModelError::UnknownModel {
                model: d.model.clone(),
                reason: "not a leaky model with tau_s".into(),
            }),
        }
    }
}

/// The ids of [`network`]'s parts a test reads.
struct Parts {
    plastic: ProjectionId,
    hidden: PopulationId,
    spikes: ReadoutId<SpikeRecorder>,
}

/// Poisson and recorded inputs → a plastic layer → (delay 3) → a fixed layer with a current.
fn builder() -> (NetworkBuilder, Parts) {
    let mut b = NetworkBuilder::new();
    let noise = b
        .add_spike_input("noise", PoissonInput::new(30, 40.0, 5))
        .unwrap();
    let trains: Vec<Vec<f64>> = (0..4)
        .map(|c| {
            (0..50)
                .map(|k| 0.003 * k as f64 + 1e-4 * c as f64)
                .collect()
        })
        .collect();
    let taxels = b
        .add_spike_input(
            "taxels",
            SpikeArrayInput::new(MultiSpikeTrain::from_channels(trains).unwrap()),
        )
        .unwrap();
    let hidden = b.add_population("hidden", Leaky::new(12, 0.02)).unwrap();
    let out = b.add_population("out", Leaky::new(3, 0.01)).unwrap();
    let plastic = b
        .connect_plastic(
            noise,
            hidden,
            Connectivity::Random {
                probability: 0.5,
                weight: 0.2,
                seed: 1,
            },
            ExpSynapse::new(5e-3),
            Stdp::additive(0.02, 0.02, 0.01, 0.011, 0.4),
        )
        .unwrap();
    b.connect(
        taxels,
        hidden,
        Connectivity::AllToAll { weight: 0.05 },
        ExpSynapse::new(3e-3).with_delay(0),
    )
    .unwrap();
    b.connect(
        hidden,
        out,
        Connectivity::AllToAll { weight: 0.3 },
        ExpSynapse::new(4e-3).with_delay(3),
    )
    .unwrap();
    let drive = b
        .add_current_input("drive", CurrentInput::constant(0.001))
        .unwrap();
    b.inject(drive, out).unwrap();
    let spikes = b.record_spikes(out).unwrap();
    (
        b,
        Parts {
            plastic,
            hidden,
            spikes,
        },
    )
}

fn network() -> (Network, Parts) {
    let (b, parts) = builder();
    (b.build(NetworkConfig { dt_s: DT }).unwrap(), parts)
}

/// A network saved after `first_s` and loaded, with its output spikes recorded, and the
/// ids of the loaded parts.
fn saved_and_loaded(path: &Path, first_s: f64) -> (Network, Parts) {
    let (mut first, _) = network();
    first.run(first_s, &OneProcess).unwrap();
    first.save(path).unwrap();
    let mut b = NetworkBuilder::load(path, &LeakyFactory).unwrap();
    assert_eq!(b.saved_dt_s(), Some(DT));
    let parts = Parts {
        plastic: b.projections()[0],
        hidden: b.population("hidden").unwrap(),
        spikes: b.record_spikes(b.population("out").unwrap()).unwrap(),
    };
    (b.build(NetworkConfig { dt_s: DT }).unwrap(), parts)
}

#[test]
fn a_loaded_network_continues_as_the_uninterrupted_one_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("net.ntnet");
    let (mut whole, w) = network();
    whole.run(0.3, &OneProcess).unwrap();
    let (mut second, s) = saved_and_loaded(&path, 0.15);
    assert_eq!(second.steps_done(), 1500);
    second.run(0.15, &OneProcess).unwrap();

    let expected: Vec<(u32, f64)> = (whole.readout(w.spikes).unwrap().spikes().iter().copied())
        .filter(|s| s.1 > 0.15 + DT / 2.0)
        .collect();
    assert!(
        expected.len() > 10,
        "the output layer spikes in the second half"
    );
    assert_eq!(
        second.readout(s.spikes).unwrap().spikes(),
        &expected[..],
        "the spikes after the save"
    );
    assert_eq!(
        second.weights(s.plastic).unwrap(),
        whole.weights(w.plastic).unwrap(),
        "plastic weights"
    );
    assert_ne!(
        whole.weights(w.plastic).unwrap().weight,
        vec![0.2; 180],
        "the weights learned"
    );
    let bits = |v: Vec<f64>| v.into_iter().map(f64::to_bits).collect::<Vec<_>>();
    assert_eq!(
        bits(second.state(s.hidden, "v").unwrap()),
        bits(whole.state(w.hidden, "v").unwrap())
    );
}

#[test]
fn a_description_through_json_builds_the_same_network() {
    let (mut first, f) = network();
    first.run(0.1, &OneProcess).unwrap();
    // Through JSON (what the Python package reads and writes), the network as it is now —
    // learned weights included — built afresh from step 0.
    let json = serde_json::to_string(&first.describe().unwrap()).unwrap();
    let description: NetworkDescription = serde_json::from_str(&json).unwrap();
    assert_eq!(description, first.describe().unwrap());
    let mut b = NetworkBuilder::from_description(&description, &LeakyFactory).unwrap();
    let plastic = b.projections()[0];
    b.record_spikes(b.population("out").unwrap()).unwrap();
    let rebuilt = b.build(NetworkConfig { dt_s: DT }).unwrap();
    assert_eq!(rebuilt.steps_done(), 0);
    assert_eq!(
        rebuilt.weights(plastic).unwrap(),
        first.weights(f.plastic).unwrap()
    );
    assert!(
        json.contains("\"kind\":\"population\"") && json.contains("\"sparse\""),
        "{json:.300}"
    );
    // A model the factory does not make is refused, naming the population.
    let mut foreign = description.clone();
    if let neurotac_core::NodeDescription::Population { model, .. } = &mut foreign.nodes[2] {
        model.model = "qif".into();
    }
    let e = NetworkBuilder::from_description(&foreign, &LeakyFactory)
        .err()
        .unwrap();
    assert!(e.to_string().contains("hidden"), "{e}");
    // So is a newer version.
    let newer = NetworkDescription {
        version: 99,
        ..description
    };
    let e = NetworkBuilder::from_description(&newer, &LeakyFactory)
        .err()
        .unwrap();
    assert!(
        matches!(e, GraphError::Description(_)) && e.to_string().contains("99"),
        "{e}"
    );
}

#[test]
fn random_wiring_in_a_description_draws_the_synapses_of_the_same_connectivity_in_code() {
    let (probability, weight, seed) = (0.3, 0.25, 17);
    let mut code = NetworkBuilder::new();
    let pre = code.add_population("pre", Leaky::new(20, 0.01)).unwrap();
    let post = code.add_population("post", Leaky::new(15, 0.01)).unwrap();
    let random = Connectivity::Random {
        probability,
        weight,
        seed,
    };
    let p = code
        .connect(pre, post, random, ExpSynapse::new(5e-3))
        .unwrap();
    code.record_spikes(post).unwrap();
    let code = code.build(NetworkConfig { dt_s: DT }).unwrap();
    let drawn = code.weights(p).unwrap();
    assert!(drawn.len() > 40 && drawn.len() < 140, "{}", drawn.len());

    let json = format!(
        r#"{{"format": "neurotac-network", "version": 1, "dt_s": {DT}, "stepping": "clock",
            "nodes": [{{"kind": "population", "name": "pre", "model": {{"model": "leaky", "size": 20, "settings": {{"tau_s": 0.01}}}}}},
                      {{"kind": "population", "name": "post", "model": {{"model": "leaky", "size": 15, "settings": {{"tau_s": 0.01}}}}}}],
            "projections": [{{"pre": "pre", "post": "post", "tau_s": 0.005, "delay_steps": 1, "plasticity": null,
                              "wiring": {{"random": {{"probability": {probability}, "weight": {weight}, "seed": {seed}}}}}}}]}}"#
    );
    let description: NetworkDescription = serde_json::from_str(&json).unwrap();
    let mut b = NetworkBuilder::from_description(&description, &LeakyFactory).unwrap();
    let p = b.projections()[0];
    b.record_spikes(b.population("post").unwrap()).unwrap();
    let described = b.build(NetworkConfig { dt_s: DT }).unwrap();
    assert_eq!(described.weights(p).unwrap(), drawn);
    // Described again, the drawn synapses are explicit.
    let again = described.describe().unwrap();
    assert!(matches!(
        again.projections[0].wiring,
        neurotac_core::WiringDescription::Sparse { .. }
    ));
}

/// `bytes` with a fresh CRC-32 in their last 4 bytes.
fn with_checksum(mut bytes: Vec<u8>) -> Vec<u8> {
    let n = bytes.len() - 4;
    let crc = crc32fast::hash(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
    bytes
}

/// The saved file with its body (CBOR) changed by `edit`, length and checksum made right.
fn with_body(file: &[u8], edit: impl FnOnce(&mut ciborium::Value)) -> Vec<u8> {
    let mut body: ciborium::Value = ciborium::de::from_reader(&file[20..file.len() - 4]).unwrap();
    edit(&mut body);
    let mut encoded = Vec::new();
    ciborium::ser::into_writer(&body, &mut encoded).unwrap();
    let mut out = file[..12].to_vec();
    out.extend((encoded.len() as u64).to_le_bytes());
    out.extend(encoded);
    out.extend([0; 4]);
    with_checksum(out)
}

/// The value at `path` in CBOR value `v`: map keys and array indices joined by dots
/// (`"state.nodes.2.model"`).
fn at<'a>(v: &'a mut ciborium::Value, path: &str) -> &'a mut ciborium::Value {
    path.split('.').fold(v, |v, step| match v {
        ciborium::Value::Array(a) => &mut a[step.parse::<usize>().unwrap()],
        ciborium::Value::Map(m) => {
            &mut m
                .iter_mut()
                .find(|(k, _)| k.as_text() == Some(step))
                .unwrap()
                .1
        }
        _ => panic!("{path}: {step} is in neither a map nor an array"),
    })
}

fn load(bytes: &[u8], path: &Path) -> Result<NetworkBuilder, NetworkFileError> {
    std::fs::write(path, bytes).unwrap();
    NetworkBuilder::load(path, &LeakyFactory)
}

#[test]
fn a_damaged_or_foreign_file_is_a_typed_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.ntnet");
    let (mut net, _) = network();
    net.run(0.05, &OneProcess).unwrap();
    net.save(&good).unwrap();
    let file = std::fs::read(&good).unwrap();
    let bad = dir.path().join("bad.ntnet");
    let named = |e: &NetworkFileError| e.to_string().contains(&bad.display().to_string());
    // Cut anywhere.
    for len in (0..file.len()).step_by(7).chain([file.len() - 1]) {
        let e = load(&file[..len], &bad)
            .err()
            .unwrap_or_else(|| panic!("cut at {len} loaded"));
        assert!(named(&e), "{e}");
        assert!(
            matches!(
                e,
                NetworkFileError::NotANetwork { .. } | NetworkFileError::Length { .. }
            ),
            "cut at {len}: {e}"
        );
    }
    // A flipped bit anywhere.
    for pos in (0..file.len()).step_by(11) {
        let mut flipped = file.clone();
        flipped[pos] ^= 1 << (pos % 8);
        let e = load(&flipped, &bad)
            .err()
            .unwrap_or_else(|| panic!("bit flipped at byte {pos} loaded"));
        assert!(named(&e), "{e}");
    }
    // From a future version.
    let mut future = file.clone();
    future[8..12].copy_from_slice(&2u32.to_le_bytes());
    let e = load(&with_checksum(future), &bad).err().unwrap();
    assert!(
        matches!(e, NetworkFileError::Version { found: 2, .. }) && e.to_string().contains("newer"),
        "{e}"
    );
    // Not a network at all.
    let e = load(b"{\"crossovers\": {}}", &bad).err().unwrap();
    assert!(matches!(e, NetworkFileError::NotANetwork { .. }), "{e}");
    // A body that is not a saved network (its checksum right).
    let e = load(
        &with_body(&file, |v| *v = ciborium::Value::Text("hello".into())),
        &bad,
    )
    .err()
    .unwrap();
    assert!(
        matches!(e, NetworkFileError::Decode { .. }) && named(&e),
        "{e}"
    );
    // A graph that does not validate: a projection onto a node that does not exist, a delay 0
    // between populations.
    let nowhere = with_body(&file, |v| {
        *at(v, "description.projections.1.post") = ciborium::Value::Text("nowhere".into());
    });
    let e = load(&nowhere, &bad).err().unwrap();
    assert!(
        matches!(e, NetworkFileError::Graph { .. }) && e.to_string().contains("nowhere"),
        "{e}"
    );
    let instant = with_body(&file, |v| {
        *at(v, "description.projections.2.delay_steps") = ciborium::Value::Integer(0.into());
    });
    let e = load(&instant, &bad).err().unwrap();
    assert!(e.to_string().contains("delay_steps"), "{e}");
    // A state that does not fit its model: refused, nothing built.
    let short = with_body(&file, |v| {
        at(v, "state.nodes.2.model.arrays.0.1")
            .as_array_mut()
            .unwrap()
            .pop();
    });
    let e = load(&short, &bad).err().unwrap();
    assert!(
        matches!(e, NetworkFileError::Graph { .. }) && e.to_string().contains("'hidden'"),
        "{e}"
    );
    // One the model itself refuses (its array renamed) is refused at build.
    let renamed = with_body(&file, |v| {
        *at(v, "state.nodes.2.model.arrays.0.0") = ciborium::Value::Text("w".into());
    });
    let mut b = load(&renamed, &bad).unwrap();
    b.record_spikes(b.population("out").unwrap()).unwrap();
    let e = b.build(NetworkConfig { dt_s: DT }).err().unwrap();
    let GraphError::Saved { path, source } = &e else {
        panic!("{e}")
    };
    assert_eq!(path, &bad);
    assert!(
        matches!(
            **source,
            GraphError::Model {
                source: ModelError::State { .. },
                ..
            }
        ) && source.to_string().contains("hidden"),
        "{e}"
    );
    // And the saved time step is the only one it builds at.
    let mut b = NetworkBuilder::load(&good, &LeakyFactory).unwrap();
    b.record_spikes(b.population("out").unwrap()).unwrap();
    assert!(b.build(NetworkConfig { dt_s: 2.0 * DT }).is_err());
}

#[test]
fn a_saved_size_larger_than_its_state_is_refused_before_anything_is_allocated() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.ntnet");
    let (net, _) = network();
    net.save(&good).unwrap();
    let file = std::fs::read(&good).unwrap();
    let bad = dir.path().join("bad.ntnet");
    let refused = |edit: &dyn Fn(&mut ciborium::Value), expected: &str| {
        let e = load(&with_body(&file, edit), &bad).err().unwrap();
        assert!(e.to_string().contains(expected), "{e}");
    };
    // "hidden" claims 2³² − 1 neurons; its saved state holds 12.
    refused(
        &|v| *at(v, "description.nodes.2.model.size") = ciborium::Value::Integer(u32::MAX.into()),
        "'hidden' has 4294967295 neurons",
    );
    // "noise" (30 channels) claims 2⁶²; its saved position holds 30 next spikes.
    refused(
        &|v| {
            *at(v, "description.nodes.0.source.poisson.size") =
                ciborium::Value::Integer((1u64 << 62).into())
        },
        "Poisson source 'noise'",
    );
    // A state missing a node's entry.
    refused(
        &|v| drop(at(v, "state.nodes").as_array_mut().unwrap().pop()),
        "node and",
    );
}

/// A saved network after a short run, its bytes and a path for the damaged copy.
fn saved_file(dir: &Path) -> (Vec<u8>, std::path::PathBuf) {
    let good = dir.join("good.ntnet");
    let (mut net, _) = network();
    net.run(0.05, &OneProcess).unwrap();
    net.save(&good).unwrap();
    (std::fs::read(&good).unwrap(), dir.join("bad.ntnet"))
}

/// `file` changed by `edit`, loaded and built: the error, which names the file.
fn refused_naming_the_file(
    file: &[u8],
    bad: &Path,
    edit: impl FnOnce(&mut ciborium::Value),
) -> String {
    let loaded = load(&with_body(file, edit), bad).map_err(|e| e.to_string());
    let e = loaded
        .and_then(|mut b| {
            b.record_spikes(b.population("out").unwrap()).unwrap();
            b.build(NetworkConfig { dt_s: DT })
                .map(|_| ())
                .map_err(|e| neurotac_core::error_chain(&e))
        })
        .expect_err("the damaged file was accepted");
    assert!(
        e.contains(&bad.display().to_string()),
        "the file is not named: {e}"
    );
    e
}

#[test]
fn a_huge_size_delay_or_step_in_a_saved_network_is_refused_before_it_is_allocated() {
    let dir = tempfile::tempdir().unwrap();
    let (file, bad) = saved_file(dir.path());
    // A delay of 2³² − 1 steps would size the spike history of 'hidden'.
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "description.projections.2.delay_steps") = ciborium::Value::Integer(u32::MAX.into())
    });
    assert!(e.contains("delay_steps") && e.contains("2²⁰"), "{e}");
    // A population of 2³² − 1 neurons whose saved state is missing.
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "description.nodes.2.model.size") = ciborium::Value::Integer(u32::MAX.into());
        *at(v, "state.nodes.2.model") = ciborium::Value::Null;
    });
    assert!(
        e.contains("'hidden' is saved without its model's state"),
        "{e}"
    );
    // A spike source saved without its position.
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "state.nodes.0.position") = ciborium::Value::Null;
    });
    assert!(
        e.contains("'noise' is saved without its source's position"),
        "{e}"
    );
    // A saved step near 2⁶⁴.
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "state.step") = ciborium::Value::Integer((u64::MAX - 5).into())
    });
    assert!(e.contains("step 18446744073709551610"), "{e}");
}

#[test]
fn a_spike_in_the_delay_lines_of_a_neuron_that_does_not_exist_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (file, bad) = saved_file(dir.path());
    let spike = |index: u64, fraction: f64| {
        ciborium::Value::Array(vec![
            ciborium::Value::Array(vec![ciborium::Value::Integer(index.into())]),
            ciborium::Value::Array(vec![ciborium::Value::Float(fraction)]),
        ])
    };
    // 'hidden' (12 neurons) feeds all-to-all (phantom spike) and is fed sparsely (a panic).
    for node in [2, 0] {
        let e = refused_naming_the_file(&file, &bad, |v| {
            *at(v, &format!("state.nodes.{node}.history.0")) = spike(999, 0.0);
        });
        assert!(e.contains("neuron 999 of"), "{e}");
    }
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "state.nodes.2.history.0") = spike(1, f64::NAN);
    });
    assert!(e.contains("fraction NaN"), "{e}");
}

#[test]
fn non_finite_currents_and_traces_are_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let (file, bad) = saved_file(dir.path());
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "state.projections.2.current.1") = ciborium::Value::Float(f64::NAN)
    });
    assert!(e.contains("projection 2: synaptic current 1 is NaN"), "{e}");
    for (side, value) in [("pre", f64::NAN), ("post", f64::INFINITY), ("pre", -1.0)] {
        let e = refused_naming_the_file(&file, &bad, |v| {
            *at(v, &format!("state.projections.0.plasticity.{side}.0.3")) =
                ciborium::Value::Float(value)
        });
        assert!(
            e.contains(&format!("STDP {side} trace 3 is {value}")),
            "{e}"
        );
    }
    let e = refused_naming_the_file(&file, &bad, |v| {
        *at(v, "state.projections.0.plasticity.post.1.0") =
            ciborium::Value::Integer(u64::MAX.into())
    });
    assert!(e.contains("after the saved step"), "{e}");
}

#[test]
fn a_state_of_another_shape_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (file, bad) = saved_file(dir.path());
    let e = refused_naming_the_file(&file, &bad, |v| {
        at(v, "state.projections.2.current")
            .as_array_mut()
            .unwrap()
            .pop();
    });
    assert!(e.contains("projection 2 has 2 currents, expected 3"), "{e}");
}

/// The description of [`network`] with `edit` made to its JSON.
fn described(edit: impl FnOnce(&mut serde_json::Value)) -> NetworkDescription {
    let (net, _) = network();
    let mut json = serde_json::to_value(net.describe().unwrap()).unwrap();
    edit(&mut json);
    serde_json::from_value(json).unwrap()
}

/// The error of building `description` (with every population's spikes recorded).
fn build_error(description: &NetworkDescription, dt_s: f64) -> String {
    let built = NetworkBuilder::from_description(description, &LeakyFactory).and_then(|mut b| {
        for name in ["hidden", "out"] {
            if let Ok(p) = b.population(name) {
                b.record_spikes(p)?;
            }
        }
        b.build(NetworkConfig { dt_s })
    });
    neurotac_core::error_chain(&built.err().expect("the description was accepted"))
}

#[test]
fn a_description_of_what_the_machine_cannot_hold_is_an_error_not_an_abort() {
    let e = build_error(
        &described(|d| d["projections"][2]["delay_steps"] = u32::MAX.into()),
        DT,
    );
    assert!(e.contains("delay_steps") && e.contains("4294967295"), "{e}");
    let e = build_error(
        &described(|d| d["nodes"][0]["source"]["poisson"]["size"] = (1u64 << 40).into()),
        DT,
    );
    assert!(e.contains("'noise'") && e.contains("2³² − 1"), "{e}");
    // A plastic 200 000 × 200 000 all-to-all projection: 4·10¹⁰ synapses.
    let e = build_error(
        &described(|d| {
            d["nodes"][0]["source"]["poisson"]["size"] = 200_000.into();
            d["nodes"][2]["model"]["size"] = 200_000.into();
            d["projections"][0]["wiring"] = serde_json::json!({"all_to_all": {"weight": 0.2}});
        }),
        DT,
    );
    assert!(
        e.contains("projection 'noise' → 'hidden'") && e.contains("more than can be allocated"),
        "{e}"
    );
}

#[test]
fn a_run_of_more_steps_than_can_be_done_is_refused_not_spun() {
    let (b, _) = builder();
    let mut net = b.build(NetworkConfig { dt_s: 1e-300 }).unwrap();
    let e = net.run(0.01, &OneProcess).unwrap_err().to_string();
    assert!(e.contains("2⁴⁰ steps"), "{e}");
    assert_eq!(net.steps_done(), 0);
    let (b, _) = builder();
    let mut net = b.build(NetworkConfig { dt_s: DT }).unwrap();
    assert!(net.run_steps(u64::MAX, &OneProcess).is_err());
    assert_eq!(net.steps_for(0.01).unwrap(), 100);
}

#[test]
fn stdp_whose_updates_overflow_and_weights_outside_the_bounds_are_refused_plainly() {
    let plastic = |rule: Stdp, weight: f64, dt_s: f64| {
        let mut b = NetworkBuilder::new();
        let input = b
            .add_spike_input("in", PoissonInput::new(4, 10.0, 1))
            .unwrap();
        let out = b.add_population("out", Leaky::new(2, 0.01)).unwrap();
        let connected = b.connect_plastic(
            input,
            out,
            Connectivity::AllToAll { weight },
            ExpSynapse::new(5e-3),
            rule,
        );
        connected
            .and_then(|_| {
                b.record_spikes(out)?;
                b.build(NetworkConfig { dt_s })
            })
            .err()
            .map(|e| e.to_string())
    };
    let rule = Stdp::additive(0.02, 0.02, 0.01, 0.011, 6.0);
    assert_eq!(plastic(rule, 0.5, DT), None);
    let e = plastic(
        Stdp {
            a_plus: 1e308,
            ..rule.multiplicative()
        },
        0.5,
        DT,
    )
    .unwrap();
    assert!(e.contains("a_plus"), "{e}");
    let e = plastic(
        Stdp {
            tau_plus_s: 5e-324,
            ..rule
        },
        0.5,
        DT,
    )
    .unwrap();
    assert!(e.contains("tau_plus_s") && e.contains("dt/τ"), "{e}");
    let e = plastic(rule, 7.0, DT).unwrap();
    assert_eq!(
        e,
        "projection 'in' → 'out': initial weight 7 of synapse 0 is outside the STDP bounds [0, 6]"
    );
    // Weights set later: said once, with the bounds they are outside.
    let (mut net, parts) = network();
    let mut w = net.weights(parts.plastic).unwrap();
    w.weight[3] = 0.9;
    let e = net.set_weights(parts.plastic, &w).unwrap_err().to_string();
    assert_eq!(
        e,
        "set_weights of projection 0: new weight 0.9 of synapse 3 is outside the STDP bounds [0, 0.4]"
    );
}
