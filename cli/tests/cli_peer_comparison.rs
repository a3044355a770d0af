//! `bench --brian2` compares like for like: the peer is asked for the same precision and
//! method, says what it ran, and no ratio is printed when the two differ. The peer here is a
//! stand-in interpreter that logs its arguments and prints a fixed answer, so the tests need
//! no Brian2.
#![cfg(unix)]

mod common;

use common::neurotac;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// A stand-in "python" in `dir` that appends its arguments (the script path first) to
/// `dir/calls` and prints `answer`.
fn fake_peer(dir: &Path, answer: &str) -> PathBuf {
    let calls = dir.join("calls");
    let path = dir.join("python");
    std::fs::write(
        &path,
        format!(
            "#!/bin/sh\necho \"$*\" >> '{}'\necho '{answer}'\n",
            calls.display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

fn calls(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join("calls"))
        .unwrap_or_default()
        .lines()
        .map(str::to_owned)
        .collect()
}

fn bench(python: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "bench",
        "neurons",
        "--n",
        "1000",
        "--duration",
        "10ms",
        "--repeats",
        "2",
        "--json",
        "--brian2",
        python.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (ok, out, err) = neurotac(&args);
    assert!(ok, "{err}");
    serde_json::from_str(out.trim()).expect("one JSON object")
}

#[test]
fn the_peer_is_asked_for_the_same_precision_and_method_and_a_ratio_only_when_it_ran_them() {
    let dir = tempfile::tempdir().unwrap();
    let answer = r#"{"peer": "peer 1", "precision": "float64", "method": "euler", "run_s": 0.5, "spikes": 3}"#;
    let python = fake_peer(dir.path(), answer);

    let r = bench(&python, &["--precision", "f64", "--integrator", "euler"]);
    assert!(r["speedup"].as_f64().unwrap() > 0.0, "{r}");
    assert_eq!(r["peer_precision"], "float64");
    assert_eq!(r["peer_method"], "euler");
    let asked = calls(dir.path());
    // One peer run per repeat, each asked for the model, precision and method.
    assert_eq!(asked.len(), 2, "{asked:?}");
    assert!(
        asked
            .iter()
            .all(|c| c.contains(" neurons lif 1000 0.01 0.0001 ") && c.ends_with(" float64 euler")),
        "{asked:?}"
    );

    // neurotac at f32 against a peer that says it ran float64: numbers, no ratio.
    let r = bench(&python, &["--precision", "f32", "--integrator", "euler"]);
    assert!(r.get("speedup").is_none(), "{r}");
    let why = r["no_ratio"].as_str().unwrap();
    assert!(why.contains("float64") && why.contains("float32"), "{why}");
    assert!(calls(dir.path())[2].ends_with(" float32 euler"));

    // A peer that does not say what it ran gets no ratio either.
    let silent = tempfile::tempdir().unwrap();
    let python = fake_peer(
        silent.path(),
        r#"{"peer": "old", "run_s": 0.5, "spikes": 3}"#,
    );
    let r = bench(&python, &["--precision", "f64", "--integrator", "euler"]);
    assert!(r["no_ratio"].as_str().unwrap().contains("unstated"), "{r}");
}

#[test]
fn an_integrator_brian2_does_not_have_is_refused_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let python = fake_peer(dir.path(), "{}");
    for integrator in [None, Some("izhikevich2003"), Some("exp-euler")] {
        let mut args = vec!["bench", "neurons", "--model", "izhikevich", "--n", "1000"];
        args.extend(integrator.iter().flat_map(|i| ["--integrator", *i]));
        args.extend(["--brian2", python.to_str().unwrap()]);
        let (ok, out, err) = neurotac(&args);
        assert!(!ok && out.is_empty(), "{out}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains("no like-for-like comparison") && err.contains("--integrator euler"),
            "{err}"
        );
    }
    assert!(calls(dir.path()).is_empty(), "the peer must not run");
}

#[test]
fn cuba_asks_the_peer_for_float64_and_exponential_euler() {
    let dir = tempfile::tempdir().unwrap();
    let answer = r#"{"peer": "peer 1", "precision": "float64", "method": "exp-euler", "run_s": 0.5, "spikes": 3}"#;
    let python = fake_peer(dir.path(), answer);
    let (ok, out, err) = neurotac(&[
        "bench",
        "cuba",
        "--neurons",
        "200",
        "--duration",
        "10ms",
        "--repeats",
        "1",
        "--json",
        "--brian2",
        python.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let r: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(
        (&r["precision"], &r["method"]),
        (&"f64".into(), &"exp-euler".into())
    );
    assert!(r["speedup"].as_f64().is_some(), "{r}");
    // The peer builds the same network: 200 neurons, 2 % connectivity.
    assert!(calls(dir.path())[0].ends_with(" float64 exp-euler 200 0.02"));
}

/// `bench stdp` with `extra` arguments (short: 1 s, 50 inputs), `(success, stdout, stderr)`.
fn bench_stdp(extra: &[&str]) -> (bool, String, String) {
    let mut args = vec!["bench", "stdp", "--duration", "1s", "--inputs", "50"];
    args.extend_from_slice(extra);
    neurotac(&args)
}

#[test]
fn stdp_asks_the_peer_for_the_same_network_and_compares_the_final_weights() {
    let dir = tempfile::tempdir().unwrap();
    // Half the peer's weights at 0, half at w_max; it fired 3 spikes.
    let answer = r#"{"peer": "peer 1", "precision": "float64", "method": "exp-euler", "run_s": 0.5, "spikes": 3, "weights": [0.0, 0.0, 0.6, 0.6], "spike_times_s": [0.1, 0.5, 0.95]}"#;
    let python = fake_peer(dir.path(), answer);
    let figure = dir.path().join("weights.svg");
    let (ok, out, err) = bench_stdp(&[
        "--seed",
        "7",
        "--json",
        "--brian2",
        python.to_str().unwrap(),
        "--figure",
        figure.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let r: serde_json::Value = serde_json::from_str(out.trim()).expect("one JSON object");
    // The peer runs the same network: 1 s at 0.1 ms, 50 inputs at 15 Hz, seed 7, float64,
    // exponential Euler, which is neurotac's exact LIF step with the current held.
    assert!(
        calls(dir.path())[0].ends_with(" stdp 1 0.0001 float64 exp-euler 50 15 7"),
        "{:?}",
        calls(dir.path())
    );
    assert_eq!(
        (&r["precision"], &r["method"]),
        (&"f64".into(), &"exp-euler".into())
    );
    assert!(r["speedup"].as_f64().unwrap() > 0.0, "{r}");
    assert_eq!(
        (r["peer_near_zero"].as_f64(), r["peer_near_max"].as_f64()),
        (Some(0.5), Some(0.5))
    );
    let rate = r["peer_final_rate_hz"].as_f64().unwrap();
    assert!(
        (rate - 10.0).abs() < 1e-9,
        "one spike in the last 0.1 s: {rate}"
    );
    // KS of 50 weights spread over [0, w_max] against 4 at the bounds.
    let ks = &r["ks"];
    assert_eq!(
        (ks["n_a"].as_u64(), ks["n_b"].as_u64()),
        (Some(50), Some(4))
    );
    let d = ks["statistic"].as_f64().unwrap();
    assert!(d > 0.0 && d < 1.0, "{ks}");
    let near = r["near_zero"].as_f64().unwrap() + r["near_max"].as_f64().unwrap();
    assert!(
        near < 1.0,
        "1 s of learning leaves weights between the bounds: {r}"
    );
    // The figure has both sides' histograms and the rate panel.
    let svg = std::fs::read_to_string(&figure).unwrap();
    assert!(svg.starts_with("<svg"), "{svg}");
    for title in [
        "neurotac: final weights",
        "peer 1: final weights",
        "output rate",
    ] {
        assert!(svg.contains(title), "{title}");
    }
}

#[test]
fn stdp_refuses_a_figure_it_cannot_write_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let python = fake_peer(dir.path(), "{}");
    let python = python.to_str().unwrap();
    let existing = dir.path().join("old.png");
    std::fs::write(&existing, b"old").unwrap();
    for (figure, says) in [
        (dir.path().join("weights.txt"), "FILE.svg or FILE.png"),
        (existing.clone(), "--force"),
    ] {
        let args = ["--brian2", python, "--figure", figure.to_str().unwrap()];
        let (ok, out, err) = bench_stdp(&args);
        assert!(!ok && out.is_empty(), "{out}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(says), "{err}");
    }
    assert!(calls(dir.path()).is_empty(), "the peer must not run");
    assert_eq!(std::fs::read(&existing).unwrap(), b"old");
}

/// The Python with Brian2 the real peer tests use: `$NEUROTAC_BRIAN2_PYTHON` (CI sets it when
/// it finds Brian2; see .ci/run), else none and the test says why it skipped.
fn brian2_python() -> Option<PathBuf> {
    match std::env::var_os("NEUROTAC_BRIAN2_PYTHON") {
        Some(python) => Some(PathBuf::from(python)),
        None => {
            eprintln!(
                "skipped: NEUROTAC_BRIAN2_PYTHON is not set (a Python with Brian2 and a C++ \
                 compiler runs the real peer)"
            );
            None
        }
    }
}

#[test]
fn stdp_against_brian2_runs_the_same_network_and_ends_with_weights_between_the_same_bounds() {
    let Some(python) = brian2_python() else {
        return;
    };
    let (ok, out, err) = neurotac(&[
        "bench",
        "stdp",
        "--duration",
        "5s",
        "--json",
        "--brian2",
        python.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let r: serde_json::Value = serde_json::from_str(out.trim()).expect("one JSON object");
    assert!(r["peer"].as_str().unwrap().starts_with("brian2"), "{r}");
    assert!(
        r["speedup"].as_f64().is_some(),
        "Brian2 ran something else: {r}"
    );
    assert_eq!(r["ks"]["n_b"].as_u64(), Some(1000), "{r}");
    // Both neurons fire, at comparable rates (the streams of the inputs differ).
    let (ours, peer) = (
        r["spikes"].as_f64().unwrap(),
        r["peer_spikes"].as_f64().unwrap(),
    );
    assert!(
        ours > 0.0 && peer > 0.0 && (ours / peer - 1.0).abs() < 0.3,
        "{r}"
    );
    assert!(r["ks"]["statistic"].as_f64().unwrap() < 0.15, "{r}");
}
