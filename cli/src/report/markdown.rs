//! `report.md`: how the run was made, then per set its tables, figures and notes.

use super::class_tables::{paper_confusion_table, phase_table, recall_table};
use super::mountings::mounting_table;
use super::tables::{
    accuracy_table, afferent_table, fitted_grids_mm, intensive_table, parameter_table,
};
use neurotac_experiments::coding::CodingName;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::reproduce::{Report, SetReport};
use std::fmt::Write as _;

/// The whole `report.md`.
pub fn report_markdown(report: &Report) -> String {
    let mut md = markdown_intro(report);
    md.push_str(&calibration_section(report));
    for set in &report.sets {
        markdown_set(set, &fitted_grids_mm(report, set), &mut md);
    }
    md.push_str(
        "Files: `report.json` (every number), `accuracy.csv`, `parameters.csv`, \
         `phase_shares.csv`, `loo_recall.csv`, `paper_confusions.csv`, `dt_sweep_<set>.csv`, \
         `bo_convergence_<set>.csv`, `confusion_<set>_<coding>.csv`, \
         `confusion_loo_<set>_<coding>.csv` (leave-one-out); every figure as SVG and PNG.\n",
    );
    md
}

/// The head of `report.md`: how the run was made and what the numbers mean.
fn markdown_intro(report: &Report) -> String {
    format!(
        "# NeuroTac reproduction\n\n`{}` (neurotac {}, seed {}): {:.1} s wall{} for the \
         datasets and pipelines, everything but writing this report (the terminal's `total` \
         adds the writing).\n\n\
         Pipeline (the paper's Methods): pixel events → background-activity filter (5 ms) → 49 \
         receptive fields → 20 ms pooling with re-centring → taxel spikes → four codings → KNN \
         (k = 4). Accuracies: leave-one-out (the paper's Tables 1 and 2), ± the standard \
         deviation of the per-sample hits as in the paper, with Wilson 95 % intervals; \
         confusion matrices: the seeded stratified 80/20 split. Δt and (τ, cos θ) are chosen \
         by leave-one-out accuracy on the same samples, as in the paper.\n\n{}",
        report.command,
        report.version,
        report.seed,
        report.time.wall_s,
        report
            .time
            .cpu_s
            .map(|c| format!(", {c:.1} s CPU on {} threads", report.time.threads))
            .unwrap_or_default(),
        if report
            .sets
            .iter()
            .any(|s| s.source.starts_with("simulated"))
        {
            "The texture sets are simulated (the paper's recordings are not public) by the \
             NeuroTac simulator, calibrated on the paper's three intensive means only (see \
             \"Calibration and hold-out\"): the comparison with the paper measures how close the \
             simulated sensor is to the real one.\n\n"
        } else {
            ""
        }
    )
}

/// The "Calibration and hold-out" section: exactly what the simulator was fitted to (empty
/// when no set is simulated).
fn calibration_section(report: &Report) -> String {
    if report.calibration.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "## Calibration and hold-out\n\nFitted (by `neurotac simulate calibrate`, each parameter \
         to one of the paper's intensive means, nothing else):\n\n\
         | parameter | value | fitted to |\n|---|---|---|\n",
    );
    for c in &report.calibration {
        let _ = writeln!(
            md,
            "| `{}` | {} | spikes per taxel on the {} mm grid = {} (paper) |",
            c.name, c.value, c.anchor_grid_mm, c.target_spikes_per_taxel
        );
    }
    md.push_str(
        "\nEvery other simulator value is a prior with its source in the parameter file \
         (`neurotac simulate params`). Held out — predictions, never fitted: every accuracy, \
         every confusion matrix, the chosen Δt, τ and cos θ, the other grids' intensive means \
         and the whole natural set.\n\n",
    );
    md
}

/// A set's section of `report.md`.
fn markdown_set(set: &SetReport, fitted_grids_mm: &[f64], md: &mut String) {
    let d = &set.direct;
    let name = &d.name;
    let samples: usize = d.samples_per_class.iter().sum();
    let _ = write!(
        md,
        "## {} set\n\n{} classes, {samples} samples ({}); {:.2} spikes per taxel on average; \
         dataset {:.1} s, readout network {:.1} s, pipeline {:.1} s wall.\n\n\
         Codings from: {} (the KNN head classified what the readouts held). Van Rossum \
         distance: {}.\n\n",
        name,
        d.class_names.len(),
        set.source,
        d.mean_spikes_per_taxel,
        set.dataset_time.wall_s,
        set.readout_time.wall_s,
        d.time.wall_s,
        d.path,
        d.van_rossum,
    );
    if set.quick {
        md.push_str(
            "A quick run (`--quick`: 10 slides per texture, 60 optimisation epochs, τ on a 10 ms \
             grid): its accuracies and chosen parameters are not comparable with the paper's.\n\n",
        );
    }
    md.push_str(&accuracy_table(set));
    md.push('\n');
    md.push_str(&mounting_table(set));
    if let Some(c) = d.codings.iter().find_map(|c| c.split_refused.as_ref()) {
        let _ = write!(
            md,
            "The 80/20 split was refused: {c}. The confusion matrices show leave-one-out.\n\n"
        );
    }
    md.push_str(&parameter_table(d));
    md.push('\n');
    md.push_str(&intensive_table(d, fitted_grids_mm));
    md.push('\n');
    markdown_class_sections(set, md);
    if let Some(a) = &set.afferent {
        let _ = write!(
            md,
            "Afferent variant: taxel spikes → exponential synapses (τ = {:.0} ms, weight {}) \
             → one {} neuron per taxel (dt = {:.2} ms), then the same pipeline (its own Δt \
             sweep and optimisation). Times include each coding's parameter search.\n\n",
            a.tau_syn_s * 1e3,
            a.weight,
            a.model,
            a.dt_s * 1e3,
        );
        md.push_str(&afferent_table(set));
        md.push('\n');
    }
    let shown: Vec<&str> = set.examples.iter().map(|(n, _)| n.as_str()).collect();
    let _ = write!(
        md,
        "![spike trains](spike_trains_{name}.svg)\n\n*Spike trains of the first sample of {} \
         of the {} classes — {} (rows: raster, spikes per taxel, spikes per taxel in the \
         chosen Δt window).*\n\n",
        shown.len(),
        d.class_names.len(),
        shown.join(", ")
    );
    md.push_str(if d.codings.iter().any(|c| c.split.is_none()) {
        "Confusion matrices (leave-one-out; the split was refused):\n\n"
    } else {
        "Confusion matrices (80/20 split):\n\n"
    });
    for c in CodingName::ALL {
        let _ = write!(
            md,
            "![{} confusion](confusion_{name}_{}.svg) ",
            c.label(),
            c.key()
        );
    }
    md.push_str("\n\n");
    if d.dt_search().is_some() {
        let _ = write!(md, "![Δt sweep](dt_sweep_{name}.svg)\n\n");
    }
    if d.bayes_search().is_some() {
        let _ = write!(md, "![BO convergence](bo_convergence_{name}.svg)\n\n");
    }
}

/// A set's per-class sections: spikes by slide phase, leave-one-out recall, and the paper's
/// named confusions next to ours (when any applies).
fn markdown_class_sections(set: &SetReport, md: &mut String) {
    let _ = write!(
        md,
        "### Spikes by slide phase\n\n{}\n### Leave-one-out recall per class\n\n{}\n",
        phase_table(set),
        recall_table(set)
    );
    let confusions = paper_confusion_table(set);
    if !confusions.is_empty() {
        let _ = write!(
            md,
            "### The paper's named confusions, measured on our leave-one-out predictions\n\n\
             {confusions}\n"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::tables::tests::{report_of, set_result};

    #[test]
    fn the_page_names_the_run_and_embeds_every_figure_of_every_set() {
        let mut report = report_of(set_result("artificial"), "simulated, 10 slides per texture");
        (report.command, report.version, report.seed) =
            ("neurotac reproduce --quick".into(), "9.9".into(), 4);
        let md = report_markdown(&report);
        assert!(md.starts_with(
            "# NeuroTac reproduction\n\n`neurotac reproduce --quick` (neurotac 9.9, seed 4)"
        ));
        assert!(md.contains("The texture sets are simulated"));
        assert!(md.contains("## artificial set"));
        assert!(md.contains("The 80/20 split was refused: class 1 has 1 sample(s)."));
        for stem in [
            "spike_trains_artificial",
            "confusion_artificial_spatial",
            "dt_sweep_artificial",
            "bo_convergence_artificial",
        ] {
            assert!(md.contains(&format!("({stem}.svg)")), "no {stem}");
        }
        for section in [
            "### Spikes by slide phase\n\nNo slide-phase table: a recorded dataset",
            "### Leave-one-out recall per class\n\n| class (LOO recall, %) |",
            "### The paper's named confusions, measured on our leave-one-out predictions",
        ] {
            assert!(md.contains(section), "no {section}");
        }
        assert!(md.ends_with("every figure as SVG and PNG.\n"));
    }

    #[test]
    fn the_page_lists_exactly_what_the_simulator_was_fitted_to() {
        let mut report = report_of(set_result("artificial"), "simulated, 10 slides per texture");
        assert!(!report_markdown(&report).contains("## Calibration and hold-out"));
        report.calibration = neurotac_sensor::sim::SimParams::default()
            .calibrated_parameters()
            .to_vec();
        let md = report_markdown(&report);
        let section = &md[md.find("## Calibration and hold-out").expect("section")..];
        for (name, grid, paper) in [
            ("contact.pin_shear_gain", "0 mm", "4.63"),
            ("contact.gap_conformity_mm", "2.5 mm", "9.84"),
            ("contact.lever_mm", "5 mm", "34.73"),
        ] {
            let row = section.lines().find(|l| l.contains(name)).expect(name);
            assert!(row.contains(grid) && row.contains(paper), "{row}");
        }
        assert!(section.contains("every accuracy"));
        assert!(section.find("## Calibration").unwrap() < section.find("## artificial").unwrap());
    }
}
