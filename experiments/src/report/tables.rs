//! The report's Markdown tables (also printed by the CLI): accuracy against the paper's, the
//! afferent variant next to the direct pipeline, and the chosen parameters and intensive means.

use crate::coding::CodingName;
use crate::reproduce::paper::{self, PaperTable};
use crate::reproduce::{SetReport, SetResult};
use std::fmt::Write as _;

/// A fraction as a percentage with one decimal (`0.785` → `78.5`).
pub(crate) fn pct(x: f64) -> String {
    format!("{:.1}", 100.0 * x)
}

/// The paper's table for this set, if it is one of the paper's sets.
pub(crate) fn paper_table(set: &SetResult) -> Option<&'static PaperTable> {
    paper::table_for(&set.name)
}

/// The comparison table of one set as Markdown rows (also printed by the CLI).
pub fn accuracy_table(set: &SetReport) -> String {
    let paper = paper_table(&set.direct);
    let mut s = String::new();
    let _ = write!(
        s,
        "| coding | parameters | LOO accuracy (%) | Wilson 95 % | 80/20 split (%) |"
    );
    if let Some(p) = paper {
        let _ = write!(s, " paper, {} (%) |", p.table);
    }
    s.push_str("\n|---|---|---|---|---|");
    if paper.is_some() {
        s.push_str("---|");
    }
    s.push('\n');
    for (i, c) in set.direct.codings.iter().enumerate() {
        let a = c.loo.accuracy;
        let split = c
            .split
            .as_ref()
            .map(|e| pct(e.accuracy.mean))
            .unwrap_or_else(|| "refused".into());
        let _ = write!(
            s,
            "| {} | {} | {} ± {} | [{}, {}] | {} |",
            c.coding.label(),
            c.parameters,
            pct(a.mean),
            pct(a.std),
            pct(a.wilson_low),
            pct(a.wilson_high),
            split
        );
        if let Some(p) = paper {
            match p.std_percent {
                Some(sd) => {
                    let _ = write!(s, " {:.1} ± {:.1} |", p.accuracy_percent[i], sd[i]);
                }
                None => {
                    let _ = write!(s, " {:.1} |", p.accuracy_percent[i]);
                }
            }
        }
        s.push('\n');
    }
    s
}

/// The afferent variant next to the direct pipeline, as Markdown rows (empty without it): per
/// coding, accuracy, parameters and time (parameter search included) of both, and the time of
/// the afferent network itself.
pub fn afferent_table(set: &SetReport) -> String {
    let Some(aff) = &set.afferent else {
        return String::new();
    };
    let mut s = format!(
        "| coding | direct: LOO (%) | direct: time (s) | {m} afferents: parameters | {m} afferents: LOO (%) | {m} afferents: time (s) |\n|---|---|---|---|---|---|\n",
        m = aff.model
    );
    for c in &set.direct.codings {
        let a = aff.result.coding(c.coding);
        let _ = writeln!(
            s,
            "| {} | {} ± {} | {:.2} | {} | {} ± {} | {:.2} |",
            c.coding.label(),
            pct(c.loo.accuracy.mean),
            pct(c.loo.accuracy.std),
            coding_seconds(&set.direct, c.coding),
            a.parameters,
            pct(a.loo.accuracy.mean),
            pct(a.loo.accuracy.std),
            coding_seconds(&aff.result, c.coding)
        );
    }
    let _ = writeln!(
        s,
        "| (afferent network, all samples) | | | | | {:.2} |",
        aff.network_time.wall_s
    );
    s
}

/// Wall time of a coding including its parameter search.
pub fn coding_seconds(set: &SetResult, coding: CodingName) -> f64 {
    let own = set.coding(coding).time.wall_s;
    own + match coding {
        CodingName::Temporal => set.dt_sweep_time.wall_s,
        CodingName::Spatiotemporal => set.bayes_time.wall_s,
        _ => 0.0,
    }
}

/// One chosen parameter or intensive class mean, with the paper's value where it gives one.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterRow {
    /// What it is (`temporal Δt (ms)`, `intensive mean, grid 2.5 mm (spikes per taxel)`, …).
    pub quantity: String,
    /// This run's value.
    pub value: f64,
    /// The paper's value (the paper reports its parameters for the artificial set only).
    pub paper: Option<f64>,
}

/// The chosen Δt, τ and cos θ, then the intensive mean of every class.
pub fn parameter_rows(set: &SetResult) -> Vec<ParameterRow> {
    let paper_set = set.name == "artificial";
    let row = |quantity: &str, value: f64, paper: f64| ParameterRow {
        quantity: quantity.into(),
        value,
        paper: paper_set.then_some(paper),
    };
    let mut rows = vec![
        row(
            "temporal Δt (ms)",
            set.dt_sweep.best_window_ms as f64,
            paper::DT_MS,
        ),
        row(
            "Van Rossum τ (ms)",
            set.bayes.best_tau_s * 1e3,
            paper::TAU_MS,
        ),
        row("Van Rossum cos θ", set.bayes.best_cos, paper::COS_THETA),
    ];
    rows.extend(
        set.class_names
            .iter()
            .zip(&set.intensive_class_means)
            .map(|(class, &value)| ParameterRow {
                quantity: format!("intensive mean, {class} (spikes per taxel)"),
                value,
                paper: paper::INTENSIVE_MEANS
                    .iter()
                    .find(|&&(mm, _)| *class == paper::grid_name(mm))
                    .map(|&(_, m)| m),
            }),
    );
    rows
}

/// The chosen parameters, and the intensive means the paper gives, against the paper's, as
/// Markdown.
pub fn parameter_table(set: &SetResult) -> String {
    let mut s = String::from("| quantity | this run | paper |\n|---|---|---|\n");
    for (i, r) in parameter_rows(set).iter().enumerate() {
        // The three parameters always; class means only where the paper has one.
        if i >= 3 && r.paper.is_none() {
            continue;
        }
        let value = if i == 0 {
            format!("{}", r.value)
        } else if i == 1 {
            format!("{:.0}", r.value)
        } else {
            format!("{:.2}", r.value)
        };
        let paper = r.paper.map_or("—".into(), |p| p.to_string());
        let _ = writeln!(s, "| {} | {value} | {paper} |", r.quantity);
    }
    s
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::protocols::{Accuracy, ConfusionMatrix, Evaluation};
    use crate::reproduce::CodingResult;
    use crate::search::bayes::{BayesResult, BayesStep};
    use crate::search::dt_sweep::DtSweep;
    use crate::timing::Timing;

    fn evaluation(mean: f64) -> Evaluation {
        Evaluation {
            tested: (0..10).collect(),
            predicted: vec![0; 10],
            accuracy: Accuracy {
                mean,
                std: 0.1,
                hits: (mean * 10.0) as usize,
                n: 10,
                wilson_low: mean - 0.2,
                wilson_high: (mean + 0.1).min(1.0),
            },
            fold_accuracies: Vec::new(),
            confusion: ConfusionMatrix {
                counts: vec![vec![4, 1], vec![0, 5]],
            },
        }
    }

    /// A hand-made result of a two-class set named `name`.
    pub(crate) fn set_result(name: &str) -> SetResult {
        let codings = CodingName::ALL
            .iter()
            .enumerate()
            .map(|(i, &coding)| CodingResult {
                coding,
                parameters: if coding == CodingName::Temporal {
                    "Δt = 3 ms".into()
                } else {
                    String::new()
                },
                loo: evaluation(0.5 + 0.1 * i as f64),
                split: (i != 1).then(|| evaluation(0.6)),
                split_refused: (i == 1).then(|| "class 1 has 1 sample(s)".into()),
                time: Timing::default(),
            })
            .collect();
        let step = BayesStep {
            epoch: 1,
            tau_s: 0.02,
            cos: 0.5,
            value: 0.8,
            best_value: 0.8,
            best_tau_s: 0.02,
            best_cos: 0.5,
        };
        SetResult {
            name: name.into(),
            class_names: vec!["grid 0.0 mm".into(), "grid 2.5 mm".into()],
            samples_per_class: vec![5, 5],
            duration_ms: 10,
            mean_spikes_per_taxel: 7.0,
            intensive_class_means: vec![4.0, 10.0],
            dt_sweep: DtSweep {
                windows_ms: vec![1, 2, 3],
                accuracy: vec![0.5, 0.6, 0.7],
                best_window_ms: 3,
                best: evaluation(0.7).accuracy,
            },
            dt_sweep_time: Timing::default(),
            bayes: BayesResult {
                best_tau_s: 0.02,
                best_cos: 0.5,
                best_value: 0.8,
                best_tau_index: 0,
                trace: vec![step],
            },
            bayes_time: Timing::default(),
            vr_matrices_computed: 1,
            codings,
            time: Timing::default(),
        }
    }

    #[test]
    fn the_accuracy_table_adds_the_papers_column_for_the_papers_sets() {
        let set = |name| SetReport {
            source: "test".into(),
            dataset_time: Timing::default(),
            direct: set_result(name),
            afferent: None,
            examples: Vec::new(),
        };
        let ours = accuracy_table(&set("artificial"));
        let lines: Vec<&str> = ours.lines().collect();
        assert_eq!(lines.len(), 2 + 4);
        assert!(lines[0].ends_with("| paper, Table 1 (%) |"), "{}", lines[0]);
        assert_eq!(
            lines[2],
            "| Intensive |  | 50.0 ± 10.0 | [30.0, 60.0] | 60.0 | 78.5 ± 41.1 |"
        );
        assert!(lines[3].contains("| refused |"), "{}", lines[3]);
        let recorded = accuracy_table(&set("my-textures"));
        assert!(!recorded.contains("paper"), "{recorded}");
        assert!(afferent_table(&set("artificial")).is_empty());
    }

    #[test]
    fn parameter_rows_compare_with_the_paper_only_where_it_reports() {
        let rows = parameter_rows(&set_result("artificial"));
        assert_eq!(rows[0].quantity, "temporal Δt (ms)");
        assert_eq!((rows[0].value, rows[0].paper), (3.0, Some(159.0)));
        assert_eq!((rows[1].value, rows[1].paper), (20.0, Some(76.0)));
        // Class means: the paper gives 0 and 2.5 mm.
        assert_eq!(rows[3].paper, Some(4.63));
        assert_eq!(rows[4].paper, Some(9.84));
        let natural = parameter_rows(&set_result("natural"));
        assert_eq!(natural[0].paper, None);
        let table = parameter_table(&set_result("artificial"));
        assert!(table.contains("| temporal Δt (ms) | 3 | 159 |"), "{table}");
        assert!(table.contains("| Van Rossum τ (ms) | 20 | 76 |"), "{table}");
    }
}
