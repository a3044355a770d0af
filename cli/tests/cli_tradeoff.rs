//! `neurotac tradeoff` without a subcommand: the accuracy ↔ cost study; with one, one trade.

mod common;
use common::neurotac;

/// The data rows of the first Markdown table after `heading`.
fn table_rows<'a>(markdown: &'a str, heading: &str) -> Vec<&'a str> {
    let at = markdown
        .find(heading)
        .unwrap_or_else(|| panic!("no `{heading}` in\n{markdown}"));
    markdown[at..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2) // header and separator
        .collect()
}

#[test]
fn bare_tradeoff_quick_measures_accuracy_against_cost_for_each_family() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let cache = dir.path().join("cache");
    let (ok, stdout, stderr) = neurotac(&[
        "tradeoff",
        "--quick",
        "--trials",
        "3",
        "--epochs",
        "10",
        "--cache",
        cache.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let summary = std::fs::read_to_string(out.join("tradeoff.md")).unwrap();
    assert!(stdout.contains("# Speed ↔ accuracy: classification accuracy against cost"));
    assert!(summary.contains("--quick**: few samples per class, so the intervals are wide"));
    for (heading, dir, reference) in [
        (
            "### Van Rossum distance",
            "artificial/vr/vr",
            "| exact (reference)",
        ),
        (
            "### LIF afferent layer",
            "artificial/afferents-lif/afferents-lif",
            "| exact 0.1 ms f64 auto (reference)",
        ),
        (
            "### Transduction",
            "artificial/transduction/transduction",
            "| pool 20 ms, BA 5 ms (reference)",
        ),
        (
            "### Simulator",
            "artificial/simulator/simulator",
            "| tolerance 0.02, mechanics 0.25 ms, shear 25 µs (reference)",
        ),
    ] {
        let rows = table_rows(&summary, heading);
        assert!(rows.len() > 2, "{heading}: {rows:?}");
        // The reference first, one recommended row, and every row has four codings'
        // accuracy with an interval.
        assert!(
            rows[0].starts_with(reference)
                || rows[0].starts_with(&format!("| **{}", &reference[2..])),
            "{rows:?}"
        );
        assert_eq!(
            rows.iter().filter(|r| r.contains('★')).count(),
            1,
            "{rows:?}"
        );
        assert!(
            rows.iter().all(|r| r.matches(" [").count() == 4),
            "{rows:?}"
        );
        for ext in ["csv", "md", "json", "svg", "png"] {
            assert!(out.join(format!("{dir}.{ext}")).is_file(), "{dir}.{ext}");
        }
        let csv = std::fs::read_to_string(out.join(format!("{dir}.csv"))).unwrap();
        assert!(csv.starts_with("setting,reference,wall_s,cpu_s,neuron_updates,"));
        assert!(csv.contains("spatiotemporal_wilson_low,spatiotemporal_wilson_high,spatiotemporal_b,spatiotemporal_c,spatiotemporal_p"));
        assert_eq!(csv.lines().count(), rows.len() + 1);
        let svg = std::fs::read_to_string(out.join(format!("{dir}.svg"))).unwrap();
        assert!(svg.contains("recommended") && svg.contains("Wilson"));
    }
    // An existing report is refused without --force, before any work.
    let (ok, _, stderr) = neurotac(&[
        "tradeoff",
        "--quick",
        "--cache",
        cache.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("tradeoff.md"), "{stderr}");
}

#[test]
fn subcommands_still_run_alone() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (ok, stdout, stderr) = neurotac(&["tradeoff", "neurons", "--quick", "--out", out]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("## Pareto front"), "{stdout}");
    assert!(dir.path().join("neurons.csv").is_file());
    assert!(!dir.path().join("tradeoff.md").exists());
    // The bare command's options belong to it alone.
    let (ok, _, _) = neurotac(&["tradeoff", "--quick", "neurons"]);
    assert!(!ok);
}

#[test]
fn families_that_re_simulate_refuse_a_recorded_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let (ok, _, stderr) = neurotac(&[
        "tradeoff",
        "--dataset",
        dir.path().join("recording").to_str().unwrap(),
        "--families",
        "vr,transduction",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("need --set, not --dataset"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(!out.exists());
}
