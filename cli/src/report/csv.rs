//! The report's CSV tables: accuracy of every pipeline and coding, chosen parameters, the Δt
//! sweep, the optimisation trace, confusion matrices, slide-phase shares, leave-one-out recall
//! per class and the paper's named confusions next to ours.

use super::tables::{coding_seconds, paper_column, paper_table, parameter_rows};
use neurotac_core::io::csv::{Error, records, table};
use neurotac_experiments::coding::CodingName;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::reproduce::paper;
use neurotac_experiments::reproduce::phases::{Phases, SlidePhase};
use neurotac_experiments::reproduce::{BayesSearch, DtSearch, Report, SetReport, SetResult};
use serde::Serialize;

/// The runs of a set: `("direct", result)` and, if run, `("afferents", result)`.
pub(crate) fn runs(set: &SetReport) -> Vec<(&'static str, &SetResult)> {
    let mut runs = vec![("direct", &set.direct)];
    if let Some(a) = &set.afferent {
        runs.push(("afferents", &a.result));
    }
    runs
}

/// A row of `accuracy.csv`.
#[derive(Serialize, Default)]
struct AccuracyRow<'a> {
    set: &'a str,
    pipeline: &'static str,
    coding: &'static str,
    parameters: &'a str,
    loo_accuracy: f64,
    loo_std: f64,
    wilson_low: f64,
    wilson_high: f64,
    split_accuracy: Option<f64>,
    paper_accuracy: Option<f64>,
    wall_s: f64,
}

/// `accuracy.csv`: one row per set, pipeline and coding.
pub fn accuracy_csv(report: &Report) -> Result<String, Error> {
    records(report.sets.iter().flat_map(accuracy_rows))
}

/// The rows of `accuracy.csv` of one set: one per pipeline and coding.
fn accuracy_rows(set: &SetReport) -> impl Iterator<Item = AccuracyRow<'_>> {
    let paper = paper_table(&set.direct);
    runs(set).into_iter().flat_map(move |(pipeline, r)| {
        r.codings.iter().map(move |c| {
            let a = c.loo.accuracy;
            AccuracyRow {
                set: &r.name,
                pipeline,
                coding: c.coding.key(),
                parameters: &c.parameters,
                loo_accuracy: a.mean,
                loo_std: a.std,
                wilson_low: a.wilson_low,
                wilson_high: a.wilson_high,
                split_accuracy: c.split.as_ref().map(|e| e.accuracy.mean),
                paper_accuracy: paper
                    .filter(|_| pipeline == "direct")
                    // The paper's percentage as a fraction, in its shortest form (0.928, not
                    // 0.9279999999999999).
                    .zip(paper_column(c.coding))
                    .map(|(p, i)| (p.accuracy_percent[i] * 1e6).round() / 1e8),
                // To the millisecond.
                wall_s: (coding_seconds(r, c.coding) * 1e3).round() / 1e3,
            }
        })
    })
}

/// A row of `parameters.csv`.
#[derive(Serialize, Default)]
struct ParameterCsvRow<'a> {
    set: &'a str,
    quantity: String,
    value: f64,
    paper: Option<f64>,
}

/// `parameters.csv`: the chosen parameters and intensive class means of every set.
pub fn parameters_csv(report: &Report) -> Result<String, Error> {
    records(report.sets.iter().flat_map(|set| {
        parameter_rows(&set.direct)
            .into_iter()
            .map(|r| ParameterCsvRow {
                set: &set.direct.name,
                quantity: r.quantity,
                value: r.value,
                paper: r.paper,
            })
    }))
}

/// A confusion matrix as CSV (rows: true class, columns: predicted).
pub fn confusion_csv(counts: &[Vec<usize>], class_names: &[String]) -> Result<String, Error> {
    let header = std::iter::once("true\\predicted").chain(class_names.iter().map(String::as_str));
    let rows = counts.iter().enumerate().map(|(i, row)| {
        let name = class_names.get(i).cloned().unwrap_or_default();
        std::iter::once(name).chain(row.iter().map(usize::to_string))
    });
    table(header, rows)
}

/// A fraction as a CSV field, empty when there is none.
fn optional(x: Option<f64>) -> String {
    x.map(|v| v.to_string()).unwrap_or_default()
}

/// `phase_shares.csv`: per set with known motion times, the share of each class's taxel spikes
/// in each slide phase, then the mean over classes (`class` = `all classes`).
pub fn phase_shares_csv(report: &Report) -> Result<String, Error> {
    let header = ["set", "class"]
        .into_iter()
        .chain(SlidePhase::ALL.map(|p| p.key()));
    let mut rows = Vec::new();
    for set in &report.sets {
        let Phases::Known(shares) = &set.phases else {
            continue;
        };
        let classes = set.direct.class_names.iter().map(String::as_str);
        let shares = shares.per_class.iter().chain([&shares.all_classes]);
        for (class, share) in classes.chain(["all classes"]).zip(shares) {
            let mut row = vec![set.direct.name.clone(), class.to_owned()];
            row.extend(SlidePhase::ALL.map(|p| share.of(p).to_string()));
            rows.push(row);
        }
    }
    table(header, rows)
}

/// `loo_recall.csv`: the leave-one-out recall of every class of every set under each coding
/// (empty for a class without samples).
pub fn loo_recall_csv(report: &Report) -> Result<String, Error> {
    // The recall is analysed under the paper's codings.
    let header = ["set", "class"]
        .into_iter()
        .chain(paper::CODINGS.map(|c| c.key()));
    let mut rows = Vec::new();
    for set in &report.sets {
        for (i, class) in set.direct.class_names.iter().enumerate() {
            let mut row = vec![set.direct.name.clone(), class.clone()];
            let recall = set.loo_analysis.recall.iter();
            row.extend(recall.map(|r| optional(r.per_class.get(i).copied().flatten())));
            rows.push(row);
        }
    }
    table(header, rows)
}

/// A row of `paper_confusions.csv`.
#[derive(Serialize, Default)]
struct PaperConfusionRow<'a> {
    set: &'a str,
    paper_statement: String,
    coding: &'static str,
    measure: String,
    ours: Option<f64>,
    paper: String,
}

/// `paper_confusions.csv`: every confusion the paper names that applies to a set, one row per
/// coding and measure: what we measure on the leave-one-out predictions (`ours`, a fraction)
/// and what the paper says.
pub fn paper_confusions_csv(report: &Report) -> Result<String, Error> {
    let mut rows = Vec::new();
    for set in &report.sets {
        let mut row = |statement: &str, coding: CodingName, measure: &str, ours, paper: &str| {
            rows.push(PaperConfusionRow {
                set: &set.direct.name,
                paper_statement: statement.to_owned(),
                coding: coding.key(),
                measure: measure.to_owned(),
                ours,
                paper: paper.to_owned(),
            });
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
    records(rows)
}

/// A row of `dt_sweep_<set>.csv`.
#[derive(Serialize, Default)]
struct DtRow {
    dt_ms: u32,
    loo_accuracy: f64,
}

/// `dt_sweep_<set>.csv`: leave-one-out accuracy at every Δt.
pub fn dt_sweep_csv(dt: &DtSearch) -> Result<String, Error> {
    let sweep = &dt.sweep;
    records(
        sweep
            .windows_ms
            .iter()
            .zip(&sweep.accuracy)
            .map(|(&w, &a)| DtRow {
                dt_ms: w,
                loo_accuracy: a,
            }),
    )
}

/// A row of `bo_convergence_<set>.csv`.
#[derive(Serialize, Default)]
struct BayesRow {
    epoch: usize,
    tau_s: f64,
    cos: f64,
    accuracy: f64,
    best_accuracy: f64,
    best_tau_s: f64,
    best_cos: f64,
}

/// `bo_convergence_<set>.csv`: every epoch of the Bayesian optimisation.
pub fn bayes_csv(bayes: &BayesSearch) -> Result<String, Error> {
    records(bayes.result.trace.iter().map(|s| BayesRow {
        epoch: s.epoch,
        tau_s: s.tau_s,
        cos: s.cos,
        accuracy: s.value,
        best_accuracy: s.best_value,
        best_tau_s: s.best_tau_s,
        best_cos: s.best_cos,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::tables::tests::{report_of, set_result};
    use neurotac_core::io::csv::read_table;

    fn report() -> Report {
        report_of(set_result("artificial"), "test")
    }

    #[test]
    fn accuracy_and_parameter_tables_have_one_row_per_item() {
        let r = report();
        let acc = accuracy_csv(&r).unwrap();
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
        let params = parameters_csv(&r).unwrap();
        assert_eq!(params.lines().count(), 1 + 3 + 2);
        assert!(
            params.contains("artificial,temporal Δt (ms),3.0,159.0\n"),
            "{params}"
        );
        assert!(
            params.contains(
                "artificial,\"intensive mean, grid 0.0 mm (spikes per taxel)\",4.0,4.63\n"
            ),
            "{params}"
        );
    }

    #[test]
    fn class_tables_have_one_row_per_class_and_measure() {
        let r = report();
        // A set without motion times has no phase rows.
        assert_eq!(
            phase_shares_csv(&r).unwrap(),
            "set,class,press,onset,sliding,stop\n"
        );
        assert_eq!(
            loo_recall_csv(&r).unwrap(),
            "set,class,intensive,spatial,temporal,spatiotemporal\n\
             artificial,grid 0.0 mm,0.8,0.8,0.8,0.8\n\
             artificial,grid 2.5 mm,1,1,1,1\n"
        );
        // Two grids: per coding the neighbour share, and the range share where the paper
        // gives a range (intensive, spatial).
        let confusions = paper_confusions_csv(&r).unwrap();
        assert_eq!(confusions.lines().count(), 1 + 4 + 2, "{confusions}");
        assert!(
            confusions
                .contains(",intensive,errors on the paper's grids,1.0,concentrated on 0–2 mm\n"),
            "{confusions}"
        );
    }

    #[test]
    fn sweep_trace_and_confusion_tables() {
        let s = set_result("x");
        assert_eq!(
            dt_sweep_csv(s.dt_search().unwrap()).unwrap(),
            "dt_ms,loo_accuracy\n1,0.5\n2,0.6\n3,0.7\n"
        );
        assert_eq!(
            bayes_csv(s.bayes_search().unwrap()).unwrap().lines().nth(1),
            Some("1,0.02,0.5,0.8,0.8,0.02,0.5")
        );
        let names = ["a,b".to_string(), "c".to_string()];
        assert_eq!(
            confusion_csv(&[vec![1, 2], vec![3, 4]], &names).unwrap(),
            "true\\predicted,\"a,b\",c\n\"a,b\",1,2\nc,3,4\n"
        );
    }

    #[test]
    fn every_table_reads_back_strictly_when_names_hold_commas_and_quotes() {
        let (set_name, class_name) = ("set \"a\", b", "grid 0.5 mm, \"fine\"");
        let mut set = set_result(set_name);
        set.class_names = vec![class_name.into(), "c".into()];
        let r = report_of(set, "test");
        let s = &r.sets[0].direct;
        let confusion = &s.codings[0].loo.confusion.counts;
        let read = |text: Result<String, Error>| read_table(&text.unwrap()).unwrap().1;
        assert_eq!(&read(accuracy_csv(&r))[0][0], set_name);
        assert_eq!(&read(parameters_csv(&r))[0][0], set_name);
        assert_eq!(&read(loo_recall_csv(&r))[0][1], class_name);
        assert_eq!(
            &read(confusion_csv(confusion, &s.class_names))[0][0],
            class_name
        );
        for text in [
            phase_shares_csv(&r),
            paper_confusions_csv(&r),
            dt_sweep_csv(s.dt_search().unwrap()),
            bayes_csv(s.bayes_search().unwrap()),
        ] {
            read(text);
        }
    }
}
