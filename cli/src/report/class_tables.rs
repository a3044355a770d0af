//! The report's per-class Markdown tables (also printed by the CLI): the share of spikes in
//! each slide phase ([`phase_table`]), the leave-one-out recall of every class under every
//! coding ([`recall_table`]), and the confusions the paper names next to ours
//! ([`paper_confusion_table`]).

use super::tables::{markdown_cell, pct};
use neurotac_experiments::reproduce::SetReport;
use neurotac_experiments::reproduce::confusions::{GridErrorRates, NamedConfusionRates};
use neurotac_experiments::reproduce::paper::{self, NEIGHBOURING_ERRORS_QUOTE};
use neurotac_experiments::reproduce::phases::{ONSET_S, PhaseShare, Phases, SlidePhase};
use std::fmt::Write as _;

/// A fraction as a percentage, `—` when there is none.
fn pct_or_dash(x: Option<f64>) -> String {
    x.map_or("—".into(), pct)
}

/// The header row and rule of a table whose columns after `first` are the paper's four
/// codings ([`paper::CODINGS`], under which the per-class analyses are made).
fn coding_header(first: &[&str]) -> String {
    let mut s = String::from("|");
    for column in first
        .iter()
        .copied()
        .chain(paper::CODINGS.iter().map(|c| c.label()))
    {
        let _ = write!(s, " {column} |");
    }
    s.push_str("\n|");
    s.push_str(&"---|".repeat(first.len() + paper::CODINGS.len()));
    s.push('\n');
    s
}

/// The share (%) of a set's taxel spikes in each slide phase, per class and over all classes,
/// as Markdown with a line on how the phases were cut; for a set without known motion times,
/// one line saying why.
pub fn phase_table(set: &SetReport) -> String {
    let shares = match &set.phases {
        Phases::Known(shares) => shares,
        Phases::Unknown(why) => return format!("No slide-phase table: {why}.\n"),
    };
    let t = shares.timing;
    let mut s = format!(
        "Share of each sample's taxel spikes (%) by slide phase, mean over the class's samples: \
         press = the press and dwell before the slide starts ({:.3} s), onset = the slide's first \
         {:.0} ms, sliding = the rest of the slide, stop = from the slide's end ({:.3} s) to the end \
         of the recording. \
         Motion times from {}.\n\n| class |",
        t.motion_start_s,
        ONSET_S * 1e3,
        t.motion_end_s,
        shares.timing_source
    );
    for p in SlidePhase::ALL {
        let _ = write!(s, " {} |", p.key());
    }
    s.push_str("\n|---|---|---|---|---|\n");
    let row = |s: &mut String, class: &str, share: &PhaseShare| {
        let _ = write!(s, "| {} |", markdown_cell(class));
        for p in SlidePhase::ALL {
            let _ = write!(s, " {} |", pct(share.of(p)));
        }
        s.push('\n');
    };
    for (class, share) in set.direct.class_names.iter().zip(&shares.per_class) {
        row(&mut s, class, share);
    }
    row(&mut s, "**all classes (mean)**", &shares.all_classes);
    if shares.samples_without_spikes > 0 {
        let _ = writeln!(
            s,
            "\n{} samples without spikes are left out.",
            shares.samples_without_spikes
        );
    }
    s
}

/// The leave-one-out recall (%) of every class (rows) under every coding (columns), as
/// Markdown.
pub fn recall_table(set: &SetReport) -> String {
    let mut s = coding_header(&["class (LOO recall, %)"]);
    for (class_index, class) in set.direct.class_names.iter().enumerate() {
        let _ = write!(s, "| {} |", markdown_cell(class));
        for r in &set.loo_analysis.recall {
            let _ = write!(
                s,
                " {} |",
                pct_or_dash(r.per_class.get(class_index).copied().flatten())
            );
        }
        s.push('\n');
    }
    s
}

/// One named confusion's row: per coding, our rate(s) and whether the paper sees it.
fn named_confusion_row(r: &NamedConfusionRates) -> String {
    let p = &r.paper;
    let mut measured = format!("{} → {}", p.truth, p.predicted);
    if p.mutual {
        let _ = write!(measured, " / {} → {}", p.predicted, p.truth);
    }
    let mut s = format!("| {} | {measured} |", p.label());
    for i in 0..paper::CODINGS.len() {
        let mut ours = pct_or_dash(r.truth_as_predicted[i]);
        if p.mutual {
            let _ = write!(ours, " / {}", pct_or_dash(r.predicted_as_truth[i]));
        }
        let paper = if p.confused_under[i] { "yes" } else { "no" };
        let _ = write!(s, " {ours} · paper: {paper} |");
    }
    s.push('\n');
    s
}

/// One coding's row of the bump-grid error table.
fn grid_error_row(r: &GridErrorRates) -> String {
    let range = match (r.in_paper_range, r.paper.concentrated_on_mm) {
        (Some(f), Some((lo, hi))) => format!("{} (true grid {lo}–{hi} mm)", pct(f)),
        _ => "—".into(),
    };
    format!(
        "| {} | {} | {} | {} | {range} |\n",
        r.coding.label(),
        r.paper.quote,
        r.errors,
        pct_or_dash(r.between_neighbours),
    )
}

/// The confusions the paper names that apply to this set, each with the rate at which our
/// leave-one-out predictions make it, as Markdown; empty when none applies (see
/// [`neurotac_experiments::reproduce::confusions`]).
pub fn paper_confusion_table(set: &SetReport) -> String {
    let a = &set.loo_analysis;
    let mut s = String::new();
    if !a.named_confusions.is_empty() {
        s.push_str(
            "Each cell: the fraction (%) of the first texture's samples our leave-one-out \
             predicts as the second (and the other way for ↔), and whether the paper sees the \
             confusion under that coding.\n\n",
        );
        s.push_str(&coding_header(&["the paper names", "measured (ours, LOO)"]));
        for r in &a.named_confusions {
            s.push_str(&named_confusion_row(r));
        }
    }
    if !a.grid_errors.is_empty() {
        if !s.is_empty() {
            s.push('\n');
        }
        let _ = write!(
            s,
            "The paper: \"{NEIGHBOURING_ERRORS_QUOTE}\", and per coding where its errors lie. \
             Ours: the leave-one-out errors, the share between neighbouring grid sizes and the \
             share whose true grid lies where the paper sees the coding's errors.\n\n\
             | coding | the paper | LOO errors | between neighbouring grids (%) | on the paper's \
             grids (%) |\n|---|---|---|---|---|\n"
        );
        for r in &a.grid_errors {
            s.push_str(&grid_error_row(r));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::tables::tests::{set_report, set_result};
    use neurotac_experiments::protocols::ConfusionMatrix;
    use neurotac_experiments::reproduce::confusions::loo_analysis;
    use neurotac_experiments::reproduce::phases::{PhaseShares, SlideTiming};

    #[test]
    fn a_recorded_set_says_in_one_line_why_it_has_no_phase_table() {
        let set = set_report(set_result("my-textures"), "recorded", false);
        let table = phase_table(&set);
        assert_eq!(table.lines().count(), 1);
        assert!(table.starts_with("No slide-phase table: a recorded dataset"));
    }

    #[test]
    fn the_phase_table_has_a_row_per_class_and_the_mean() {
        let mut set = set_report(set_result("artificial"), "simulated", false);
        let share = |press, onset, sliding, stop| PhaseShare {
            press,
            onset,
            sliding,
            stop,
        };
        set.phases = Phases::Known(PhaseShares {
            timing: SlideTiming {
                motion_start_s: 0.25,
                motion_end_s: 4.25,
            },
            timing_source: "the nominal kinematics".into(),
            per_class: vec![share(0.0, 0.2, 0.7, 0.1), share(0.1, 0.1, 0.7, 0.1)],
            all_classes: share(0.05, 0.15, 0.7, 0.1),
            samples_without_spikes: 0,
        });
        let table = phase_table(&set);
        assert!(
            table.contains("| class | press | onset | sliding | stop |"),
            "{table}"
        );
        assert!(
            table.contains("| grid 0.0 mm | 0.0 | 20.0 | 70.0 | 10.0 |"),
            "{table}"
        );
        assert!(
            table.contains("| **all classes (mean)** | 5.0 | 15.0 | 70.0 | 10.0 |"),
            "{table}"
        );
        assert!(table.contains("first 200 ms") && table.contains("(4.250 s)"));
    }

    #[test]
    fn recall_and_the_papers_confusions_are_tabulated_per_coding() {
        let mut direct = set_result("natural");
        direct.class_names = ["foam", "fake fur", "liquid satin", "felt"]
            .map(String::from)
            .to_vec();
        let truth = [0, 0, 1, 1, 2, 2, 3, 3];
        let predicted: [&[usize]; 4] = [
            &[0, 0, 3, 3, 2, 2, 3, 3],
            &[0, 0, 1, 1, 2, 2, 3, 3],
            &[0, 0, 1, 1, 2, 2, 3, 3],
            &[0, 0, 1, 1, 0, 2, 3, 3],
        ];
        for (c, p) in direct.codings.iter_mut().zip(predicted) {
            c.loo.confusion = ConfusionMatrix::of(p, &truth, 4);
        }
        let set = set_report(direct, "simulated", false);
        assert_eq!(set.loo_analysis, loo_analysis(&set.direct));
        let recall = recall_table(&set);
        assert!(
            recall.contains("| fake fur | 0.0 | 100.0 | 100.0 | 100.0 |"),
            "{recall}"
        );
        assert!(recall.contains("| liquid satin | 100.0 | 100.0 | 100.0 | 50.0 |"));
        let table = paper_confusion_table(&set);
        assert!(
            table.contains(
                "| fake fur ↔ felt (6 ↔ 17) | fake fur → felt / felt → fake fur | \
                 100.0 / 0.0 · paper: yes | 0.0 / 0.0 · paper: yes | 0.0 / 0.0 · paper: no |"
            ),
            "{table}"
        );
        assert!(
            table.contains(
                "| liquid satin → foam (7 → 1) | liquid satin → foam | 0.0 · paper: no |"
            ),
            "{table}"
        );
        assert!(table.trim_end().ends_with("50.0 · paper: yes |"), "{table}");
        assert!(!table.contains("neighbouring"));
    }

    #[test]
    fn a_grid_set_gets_the_neighbouring_error_table() {
        let mut direct = set_result("artificial");
        // grid 0.0 mm and grid 2.5 mm: every error is between neighbours.
        direct.codings[0].loo.confusion = ConfusionMatrix {
            counts: vec![vec![3, 2], vec![1, 4]],
        };
        let set = set_report(direct, "simulated", false);
        let table = paper_confusion_table(&set);
        assert!(table.starts_with("The paper: \"classification errors occur most often"));
        assert!(
            table.contains("| Intensive | the least effective, particularly for the smoother textures (0–2 mm) | 3 | 100.0 | 66.7 (true grid 0–2 mm) |"),
            "{table}"
        );
        assert!(
            table.contains("| Temporal | near-perfect | 1 | 100.0 | — |"),
            "{table}"
        );
    }
}
