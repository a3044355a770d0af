//! The report's Markdown tables (also printed by the CLI): accuracy against the paper's, the
//! afferent variant next to the direct pipeline, and the chosen parameters and intensive means.

use neurotac_experiments::coding::CodingName;
use neurotac_experiments::reproduce::paper::{self, PaperTable};
use neurotac_experiments::reproduce::{Report, SetReport, SetResult};
use neurotac_experiments::search::bayes::BayesStep;
use neurotac_experiments::search::{NoiseBand, noise_band};
use std::fmt::Write as _;

/// A text as one Markdown table cell: a `|` escaped as `\|` (GitHub's tables read it as part of
/// the cell), a line break as a blank.
pub fn markdown_cell(text: &str) -> std::borrow::Cow<'_, str> {
    match text.contains(['|', '\n', '\r']) {
        true => text.replace('|', "\\|").replace(['\n', '\r'], " ").into(),
        false => text.into(),
    }
}

/// A fraction as a percentage with one decimal (`0.785` → `78.5`).
pub(crate) fn pct(x: f64) -> String {
    format!("{:.1}", 100.0 * x)
}

/// Appended to the paper's column of a `--quick` run's table.
pub const QUICK_MARK: &str = " — not comparable: --quick run";

/// The paper's table for this set, if it is one of the paper's sets.
pub(crate) fn paper_table(set: &SetResult) -> Option<&'static PaperTable> {
    paper::table_for(&set.name)
}

/// The index of `coding` in the paper's tables ([`paper::CODINGS`]), `None` for a coding the
/// paper did not run.
pub(crate) fn paper_column(coding: CodingName) -> Option<usize> {
    paper::CODINGS.iter().position(|&c| c == coding)
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
        let _ = write!(
            s,
            " paper, {} (%){} |",
            p.table,
            QUICK_MARK.repeat(set.quick as usize)
        );
    }
    s.push_str("\n|---|---|---|---|---|");
    if paper.is_some() {
        s.push_str("---|");
    }
    s.push('\n');
    for c in &set.direct.codings {
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
            // A coding the paper did not run has no paper column.
            match (paper_column(c.coding), p.std_percent) {
                (None, _) => s.push_str(" — |"),
                (Some(i), Some(sd)) => {
                    let _ = write!(s, " {:.1} ± {:.1} |", p.accuracy_percent[i], sd[i]);
                }
                (Some(i), None) => {
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
    set.coding(coding).seconds_with_search()
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

/// A parameter chosen by a search, as the parameter table shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct ChosenParameter {
    /// The value against the paper's.
    pub row: ParameterRow,
    /// The value as the table prints it (`159`, `76`, `0.40`).
    pub printed: String,
    /// Why it is suspect: it sits on a bound of its search (the optimum may lie beyond it);
    /// `None` when inside.
    pub bound_note: Option<String>,
    /// Why it is not determined: other candidates of its search score within the best's
    /// noise ([`noise_band`]), so the data single out a range, not this value; `None` when
    /// the best stands alone.
    pub noise_note: Option<String>,
}

/// The value `printed` of a search's choice and its noise note: when other candidates score
/// within the best's noise the printed value says it is not determined and gives the range
/// (`159, not determined: 40–200`), and the note says how many candidates that range holds.
fn undetermined(
    printed: String,
    band: Option<NoiseBand>,
    what: &str,
    (scale, decimals, unit): (f64, usize, &str),
) -> (String, Option<String>) {
    match band {
        Some(b) if !b.determined() => (
            format!(
                "{printed}, not determined: {:.decimals$}–{:.decimals$}{unit}",
                b.low * scale,
                b.high * scale
            ),
            Some(format!(
                "{} of {} {what} score within the best's Wilson 95 % interval",
                b.count, b.of
            )),
        ),
        _ => (printed, None),
    }
}

/// The note of `value` when it sits on a bound of its search `[low, high]` (within
/// `half_step`): `on the search bound (τ ≤ 100 ms)`, the bound printed in `unit` after
/// `scale`.
fn bound_note(
    value: f64,
    (low, high): (f64, f64),
    half_step: f64,
    what: &str,
    (scale, unit): (f64, &str),
) -> Option<String> {
    let on = |op: &str, b: f64| {
        Some(format!(
            "on the search bound ({what} {op} {:.0}{unit})",
            b * scale
        ))
    };
    if value >= high - half_step {
        on("≤", high)
    } else if value <= low + half_step {
        on("≥", low)
    } else {
        None
    }
}

/// The parameters the searches chose — Δt (the Δt sweep), τ and cos θ (the Bayesian
/// optimisation) — each against the paper's and flagged when on a bound of its search.
pub fn chosen_parameters(set: &SetResult) -> Vec<ChosenParameter> {
    let paper_set = set.name == "artificial";
    let chosen = |quantity: &str,
                  value: f64,
                  paper: f64,
                  (printed, noise_note): (String, Option<String>),
                  bound_note| ChosenParameter {
        row: ParameterRow {
            quantity: quantity.into(),
            value,
            paper: paper_set.then_some(paper),
        },
        printed,
        bound_note,
        noise_note,
    };
    // Every search scores leave-one-out accuracy on all the set's samples.
    let n: usize = set.samples_per_class.iter().sum();
    let mut out = Vec::new();
    if let Some(dt) = set.dt_search() {
        let w = dt.sweep.best_window_ms;
        let span = (1.0, dt.max_window_ms as f64);
        let note = bound_note(w as f64, span, 0.0, "Δt", (1.0, " ms"));
        let candidates: Vec<(f64, f64)> = (dt.sweep.windows_ms.iter())
            .zip(&dt.sweep.accuracy)
            .map(|(&w, &a)| (w as f64, a))
            .collect();
        let band = noise_band(&candidates, dt.sweep.best.n);
        out.push(chosen(
            "temporal Δt (ms)",
            w as f64,
            paper::DT_MS,
            undetermined(w.to_string(), band, "windows", (1.0, 0, " ms")),
            note,
        ));
    }
    if let Some(b) = set.bayes_search() {
        let (tau, cos) = (b.result.best_tau_s, b.result.best_cos);
        // ms on the search's grid, rounded so it prints in its shortest form (35, not
        // 35.00000000000001).
        let tau_ms = (tau * 1e3 * 1e9).round() / 1e9;
        let span = (b.tau_min_s, b.tau_max_s);
        let tau_note = bound_note(tau, span, b.tau_step_s / 2.0, "τ", (1e3, " ms"));
        let trace = &b.result.trace;
        let band = |pick: fn(&BayesStep) -> f64| {
            let candidates: Vec<(f64, f64)> = trace.iter().map(|s| (pick(s), s.value)).collect();
            noise_band(&candidates, n)
        };
        let evaluations = "evaluations";
        out.push(chosen(
            "Van Rossum τ (ms)",
            tau_ms,
            paper::TAU_MS,
            undetermined(
                format!("{tau_ms:.0}"),
                band(|s| s.tau_s),
                evaluations,
                (1e3, 0, " ms"),
            ),
            tau_note,
        ));
        let cos_note = bound_note(cos, (0.0, 1.0), b.cos_step / 2.0, "cos θ", (1.0, ""));
        out.push(chosen(
            "Van Rossum cos θ",
            cos,
            paper::COS_THETA,
            undetermined(
                format!("{cos:.2}"),
                band(|s| s.cos),
                evaluations,
                (1.0, 2, ""),
            ),
            cos_note,
        ));
    }
    out
}

/// The intensive mean of every class, with the paper's where it gives one.
pub fn class_mean_rows(set: &SetResult) -> Vec<ParameterRow> {
    (set.class_names.iter())
        .zip(&set.intensive_class_means)
        .map(|(class, &value)| ParameterRow {
            quantity: format!("intensive mean, {class} (spikes per taxel)"),
            value,
            paper: paper::INTENSIVE_MEANS
                .iter()
                .find(|&&(mm, _)| *class == paper::grid_name(mm))
                .map(|&(_, m)| m),
        })
        .collect()
}

/// The chosen parameters ([`chosen_parameters`]), then the intensive mean of every class.
pub fn parameter_rows(set: &SetResult) -> Vec<ParameterRow> {
    (chosen_parameters(set).into_iter().map(|c| c.row))
        .chain(class_mean_rows(set))
        .collect()
}

/// The chosen Δt, τ and cos θ against the paper's, each flagged when it sits on a bound of its
/// search, as Markdown.
pub fn parameter_table(set: &SetResult) -> String {
    let mut s = String::from("| quantity | this run | paper | note |\n|---|---|---|---|\n");
    for c in chosen_parameters(set) {
        let paper = c.row.paper.map_or("—".into(), |p| p.to_string());
        let note = [c.bound_note, c.noise_note]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>()
            .join("; ");
        let _ = writeln!(
            s,
            "| {} | {} | {paper} | {note} |",
            c.row.quantity, c.printed
        );
    }
    s
}

/// The grid sizes (mm) whose intensive means the simulator was fitted to, for `set`: the
/// calibration's anchors when the set is simulated, none for a recorded set.
pub fn fitted_grids_mm(report: &Report, set: &SetReport) -> Vec<f64> {
    match set.source.starts_with("simulated") {
        true => report
            .calibration
            .iter()
            .map(|c| c.anchor_grid_mm)
            .collect(),
        false => Vec::new(),
    }
}

/// Marks a value the simulator was fitted to ([`intensive_table`]'s footnote says so).
pub const FITTED_MARK: &str = "†";

/// The intensive mean (spikes per taxel) of every class in class order, with the paper's where
/// it gives one, then for bump grids whether the means rise with grid size, as Markdown. The
/// classes of `fitted_grids_mm` ([`fitted_grids_mm`]) are marked † with a footnote: their
/// agreement with the paper was fitted, not predicted.
pub fn intensive_table(set: &SetResult, fitted_grids_mm: &[f64]) -> String {
    let mut s =
        String::from("| class | intensive mean (spikes per taxel) | paper |\n|---|---|---|\n");
    let mut marked = false;
    for (r, name) in class_mean_rows(set).into_iter().zip(&set.class_names) {
        let fitted = paper::grid_size_mm(name)
            .is_some_and(|mm| fitted_grids_mm.iter().any(|&f| (f - mm).abs() < 1e-9));
        marked |= fitted;
        let mark = if fitted { FITTED_MARK } else { "" };
        let paper = r.paper.map_or("—".into(), |p| p.to_string());
        let name = markdown_cell(name);
        let _ = writeln!(s, "| {name} | {:.2}{mark} | {paper} |", r.value);
    }
    if marked {
        let _ = writeln!(
            s,
            "\n{FITTED_MARK} fitted: the simulator's calibration target (one simulator \
             parameter is fitted to each of these paper means), so agreement here is by \
             construction, not a prediction."
        );
    }
    if let Some(line) = monotonicity(set) {
        let _ = writeln!(s, "\n{line}");
    }
    s
}

/// For a set of bump grids (classes named `grid D mm`, sorted by D): whether the intensive
/// means rise with grid size, naming every step where they do not.
pub fn monotonicity(set: &SetResult) -> Option<String> {
    let sizes: Vec<f64> = set
        .class_names
        .iter()
        .map(|n| paper::grid_size_mm(n))
        .collect::<Option<_>>()?;
    if sizes.len() < 2 || sizes.windows(2).any(|w| w[0] >= w[1]) {
        return None;
    }
    let falls: Vec<String> = sizes
        .windows(2)
        .zip(set.intensive_class_means.windows(2))
        .filter(|(_, m)| m[1] <= m[0])
        .map(|(d, m)| format!("{:.1} → {:.1} mm ({:.2} → {:.2})", d[0], d[1], m[0], m[1]))
        .collect();
    Some(if falls.is_empty() {
        "The intensive mean rises with every grid size.".to_owned()
    } else {
        format!(
            "The intensive mean does not rise with grid size at {}.",
            falls.join(", ")
        )
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use neurotac_experiments::menu::Menu;
    use neurotac_experiments::protocols::{Accuracy, ConfusionMatrix, Evaluation};
    use neurotac_experiments::reproduce::{BayesSearch, CodingResult, DtSearch, Scored, Search};
    use neurotac_experiments::search::bayes::{BayesResult, BayesStep};
    use neurotac_experiments::search::dt_sweep::DtSweep;
    use neurotac_experiments::timing::Timing;

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
        let step = BayesStep {
            epoch: 1,
            tau_s: 0.02,
            cos: 0.5,
            value: 0.8,
            best_value: 0.8,
            best_tau_s: 0.02,
            best_cos: 0.5,
        };
        let codings = CodingName::ALL
            .iter()
            .enumerate()
            .map(|(i, &coding)| CodingResult {
                coding,
                scored: Scored {
                    parameters: if coding == CodingName::Temporal {
                        "Δt = 3 ms".into()
                    } else {
                        String::new()
                    },
                    loo: evaluation(0.5 + 0.1 * i as f64),
                    split: (i != 1).then(|| evaluation(0.6)),
                    split_refused: (i == 1).then(|| "class 1 has 1 sample(s)".into()),
                    time: Timing::default(),
                    search: match coding {
                        CodingName::Temporal => Some(Search::DtSweep(DtSearch {
                            sweep: DtSweep {
                                windows_ms: vec![1, 2, 3],
                                accuracy: vec![0.5, 0.6, 0.7],
                                best_window_ms: 3,
                                best: evaluation(0.7).accuracy,
                            },
                            max_window_ms: 3,
                            time: Timing::default(),
                        })),
                        CodingName::Spatiotemporal => Some(Search::Bayes(BayesSearch {
                            result: BayesResult {
                                best_tau_s: 0.02,
                                best_cos: 0.5,
                                best_value: 0.8,
                                best_tau_index: 0,
                                trace: vec![step],
                            },
                            tau_min_s: 0.01,
                            tau_max_s: 0.1,
                            tau_step_s: 0.005,
                            cos_step: 0.01,
                            matrices_computed: 1,
                            time: Timing::default(),
                        })),
                        _ => None,
                    },
                },
            })
            .collect();
        SetResult {
            name: name.into(),
            path: "network: taxel input → four coding readouts".into(),
            van_rossum: "exact, from the readout's spike trains".into(),
            class_names: vec!["grid 0.0 mm".into(), "grid 2.5 mm".into()],
            samples_per_class: vec![5, 5],
            duration_ms: 10,
            mean_spikes_per_taxel: 7.0,
            intensive_class_means: vec![4.0, 10.0],
            codings,
            time: Timing::default(),
        }
    }

    /// The set report of `direct` (no afferents, no examples), its source named `source`, its
    /// phases unknown as a recorded set's.
    pub(crate) fn set_report(direct: SetResult, source: &str, quick: bool) -> SetReport {
        SetReport {
            source: source.into(),
            dataset_time: Timing::default(),
            readout_time: Timing::default(),
            phases: neurotac_experiments::reproduce::phases::Phases::recorded(),
            loo_analysis: neurotac_experiments::reproduce::confusions::loo_analysis(&direct),
            direct,
            afferent: None,
            examples: Vec::new(),
            mountings: Vec::new(),
            quick,
        }
    }

    /// A one-set report of `direct`, its source named `source`.
    pub(crate) fn report_of(
        direct: SetResult,
        source: &str,
    ) -> neurotac_experiments::reproduce::Report {
        neurotac_experiments::reproduce::Report {
            command: "neurotac reproduce".into(),
            version: "0".into(),
            seed: 1,
            sets: vec![set_report(direct, source, false)],
            calibration: Vec::new(),
            time: Timing::default(),
        }
    }

    #[test]
    fn the_accuracy_table_adds_the_papers_column_for_the_papers_sets() {
        let set = |name| set_report(set_result(name), "test", false);
        let ours = accuracy_table(&set("artificial"));
        let lines: Vec<&str> = ours.lines().collect();
        assert_eq!(lines.len(), 2 + CodingName::ALL.len());
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
        assert!(
            table.contains(
                "| temporal Δt (ms) | 3, not determined: 1–3 ms | 159 | on the search bound \
                 (Δt ≤ 3 ms); 3 of 3 windows score within the best's Wilson 95 % interval |"
            ),
            "{table}"
        );
        assert!(
            table.contains("| Van Rossum τ (ms) | 20 | 76 |  |"),
            "{table}"
        );
    }

    /// A choice on a search bound is flagged, one inside is not.
    #[test]
    fn choices_on_a_search_bound_are_flagged() {
        let bound_notes = |set: &SetResult| -> Vec<Option<String>> {
            (chosen_parameters(set).into_iter())
                .map(|c| c.bound_note)
                .collect()
        };
        let mut set = set_result("natural");
        assert_eq!(
            bound_notes(&set),
            [
                Some("on the search bound (Δt ≤ 3 ms)".to_owned()),
                None,
                None
            ]
        );
        for c in &mut set.codings {
            match &mut c.search {
                Some(Search::DtSweep(dt)) => dt.sweep.best_window_ms = 2,
                Some(Search::Bayes(b)) => (b.result.best_tau_s, b.result.best_cos) = (0.1, 0.0),
                None => {}
            }
        }
        assert_eq!(
            bound_notes(&set),
            [
                None,
                Some("on the search bound (τ ≤ 100 ms)".to_owned()),
                Some("on the search bound (cos θ ≥ 0)".to_owned())
            ]
        );
        for c in &mut set.codings {
            if let Some(Search::Bayes(b)) = &mut c.search {
                b.result.best_tau_s = 0.012;
            }
        }
        assert_eq!(
            bound_notes(&set)[1].as_deref(),
            Some("on the search bound (τ ≥ 10 ms)")
        );
    }

    /// A search whose other candidates score within the best's noise does not report its
    /// choice as determined: the range is printed instead; a best that stands out is printed
    /// alone.
    #[test]
    fn a_choice_within_the_noise_of_others_is_reported_as_not_determined() {
        let mut set = set_result("natural");
        set.samples_per_class = vec![500, 500];
        for c in &mut set.codings {
            match &mut c.search {
                // 1000 samples: 70 % stands out from 60 % and 50 %.
                Some(Search::DtSweep(dt)) => dt.sweep.best.n = 1000,
                Some(Search::Bayes(b)) => {
                    let step = b.result.trace[0];
                    b.result.trace = [(0.02, 0.5, 0.8), (0.05, 0.9, 0.79), (0.09, 0.1, 0.5)]
                        .map(|(tau_s, cos, value)| BayesStep {
                            tau_s,
                            cos,
                            value,
                            ..step
                        })
                        .to_vec();
                }
                None => {}
            }
        }
        let chosen = chosen_parameters(&set);
        assert_eq!(
            (chosen[0].printed.as_str(), &chosen[0].noise_note),
            ("3", &None)
        );
        // 79 % on 1000 samples is within the Wilson interval of 80 %: τ 20–50 ms, cos 0.5–0.9.
        assert_eq!(chosen[1].printed, "20, not determined: 20–50 ms");
        assert_eq!(chosen[2].printed, "0.50, not determined: 0.50–0.90");
        assert_eq!(
            chosen[1].noise_note.as_deref(),
            Some("2 of 3 evaluations score within the best's Wilson 95 % interval")
        );
    }

    /// The three class means the simulator was fitted to are marked in a simulated set's
    /// table, with a footnote; a recorded set's are not.
    #[test]
    fn the_fitted_intensive_means_are_marked_for_simulated_sets_only() {
        let set = set_result("artificial");
        let table = intensive_table(&set, &[0.0, 2.5, 5.0]);
        assert!(table.contains("| grid 0.0 mm | 4.00† | 4.63 |"), "{table}");
        assert!(table.contains("| grid 2.5 mm | 10.00† | 9.84 |"), "{table}");
        assert!(
            table.contains("† fitted: the simulator's calibration target"),
            "{table}"
        );
        let mut report = report_of(set_result("artificial"), "simulated, 3 slides per texture");
        report.calibration = neurotac_sensor::sim::SimParams::default()
            .calibrated_parameters()
            .to_vec();
        assert_eq!(fitted_grids_mm(&report, &report.sets[0]), [0.0, 2.5, 5.0]);
        report.sets[0].source = "recorded: textures/".into();
        assert!(fitted_grids_mm(&report, &report.sets[0]).is_empty());
    }

    /// Every class's intensive mean is shown, and a fall with grid size is named.
    #[test]
    fn every_intensive_mean_is_shown_and_monotonicity_is_checked() {
        let mut set = set_result("artificial");
        let table = intensive_table(&set, &[]);
        assert!(table.contains("| grid 0.0 mm | 4.00 | 4.63 |"), "{table}");
        assert!(table.contains("| grid 2.5 mm | 10.00 | 9.84 |"), "{table}");
        assert!(!table.contains(FITTED_MARK), "{table}");
        assert!(
            table.ends_with("The intensive mean rises with every grid size.\n"),
            "{table}"
        );
        set.intensive_class_means = vec![10.0, 4.0];
        assert_eq!(
            monotonicity(&set).unwrap(),
            "The intensive mean does not rise with grid size at 0.0 → 2.5 mm (10.00 → 4.00)."
        );
        set.class_names = vec!["cotton".into(), "denim".into()];
        assert_eq!(monotonicity(&set), None);
        assert!(intensive_table(&set, &[0.0, 2.5, 5.0]).contains("| cotton | 10.00 | — |"));
    }

    /// A --quick run's table says it is not comparable with the paper's.
    #[test]
    fn a_quick_tables_paper_column_is_marked() {
        let set = set_report(set_result("artificial"), "test", true);
        let first = accuracy_table(&set).lines().next().unwrap().to_owned();
        assert!(
            first.ends_with("| paper, Table 1 (%) — not comparable: --quick run |"),
            "{first}"
        );
    }

    /// A class name holding a `|` or a line break stays one cell of its row.
    #[test]
    fn a_name_holding_a_pipe_or_a_line_break_stays_one_cell() {
        assert_eq!(markdown_cell("plain"), "plain");
        assert_eq!(markdown_cell("a|b\nc"), "a\\|b c");
        let mut set = set_result("textures");
        set.class_names = vec!["fine|coarse".into(), "denim".into()];
        let table = intensive_table(&set, &[]);
        assert!(table.contains("| fine\\|coarse | 4.00 | — |"), "{table}");
    }
}
