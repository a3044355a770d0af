//! `neurotac recognise` as a user runs it: replaying an event file against a
//! training set, `--json`, bad input, and `--eval`.

mod common;

use common::neurotac;
use neurotac_core::SpikeDataset;
use neurotac_experiments::coding::CodingName;
use neurotac_experiments::menu::Menu;
use std::path::{Path, PathBuf};

/// `neurotac simulate` of 2 slides per artificial texture with their pixel events.
fn simulated(dir: &Path) -> (PathBuf, PathBuf) {
    let out = dir.join("sim");
    let (ok, _, stderr) = neurotac(&[
        "simulate",
        "--set",
        "artificial",
        "--trials",
        "2",
        "--pixel-events",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        dir.join("cache").to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    (
        out.join("artificial.bin"),
        out.join("events/05-grid_2.5_mm/001.aedat4"),
    )
}

#[test]
fn recognise_replays_an_event_file_and_reports_every_window_and_bad_input_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let (train, events) = simulated(dir.path());
    let (train_s, events_s) = (train.to_str().unwrap(), events.to_str().unwrap());

    let recognise = |train: &Path, input: &Path| {
        neurotac(&[
            "recognise",
            "--train",
            train.to_str().unwrap(),
            "--input",
            input.to_str().unwrap(),
        ])
    };

    // Text: one line per decision change, a final line with the latency.
    let (ok, stdout, stderr) = recognise(&train, &events);
    assert!(ok, "{stderr}");
    assert!(
        stdout.starts_with("training: 22 slides of 11 textures"),
        "{stdout}"
    );
    let last = stdout.lines().last().unwrap();
    assert!(
        last.starts_with("final: grid ") && last.contains("decision latency p50"),
        "{stdout}"
    );

    // JSON: every window's decision, then the final one, for every coding of the menu.
    for coding in CodingName::ALL.iter().map(|c| c.key()) {
        let (ok, stdout, stderr) = neurotac(&[
            "recognise",
            "--train",
            train_s,
            "--input",
            events_s,
            "--coding",
            coding,
            "--json",
        ]);
        assert!(ok, "{coding}: {stderr}");
        let lines: Vec<serde_json::Value> = stdout
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        let (windows, last) = lines.split_at(lines.len() - 1);
        // A recording lasts the paper's 4.528 s at 15 mm/s give or take the loop's latencies
        // (a few ms): about 226 windows of 20 ms.
        assert!(
            (223..=230).contains(&windows.len()),
            "{coding}: {}",
            windows.len()
        );
        assert!((windows[0]["t_s"].as_f64().unwrap() - 0.02).abs() < 1e-12);
        // The sensor is at rest for the first windows: every training prefix is equally far,
        // so the vote is a tie, said as one and never stable.
        assert_eq!(windows[0]["tie"], true, "{coding}: {}", windows[0]);
        assert_eq!(windows[0]["stable"], false, "{coding}");
        assert_eq!(windows[0]["same_for_windows"], 0, "{coding}");
        assert!(windows.iter().any(|w| w["tie"] == false), "{coding}");
        assert!(
            last[0]["final"]["class_name"]
                .as_str()
                .unwrap()
                .starts_with("grid ")
        );
    }

    // A training set made for another sensor.
    let mut data = SpikeDataset::load(&train).unwrap();
    data.meta_mut()["transduction"]["width"] = 346.into();
    let other = dir.path().join("other.bin");
    data.save_binary(&other).unwrap();
    let (ok, _, stderr) = recognise(&other, &events);
    assert!(!ok);
    assert!(
        stderr.contains("346×180 sensor") && stderr.contains("240×180"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");

    // Spike times in other units.
    let mut data = SpikeDataset::load(&train).unwrap();
    data.meta_mut().insert("time_unit".into(), "ms".into());
    data.save_binary(&other).unwrap();
    let (ok, _, stderr) = recognise(&other, &events);
    assert!(!ok && stderr.contains("'ms'"), "{stderr}");

    // An empty stream.
    let empty = dir.path().join("empty.csv");
    std::fs::write(&empty, "t,x,y,on\n").unwrap();
    let (ok, _, stderr) = recognise(&train, &empty);
    assert!(
        !ok && stderr.contains("the event stream is empty"),
        "{stderr}"
    );

    // Events out of order after 0.1 s: the error names the event; what was decided is said.
    let backwards = dir.path().join("backwards.csv");
    let mut csv = String::from("t,x,y,on\n");
    for k in 0..400 {
        csv.push_str(&format!("{},120,90,1\n", k * 300));
    }
    csv.push_str("5,120,90,1\n");
    std::fs::write(&backwards, csv).unwrap();
    let (ok, _, stderr) = recognise(&train, &backwards);
    assert!(!ok, "{stderr}");
    assert!(stderr.contains("decided so far:"), "{stderr}");
    assert!(stderr.contains("earlier than the previous"), "{stderr}");
}

/// Without a source the error names every one: `--input`, `--device` and `--eval`.
#[test]
fn recognise_without_a_source_names_every_source() {
    let (ok, _, stderr) = neurotac(&["recognise", "--train", "t.json"]);
    assert!(!ok, "{stderr}");
    for flag in ["--input", "--device", "--eval"] {
        assert!(stderr.contains(flag), "{flag}: {stderr}");
    }
    let (ok, _, stderr) = neurotac(&["recognise", "--train", "t.json", "--input", "x", "--device"]);
    assert!(!ok && stderr.contains("cannot be used with"), "{stderr}");
}

#[test]
fn recognise_eval_writes_accuracy_against_time_for_every_coding() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("eval");
    let (ok, stdout, stderr) = neurotac(&[
        "recognise",
        "--eval",
        "--set",
        "artificial",
        "--trials",
        "5",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        dir.path().join("cache").to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("| spatiotemporal |"), "{stdout}");
    for f in [
        "summary.md",
        "summary.json",
        "accuracy_vs_time.csv",
        "accuracy_vs_time.svg",
        "accuracy_vs_time.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(out.join("accuracy_vs_time.csv")).unwrap();
    let keys: Vec<&str> = CodingName::ALL.iter().map(|c| c.key()).collect();
    assert!(
        csv.starts_with(&format!("t_s,{}\n0.020,", keys.join(","))),
        "{csv}"
    );
    // A header, then one row per 20 ms window of the recordings (about 4.53 s each).
    assert!((1 + 223..=1 + 230).contains(&csv.lines().count()), "{csv}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["n_test"], 11);
    // Self-describing: named latency fields, the k used, every file written.
    assert_eq!(summary["k"], 4);
    for coding in summary["codings"].as_array().unwrap() {
        let latency = &coding["latency"];
        for field in ["p50_ms", "p99_ms", "max_ms"] {
            assert!(latency[field].as_f64().unwrap() >= 0.0, "{coding}");
        }
    }
    let files: Vec<&str> = summary["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(files.len(), 5);
    for f in &files {
        assert!(out.join(f).is_file(), "{f}");
        assert!(
            stdout.contains(&format!("`{f}`")),
            "{f} not listed:\n{stdout}"
        );
    }
    assert!(stdout.contains("k = 4"), "{stdout}");
    // An existing report is refused without --force.
    let (ok, _, stderr) = neurotac(&[
        "recognise",
        "--eval",
        "--set",
        "artificial",
        "--trials",
        "5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("exists"), "{stderr}");
}

/// A real-time replay does not wait for an event far past the kept duration (10¹⁵ µs, years):
/// nothing after the training slides' duration is used.
#[test]
fn realtime_replay_does_not_wait_past_the_kept_duration() {
    let dir = tempfile::tempdir().unwrap();
    let (train, _) = simulated(dir.path());
    let events = dir.path().join("far.csv");
    std::fs::write(
        &events,
        "t,x,y,p\n0,100,90,1\n1000,101,90,1\n1000000000000000,102,90,1\n",
    )
    .unwrap();
    let (ok, stdout, stderr) = neurotac(&[
        "recognise",
        "--train",
        train.to_str().unwrap(),
        "--input",
        events.to_str().unwrap(),
        "--speed",
        "realtime",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.lines().last().unwrap().starts_with("final: "),
        "{stdout}"
    );
}
