//! A reproduction's report folder: `report.json` (every number), CSV tables, figures as SVG and
//! PNG (see [`crate::png`]), and a `report.md` that embeds them.
//!
//! The folder is written next to its destination under a temporary name and renamed into place
//! only when complete, so a failed or interrupted run never leaves a folder that looks finished;
//! an existing destination is replaced only when asked to.

use super::paper::{self, PaperTable};
use super::{CodingName, SetResult};
use crate::figures::{confusion_figure, raster_chart, spatial_chart, temporal_chart};
use crate::png::PngRenderer;
use crate::svg::{Axis, Chart, Marker, PALETTE, Series, panels};
use crate::timing::Timing;
use neurotac_core::{MultiSpikeTrain, SpikeDataset};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The destination exists and replacing it was not asked for.
    #[error("{0} already exists (use --force to replace it)")]
    Exists(PathBuf),
    /// A figure could not be rasterised.
    #[error("cannot draw {path}")]
    Png {
        /// The PNG's path.
        path: PathBuf,
        /// Why.
        source: crate::png::PngError,
    },
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// The afferent-network variant of one set.
#[derive(Debug, Clone, Serialize)]
pub struct AfferentRun {
    /// `lif` or `izhikevich`.
    pub model: String,
    /// Synaptic weight, synaptic τ (s) and step (s) used.
    pub weight: f64,
    /// Synaptic time constant (s).
    pub tau_syn_s: f64,
    /// Network time step (s).
    pub dt_s: f64,
    /// Time to run every sample through the afferent network.
    pub network_time: Timing,
    /// The pipeline on the afferents' spikes.
    pub result: SetResult,
}

/// One set: where its data came from, the direct pipeline, and the afferent variant if run.
#[derive(Debug, Clone, Serialize)]
pub struct SetReport {
    /// `simulated (…)` or the recorded dataset's folder.
    pub source: String,
    /// Time to build or load the taxel spike dataset.
    pub dataset_time: Timing,
    /// Taxel spikes → codings (the paper's pipeline).
    pub direct: SetResult,
    /// Taxel spikes → afferent neurons → codings.
    pub afferent: Option<AfferentRun>,
    /// One sample of each class shown in the spike-train figure: `(class name, sample)`.
    #[serde(skip)]
    pub examples: Vec<(String, MultiSpikeTrain)>,
}

/// A whole run.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// The command line.
    pub command: String,
    /// neurotac's version.
    pub version: String,
    /// Seed of the datasets, the split and the search.
    pub seed: u64,
    /// The sets, in run order.
    pub sets: Vec<SetReport>,
    /// Wall and CPU time of the datasets and pipelines (writing the report not included).
    pub time: Timing,
}

/// The samples to draw in the spike-train figure: the first sample of the 0, 2.5 and 5 mm
/// grids when the set has them (the paper's figure), else of the first, middle and last class.
pub fn example_samples(data: &SpikeDataset) -> Vec<(String, MultiSpikeTrain)> {
    let names = data.class_names();
    let wanted: Vec<usize> = {
        let grids: Vec<usize> = paper::INTENSIVE_MEANS
            .iter()
            .filter_map(|&(mm, _)| names.iter().position(|n| *n == grid_name(mm)))
            .collect();
        if grids.len() == 3 {
            grids
        } else {
            let n = data.n_classes();
            let mut v = vec![0, n / 2, n.saturating_sub(1)];
            v.dedup();
            v
        }
    };
    wanted
        .into_iter()
        .filter_map(|c| {
            let i = data.labels().iter().position(|&l| l == c)?;
            Some((names[c].clone(), data.observations()[i].clone()))
        })
        .collect()
}

fn grid_name(mm: f64) -> String {
    format!("grid {mm:.1} mm")
}

fn pct(x: f64) -> String {
    format!("{:.1}", 100.0 * x)
}

/// The paper's table for this set, if it is one of the paper's sets.
fn paper_table(set: &SetResult) -> Option<&'static PaperTable> {
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
                    .find(|&&(mm, _)| *class == grid_name(mm))
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

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Fails when `out` exists and `force` is not set (checked before a run starts, and again when
/// the report is moved into place).
pub fn check_destination(out: &Path, force: bool) -> Result<(), ReportError> {
    if out.exists() && !force {
        return Err(ReportError::Exists(out.to_owned()));
    }
    Ok(())
}

/// Writes `report` into the folder `out` (see the module docs); an existing `out` is replaced
/// only with `force`.
pub fn write_report(out: &Path, report: &Report, force: bool) -> Result<(), ReportError> {
    check_destination(out, force)?;
    // Written into a hidden partial folder, then swapped in (neurotac_core::io::AtomicDir).
    let partial = neurotac_core::io::AtomicDir::create(out).map_err(io(out))?;
    write_files(partial.path(), report)?;
    check_destination(out, force)?;
    partial.commit().map_err(io(out))
}

fn write(dir: &Path, file: &str, text: &str) -> Result<(), ReportError> {
    let path = dir.join(file);
    std::fs::write(&path, text).map_err(io(&path))
}

/// Writes a figure as `<stem>.svg` and `<stem>.png`.
fn figure(dir: &Path, stem: &str, svg: &str, png: &PngRenderer) -> Result<(), ReportError> {
    write(dir, &format!("{stem}.svg"), svg)?;
    let path = dir.join(format!("{stem}.png"));
    let bytes = png.render(svg, 1.5).map_err(|source| ReportError::Png {
        path: path.clone(),
        source,
    })?;
    std::fs::write(&path, bytes).map_err(io(&path))
}

/// The chart of the Δt sweep (accuracy against Δt, the chosen window marked).
fn dt_chart(set: &SetResult) -> Chart {
    let sweep = &set.dt_sweep;
    let points = sweep
        .windows_ms
        .iter()
        .zip(&sweep.accuracy)
        .map(|(&w, &a)| (w as f64, 100.0 * a))
        .collect();
    let best = (
        sweep.best_window_ms as f64,
        100.0 * sweep.accuracy[sweep.best_window_ms as usize - 1],
    );
    Chart {
        title: format!("{}: Δt sweep (leave-one-out, k = 4)", set.name),
        x: Axis::linear("Δt (ms)"),
        y: Axis::linear("accuracy (%)"),
        series: vec![
            Series {
                label: "accuracy".into(),
                points,
                color: PALETTE[0].into(),
                marker: Marker::None,
                filled: false,
                line: true,
            },
            Series {
                label: format!("best: {} ms", sweep.best_window_ms),
                points: vec![best],
                color: PALETTE[2].into(),
                marker: Marker::Circle,
                filled: true,
                line: false,
            },
        ],
    }
}

/// The optimisation's convergence: τ and cos θ evaluated at every epoch, and the best so far
/// (the paper's convergence figure), with the best accuracy.
fn bayes_charts(set: &SetResult) -> Vec<Chart> {
    let trace = &set.bayes.trace;
    let series =
        |label: &str, f: &dyn Fn(&crate::search::bayes::BayesStep) -> f64, c: usize| Series {
            label: label.into(),
            points: trace.iter().map(|s| (s.epoch as f64, f(s))).collect(),
            color: PALETTE[c].into(),
            marker: Marker::None,
            filled: false,
            line: true,
        };
    let evaluated = |label: &str, f: &dyn Fn(&crate::search::bayes::BayesStep) -> f64| Series {
        label: label.into(),
        points: trace.iter().map(|s| (s.epoch as f64, f(s))).collect(),
        color: "#bbb".into(),
        marker: Marker::Circle,
        filled: true,
        line: false,
    };
    vec![
        Chart {
            title: format!("{}: convergence of τ", set.name),
            x: Axis::linear("epoch"),
            y: Axis::linear("τ (ms)"),
            series: vec![
                evaluated("evaluated", &|s| s.tau_s * 1e3),
                series("best so far", &|s| s.best_tau_s * 1e3, 0),
            ],
        },
        Chart {
            title: format!("{}: convergence of cos θ", set.name),
            x: Axis::linear("epoch"),
            y: Axis::linear("cos θ"),
            series: vec![
                evaluated("evaluated", &|s| s.cos),
                series("best so far", &|s| s.best_cos, 1),
            ],
        },
        Chart {
            title: format!("{}: best accuracy", set.name),
            x: Axis::linear("epoch"),
            y: Axis::linear("LOO accuracy (%)"),
            series: vec![series("best so far", &|s| 100.0 * s.best_value, 2)],
        },
    ]
}

/// The paper's spike-train figure: one column per example, raster / spatial / temporal rows.
fn spike_train_figure(set: &SetReport) -> String {
    let dt_s = set.direct.dt_sweep.best_window_ms as f64 * 1e-3;
    let ex = &set.examples;
    let mut charts: Vec<Chart> = ex.iter().map(|(n, t)| raster_chart(t, n)).collect();
    charts.extend(
        ex.iter()
            .map(|(n, t)| spatial_chart(t, &format!("{n}: spatial"))),
    );
    charts.extend(
        ex.iter()
            .map(|(n, t)| temporal_chart(t, dt_s, &format!("{n}: temporal"))),
    );
    panels(&charts, ex.len().max(1))
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

fn write_files(dir: &Path, report: &Report) -> Result<(), ReportError> {
    let png = PngRenderer::new();
    let json = serde_json::to_string_pretty(report).expect("the report serialises");
    write(dir, "report.json", &json)?;
    let mut accuracy = String::from(
        "set,pipeline,coding,parameters,loo_accuracy,loo_std,wilson_low,wilson_high,split_accuracy,paper_accuracy,wall_s\n",
    );
    let mut parameters = String::from("set,quantity,value,paper\n");
    let mut md = markdown_intro(report);
    for set in &report.sets {
        accuracy_rows(set, &mut accuracy);
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
        write_set_files(dir, set, &png)?;
        markdown_set(set, &mut md);
    }
    md.push_str(
        "Files: `report.json` (every number), `accuracy.csv`, `parameters.csv`, \
         `dt_sweep_<set>.csv`, `bo_convergence_<set>.csv`, `confusion_<set>_<coding>.csv`; every \
         figure as SVG and PNG.\n",
    );
    write(dir, "accuracy.csv", &accuracy)?;
    write(dir, "parameters.csv", &parameters)?;
    write(dir, "report.md", &md)
}

/// The runs of a set: `("direct", result)` and, if run, `("afferents", result)`.
fn runs(set: &SetReport) -> Vec<(&'static str, &SetResult)> {
    let mut runs = vec![("direct", &set.direct)];
    if let Some(a) = &set.afferent {
        runs.push(("afferents", &a.result));
    }
    runs
}

/// One CSV row per pipeline and coding.
fn accuracy_rows(set: &SetReport, out: &mut String) {
    let paper = paper_table(&set.direct);
    for (pipeline, r) in runs(set) {
        for (i, c) in r.codings.iter().enumerate() {
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
                    .map(|p| (p.accuracy_percent[i] / 100.0).to_string())
                    .unwrap_or_default(),
                coding_seconds(r, c.coding)
            );
        }
    }
}

/// A confusion matrix as CSV (rows: true class, columns: predicted).
fn confusion_csv(counts: &[Vec<usize>], class_names: &[String]) -> String {
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

/// A set's own files: Δt sweep and BO trace (CSV + figure), spike-train figure, and the
/// confusion matrices of every run (CSV + figure).
fn write_set_files(dir: &Path, set: &SetReport, png: &PngRenderer) -> Result<(), ReportError> {
    let d = &set.direct;
    let name = &d.name;
    let mut dt_csv = String::from("dt_ms,loo_accuracy\n");
    for (w, a) in d.dt_sweep.windows_ms.iter().zip(&d.dt_sweep.accuracy) {
        let _ = writeln!(dt_csv, "{w},{a}");
    }
    write(dir, &format!("dt_sweep_{name}.csv"), &dt_csv)?;
    figure(dir, &format!("dt_sweep_{name}"), &dt_chart(d).to_svg(), png)?;
    let mut bo_csv = String::from("epoch,tau_s,cos,accuracy,best_accuracy,best_tau_s,best_cos\n");
    for s in &d.bayes.trace {
        let _ = writeln!(
            bo_csv,
            "{},{},{},{},{},{},{}",
            s.epoch, s.tau_s, s.cos, s.value, s.best_value, s.best_tau_s, s.best_cos
        );
    }
    write(dir, &format!("bo_convergence_{name}.csv"), &bo_csv)?;
    figure(
        dir,
        &format!("bo_convergence_{name}"),
        &panels(&bayes_charts(d), 3),
        png,
    )?;
    figure(
        dir,
        &format!("spike_trains_{name}"),
        &spike_train_figure(set),
        png,
    )?;
    for (pipeline, r) in runs(set) {
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
                pct(e.accuracy.mean)
            );
            let file = format!("confusion_{name}_{}{suffix}", c.coding.key());
            figure(
                dir,
                &file,
                &confusion_figure(&e.confusion.counts, &r.class_names, &title),
                png,
            )?;
            write(
                dir,
                &format!("{file}.csv"),
                &confusion_csv(&e.confusion.counts, &r.class_names),
            )?;
        }
    }
    Ok(())
}

/// The head of `report.md`: how the run was made and what the numbers mean.
fn markdown_intro(report: &Report) -> String {
    format!(
        "# NeuroTac reproduction\n\n`{}` (neurotac {}, seed {}): {:.1} s wall{}.\n\n\
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
             NeuroTac simulator, whose one calibrated parameter was set on the 5 mm grid's spikes \
             per taxel and never on accuracies: the comparison with the paper measures how close \
             the simulated sensor is to the real one.\n\n"
        } else {
            ""
        }
    )
}

/// A set's section of `report.md`.
fn markdown_set(set: &SetReport, md: &mut String) {
    let d = &set.direct;
    let name = &d.name;
    let samples: usize = d.samples_per_class.iter().sum();
    let _ = write!(
        md,
        "## {} set\n\n{} classes, {samples} samples ({}); {:.2} spikes per taxel on average; \
         dataset {:.1} s, pipeline {:.1} s wall.\n\n",
        name,
        d.class_names.len(),
        set.source,
        d.mean_spikes_per_taxel,
        set.dataset_time.wall_s,
        d.time.wall_s
    );
    md.push_str(&accuracy_table(set));
    md.push('\n');
    if let Some(c) = d.codings.iter().find_map(|c| c.split_refused.as_ref()) {
        let _ = write!(
            md,
            "The 80/20 split was refused: {c}. The confusion matrices show leave-one-out.\n\n"
        );
    }
    md.push_str(&parameter_table(d));
    md.push('\n');
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
    let _ = write!(
        md,
        "![spike trains](spike_trains_{name}.svg)\n\n*Spike trains of one sample per \
         texture (rows: raster, spikes per taxel, spikes per taxel in the chosen Δt \
         window).*\n\n"
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
    let _ = write!(
        md,
        "\n\n![Δt sweep](dt_sweep_{name}.svg)\n\n![BO convergence](bo_convergence_{name}.svg)\n\n"
    );
}
