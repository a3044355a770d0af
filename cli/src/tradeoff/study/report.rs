//! The study's files: per set and family `<set>/<family>/<family>.{csv,md,json,svg,png}` (the
//! figure: accuracy with its Wilson interval against wall time, one series per coding, the
//! front and the recommended point marked) and the summary `tradeoff.md`.

use super::{ALPHA, FamilyStudy, SetStudy, SettingResult};
use crate::report::svg::{Axis, Chart, Marker, Series};
use crate::report::tables::markdown_cell;
use crate::tradeoff::table::{error_series, write_files, write_trade};
use crate::tradeoff::{TradeoffError, trade_files};
use neurotac_core::io::{AtomicFileSet, csv};
use neurotac_experiments::menu::Menu;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The folder of `family` on `set`, relative to the summary.
pub fn family_dir(set: &str, family: &str) -> PathBuf {
    Path::new(set).join(family)
}

fn percent(x: f64) -> String {
    format!("{:.1}", 100.0 * x)
}

fn count(x: Option<u64>) -> String {
    x.map_or_else(String::new, |n| n.to_string())
}

/// A header and rows of texts, written as CSV or Markdown.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Rows {
    /// Column names.
    pub header: Vec<String>,
    /// One text per column in each row.
    pub rows: Vec<Vec<String>>,
}

impl Rows {
    /// CSV ([`neurotac_core::io::csv`]: a text holding a comma, a quote or a line break is
    /// quoted). Fails when a row has not as many texts as the header.
    pub fn to_csv(&self) -> Result<String, csv::Error> {
        csv::table(&self.header, &self.rows)
    }

    /// A Markdown table (a `|` in a text escaped, [`markdown_cell`]).
    pub fn to_markdown(&self) -> String {
        let line = |texts: &[String]| {
            let cells: Vec<_> = texts.iter().map(|t| markdown_cell(t)).collect();
            format!("| {} |\n", cells.join(" | "))
        };
        let mut s = line(&self.header);
        let _ = writeln!(s, "|{}", "---|".repeat(self.header.len()));
        for r in &self.rows {
            s.push_str(&line(r));
        }
        s
    }
}

/// One row per setting: cost, work, numerical error, then per coding its accuracy, Wilson
/// interval and McNemar b, c, p.
pub fn table(study: &FamilyStudy) -> Rows {
    let mut columns: Vec<String> = [
        "setting",
        "reference",
        "wall_s",
        "cpu_s",
        "neuron_updates",
        "synaptic_events",
        "output_spikes",
        "error_mean",
        "error_max",
        "mean_accuracy_pct",
    ]
    .map(String::from)
    .to_vec();
    for c in &study.settings[0].codings {
        let k = c.coding.key();
        for col in ["pct", "wilson_low", "wilson_high", "b", "c", "p"] {
            columns.push(format!("{k}_{col}"));
        }
    }
    columns.extend(["front", "recommended"].map(String::from));
    let mut t = Rows {
        header: columns,
        rows: Vec::new(),
    };
    for r in &study.settings {
        let mut cells = vec![
            r.label.clone(),
            r.reference.to_string(),
            format!("{:.3}", r.wall_s),
            r.cpu_s.map_or_else(String::new, |c| format!("{c:.2}")),
            count(r.neuron_updates),
            count(r.synaptic_events),
            r.output_spikes.to_string(),
            format!("{:.3e}", r.error.mean),
            format!("{:.3e}", r.error.max),
            percent(r.mean_accuracy()),
        ];
        for c in &r.codings {
            cells.extend([
                percent(c.loo.mean),
                percent(c.loo.wilson_low),
                percent(c.loo.wilson_high),
                c.mcnemar.b.to_string(),
                c.mcnemar.c.to_string(),
                format!("{:.3}", c.mcnemar.p),
            ]);
        }
        cells.extend([r.front.to_string(), r.recommended.to_string()]);
        t.rows.push(cells);
    }
    t
}

/// The compact Markdown table of a family (what the summary and the terminal show): per
/// setting its cost and, per coding, `accuracy [Wilson] (b/c, p)`.
pub fn compact_markdown(study: &FamilyStudy) -> String {
    let mut head = vec!["setting".to_owned(), "wall s".into(), "CPU s".into()];
    let afferents = study.settings[0].neuron_updates.is_some();
    if afferents {
        head.push("neuron updates".into());
    }
    head.push(study.error_name.into());
    for c in &study.settings[0].codings {
        head.push(format!(
            "{} % [95 % CI] (b/c, p)",
            c.coding.scheme().label()
        ));
    }
    let mut t = Rows {
        header: head,
        rows: Vec::new(),
    };
    for r in &study.settings {
        let mut label = r.label.clone();
        if r.reference {
            label.push_str(" (reference)");
        }
        if r.front {
            label.push_str(" ◆");
        }
        if r.recommended {
            label = format!("**{label} ★**");
        }
        let mut cells = vec![
            label,
            format!("{:.2}", r.wall_s),
            r.cpu_s.map_or_else(|| "–".into(), |c| format!("{c:.1}")),
        ];
        if afferents {
            cells.push(
                r.neuron_updates
                    .map_or_else(|| "–".into(), |n| format!("{n:.2e}", n = n as f64)),
            );
        }
        cells.push(match r.reference {
            true => "–".into(),
            false => format!("{:.2e} (max {:.2e})", r.error.mean, r.error.max),
        });
        for c in &r.codings {
            let test = match r.reference {
                true => String::new(),
                false => format!(" ({}/{}, {:.2})", c.mcnemar.b, c.mcnemar.c, c.mcnemar.p),
            };
            cells.push(format!(
                "{} [{}, {}]{test}",
                percent(c.loo.mean),
                percent(c.loo.wilson_low),
                percent(c.loo.wilson_high)
            ));
        }
        t.rows.push(cells);
    }
    t.to_markdown()
}

/// The recommendation in one sentence.
pub fn recommendation(study: &FamilyStudy) -> String {
    let r = &study.settings[study.recommended];
    let reference = &study.settings[0];
    if r.reference {
        return format!(
            "Recommended: **{}** (the reference): no cheaper setting keeps every coding's accuracy within the reference's (McNemar p ≥ {ALPHA} or not lower, Wilson interval not entirely below).",
            r.label
        );
    }
    format!(
        "Recommended: **{}** — {:.2} s instead of {:.2} s ({:.1}× faster), mean accuracy {} % against {} %; no coding is significantly below the reference (McNemar p ≥ {ALPHA} or not lower) and no interval lies entirely below the reference's.",
        r.label,
        r.wall_s,
        reference.wall_s,
        reference.wall_s / r.wall_s.max(1e-9),
        percent(r.mean_accuracy()),
        percent(reference.mean_accuracy())
    )
}

/// The figure: accuracy with its Wilson interval against wall time, one series per coding;
/// the front (mean accuracy of the codings) as a line, the recommended point as a square.
pub fn to_svg(set: &str, study: &FamilyStudy) -> String {
    let rows = &study.settings;
    let mut series: Vec<Series> = Vec::new();
    for (k, c) in rows[0].codings.iter().enumerate() {
        let mut s = error_series(
            c.coding.scheme().label(),
            k,
            Marker::Circle,
            rows.iter()
                .map(|r| (r.wall_s, r.codings[k].loo.mean))
                .collect(),
        );
        s.line = false;
        s.y_ranges = (rows.iter())
            .map(|r| (r.codings[k].loo.wilson_low, r.codings[k].loo.wilson_high))
            .collect();
        series.push(s);
    }
    let mut front: Vec<&SettingResult> = rows.iter().filter(|r| r.front).collect();
    front.sort_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
    let mut line = error_series(
        "front (mean of codings)",
        9,
        Marker::Triangle,
        front
            .iter()
            .map(|r| (r.wall_s, r.mean_accuracy()))
            .collect(),
    );
    line.color = "#333".into();
    line.filled = false;
    series.push(line);
    let best = &rows[study.recommended];
    let mut recommended = error_series(
        "recommended",
        6,
        Marker::Square,
        vec![(best.wall_s, best.mean_accuracy())],
    );
    recommended.line = false;
    series.push(recommended);
    let low = (rows
        .iter()
        .flat_map(|r| r.codings.iter().map(|c| c.loo.wilson_low)))
    .fold(1.0, f64::min);
    let high = (rows
        .iter()
        .flat_map(|r| r.codings.iter().map(|c| c.loo.wilson_high)))
    .fold(0.0, f64::max);
    let mut y = Axis::linear("leave-one-out accuracy (95 % Wilson interval)");
    y.range = Some(((low - 0.02).max(0.0), (high + 0.02).min(1.0)));
    Chart {
        title: format!("{set}: {}", study.title),
        x: Axis::log("wall time of encoding + 4 codings' LOO (s)"),
        y,
        series,
    }
    .to_svg()
}

/// Writes one family's files in `dir`.
pub fn write_family(
    files: &mut AtomicFileSet,
    dir: &Path,
    set: &SetStudy,
    study: &FamilyStudy,
) -> Result<(), TradeoffError> {
    let t = table(study);
    let markdown = format!(
        "# {}: {}\n\nParameters of every setting (chosen by the reference's full pipeline): {}.\n\n{}\n{}\n\n## Every column\n\n{}",
        set.name,
        study.title,
        study.parameters,
        compact_markdown(study),
        recommendation(study),
        t.to_markdown()
    );
    write_trade(
        files,
        dir,
        &study.family,
        t.to_csv(),
        &markdown,
        &to_svg(&set.name, study),
    )?;
    let json = serde_json::to_string_pretty(study).map_err(|e| TradeoffError::Io {
        path: dir.join(format!("{}.json", study.family)),
        source: e.into(),
    })?;
    write_files(files, dir, &[(&format!("{}.json", study.family), &json)])
}

/// Every file a study of `sets` × `families` writes under `out` (for the overwrite check).
pub fn study_files(out: &Path, sets: &[String], families: &[String]) -> Vec<PathBuf> {
    let mut v = vec![out.join("tradeoff.md")];
    for s in sets {
        for f in families {
            let dir = out.join(family_dir(s, f));
            v.extend(trade_files(&dir, f));
            v.push(dir.join(format!("{f}.json")));
        }
    }
    v
}

/// The summary page: how the study was made, then per set and family the compact table, the
/// recommendation and links.
pub fn summary_markdown(header: &str, quick: bool, sets: &[SetStudy]) -> String {
    let mut s = String::from("# Speed ↔ accuracy: classification accuracy against cost\n\n");
    let _ = writeln!(s, "{header}\n");
    s.push_str("Each setting is scored by the leave-one-out KNN accuracy of the four codings on the texture set, with its Wilson 95 % interval, and compared with the family's reference setting on the same samples by McNemar's exact test (b: samples the reference gets right and the setting wrong, c: the reverse, p: two-sided exact binomial test of b against b + c). The reference runs the paper's whole pipeline (Δt sweep, (τ, cos θ) optimisation), so its accuracy is `neurotac reproduce`'s for the same set, seed and trials; every other setting reuses the reference's chosen Δt, τ and cos θ, so the setting is the only thing that changes.\n\n");
    s.push_str("Cost: wall and CPU time of encoding the set (offline encoders, or the readout network with the afferent layer) and of the four codings' distance matrices and leave-one-out. Work counted: neuron updates of the afferent layer (the network's own count: every afferent every step when clock-driven, only afferents with input in the steps the automatic stepping runs event-driven) and synaptic events delivered (one per taxel spike). Distance-kernel evaluations are not counted. ◆ marks the Pareto front of (wall time, mean accuracy of the codings); ★ the recommended setting: the cheapest whose every coding is not significantly below the reference (p ≥ 0.05 or accuracy ≥ the reference's) and whose Wilson interval never lies entirely below the reference's.\n\n");
    if quick {
        s.push_str("**--quick**: few samples per class, so the intervals are wide and McNemar's test has little power — a setting passes unless it is grossly worse. Run without --quick before relying on a recommendation.\n\n");
    }
    for set in sets {
        let _ = writeln!(
            s,
            "## {} set ({} samples, {} classes)\n",
            set.name, set.samples, set.classes
        );
        for f in &set.families {
            let dir = family_dir(&set.name, &f.family);
            let d = dir.display();
            let _ = writeln!(
                s,
                "### {}\n\nParameters (the reference's): {}; the reference's whole pipeline took {:.1} s.\n\n{}\n{}\n\n![{}]({d}/{stem}.png)\n\nData: [{stem}.csv]({d}/{stem}.csv) · [{stem}.json]({d}/{stem}.json) · figure: [{stem}.svg]({d}/{stem}.svg) · every column: [{stem}.md]({d}/{stem}.md)\n",
                f.title,
                f.parameters,
                f.reference_pipeline_s,
                compact_markdown(f),
                recommendation(f),
                f.title,
                stem = f.family
            );
        }
    }
    s.push_str("## How to choose\n\nRead a family's figure from the left: the cheapest settings are there. Stop at the first point whose error bars overlap the reference's on every coding you use — the ★ row is that choice made for all four codings at once. If you use one coding only, look at its column: a setting may be fine for it and not for another.\n");
    s
}

/// Adds every set's family files and the summary to `files` under `out`.
pub fn write_study(
    files: &mut AtomicFileSet,
    out: &Path,
    header: &str,
    quick: bool,
    sets: &[SetStudy],
) -> Result<String, TradeoffError> {
    for set in sets {
        for f in &set.families {
            write_family(files, &out.join(family_dir(&set.name, &f.family)), set, f)?;
        }
    }
    let summary = summary_markdown(header, quick, sets);
    write_files(files, out, &[("tradeoff.md", &summary)])?;
    Ok(summary)
}
