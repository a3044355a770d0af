//! The simulator's speed ↔ accuracy trade: the pixel model's step tolerance
//! (`solver.step_tolerance`, the largest change of log intensity per step; spec §3.2) against
//! events per trial, event-timing error relative to a fine-step run, and trials per second.
//!
//! Every tolerance simulates the same trials (same seeds, same camera) of the flat plate and
//! the 5 mm grid on one thread. Timing error: every signal (pin) event of a run is matched to
//! the nearest signal event of the same pixel and polarity in the reference run (tolerance
//! 0.002); the difference in event counts is reported apart.

use super::error::TradeoffError;
use super::table::{Table, error_series, mark_front, write_trade};
use crate::report::svg::{Axis, Chart, Marker, panels};
use neurotac_core::io::{AtomicFileSet, csv};
use neurotac_experiments::datasets::{DatasetsError, TextureSet, camera_seed, trial_seed};
use neurotac_experiments::threads::{ThreadPoolError, with_threads};
use neurotac_sensor::sim::{Camera, SimParams, SimulatedTrial, Simulator, Texture, taxel_spikes};
use serde::Serialize;
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// What to sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatorTradeoffConfig {
    /// Step tolerances to measure. Default 0.01, 0.03, 0.067 (the default), 0.15, 0.3.
    pub tolerances: Vec<f64>,
    /// Tolerance of the reference run. Default 0.002.
    pub reference_tolerance: f64,
    /// Slides per texture. Default 3.
    pub trials: usize,
    /// Seed. Default 1.
    pub seed: u64,
    /// Base parameters.
    pub params: SimParams,
}

impl Default for SimulatorTradeoffConfig {
    fn default() -> Self {
        Self {
            tolerances: vec![0.01, 0.03, 0.067, 0.15, 0.3],
            reference_tolerance: 0.002,
            trials: 3,
            seed: 1,
            params: SimParams::default(),
        }
    }
}

/// One measured tolerance.
#[derive(Debug, Clone, Serialize)]
pub struct SimulatorTradeoffRow {
    /// Step tolerance (log intensity per step).
    pub tolerance: f64,
    /// Mean pixel events per trial.
    pub events_per_trial: f64,
    /// Mean signal (pin) events per trial.
    pub signal_events_per_trial: f64,
    /// Relative difference of the signal-event count from the reference.
    pub count_error: f64,
    /// Mean distance of a signal event to the nearest reference event of its pixel and
    /// polarity (µs).
    pub mean_timing_error_us: f64,
    /// Median of that distance (µs, nearest rank).
    pub median_timing_error_us: f64,
    /// 95th percentile of that distance (µs, nearest rank).
    pub p95_timing_error_us: f64,
    /// Largest such distance (µs): the tail that can put the mean above the 95th percentile.
    pub max_timing_error_us: f64,
    /// Mean spikes per taxel (all textures).
    pub spikes_per_taxel: f64,
    /// Pixel updates per trial.
    pub pixel_steps_per_trial: f64,
    /// Trials per second on one thread (simulation only).
    pub trials_per_s: f64,
    /// No other tolerance is both faster (trials/s) and more accurate (mean timing error).
    pub pareto: bool,
}

type Key = (u16, u16, bool);

fn signal_times(trial: &SimulatedTrial) -> HashMap<Key, Vec<i64>> {
    let mut map: HashMap<Key, Vec<i64>> = HashMap::new();
    for (e, l) in trial.events.iter().zip(&trial.labels) {
        if !l.is_noise() {
            map.entry((e.x, e.y, e.polarity)).or_default().push(e.t.0);
        }
    }
    map
}

/// Distance from `t` to the nearest entry of the sorted, non-empty `sorted`.
fn nearest_distance(sorted: &[i64], t: i64) -> u64 {
    let i = sorted.partition_point(|&r| r < t);
    [i.checked_sub(1), (i < sorted.len()).then_some(i)]
        .into_iter()
        .flatten()
        .map(|j| sorted[j].abs_diff(t))
        .min()
        .expect("non-empty")
}

/// The `q`-quantile of `sorted` (ascending) by nearest rank: the smallest value with at least
/// a fraction `q` of the values at or below it (0 for no values).
fn percentile(sorted: &[f64], q: f64) -> f64 {
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted
        .get(rank.clamp(1, sorted.len().max(1)) - 1)
        .copied()
        .unwrap_or(0.0)
}

/// Runs the sweep.
pub fn simulator_tradeoff(
    config: &SimulatorTradeoffConfig,
) -> Result<Vec<SimulatorTradeoffRow>, DatasetsError> {
    let textures = [(0usize, 0.0), (10usize, 5.0)];
    neurotac_sensor::sim::check_trials(config.trials, textures.len())?;
    let camera = Camera::new(&config.params, camera_seed(config.seed));
    let run_all = |tolerance: f64| -> Result<(Vec<SimulatedTrial>, f64), DatasetsError> {
        let mut p = config.params;
        p.solver.step_tolerance = tolerance;
        let mut sim = Simulator::new(p, &camera)?;
        let mut trials = Vec::new();
        let mut wall = 0.0;
        for &(class, d) in &textures {
            let texture = sim.prepare(Texture::Grid { size_mm: d });
            for i in 0..config.trials {
                let seed = trial_seed(config.seed, TextureSet::Artificial, class, i);
                let start = Instant::now();
                let trial = sim.simulate(&texture, seed);
                wall += start.elapsed().as_secs_f64();
                trials.push(trial);
            }
        }
        Ok((trials, wall))
    };
    let one_thread = |tolerance| -> Result<_, DatasetsError> {
        with_threads(1, || run_all(tolerance)).map_err(|e: ThreadPoolError| e)?
    };
    let (reference, _) = one_thread(config.reference_tolerance)?;
    let reference_times: Vec<_> = reference.iter().map(signal_times).collect();
    let mut rows = Vec::new();
    for &tolerance in &config.tolerances {
        let (trials, wall) = one_thread(tolerance)?;
        let (mut errors, mut count, mut count_ref) = (Vec::new(), 0usize, 0usize);
        let mut spikes = 0.0;
        for (trial, reference) in trials.iter().zip(&reference_times) {
            let times = signal_times(trial);
            count += times.values().map(Vec::len).sum::<usize>();
            count_ref += reference.values().map(Vec::len).sum::<usize>();
            for (key, ts) in &times {
                if let Some(rs) = reference.get(key) {
                    errors.extend(ts.iter().map(|&t| nearest_distance(rs, t) as f64));
                }
            }
            spikes += taxel_spikes(trial)?.spikes.total_spikes() as f64 / 49.0;
        }
        errors.sort_by(f64::total_cmp);
        let n = trials.len() as f64;
        let mean_err = if errors.is_empty() {
            0.0
        } else {
            errors.iter().sum::<f64>() / errors.len() as f64
        };
        rows.push(SimulatorTradeoffRow {
            tolerance,
            events_per_trial: trials.iter().map(|t| t.events.len() as f64).sum::<f64>() / n,
            signal_events_per_trial: count as f64 / n,
            count_error: count as f64 / count_ref.max(1) as f64 - 1.0,
            mean_timing_error_us: mean_err,
            median_timing_error_us: percentile(&errors, 0.5),
            p95_timing_error_us: percentile(&errors, 0.95),
            max_timing_error_us: errors.last().copied().unwrap_or(0.0),
            spikes_per_taxel: spikes / n,
            pixel_steps_per_trial: trials
                .iter()
                .map(|t| t.info.pixel_stats.pixel_steps as f64)
                .sum::<f64>()
                / n,
            trials_per_s: n / wall,
            pareto: false,
        });
    }
    mark_front(
        &mut rows,
        |r| Some((r.trials_per_s, r.mean_timing_error_us)),
        |r, on_front| r.pareto = on_front,
    );
    Ok(rows)
}

const COLUMNS: [&str; 12] = [
    "tolerance",
    "events_per_trial",
    "signal_events_per_trial",
    "count_error",
    "mean_timing_error_us",
    "median_timing_error_us",
    "p95_timing_error_us",
    "max_timing_error_us",
    "spikes_per_taxel",
    "pixel_steps_per_trial",
    "trials_per_s",
    "pareto",
];

/// The cells of one row, in [`COLUMNS`] order.
fn cells(r: &SimulatorTradeoffRow) -> [String; 12] {
    [
        format!("{}", r.tolerance),
        format!("{:.0}", r.events_per_trial),
        format!("{:.0}", r.signal_events_per_trial),
        format!("{:+.3}", r.count_error),
        format!("{:.1}", r.mean_timing_error_us),
        format!("{:.1}", r.median_timing_error_us),
        format!("{:.1}", r.p95_timing_error_us),
        format!("{:.0}", r.max_timing_error_us),
        format!("{:.2}", r.spikes_per_taxel),
        format!("{:.3e}", r.pixel_steps_per_trial),
        format!("{:.2}", r.trials_per_s),
        format!("{}", r.pareto),
    ]
}

/// The table of `rows`, in the order given (the same cells in CSV and Markdown).
fn table<'a>(rows: impl IntoIterator<Item = &'a SimulatorTradeoffRow>) -> Table {
    let mut table = Table::new(COLUMNS);
    for r in rows {
        table.push(cells(r));
    }
    table
}

/// The rows as CSV.
pub fn to_csv(rows: &[SimulatorTradeoffRow]) -> Result<String, csv::Error> {
    table(rows).to_csv()
}

/// The Pareto front (no other tolerance both faster and more accurate) as a Markdown table,
/// fastest first.
pub fn pareto_table(rows: &[SimulatorTradeoffRow]) -> String {
    let mut front: Vec<&SimulatorTradeoffRow> = rows.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| b.trials_per_s.total_cmp(&a.trials_per_s));
    table(front).to_markdown()
}

/// The rows as a Markdown table.
pub fn to_markdown(rows: &[SimulatorTradeoffRow], config: &SimulatorTradeoffConfig) -> String {
    let mut s = format!(
        "# Simulator step tolerance: speed ↔ event timing\n\nFlat plate and 5 mm grid, {} slides each, one thread; reference: tolerance {}. Timing error: distance (µs) of each pin event to the nearest reference event of the same pixel and polarity; count error: relative difference of the pin-event count. The distances are heavy-tailed: most events land within a few µs of their reference event, while the few with no counterpart nearby are milliseconds off, so the mean can exceed the 95th percentile (the max column shows that tail); the median is the typical error.\n\n",
        config.trials, config.reference_tolerance
    );
    s += &table(rows).to_markdown();
    s
}

/// The quick settings: one slide per texture and three tolerances (a few seconds).
pub fn quick(config: &mut SimulatorTradeoffConfig) {
    config.trials = 1;
    config.tolerances = vec![0.02, 0.067, 0.2];
}

/// Measures the sweep and adds `simulator.{csv,md,svg,png}` in `out` to `files`.
pub fn report(
    config: &SimulatorTradeoffConfig,
    out: &Path,
    files: &mut AtomicFileSet,
) -> Result<Vec<SimulatorTradeoffRow>, TradeoffError> {
    let rows = simulator_tradeoff(config)?;
    let markdown = to_markdown(&rows, config);
    let (csv, svg) = (to_csv(&rows), to_svg(&rows));
    write_trade(files, out, "simulator", csv, &markdown, &svg)?;
    Ok(rows)
}

/// Mean, median and 95th-percentile event-timing error against trials per second, one point
/// per tolerance (a median of 0 µs is left off the log axis).
pub fn to_svg(rows: &[SimulatorTradeoffRow]) -> String {
    let series = |label: &str, c: usize, marker, error: fn(&SimulatorTradeoffRow) -> f64| {
        error_series(
            label,
            c,
            marker,
            rows.iter().map(|r| (r.trials_per_s, error(r))).collect(),
        )
    };
    let chart = Chart {
        title: "simulator step tolerance: event-timing error vs speed (points: tolerance)"
            .to_owned(),
        x: Axis::log("trials per second (1 thread)"),
        y: Axis::log("pin-event timing error (µs)"),
        series: vec![
            series("mean", 0, Marker::Circle, |r| r.mean_timing_error_us),
            series("median", 2, Marker::Triangle, |r| r.median_timing_error_us),
            series("95th percentile", 1, Marker::Square, |r| {
                r.p95_timing_error_us
            }),
        ],
    };
    panels(&[chart], 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tradeoff::table::{Column, columns_written_differently};

    #[test]
    fn percentiles_are_nearest_rank_and_a_tail_can_lift_the_mean_above_p95() {
        let mut errors: Vec<f64> = vec![1.0; 97];
        errors.extend([10_000.0, 20_000.0, 30_000.0]);
        assert_eq!(percentile(&errors, 0.5), 1.0);
        assert_eq!(percentile(&errors, 0.95), 1.0);
        assert_eq!(percentile(&errors, 0.98), 10_000.0);
        assert_eq!(percentile(&errors, 1.0), 30_000.0);
        assert_eq!(percentile(&[], 0.95), 0.0);
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        assert!(mean > percentile(&errors, 0.95));
        let ramp: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(percentile(&ramp, 0.95), 19.0);
    }

    /// The CSV and the report's table show the same cells.
    #[test]
    fn the_csv_and_markdown_tables_have_the_same_cells() {
        let row = |tolerance, trials_per_s, pareto| SimulatorTradeoffRow {
            tolerance,
            events_per_trial: 12_345.6,
            signal_events_per_trial: 6_789.1,
            count_error: -0.012_34,
            mean_timing_error_us: 123.45,
            median_timing_error_us: 2.5,
            p95_timing_error_us: 40.04,
            max_timing_error_us: 9_876.5,
            spikes_per_taxel: 3.456,
            pixel_steps_per_trial: 1.234_5e7,
            trials_per_s,
            pareto,
        };
        let rows = [row(0.01, 1.5, true), row(0.3, 0.25, false)];
        let config = SimulatorTradeoffConfig::default();
        let none: [&str; 0] = [];
        assert_eq!(
            columns_written_differently(
                &COLUMNS.map(Column::from),
                &to_csv(&rows).unwrap(),
                &to_markdown(&rows, &config)
            ),
            none
        );
    }
}
