//! The `reproduce_pipeline` example's own code, run and checked (the paper's pipeline from
//! Rust code runs in CI).

#[path = "../examples/reproduce_pipeline.rs"]
mod example;

use neurotac::experiments::coding::CodingName;
use neurotac::experiments::menu::Menu;

#[test]
fn the_papers_pipeline_runs_from_rust_code_and_writes_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let report = example::run(3, &dir.path().join("cache")).unwrap();
    assert_eq!(report.sets.len(), 1);
    let set = &report.sets[0].direct;
    assert_eq!(set.name, "artificial");
    assert_eq!(set.samples_per_class, vec![3; 11]);
    let order: Vec<CodingName> = set.codings.iter().map(|c| c.coding).collect();
    assert_eq!(order, CodingName::ALL);
    for c in &set.codings {
        assert_eq!(c.loo.accuracy.n, 33);
        assert!((0.0..=1.0).contains(&c.loo.accuracy.mean));
    }
    // Eleven classes: the best coding at twice chance (1/11) shows the textures are told apart.
    let best = set
        .codings
        .iter()
        .map(|c| c.loo.accuracy.mean)
        .fold(0.0, f64::max);
    assert!(best > 2.0 / 11.0, "best LOO accuracy {best}");
    assert_eq!(set.bayes_search().unwrap().result.trace.len(), 20);
    let out = dir.path().join("report");
    neurotac_cli::report::write_report(&out, &report, false).unwrap();
    for file in [
        "report.md",
        "report.json",
        "accuracy.csv",
        "spike_trains_artificial.png",
    ] {
        assert!(out.join(file).exists(), "no {file}");
    }
}
