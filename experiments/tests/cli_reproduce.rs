//! `neurotac reproduce` (issue 8): a small run end to end, its report folder, and its refusals.

mod common;

use common::neurotac;
use std::path::{Path, PathBuf};

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("neurotac-reproduce-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small artificial run (3 slides per texture, 12 epochs) into `out`, caching datasets in
/// `cache`.
fn small_run(out: &Path, cache: &Path, extra: &[&str]) -> (bool, String, String) {
    let (out, cache) = (out.to_str().unwrap(), cache.to_str().unwrap());
    let mut args = vec![
        "reproduce",
        "--set",
        "artificial",
        "--trials",
        "3",
        "--epochs",
        "12",
        "--tau-step",
        "0.03",
        "--out",
        out,
        "--cache",
        cache,
    ];
    args.extend_from_slice(extra);
    neurotac(&args)
}

#[test]
fn a_small_run_prints_the_tables_and_writes_the_whole_report() {
    let dir = scratch("small");
    let (out, cache) = (dir.join("report"), dir.join("cache"));
    let (ok, stdout, stderr) = small_run(&out, &cache, &[]);
    assert!(ok, "{stderr}");
    for needle in [
        "paper, Table 1",
        "| Intensive |",
        "| Spatiotemporal | τ = ",
        "78.5 ± 41.1",
        "| temporal Δt (ms) |",
        "intensive mean, grid 2.5 mm",
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
    for c in ["intensive", "spatial", "temporal", "spatiotemporal"] {
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
    assert_eq!(set["codings"].as_array().unwrap().len(), 4);
    assert_eq!(set["bayes"]["trace"].as_array().unwrap().len(), 12);
    assert_eq!(set["codings"][0]["loo"]["accuracy"]["n"], 33);
    // Four codings of one set in the accuracy table, plus the header.
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("![spike trains](spike_trains_artificial.svg)"));
    // Nothing partial is left beside the report.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.contains("partial"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // The same seed gives the same numbers (the cached dataset is reused).
    let again = dir.join("again");
    let (ok, stdout2, stderr) = small_run(&again, &cache, &[]);
    assert!(ok, "{stderr}");
    let table = |s: &str| -> String { s.lines().filter(|l| l.starts_with('|')).collect() };
    assert_eq!(table(&stdout), table(&stdout2));

    // An existing report folder is refused without --force, and kept as it was.
    let before = std::fs::read_to_string(out.join("report.json")).unwrap();
    let (ok, _, stderr) = small_run(&out, &cache, &["--seed", "2"]);
    assert!(!ok);
    assert!(
        stderr.contains("already exists") && stderr.contains("--force"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("report.json")).unwrap(),
        before
    );
    let (ok, _, stderr) = small_run(&out, &cache, &["--seed", "2", "--force"]);
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
    let (ok, stdout, stderr) = small_run(&out, &cache, &["--afferents", "lif"]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("afferents: LOO (%)") && stdout.contains("time: direct / afferents (s)"),
        "{stdout}"
    );
    assert!(stdout.contains("lif afferents: network"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    assert_eq!(
        csv.lines().filter(|l| l.contains(",afferents,")).count(),
        4,
        "{csv}"
    );
    assert!(
        out.join("confusion_artificial_spatial_afferents.svg")
            .is_file()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
