//! The report's CSV tables: accuracy of every pipeline and coding, chosen parameters, the Δt
//! sweep, the optimisation trace, confusion matrices, slide-phase shares, leave-one-out recall
//! per class and the paper's named confusions next to ours.

use super::tables::{coding_seconds, paper_column, paper_table, parameter_rows};
use neurotac_experiments::coding::CodingName;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::reproduce::paper;
use neurotac_experiments::reproduce::phases::{Phases, SlidePhase};
use neurotac_experiments::reproduce::{BayesSearch, DtSearch, Report, SetReport, SetResult};
use std::fmt::Write as _;

/// A CSV field, quoted when it holds a comma, a quote or a line break.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The runs of a set: `("direct", result)` and, if run, `("afferents", result)`.
pub(crate) fn runs(set: &SetReport) -> Vec<(&'static str, &SetResult)> {
    let mut runs = vec![("direct", &set.direct)];
    if let Some(a) = &set.afferent {
        runs.push(("afferents", &a.result));
    }
    runs
}

/// `accuracy.csv`: one row per set, pipeline and coding.
pub fn accuracy_csv(report: &Report) -> String {
    let mut out = String::from(
        "set,pipeline,coding,parameters,loo_accuracy,loo_std,wilson_low,wilson_high,split_accuracy,paper_accuracy,wall_s\n",
    );
    for set in &report.sets {
        accuracy_rows(set, &mut out);
    }
    out
}

/// `parameters.csv`: the chosen parameters and intensive class means of every set.
pub fn parameters_csv(report: &Report) -> String {
    let mut parameters = String::from("set,quantity,value,paper\n");
    for set in &report.sets {
        for r in parameter_rows(&set.direct) {
            let _ = writeln!(
                parameters,
                "{},{},{},{}",
                csv_field(&set.direct.name),
                csv_field(&r.quantity),
                r.value,
                r.paper.map(|p| p.to_string()).unwrap_or_default()
            );
        }
    }
    parameters
}

/// One CSV row per pipeline and coding.
fn accuracy_rows(set: &SetReport, out: &mut String) {
    let paper = paper_table(&set.direct);
    for (pipeline, r) in runs(set) {
        for c in &r.codings {
            let a = c.loo.accuracy;
            let _ = writeln!(
                out,
                "{},{pipeline},{},{},{},{},{},{},{},{},{:.3}",
                csv_field(&r.name),
                c.coding.key(),
                csv_field(&c.parameters),
                a.mean,
                a.std,
                a.wilson_low,
                a.wilson_high,
                c.split
                    .as_ref()
                    .map(|e| e.accuracy.mean.to_string())
                    .unwrap_or_default(),
                paper
                    .filter(|_| pipeline == "direct")
                    // The paper's percentage as a fraction, in its shortest form (0.928, not
                    // 0.9279999999999999).
                    .zip(paper_column(c.coding))
                    .map(|(p, i)| ((p.accuracy_percent[i] * 1e6).round() / 1e8).to_string())
                    .unwrap_or_default(),
                coding_seconds(r, c.coding)
            );
        }
    }
}

/// A confusion matrix as CSV (rows: true class, columns: predicted).
pub fn confusion_csv(counts: &[Vec<usize>], class_names: &[String]) -> String {
    let mut csv = String::from("true\\predicted");
    for n in class_names {
        let _ = write!(csv, ",{}", csv_field(n));
    }
    csv.push('\n');
    for (i, row) in counts.iter().enumerate() {
        csv.push_str(&csv_field(
            class_names.get(i).map(String::as_str).unwrap_or(""),
        ));
        for v in row {
            let _ = write!(csv, ",{v}");
        }
        csv.push('\n');
    }
    csv
}

/// A fraction as a CSV field, empty when there is none.
fn optional(x: Option<f64>) -> String {
    x.map(|v| v.to_string()).unwrap_or_default()
}

/// `phase_shares.csv`: per set with known motion times, the share of each class's taxel spikes
/// in each slide phase, then the mean over classes (`class` = `all classes`).
pub fn phase_shares_csv(report: &Report) -> String {
    let mut out = String::from("set,class");
    for p in SlidePhase::ALL {
        let _ = write!(out, ",{}", p.key());
    }
    out.push('\n');
    for set in &report.sets {
        let Phases::Known(shares) = &set.phases else {
            continue;
        };
        let classes = set.direct.class_names.iter().map(String::as_str);
        let rows = shares.per_class.iter().chain([&shares.all_classes]);
        for (class, share) in classes.chain(["all classes"]).zip(rows) {
            let _ = write!(out, "{},{}", csv_field(&set.direct.name), csv_field(class));
            for p in SlidePhase::ALL {
                let _ = write!(out, ",{}", share.of(p));
            }
            out.push('\n');
        }
    }
    out
}

/// `loo_recall.csv`: the leave-one-out recall of every class of every set under each coding
/// (empty for a class without samples).
pub fn loo_recall_csv(report: &Report) -> String {
    let mut out = String::from("set,class");
    // The recall is analysed under the paper's codings.
    for c in paper::CODINGS {
        let _ = write!(out, ",{}", c.key());
    }
    out.push('\n');
    for set in &report.sets {
        for (i, class) in set.direct.class_names.iter().enumerate() {
            let _ = write!(out, "{},{}", csv_field(&set.direct.name), csv_field(class));
            for r in &set.loo_analysis.recall {
                let _ = write!(out, ",{}", optional(r.per_class.get(i).copied().flatten()));
            }
            out.push('\n');
        }
    }
    out
}

/// `paper_confusions.csv`: every confusion the paper names that applies to a set, one row per
/// coding and measure: what we measure on the leave-one-out predictions (`ours`, a fraction)
/// and what the paper says.
pub fn paper_confusions_csv(report: &Report) -> String {
    let mut out = String::from("set,paper_statement,coding,measure,ours,paper\n");
    for set in &report.sets {
        let name = csv_field(&set.direct.name);
        let mut row = |statement: &str, coding: CodingName, measure: &str, ours, paper: &str| {
            let _ = writeln!(
                out,
                "{name},{},{},{},{},{}",
                csv_field(statement),
                coding.key(),
                csv_field(measure),
                optional(ours),
                csv_field(paper)
            );
        };
        let a = &set.loo_analysis;
        for r in &a.named_confusions {
            let p = &r.paper;
            for (i, coding) in paper::CODINGS.into_iter().enumerate() {
                let paper = if p.confused_under[i] {
                    "confused"
                } else {
                    "told apart"
                };
                let label = p.label();
                let forward = format!("{} → {}", p.truth, p.predicted);
                row(&label, coding, &forward, r.truth_as_predicted[i], paper);
                if p.mutual {
                    let back = format!("{} → {}", p.predicted, p.truth);
                    row(&label, coding, &back, r.predicted_as_truth[i], paper);
                }
            }
        }
        for r in &a.grid_errors {
            let q = r.paper.quote;
            let measure = "errors between neighbouring grids";
            row(q, r.coding, measure, r.between_neighbours, "most errors");
            if let Some((lo, hi)) = r.paper.concentrated_on_mm {
                let paper = format!("concentrated on {lo}–{hi} mm");
                let measure = "errors on the paper's grids";
                row(q, r.coding, measure, r.in_paper_range, &paper);
            }
        }
    }
    out
}

/// `dt_sweep_<set>.csv`: leave-one-out accuracy at every Δt.
pub fn dt_sweep_csv(dt: &DtSearch) -> String {
    let mut dt_csv = String::from("dt_ms,loo_accuracy\n");
    for (w, a) in dt.sweep.windows_ms.iter().zip(&dt.sweep.accuracy) {
        let _ = writeln!(dt_csv, "{w},{a}");
    }
    dt_csv
}

/// `bo_convergence_<set>.csv`: every epoch of the Bayesian optimisation.
pub fn bayes_csv(bayes: &BayesSearch) -> String {
    let mut bo_csv = String::from("epoch,tau_s,cos,accuracy,best_accuracy,best_tau_s,best_cos\n");
    for s in &bayes.result.trace {
        let _ = writeln!(
            bo_csv,
            "{},{},{},{},{},{},{}",
            s.epoch, s.tau_s, s.cos, s.value, s.best_value, s.best_tau_s, s.best_cos
        );
    }
    bo_csv
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::tables::tests::{report_of, set_result};

    fn report() -> Report {
        report_of(set_result("artificial"), "test")
    }

    #[test]
    fn fields_with_commas_or_quotes_are_quoted() {
        assert_eq!(csv_field("plain"), "plain");
        assert_eq!(csv_field("a, b"), "\"a, b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }

    #[test]
    fn accuracy_and_parameter_tables_have_one_row_per_item() {
        let r = report();
        let acc = accuracy_csv(&r);
        let lines: Vec<&str> = acc.lines().collect();
        assert_eq!(lines.len(), 1 + CodingName::ALL.len());
        assert!(
            lines[1].starts_with("artificial,direct,intensive,,0.5,0.1,"),
            "{}",
            lines[1]
        );
        // The paper's intensive accuracy as a fraction; no split for the refused coding.
        assert!(lines[1].contains(",0.785,"), "{}", lines[1]);
        assert!(lines[2].contains(",0.7,,0.955,"), "{}", lines[2]);
        let params = parameters_csv(&r);
        assert_eq!(params.lines().count(), 1 + 3 + 2);
        assert!(
            params.contains("artificial,temporal Δt (ms),3,159\n"),
            "{params}"
        );
        assert!(
            params
                .contains("artificial,\"intensive mean, grid 0.0 mm (spikes per taxel)\",4,4.63\n"),
            "{params}"
        );
    }

    #[test]
    fn class_tables_have_one_row_per_class_and_measure() {
        let r = report();
        // A set without motion times has no phase rows.
        assert_eq!(phase_shares_csv(&r), "set,class,rest,onset,sliding,stop\n");
        assert_eq!(
            loo_recall_csv(&r),
            "set,class,intensive,spatial,temporal,spatiotemporal\n\
             artificial,grid 0.0 mm,0.8,0.8,0.8,0.8\n\
             artificial,grid 2.5 mm,1,1,1,1\n"
        );
        // Two grids: per coding the neighbour share, and the range share where the paper
        // gives a range (intensive, spatial).
        let confusions = paper_confusions_csv(&r);
        assert_eq!(confusions.lines().count(), 1 + 4 + 2, "{confusions}");
        assert!(
            confusions
                .contains(",intensive,errors on the paper's grids,1,concentrated on 0–2 mm\n"),
            "{confusions}"
        );
    }

    #[test]
    fn sweep_trace_and_confusion_tables() {
        let s = set_result("x");
        assert_eq!(
            dt_sweep_csv(s.dt_search().unwrap()),
            "dt_ms,loo_accuracy\n1,0.5\n2,0.6\n3,0.7\n"
        );
        assert_eq!(
            bayes_csv(s.bayes_search().unwrap()).lines().nth(1),
            Some("1,0.02,0.5,0.8,0.8,0.02,0.5")
        );
        let names = ["a,b".to_string(), "c".to_string()];
        assert_eq!(
            confusion_csv(&[vec![1, 2], vec![3, 4]], &names),
            "true\\predicted,\"a,b\",c\n\"a,b\",1,2\nc,3,4\n"
        );
    }
}
