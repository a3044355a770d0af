//! `neurotac tradeoff` without a subcommand: every trade, one summary page.

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
fn bare_tradeoff_quick_writes_one_summary_with_three_pareto_tables() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let (ok, stdout, stderr) = neurotac(&["tradeoff", "--quick", "--out", out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let summary = std::fs::read_to_string(out.join("tradeoff.md")).unwrap();
    assert!(stdout.contains("# Speed ↔ accuracy trade-offs"), "{stdout}");
    for (heading, files) in [
        ("## Neuron simulation", "neurons/neurons"),
        ("## Van Rossum distance", "vr/vr"),
        ("## Simulator step tolerance", "simulator/simulator"),
    ] {
        let rows = table_rows(&summary, heading);
        assert!(!rows.is_empty(), "empty Pareto table under {heading}");
        for ext in ["csv", "md", "svg"] {
            let link = format!("({files}.{ext})");
            assert!(summary.contains(&link), "no link {link}");
            assert!(
                out.join(format!("{files}.{ext}")).is_file(),
                "{files}.{ext}"
            );
        }
    }
    assert_eq!(summary.matches("How to choose:").count(), 3);
    // Both neuron models have a front; the Van Rossum front holds exact and/or trace rows.
    let neurons = table_rows(&summary, "## Neuron simulation");
    assert!(neurons.iter().any(|r| r.starts_with("| lif |")));
    assert!(neurons.iter().any(|r| r.starts_with("| izhikevich |")));
    let vr = table_rows(&summary, "## Van Rossum distance");
    assert!(
        vr.iter()
            .all(|r| r.starts_with("| exact |") || r.starts_with("| traces |")),
        "{vr:?}"
    );
    let csv = std::fs::read_to_string(out.join("vr/vr.csv")).unwrap();
    assert!(csv.starts_with("method,trace_dt_s,precision,wall_s,cpu_s,loo_accuracy,"));
    assert_eq!(csv.lines().count(), 1 + 1 + 2, "{csv}");
    // Every simulator row shown is on the front, as the per-trade CSV says.
    let simulator = table_rows(&summary, "## Simulator step tolerance");
    assert!(
        simulator.iter().all(|r| r.ends_with("| true |")),
        "{simulator:?}"
    );
    let csv = std::fs::read_to_string(out.join("simulator/simulator.csv")).unwrap();
    let on_front = csv.lines().filter(|l| l.ends_with(",true")).count();
    assert_eq!(on_front, simulator.len());
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
