//! `neurotac reproduce`: a small run end to end, its report folder, and its refusals.

mod common;

use common::{neurotac, recorded_dataset, small_reproduce};
use neurotac_experiments::coding::CodingName;
use neurotac_experiments::menu::Menu;
use neurotac_sensor::format::{Compression, Format, to_bytes};
use std::path::{Path, PathBuf};

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("neurotac-reproduce-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_small_run_prints_the_tables_and_writes_the_whole_report() {
    let dir = scratch("small");
    let (out, cache) = (dir.join("report"), dir.join("cache"));
    let (ok, stdout, stderr) = small_reproduce(&out, &cache, &[]);
    assert!(ok, "{stderr}");
    for needle in [
        "paper, Table 1",
        "| Intensive |",
        "| Spatiotemporal | τ = ",
        "78.5 ± 41.1",
        "| temporal Δt (ms) |",
        "| grid 2.5 mm | ",
        "| grid 4.5 mm | ",
        "The intensive mean ",
        "total: ",
    ] {
        assert!(stdout.contains(needle), "missing {needle:?} in\n{stdout}");
    }
    let mut files = vec![
        "report.json".to_owned(),
        "report.md".into(),
        "accuracy.csv".into(),
        "parameters.csv".into(),
        "dt_sweep_artificial.svg".into(),
        "dt_sweep_artificial.csv".into(),
        "bo_convergence_artificial.svg".into(),
        "spike_trains_artificial.svg".into(),
    ];
    let codings: Vec<&str> = CodingName::ALL.iter().map(|c| c.key()).collect();
    for c in &codings {
        files.push(format!("confusion_artificial_{c}.svg"));
        files.push(format!("confusion_artificial_{c}.csv"));
    }
    for f in &files {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let set = &json["sets"][0]["direct"];
    assert_eq!(set["name"], "artificial");
    assert_eq!(set["codings"].as_array().unwrap().len(), codings.len());
    let spatiotemporal = codings.iter().position(|&c| c == "spatiotemporal").unwrap();
    let bayes = &set["codings"][spatiotemporal]["search"]["bayes"];
    assert_eq!(bayes["result"]["trace"].as_array().unwrap().len(), 12);
    assert_eq!(set["codings"][0]["loo"]["accuracy"]["n"], 33);
    // Every coding of the menu of one set in the accuracy table, plus the header.
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + codings.len(), "{csv}");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("![spike trains](spike_trains_artificial.svg)"));
    // One total: the report's time is the terminal's, and each says what it covers.
    let report_s = md
        .split_once("): ")
        .and_then(|(_, rest)| rest.split_once(" s wall"))
        .map(|(s, _)| s)
        .expect("report.md states its time");
    assert!(md.contains("everything but writing this report"), "{md}");
    assert!(
        stdout.contains(&format!(
            "({report_s} s datasets and pipelines, as report.md states, + "
        )),
        "report.md says {report_s} s; terminal:\n{stdout}"
    );
    // Nothing partial is left beside the report.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.contains("partial"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // The same seed gives the same numbers on one thread (the cached dataset is reused).
    let again = dir.join("again");
    let (ok, stdout2, stderr) = small_reproduce(&again, &cache, &["--threads", "1"]);
    assert!(ok, "{stderr}");
    let table = |s: &str| -> String { s.lines().filter(|l| l.starts_with('|')).collect() };
    assert_eq!(table(&stdout), table(&stdout2));
    let numbers = |dir: &Path| std::fs::read_to_string(dir.join("accuracy.csv")).unwrap();
    let without_time = |csv: String| -> Vec<String> {
        csv.lines()
            .map(|l| l.rsplit_once(',').map_or(l, |(head, _)| head).to_owned())
            .collect()
    };
    assert_eq!(without_time(numbers(&out)), without_time(numbers(&again)));

    // An existing report folder is refused without --force, and kept as it was.
    let before = std::fs::read_to_string(out.join("report.json")).unwrap();
    let (ok, _, stderr) = small_reproduce(&out, &cache, &["--seed", "2"]);
    assert!(!ok);
    assert!(
        stderr.contains("already exists") && stderr.contains("--force"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("report.json")).unwrap(),
        before
    );
    let (ok, _, stderr) = small_reproduce(&out, &cache, &["--seed", "2", "--force"]);
    assert!(ok, "{stderr}");
    assert_ne!(
        std::fs::read_to_string(out.join("report.json")).unwrap(),
        before
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_afferent_variant_reports_accuracy_and_time_next_to_the_direct_pipeline() {
    let dir = scratch("afferents");
    let (out, cache) = (dir.join("report"), dir.join("cache"));
    // The afferents step automatically with the crossovers stored in --cache: an unusable
    // file there is named in a warning, and the run goes on with the built-in ones.
    std::fs::create_dir_all(&cache).unwrap();
    let crossovers = cache.join("stepping-crossovers.json");
    std::fs::write(&crossovers, r#"{"crossovers": {"LIF": 0.0}}"#).unwrap();
    let (ok, stdout, stderr) = small_reproduce(&out, &cache, &["--afferents", "lif"]);
    assert!(ok, "{stderr}");
    let warning = format!("{}", crossovers.display());
    assert!(
        stderr.contains(&warning) && stderr.contains("using the built-in crossovers"),
        "{stderr}"
    );
    assert!(
        stdout.contains("| lif afferents: LOO (%) |") && stdout.contains("| direct: time (s) |"),
        "{stdout}"
    );
    assert!(
        stdout.contains("| (afferent network, all samples) |"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    assert_eq!(
        csv.lines().filter(|l| l.contains(",afferents,")).count(),
        CodingName::ALL.len(),
        "{csv}"
    );
    assert!(
        out.join("confusion_artificial_spatial_afferents.svg")
            .is_file()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `neurotac reproduce --dataset data --out out`, small search.
fn reproduce_recorded(data: &Path, out: &Path) -> (bool, String, String) {
    neurotac(&[
        "reproduce",
        "--dataset",
        data.to_str().unwrap(),
        "--epochs",
        "8",
        "--tau-step",
        "30ms",
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn a_recorded_dataset_runs_through_the_same_pipeline() {
    let dir = scratch("recorded");
    let data = dir.join("my-textures");
    recorded_dataset(&data, &[4, 4]);
    let out = dir.join("report");
    let (ok, stdout, stderr) = reproduce_recorded(&data, &out);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("my-textures set — 2 classes × 8 samples"),
        "{stdout}"
    );
    assert!(!stdout.contains("paper, Table"), "{stdout}");
    // What is not read is listed, not skipped without a word.
    assert!(
        stderr.contains("my-textures: skipped 2 entries")
            && stderr.contains("texture0/notes.md, texture1/notes.md"),
        "{stderr}"
    );
    assert!(out.join("confusion_my-textures_temporal.svg").is_file());
    assert!(out.join("confusion_my-textures_temporal.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_one_sample_class_keeps_leave_one_out_and_the_split_says_why_it_refuses() {
    let dir = scratch("lonely");
    let data = dir.join("lonely");
    recorded_dataset(&data, &[5, 1]);
    let out = dir.join("report");
    let (ok, stdout, stderr) = reproduce_recorded(&data, &out);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("80/20 split refused: class 1 has 1 sample(s)"),
        "{stdout}"
    );
    assert!(stdout.contains("| refused |"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_datasets_are_clear_errors_and_leave_no_report() {
    let dir = scratch("bad");
    let out = dir.join("report");
    let run = |data: &Path| reproduce_recorded(data, &out);

    // Class folders without any event file.
    let empty = dir.join("empty");
    std::fs::create_dir_all(empty.join("a")).unwrap();
    std::fs::create_dir_all(empty.join("b")).unwrap();
    std::fs::write(empty.join("a").join("notes.md"), "x").unwrap();
    let (ok, _, stderr) = run(&empty);
    assert!(!ok);
    assert!(stderr.contains("no event files"), "{stderr}");
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with("error")).count(),
        1,
        "{stderr}"
    );
    // A folder that does not exist.
    let (ok, _, stderr) = run(&dir.join("nowhere"));
    assert!(!ok && stderr.contains("does not exist"), "{stderr}");
    // An AEDAT 4.0 file of a 346 × 260 sensor among the CSV files of a DAVIS240.
    let mixed = dir.join("mixed");
    recorded_dataset(&mixed, &[3, 3]);
    let events = neurotac_sensor::format::read_file(&mixed.join("texture0").join("00.csv"))
        .unwrap()
        .0;
    let bytes = to_bytes(&events, Format::Aedat4(Compression::Lz4), (346, 260)).unwrap();
    std::fs::write(mixed.join("texture0").join("99.aedat4"), bytes).unwrap();
    let (ok, _, stderr) = run(&mixed);
    assert!(!ok);
    assert!(stderr.contains("346"), "{stderr}");
    assert!(!out.exists(), "no report after a failed run");
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.contains("partial"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A search grid too fine to hold, or a synthetic set too large to draw, is refused in one
/// line before any dataset is simulated or drawn.
#[test]
fn searches_and_synthetic_sets_over_their_budget_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("out"), dir.path().join("cache"));
    let s = |p: &Path| p.to_str().unwrap().to_owned();
    let (ok, _, stderr) = neurotac(&[
        "reproduce",
        "--quick",
        "--tau-step",
        "1e-300",
        "--out",
        &s(&out),
        "--cache",
        &s(&cache),
    ]);
    assert!(
        !ok && stderr.contains("is below the smallest, 100µs"),
        "{stderr}"
    );
    assert!(
        !cache.exists() && !out.exists(),
        "nothing simulated, nothing written"
    );
    let synth = dir.path().join("s.json");
    let (ok, _, stderr) = neurotac(&[
        "synth",
        "--output",
        &s(&synth),
        "--spikes-per-unit",
        "1e300",
    ]);
    assert!(
        !ok && stderr.contains("spikes_per_unit = 1e300: at most 2 × 10⁸"),
        "{stderr}"
    );
    let (ok, _, stderr) = neurotac(&["synth", "--output", &s(&synth), "--samples", "10"]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = neurotac(&[
        "search",
        "vr",
        "--input",
        &s(&synth),
        "--cos-step",
        "1e-300",
    ]);
    assert!(!ok && stderr.contains("= 1e-300: at most 10⁴"), "{stderr}");
    // A τ grid that fine cannot even be asked for: its flag's range refuses it.
    let (ok, _, stderr) = neurotac(&[
        "search",
        "vr",
        "--input",
        &s(&synth),
        "--tau-step",
        "1e-300",
    ]);
    assert!(!ok && stderr.contains("below the smallest"), "{stderr}");
}
