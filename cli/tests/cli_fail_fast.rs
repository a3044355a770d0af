//! What a long run must not do: start the work and only then find it cannot write its output
//! (every output is checked before any work: kind, overwrite rule, a write probe), lose the
//! system's reason of an I/O error, or leave a log without its stages.
//!
//! A path under a regular file is the unwritable target: it cannot be created even by root, to
//! which permission bits mean nothing.

mod common;
use common::{neurotac, small_simulate};
use std::path::{Path, PathBuf};
use std::process::Command;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A regular file in `dir`, and a path under it that can never be created.
fn under_a_file(dir: &Path) -> (PathBuf, PathBuf) {
    let file = dir.join("plain");
    std::fs::write(&file, "not a folder").unwrap();
    let under = file.join("sub");
    (file, under)
}

#[test]
fn every_command_that_writes_refuses_an_unwritable_output_before_reading_or_computing() {
    let dir = tempfile::tempdir().unwrap();
    let (file, under) = under_a_file(dir.path());
    let cache = dir.path().join("cache");
    // Inputs that do not exist: a command that read (or simulated) before checking its output
    // would fail on them, or run, instead.
    let missing = dir.path().join("missing.json");
    let events = dir.path().join("missing.aedat4");
    let (missing, events, cache) = (s(&missing), s(&events), s(&cache));
    let at = |name: &str| under.join(name).to_str().unwrap().to_owned();
    let (under_s, json, csv, aedat) = (s(&under), at("x.json"), at("x.csv"), at("x.aedat4"));
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["export", missing, &json], "OUT"),
        (vec!["convert", events, &csv], "OUTPUT"),
        (vec!["filter", events, &aedat], "OUTPUT"),
        (vec!["transduce", events, "--out", &json], "--out"),
        (vec!["layout", events, "--out", &json], "--out"),
        (vec!["synth", "--output", &json], "--output"),
        (
            vec![
                "distances",
                "--input",
                missing,
                "--metric",
                "euclidean",
                "--coding",
                "spatial",
                "--output",
                &json,
            ],
            "--output",
        ),
        (
            vec![
                "classify", "--input", missing, "--coding", "spatial", "--matrix", &json,
            ],
            "--matrix",
        ),
        (
            vec!["search", "vr", "--input", missing, "--trace", &json],
            "--trace",
        ),
        (vec!["record", "--out", &aedat, "--duration", "1s"], "--out"),
        (
            vec![
                "simulate",
                "--set",
                "artificial",
                "--trials",
                "1",
                "--out",
                under_s,
                "--cache",
                cache,
            ],
            "--out",
        ),
        (vec!["simulate", "check", "--out", under_s], "--out"),
        (vec!["simulate", "calibrate", "--out", &json], "--out"),
        (
            vec![
                "reproduce",
                "--quick",
                "--set",
                "artificial",
                "--out",
                under_s,
                "--cache",
                cache,
            ],
            "--out",
        ),
        (
            vec!["tradeoff", "--quick", "--out", under_s, "--cache", cache],
            "--out",
        ),
        (
            vec!["tradeoff", "neurons", "--quick", "--out", under_s],
            "--out",
        ),
        (
            vec!["tradeoff", "simulator", "--quick", "--out", under_s],
            "--out",
        ),
        (
            vec![
                "recognise",
                "--eval",
                "--set",
                "artificial",
                "--out",
                under_s,
                "--cache",
                cache,
            ],
            "--out",
        ),
    ];
    let said = format!("{}, which is a file, not a folder", file.display());
    for (args, flag) in cases {
        let (ok, _, stderr) = neurotac(&args);
        assert!(!ok, "{args:?}: {stderr}");
        assert!(
            stderr.starts_with(&format!("error: {flag} ")) && stderr.contains(&said),
            "{args:?}: {stderr}"
        );
        // No stage started.
        assert!(!stderr.contains('▸'), "{args:?}: {stderr}");
    }
}

#[test]
fn a_file_given_where_a_folder_is_wanted_is_named_as_such_before_simulating() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("artificial.bin");
    std::fs::write(&out, "a dataset").unwrap();
    let (ok, _, stderr) = small_simulate(&out, &dir.path().join("cache"), &[]);
    assert!(!ok);
    assert_eq!(
        stderr,
        format!(
            "error: --out must be a folder: {} is a file\n",
            out.display()
        )
    );
}

#[test]
fn a_folder_given_where_a_file_is_wanted_is_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = dir.path().join("m.json");
    std::fs::create_dir(&matrix).unwrap();
    let (ok, _, stderr) = neurotac(&[
        "classify",
        "--input",
        "missing.json",
        "--coding",
        "spatial",
        "--matrix",
        s(&matrix),
    ]);
    assert!(!ok);
    assert_eq!(
        stderr,
        format!(
            "error: --matrix must be a file: {} is a folder\n",
            matrix.display()
        )
    );
}

#[test]
fn a_missing_event_file_error_says_read_and_the_system_cause() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothere.aedat4");
    let out = dir.path().join("out.csv");
    let (ok, _, stderr) = neurotac(&["convert", s(&missing), s(&out)]);
    assert!(!ok);
    assert_eq!(
        stderr,
        format!(
            "error: cannot read {}: No such file or directory (os error 2)\n",
            missing.display()
        )
    );
}

/// `neurotac ARGS` with `NEUROTAC_CACHE` set to `cache`: (success, stderr).
fn with_cache_variable(cache: &Path, args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(args)
        .env("NEUROTAC_CACHE", cache)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn an_unwritable_cache_is_said_first_with_its_source_and_the_fix_and_pixel_events_still_land() {
    let dir = tempfile::tempdir().unwrap();
    let (_, cache) = under_a_file(dir.path());
    let out = dir.path().join("out");
    let (ok, stderr) = with_cache_variable(
        &cache,
        &[
            "simulate",
            "--set",
            "artificial",
            "--trials",
            "1",
            "--threads",
            "1",
            "--pixel-events",
            "--out",
            s(&out),
        ],
    );
    assert!(ok, "{stderr}");
    let first = stderr.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("warning: the cache folder is unusable: NEUROTAC_CACHE ")
            && first.contains("--cache DIR or NEUROTAC_CACHE=DIR"),
        "{stderr}"
    );
    assert!(out.join("artificial.bin").is_file());
    assert!(out.join("events").is_dir());
}

#[test]
fn with_stderr_in_a_log_every_stage_says_when_it_starts_and_ends() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = small_simulate(
        &dir.path().join("out"),
        &dir.path().join("cache"),
        &["--threads", "1"],
    );
    assert!(ok, "{stderr}");
    // One set: its stage starts with its steps and ends with its wall time.
    assert!(stderr.contains("  ▸ artificial (11 steps)\n"), "{stderr}");
    let end = stderr
        .lines()
        .find(|l| l.starts_with("  ✓ artificial — "))
        .unwrap_or_else(|| panic!("{stderr}"));
    assert!(end.ends_with(" s"), "{stderr}");
    // A standalone meter (the simulator check's) too.
    let (ok, _, stderr) = neurotac(&[
        "simulate",
        "check",
        "--trials",
        "2",
        "--variability-trials",
        "2",
        "--threads",
        "1",
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("  ▸ check ("), "{stderr}");
    assert!(stderr.contains("  ✓ check — "), "{stderr}");
}
