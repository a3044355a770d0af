//! Paper-style figures of taxel spike trains (SVG): the raster of Fig. "spike trains", with
//! its spatial (spikes per taxel) and temporal (rolling-window) distributions, and confusion
//! matrices as heat maps.

use super::svg::{Axis, Chart, Marker, PALETTE, Series, escape, panels};
use neurotac_core::MultiSpikeTrain;
use neurotac_experiments::reproduce::{BayesSearch, DtSearch, SetReport, SetResult};

/// A raster: one row of ticks per taxel (y = taxel index, x = time in s).
pub fn raster_chart(trains: &MultiSpikeTrain, title: &str) -> Chart {
    let points = trains
        .channels()
        .enumerate()
        .flat_map(|(c, times)| times.iter().map(move |&t| (t, c as f64)))
        .collect();
    Chart {
        title: title.to_owned(),
        x: Axis::linear("time (s)"),
        y: Axis {
            label: "taxel".into(),
            log: false,
            range: Some((-1.0, trains.n_channels() as f64)),
        },
        series: vec![Series {
            label: format!("{} spikes", trains.total_spikes()),
            points,
            color: "#222".into(),
            marker: Marker::Tick,
            filled: true,
            line: false,
            y_ranges: Vec::new(),
        }],
    }
}

/// Spikes per taxel (the spatial coding's view).
pub fn spatial_chart(trains: &MultiSpikeTrain, title: &str) -> Chart {
    let points = trains
        .counts()
        .iter()
        .enumerate()
        .map(|(c, &n)| (c as f64, n as f64))
        .collect();
    Chart {
        title: title.to_owned(),
        x: Axis {
            label: "taxel".into(),
            log: false,
            range: Some((-1.0, trains.n_channels() as f64)),
        },
        y: from_zero(
            "spikes",
            trains.counts().iter().copied().max().unwrap_or(0) as f64,
        ),
        series: vec![Series {
            label: "spikes per taxel".into(),
            points,
            color: PALETTE[0].into(),
            marker: Marker::Square,
            filled: true,
            line: false,
            y_ranges: Vec::new(),
        }],
    }
}

/// A linear y axis from 0 to a little above `max` (counts start at 0, so their axis does too).
fn from_zero(label: &str, max: f64) -> Axis {
    Axis {
        label: label.into(),
        log: false,
        range: Some((0.0, if max > 0.0 { max * 1.05 } else { 1.0 })),
    }
}

/// Spikes per taxel in a window of `window_s` rolled in 1 ms steps over `[0, end)` (the
/// temporal coding's view): value at `s` = spikes in `[s, s + window)` over all taxels / N.
pub fn temporal_chart(trains: &MultiSpikeTrain, window_s: f64, title: &str) -> Chart {
    let pooled = trains.pooled();
    let end = pooled.last().copied().unwrap_or(0.0).max(window_s);
    let n = trains.n_channels().max(1) as f64;
    let steps = ((end - window_s).max(0.0) / 1e-3).floor() as usize + 1;
    let points: Vec<(f64, f64)> = (0..steps)
        .map(|k| {
            let s = k as f64 * 1e-3;
            let lo = pooled.partition_point(|&t| t < s);
            let hi = pooled.partition_point(|&t| t < s + window_s);
            (s, (hi - lo) as f64 / n)
        })
        .collect();
    Chart {
        title: title.to_owned(),
        x: Axis::linear("window start (s)"),
        y: from_zero(
            &format!("spikes per taxel in {:.0} ms", window_s * 1e3),
            points.iter().map(|p| p.1).fold(0.0, f64::max),
        ),
        series: vec![Series {
            label: format!("Δt = {:.0} ms", window_s * 1e3),
            points,
            color: PALETTE[1].into(),
            marker: Marker::None,
            filled: false,
            line: true,
            y_ranges: Vec::new(),
        }],
    }
}

/// The three views stacked (raster, spatial, temporal) as one SVG document.
pub fn spike_train_figure(trains: &MultiSpikeTrain, title: &str, window_s: f64) -> String {
    panels(
        &[
            raster_chart(trains, title),
            spatial_chart(trains, "spatial distribution"),
            temporal_chart(trains, window_s, "temporal distribution"),
        ],
        1,
    )
}

/// A confusion matrix as an SVG heat map (rows: true class, columns: predicted; cell shade ∝
/// the fraction of the row's samples, that fraction printed as a percentage in each non-empty
/// cell), like the paper's confusion-matrix figures, with a colour bar (0–100 % of a row) and,
/// right of each row, `n =` the number of test samples of that class; `note`, when given, is
/// printed under the title (e.g. how few test samples a quick run has).
pub fn confusion_figure(
    counts: &[Vec<usize>],
    class_names: &[String],
    title: &str,
    note: Option<&str>,
) -> String {
    use std::fmt::Write;
    let n = counts.len();
    let name = |i: usize| {
        escape(
            class_names
                .get(i)
                .map(String::as_str)
                .unwrap_or(&i.to_string()),
        )
    };
    let cell = (440.0 / n.max(1) as f64).clamp(14.0, 40.0);
    let (left, top) = (130.0, 60.0);
    let side = cell * n as f64;
    let bar_x = left + side + 60.0;
    let (w, h) = (
        (bar_x + 80.0).max(300.0),
        (top + side + 120.0).max(top + 260.0),
    );
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="sans-serif"><rect width="100%" height="100%" fill="white"/><text x="{:.1}" y="24" font-size="15" text-anchor="middle">{}</text>"#,
        w / 2.0,
        escape(title)
    );
    if let Some(note) = note {
        let _ = write!(
            svg,
            r##"<text x="{:.1}" y="44" font-size="12" text-anchor="middle" fill="#a33">{}</text>"##,
            w / 2.0,
            escape(note)
        );
    }
    let shade = |f: f64| {
        // White → the palette's blue.
        let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
        format!(
            "#{:02x}{:02x}{:02x}",
            mix(255.0, 0x2b as f64),
            mix(255.0, 0x59 as f64),
            mix(255.0, 0x8c as f64)
        )
    };
    let font = (cell * 0.38).clamp(6.0, 11.0);
    for (i, row) in counts.iter().enumerate() {
        let total: usize = row.iter().sum();
        let y = top + i as f64 * cell;
        let _ = write!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" font-size="{font:.1}" text-anchor="end">{}</text>"#,
            left - 6.0,
            y + cell / 2.0 + font / 3.0,
            name(i)
        );
        for (j, &c) in row.iter().enumerate() {
            let f = if total == 0 {
                0.0
            } else {
                c as f64 / total as f64
            };
            let x = left + j as f64 * cell;
            let _ = write!(
                svg,
                r##"<rect x="{x:.1}" y="{y:.1}" width="{cell:.1}" height="{cell:.1}" fill="{}" stroke="#ddd"/>"##,
                shade(f)
            );
            if c > 0 {
                let _ = write!(
                    svg,
                    r#"<text x="{:.1}" y="{:.1}" font-size="{font:.1}" text-anchor="middle" fill="{}">{:.0}</text>"#,
                    x + cell / 2.0,
                    y + cell / 2.0 + font / 3.0,
                    if f > 0.5 { "white" } else { "black" },
                    100.0 * f
                );
            }
        }
        let _ = write!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" font-size="{font:.1}">n = {total}</text>"#,
            left + side + 4.0,
            y + cell / 2.0 + font / 3.0
        );
    }
    // Colour bar: the share of a row's samples, 0 at the bottom, 100 % at the top.
    let bar_h = side.max(160.0);
    for k in 0..50 {
        let f = 1.0 - k as f64 / 50.0;
        let _ = write!(
            svg,
            r#"<rect x="{bar_x:.1}" y="{:.1}" width="14" height="{:.2}" fill="{}"/>"#,
            top + bar_h * k as f64 / 50.0,
            bar_h / 50.0 + 0.3,
            shade(f)
        );
    }
    let _ = write!(
        svg,
        r##"<rect x="{bar_x:.1}" y="{top:.1}" width="14" height="{bar_h:.1}" fill="none" stroke="#999"/>"##
    );
    for pct in [0, 50, 100] {
        let y = top + bar_h * (1.0 - pct as f64 / 100.0);
        let _ = write!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" font-size="10">{pct} %</text>"#,
            bar_x + 18.0,
            y + 3.5
        );
    }
    let _ = write!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" font-size="10" text-anchor="middle" transform="rotate(-90 {:.1} {:.1})">% of the true class (row)</text>"#,
        bar_x + 60.0,
        top + bar_h / 2.0,
        bar_x + 60.0,
        top + bar_h / 2.0
    );
    for j in 0..n {
        let x = left + j as f64 * cell + cell / 2.0 + font / 3.0;
        let y = top + side + 6.0;
        let _ = write!(
            svg,
            r#"<text x="{x:.1}" y="{y:.1}" font-size="{font:.1}" transform="rotate(90 {x:.1} {y:.1})">{}</text>"#,
            name(j)
        );
    }
    let _ = write!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" font-size="12" text-anchor="middle">predicted class</text><text x="14" y="{:.1}" font-size="12" text-anchor="middle" transform="rotate(-90 14 {:.1})">true class</text></svg>"#,
        left + side / 2.0,
        h - 8.0,
        top + side / 2.0,
        top + side / 2.0
    );
    svg.push('\n');
    svg
}

/// The chart of the Δt sweep (accuracy against Δt, the chosen window marked).
pub fn dt_chart(set: &SetResult, dt: &DtSearch) -> Chart {
    let sweep = &dt.sweep;
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
                y_ranges: Vec::new(),
            },
            Series {
                label: format!("best: {} ms", sweep.best_window_ms),
                points: vec![best],
                color: PALETTE[2].into(),
                marker: Marker::Circle,
                filled: true,
                line: false,
                y_ranges: Vec::new(),
            },
        ],
    }
}

/// The optimisation's convergence: τ and cos θ evaluated at every epoch, and the best so far
/// (the paper's convergence figure), with the best accuracy.
pub fn bayes_charts(set: &SetResult, bayes: &BayesSearch) -> Vec<Chart> {
    let trace = &bayes.result.trace;
    let series = |label: &str,
                  f: &dyn Fn(&neurotac_experiments::search::bayes::BayesStep) -> f64,
                  c: usize| Series {
        label: label.into(),
        points: trace.iter().map(|s| (s.epoch as f64, f(s))).collect(),
        color: PALETTE[c].into(),
        marker: Marker::None,
        filled: false,
        line: true,
        y_ranges: Vec::new(),
    };
    let evaluated =
        |label: &str, f: &dyn Fn(&neurotac_experiments::search::bayes::BayesStep) -> f64| Series {
            label: label.into(),
            points: trace.iter().map(|s| (s.epoch as f64, f(s))).collect(),
            color: "#bbb".into(),
            marker: Marker::Circle,
            filled: true,
            line: false,
            y_ranges: Vec::new(),
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

/// The paper's spike-train figure: one column per example, raster / spatial / temporal rows
/// (the temporal row at the chosen Δt, when a Δt sweep ran).
pub fn set_spike_train_figure(set: &SetReport) -> String {
    let dt_s = (set.direct.dt_search()).map(|dt| dt.sweep.best_window_ms as f64 * 1e-3);
    let ex = &set.examples;
    let mut charts: Vec<Chart> = ex.iter().map(|(n, t)| raster_chart(t, n)).collect();
    charts.extend(
        ex.iter()
            .map(|(n, t)| spatial_chart(t, &format!("{n}: spatial"))),
    );
    if let Some(dt_s) = dt_s {
        charts.extend(
            ex.iter()
                .map(|(n, t)| temporal_chart(t, dt_s, &format!("{n}: temporal"))),
        );
    }
    panels(&charts, ex.len().max(1))
}

/// One simulator's run of the Song–Abbott network, as [`song_abbott_figure`] draws it.
pub struct StdpRunView<'a> {
    /// Legend and panel title (`neurotac`, `brian2 2.9.0`).
    pub label: &'a str,
    /// Final weights (mV).
    pub weights: &'a [f64],
    /// Output spike times (s).
    pub spike_times_s: &'a [f64],
}

/// The final weights of each run as histograms side by side (20 bins over `[0, w_max]`, the
/// same bins and count axis in every panel) and, below, every run's output rate over time
/// (100 bins over `[0, duration_s)`).
pub fn song_abbott_figure(runs: &[StdpRunView<'_>], duration_s: f64) -> String {
    use neurotac_experiments::song_abbott::{W_MAX_MV, histogram, rate_over_time};
    const BINS: usize = 20;
    // Run `k`'s line, in its colour.
    let line = |label: String, points: Vec<(f64, f64)>, k: usize| Series {
        label,
        points,
        color: PALETTE[k % PALETTE.len()].into(),
        marker: Marker::None,
        filled: false,
        line: true,
        y_ranges: Vec::new(),
    };
    let counts: Vec<Vec<usize>> = runs.iter().map(|r| histogram(r.weights, BINS)).collect();
    let highest = counts.iter().flatten().copied().max().unwrap_or(0) as f64;
    let width = W_MAX_MV / BINS as f64;
    let mut charts: Vec<Chart> = runs
        .iter()
        .zip(&counts)
        .enumerate()
        .map(|(k, (run, counts))| {
            // The histogram's outline: up and across each bin.
            let mut points = vec![(0.0, 0.0)];
            for (b, &c) in counts.iter().enumerate() {
                let (lo, hi) = (b as f64 * width, (b + 1) as f64 * width);
                points.extend([(lo, c as f64), (hi, c as f64)]);
            }
            points.push((W_MAX_MV, 0.0));
            Chart {
                title: format!("{}: final weights", run.label),
                x: Axis {
                    label: "weight (mV)".into(),
                    log: false,
                    range: Some((0.0, W_MAX_MV)),
                },
                y: from_zero("synapses", highest),
                series: vec![line(format!("{} synapses", run.weights.len()), points, k)],
            }
        })
        .collect();
    let bin_s = duration_s / 100.0;
    let rates: Vec<Series> = runs
        .iter()
        .enumerate()
        .map(|(k, run)| {
            let points = rate_over_time(run.spike_times_s, duration_s, bin_s);
            line(run.label.to_owned(), points, k)
        })
        .collect();
    let fastest = rates
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0, f64::max);
    charts.push(Chart {
        title: format!("output rate ({} s bins)", (bin_s * 1e3).round() / 1e3),
        x: Axis {
            label: "time (s)".into(),
            log: false,
            range: Some((0.0, duration_s)),
        },
        y: from_zero("rate (Hz)", fastest),
        series: rates,
    });
    panels(&charts, runs.len().max(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_show_every_spike_and_the_rolling_mean() {
        let trains =
            MultiSpikeTrain::from_channels(vec![vec![0.01, 0.5], vec![], vec![0.2]]).unwrap();
        let raster = raster_chart(&trains, "t");
        assert_eq!(
            raster.series[0].points,
            vec![(0.01, 0.0), (0.5, 0.0), (0.2, 2.0)]
        );
        let temporal = temporal_chart(&trains, 0.1, "t");
        // Window [0.2, 0.3) holds one spike of three taxels.
        assert_eq!(temporal.series[0].points[200], (0.2, 1.0 / 3.0));
        let svg = spike_train_figure(&trains, "3 taxels", 0.1);
        assert!(svg.matches("<line x1").count() >= 3);
        assert!(svg.contains("spatial distribution") && svg.contains("temporal distribution"));
    }

    #[test]
    fn confusion_figure_draws_one_cell_per_pair_and_prints_the_counts() {
        let names = vec!["a<b".to_owned(), "c".to_owned()];
        let svg = confusion_figure(&[vec![3, 1], vec![0, 4]], &names, "t & u", None);
        assert_eq!(svg.matches("<rect x=").count(), 4 + 50 + 1);
        // Row percentages, the row totals and the colour bar's scale.
        assert!(svg.contains(">75</text>") && svg.contains(">25</text>"));
        assert!(svg.contains(">100</text>") && svg.contains(">n = 4</text>"));
        assert!(svg.contains(">100 %</text>") && svg.contains(">0 %</text>"));
        // Empty cells print nothing; text is escaped.
        assert!(!svg.contains(">0</text>"));
        assert!(svg.contains("a&lt;b") && svg.contains("t &amp; u"));
        let quick = confusion_figure(&[vec![1, 1]], &names, "t", Some("2 test samples"));
        assert!(quick.contains(">2 test samples</text>"));
    }

    #[test]
    fn count_axes_start_at_zero() {
        let trains = MultiSpikeTrain::from_channels(vec![vec![0.1; 3], vec![0.2; 5]]).unwrap();
        let spatial = spatial_chart(&trains, "s");
        assert_eq!(spatial.y.range.map(|r| r.0), Some(0.0));
        assert!(spatial.y.range.unwrap().1 >= 5.0);
        assert_eq!(
            temporal_chart(&trains, 0.1, "t").y.range.map(|r| r.0),
            Some(0.0)
        );
    }
}
