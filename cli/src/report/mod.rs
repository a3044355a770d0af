//! A reproduction's report folder ([`write_report`]): `report.json` (every number), CSV tables
//! ([`csv`]), figures as SVG ([`svg`], [`figures`]) and PNG ([`png`]), and a `report.md`
//! ([`markdown`]) that embeds them with the Markdown tables of [`tables`] and
//! [`class_tables`]; the folder is written atomically ([`folder`]), and every failure is a
//! [`ReportError`].

pub mod class_tables;
pub mod csv;
mod error;
pub mod figures;
pub mod folder;
pub mod markdown;
pub mod mountings;
pub mod png;
pub mod svg;
pub mod tables;

use figures::{bayes_charts, dt_chart, set_spike_train_figure};
use folder::{write, write_csv, write_figure, write_folder_atomically};
use neurotac_experiments::menu::Menu;
use neurotac_experiments::reproduce::{Report, SetReport};
use png::PngRenderer;
use std::path::Path;
use svg::panels;

pub use error::ReportError;

/// Writes `report` into the folder `out` atomically (see [`folder`]); an existing `out` is
/// replaced only with `force`.
pub fn write_report(out: &Path, report: &Report, force: bool) -> Result<(), ReportError> {
    write_folder_atomically(out, force, |dir| write_files(dir, report))
}

fn write_files(dir: &Path, report: &Report) -> Result<(), ReportError> {
    let png = PngRenderer::new();
    let json = serde_json::to_string_pretty(report).expect("the report serialises");
    write(dir, "report.json", &json)?;
    for set in &report.sets {
        write_set_files(dir, set, &png)?;
    }
    write_csv(dir, "accuracy.csv", csv::accuracy_csv(report))?;
    write_csv(dir, "parameters.csv", csv::parameters_csv(report))?;
    write_csv(dir, "phase_shares.csv", csv::phase_shares_csv(report))?;
    write_csv(dir, "loo_recall.csv", csv::loo_recall_csv(report))?;
    write_csv(
        dir,
        "paper_confusions.csv",
        csv::paper_confusions_csv(report),
    )?;
    write(dir, "report.md", &markdown::report_markdown(report))
}

/// A set's own files: Δt sweep and BO trace (CSV + figure), spike-train figure, and the
/// confusion matrices of every run (CSV + figure; the leave-one-out ones as CSV).
fn write_set_files(dir: &Path, set: &SetReport, png: &PngRenderer) -> Result<(), ReportError> {
    let d = &set.direct;
    let name = &d.name;
    if let Some(dt) = d.dt_search() {
        write_csv(dir, &format!("dt_sweep_{name}.csv"), csv::dt_sweep_csv(dt))?;
        let svg = dt_chart(d, dt).to_svg();
        write_figure(dir, &format!("dt_sweep_{name}"), &svg, png)?;
    }
    if let Some(bayes) = d.bayes_search() {
        write_csv(
            dir,
            &format!("bo_convergence_{name}.csv"),
            csv::bayes_csv(bayes),
        )?;
        // Stacked: one panel per row stays readable when the figure is scaled to a page.
        let svg = panels(&bayes_charts(d, bayes), 1);
        write_figure(dir, &format!("bo_convergence_{name}"), &svg, png)?;
    }
    write_figure(
        dir,
        &format!("spike_trains_{name}"),
        &set_spike_train_figure(set),
        png,
    )?;
    for (pipeline, r) in csv::runs(set) {
        let (suffix, label) = match pipeline {
            "direct" => ("", ""),
            _ => ("_afferents", " (afferents)"),
        };
        for c in &r.codings {
            let (e, how) = match &c.split {
                Some(e) => (e, "80/20 split"),
                None => (&c.loo, "leave-one-out (split refused)"),
            };
            let title = format!(
                "{name}{label}: {} coding, {how}, {} %",
                c.coding.label(),
                tables::pct(e.accuracy.mean)
            );
            let file = format!("confusion_{name}_{}{suffix}", c.coding.key());
            let note = set.quick.then(|| {
                let per_class: Vec<usize> =
                    e.confusion.counts.iter().map(|r| r.iter().sum()).collect();
                let (lo, hi) = (
                    per_class.iter().min().copied().unwrap_or(0),
                    per_class.iter().max().copied().unwrap_or(0),
                );
                let n = if lo == hi {
                    lo.to_string()
                } else {
                    format!("{lo}–{hi}")
                };
                format!(
                    "--quick: only {n} test samples per class; one sample moves a row by {:.0} %",
                    100.0 / lo.max(1) as f64
                )
            });
            write_figure(
                dir,
                &file,
                &figures::confusion_figure(
                    &e.confusion.counts,
                    &r.class_names,
                    &title,
                    note.as_deref(),
                ),
                png,
            )?;
            write_csv(
                dir,
                &format!("{file}.csv"),
                csv::confusion_csv(&e.confusion.counts, &r.class_names),
            )?;
            write_csv(
                dir,
                &format!("confusion_loo_{name}_{}{suffix}.csv", c.coding.key()),
                csv::confusion_csv(&c.loo.confusion.counts, &r.class_names),
            )?;
        }
    }
    Ok(())
}
