//! The committed corpora of the fuzz targets `saved_network` and `description`
//! (`fuzz/corpus/<target>/`), replayed on stable through the fuzzer's own checks
//! (`neurotac_neurons::testing`): every file reads, builds and runs, or fails with a typed error —
//! never a panic or an abort — within a memory budget set by its size. The named seeds (saved
//! networks and descriptions of the built-in models, and every crafted case of the issue that
//! made loading validation: huge delays, sizes and steps, a population saved without its state,
//! spikes of neurons that do not exist, NaN currents and traces, a time step of 10⁻³⁰⁰ s) are
//! written by `write_the_named_seeds` (`fuzz/make_seeds.sh` runs it), and each crafted one is
//! checked to be refused for its reason.

use ciborium::Value;
use neurotac_core::testing::fuzz::{
    FUZZ_PATH, PeakAllocator, corpus, peak_since, reset_peak, saved_network_file,
};
use neurotac_core::{
    Connectivity, CurrentInput, ExpSynapse, MultiSpikeTrain, Network, NetworkBuilder,
    NetworkConfig, OneProcess, PoissonInput, SpikeArrayInput, Stdp, Stepping,
};
use neurotac_neurons::testing::{check_description_text, check_saved_network_bytes};
use neurotac_neurons::{BuiltinModels, Izhikevich, IzhikevichParams, Lif, LifParams};
use std::path::{Path, PathBuf};

#[global_allocator]
static GLOBAL: PeakAllocator = PeakAllocator;

/// Fixed part of the memory budget of one file: a small network built and run.
const BUDGET_FIXED_BYTES: usize = 32 << 20;

/// Memory budget per input byte (a JSON number becomes a value, a list a vector, in the
/// description and again in the network).
const BUDGET_PER_INPUT_BYTE: usize = 256;

/// Poisson (20) and recorded (3) inputs → LIF f64 (10, plastic) → (delay 2, plastic,
/// multiplicative) → Izhikevich f32 (4) with a current, stepped as `stepping`, run 20 ms.
fn network(stepping: Stepping) -> Network {
    let mut b = NetworkBuilder::new();
    b.stepping(stepping);
    let noise = b
        .add_spike_input("noise", PoissonInput::new(20, 80.0, 3))
        .unwrap();
    let trains = MultiSpikeTrain::from_channels(vec![vec![0.001, 0.004], vec![], vec![0.0025]]);
    let taxels = b
        .add_spike_input("taxels", SpikeArrayInput::new(trains.unwrap()))
        .unwrap();
    let hidden = b
        .add_population("hidden", Lif::<f64>::new(10, LifParams::default()))
        .unwrap();
    let out = b
        .add_population(
            "out",
            Izhikevich::<f32>::new(4, IzhikevichParams::default()),
        )
        .unwrap();
    let random = Connectivity::Random {
        probability: 0.5,
        weight: 0.4,
        seed: 2,
    };
    let stdp = Stdp::additive(0.02, 0.02, 0.02, 0.022, 0.8);
    b.connect_plastic(
        noise,
        hidden,
        random,
        ExpSynapse::new(5e-3).with_delay(0),
        stdp,
    )
    .unwrap();
    b.connect(
        taxels,
        hidden,
        Connectivity::AllToAll { weight: 0.6 },
        ExpSynapse::new(3e-3).with_delay(0),
    )
    .unwrap();
    let to_out = Stdp::additive(0.02, 0.02, 0.1, 0.11, 6.0).multiplicative();
    b.connect_plastic(
        hidden,
        out,
        Connectivity::AllToAll { weight: 3.0 },
        ExpSynapse::new(5e-3).with_delay(2),
        to_out,
    )
    .unwrap();
    let drive = b
        .add_current_input("drive", CurrentInput::constant(2.0))
        .unwrap();
    b.inject(drive, out).unwrap();
    b.record_spikes(out).unwrap();
    let mut net = b.build(NetworkConfig { dt_s: 1e-4 }).unwrap();
    net.run(0.02, &OneProcess).unwrap();
    net
}

/// The value at `path` in `v` (map keys and array indices joined by dots).
fn at<'a>(v: &'a mut Value, path: &str) -> &'a mut Value {
    path.split('.').fold(v, |v, step| match v {
        Value::Array(a) => &mut a[step.parse::<usize>().unwrap()],
        Value::Map(m) => {
            &mut m
                .iter_mut()
                .find(|(k, _)| k.as_text() == Some(step))
                .unwrap()
                .1
        }
        _ => panic!("{path}: {step} is in neither a map nor an array"),
    })
}

fn cbor(v: &Value) -> Vec<u8> {
    let mut out = Vec::new();
    ciborium::ser::into_writer(v, &mut out).unwrap();
    out
}

/// The crafted saved-network bodies (CBOR), each with the words its refusal must contain.
fn crafted_bodies(body: &Value) -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let edit = |f: &dyn Fn(&mut Value)| {
        let mut v = body.clone();
        f(&mut v);
        cbor(&v)
    };
    let int = |n: u64| Value::Integer(n.into());
    vec![
        (
            "delay_u32_max",
            edit(&|v| *at(v, "description.projections.2.delay_steps") = int(u32::MAX.into())),
            "delay_steps",
        ),
        (
            "population_without_state",
            edit(&|v| {
                *at(v, "description.nodes.2.model.size") = int(u32::MAX.into());
                *at(v, "state.nodes.2.model") = Value::Null;
            }),
            "saved without its model's state",
        ),
        (
            "poisson_2_40_channels",
            edit(&|v| *at(v, "description.nodes.0.source.poisson.size") = int(1 << 40)),
            "'noise'",
        ),
        (
            "history_index_out_of_range",
            edit(&|v| {
                *at(v, "state.nodes.2.history.0") = Value::Array(vec![
                    Value::Array(vec![int(999)]),
                    Value::Array(vec![Value::Float(0.0)]),
                ])
            }),
            "neuron 999 of 10",
        ),
        (
            "step_near_2_64",
            edit(&|v| *at(v, "state.step") = int(u64::MAX - 5)),
            "step 18446744073709551610",
        ),
        (
            "nan_current",
            edit(&|v| *at(v, "state.projections.2.current.0") = Value::Float(f64::NAN)),
            "synaptic current 0 is NaN",
        ),
        (
            "nan_trace",
            edit(&|v| *at(v, "state.projections.0.plasticity.pre.0.0") = Value::Float(f64::NAN)),
            "STDP pre trace 0 is NaN",
        ),
    ]
}

/// The crafted descriptions (JSON), each with the words its refusal must contain.
fn crafted_descriptions(d: &serde_json::Value) -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let edit = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut v = d.clone();
        f(&mut v);
        serde_json::to_vec(&v).unwrap()
    };
    vec![
        (
            "delay_u32_max",
            edit(&|v| v["projections"][2]["delay_steps"] = u32::MAX.into()),
            "delay_steps",
        ),
        (
            "poisson_2_40_channels",
            edit(&|v| v["nodes"][0]["source"]["poisson"]["size"] = (1u64 << 40).into()),
            "'noise'",
        ),
        (
            "population_u32_max",
            edit(&|v| v["nodes"][2]["model"]["size"] = u32::MAX.into()),
            "more than can be allocated",
        ),
        (
            "plastic_all_to_all_200k",
            edit(&|v| {
                v["nodes"][0]["source"]["poisson"]["size"] = 200_000.into();
                v["nodes"][2]["model"]["size"] = 200_000.into();
                v["nodes"][2]["model"]["settings"]["initial"] =
                    serde_json::json!({"constant": 0.0});
                v["projections"][0]["wiring"] = serde_json::json!({"all_to_all": {"weight": 0.4}});
            }),
            "more than can be allocated",
        ),
        (
            "tau_plus_5e-324",
            edit(&|v| v["projections"][0]["plasticity"]["tau_plus_s"] = 5e-324.into()),
            "tau_plus_s",
        ),
        (
            "a_plus_1e308_multiplicative",
            edit(&|v| v["projections"][2]["plasticity"]["a_plus"] = 1e308.into()),
            "a_plus",
        ),
    ]
}

/// The refusal of `bytes` read as a saved-network body (`None`: it builds).
fn saved_refusal(body: &[u8]) -> Option<String> {
    let file = saved_network_file(body);
    let result = NetworkBuilder::from_saved_bytes(&file, Path::new(FUZZ_PATH), &BuiltinModels)
        .map_err(|e| neurotac_core::error_chain(&e))
        .and_then(|b| built(b, None));
    result.err()
}

/// The refusal of `text` read as a description (`None`: it builds).
fn description_refusal(text: &[u8]) -> Option<String> {
    let d: neurotac_core::NetworkDescription = serde_json::from_slice(text).ok()?;
    NetworkBuilder::from_description(&d, &BuiltinModels)
        .map_err(|e| neurotac_core::error_chain(&e))
        .and_then(|b| built(b, Some(d.dt_s)))
        .err()
}

fn built(mut b: NetworkBuilder, dt_s: Option<f64>) -> Result<(), String> {
    let dt_s = dt_s.or(b.saved_dt_s()).unwrap();
    let out = b.population("out").map_err(|e| e.to_string())?;
    b.record_spikes(out).map_err(|e| e.to_string())?;
    let mut net = b
        .build(NetworkConfig { dt_s })
        .map_err(|e| neurotac_core::error_chain(&e))?;
    net.run(0.001, &OneProcess)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

fn corpus_folder(target: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fuzz/corpus")
        .join(target)
}

/// Writes the named seeds (`fuzz/make_seeds.sh` runs this).
#[test]
#[ignore = "writes fuzz/corpus/saved_network and fuzz/corpus/description; run by fuzz/make_seeds.sh"]
fn write_the_named_seeds() {
    let (saved, described) = (corpus_folder("saved_network"), corpus_folder("description"));
    std::fs::create_dir_all(&saved).unwrap();
    std::fs::create_dir_all(&described).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (name, stepping) in [("clock", Stepping::Clock), ("event", Stepping::Event)] {
        let net = network(stepping);
        let file = dir.path().join("net.ntnet");
        net.save(&file).unwrap();
        let bytes = std::fs::read(&file).unwrap();
        std::fs::write(saved.join(format!("{name}.ntnet")), &bytes).unwrap();
        let body = &bytes[20..bytes.len() - 4];
        std::fs::write(saved.join(format!("{name}_body.cbor")), body).unwrap();
        for cut in [1, 9, 40, body.len() / 2, body.len() - 1] {
            std::fs::write(
                saved.join(format!("{name}_body_cut_{cut}.cbor")),
                &body[..cut],
            )
            .unwrap();
        }
        let json = serde_json::to_vec_pretty(&net.describe().unwrap()).unwrap();
        std::fs::write(described.join(format!("{name}.json")), &json).unwrap();
        for cut in [1, 30, json.len() / 2, json.len() - 1] {
            std::fs::write(
                described.join(format!("{name}_cut_{cut}.json")),
                &json[..cut],
            )
            .unwrap();
        }
    }
    let bytes = std::fs::read(saved.join("clock.ntnet")).unwrap();
    let body: Value = ciborium::de::from_reader(&bytes[20..bytes.len() - 4]).unwrap();
    for (name, crafted, _) in crafted_bodies(&body) {
        std::fs::write(saved.join(format!("{name}.cbor")), crafted).unwrap();
    }
    let d: serde_json::Value =
        serde_json::from_slice(&std::fs::read(described.join("clock.json")).unwrap()).unwrap();
    for (name, crafted, _) in crafted_descriptions(&d) {
        std::fs::write(described.join(format!("{name}.json")), crafted).unwrap();
    }
    let mut tiny = d.clone();
    tiny["dt_s"] = 1e-300.into();
    std::fs::write(
        described.join("dt_1e-300.json"),
        serde_json::to_vec(&tiny).unwrap(),
    )
    .unwrap();
    for (name, text) in [
        ("empty_object", "{}"),
        ("array", "[]"),
        (
            "weight_overflow",
            "{\"format\":\"neurotac-network\",\"version\":1,\"dt_s\":1e-4,\"stepping\":\"clock\",\"nodes\":[],\"projections\":[{\"pre\":\"a\",\"post\":\"b\",\"tau_s\":1e999,\"delay_steps\":1,\"wiring\":{\"all_to_all\":{\"weight\":1}},\"plasticity\":null}]}",
        ),
        (
            "unknown_node",
            "{\"format\":\"neurotac-network\",\"version\":1,\"dt_s\":1e-4,\"stepping\":\"clock\",\"nodes\":[],\"projections\":[{\"pre\":\"a\",\"post\":\"b\",\"tau_s\":0.005,\"delay_steps\":1,\"wiring\":{\"all_to_all\":{\"weight\":1}},\"plasticity\":null}]}",
        ),
    ] {
        std::fs::write(described.join(format!("{name}.json")), text).unwrap();
    }
}

/// Replays `target`'s corpus through `check` within the memory budget; the files replayed.
fn replay(target: &str, check: fn(&[u8])) -> Option<usize> {
    let files = corpus(target)?;
    assert!(!files.is_empty(), "{target}: empty corpus");
    let mut total_bytes = 0;
    for (name, bytes) in &files {
        let start = reset_peak();
        if std::panic::catch_unwind(|| check(bytes)).is_err() {
            panic!("{target}/{name}: a check failed (message above)");
        }
        let used = peak_since(start);
        let budget = BUDGET_FIXED_BYTES + BUDGET_PER_INPUT_BYTE * bytes.len();
        assert!(
            used <= budget,
            "{target}/{name}: {used} bytes allocated at the peak, budget {budget}"
        );
        total_bytes += bytes.len();
    }
    assert!(
        total_bytes <= 1_000_000,
        "{target}: corpus of {total_bytes} bytes"
    );
    Some(files.len())
}

#[test]
fn every_saved_network_and_description_corpus_file_runs_or_fails_typed() {
    let Some(saved) = replay("saved_network", check_saved_network_bytes) else {
        return;
    };
    let Some(described) = replay("description", check_description_text) else {
        return;
    };
    // The named seeds: the good ones build and run, each crafted one is refused for its reason.
    let read = |target: &str, name: &str| {
        std::fs::read(corpus_folder(target).join(name))
            .unwrap_or_else(|e| panic!("{target}/{name}: {e}"))
    };
    for stepping in ["clock", "event"] {
        assert_eq!(
            saved_refusal(&read("saved_network", &format!("{stepping}_body.cbor"))),
            None
        );
        assert_eq!(
            description_refusal(&read("description", &format!("{stepping}.json"))),
            None
        );
    }
    let body: Value =
        ciborium::de::from_reader(&read("saved_network", "clock_body.cbor")[..]).unwrap();
    for (name, _, reason) in crafted_bodies(&body) {
        let e = saved_refusal(&read("saved_network", &format!("{name}.cbor")))
            .unwrap_or_else(|| panic!("saved_network/{name}.cbor was accepted"));
        assert!(
            e.contains(reason) && e.contains(FUZZ_PATH),
            "saved_network/{name}.cbor: {e}"
        );
    }
    let d: serde_json::Value = serde_json::from_slice(&read("description", "clock.json")).unwrap();
    for (name, _, reason) in crafted_descriptions(&d) {
        let e = description_refusal(&read("description", &format!("{name}.json")))
            .unwrap_or_else(|| panic!("description/{name}.json was accepted"));
        assert!(e.contains(reason), "description/{name}.json: {e}");
    }
    let e = description_refusal(&read("description", "dt_1e-300.json"));
    assert!(e.is_some_and(|e| e.contains("2⁴⁰ steps")), "dt_1e-300.json");
    eprintln!("replayed {saved} saved-network and {described} description corpus files");
}
