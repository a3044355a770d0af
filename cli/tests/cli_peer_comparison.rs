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
