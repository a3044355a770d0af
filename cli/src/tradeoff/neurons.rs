//! The speed ↔ accuracy trade of neuron simulation: model × integrator × dt × precision ×
//! spike-time stamping, each point measured for accuracy against a truth and for speed.
//!
//! Every model of the menu, on its benchmark case from rest. Truths: the model's closed form
//! where it has one (LIF, `I = 1.04` from `v = 0`: `t_k = k·τ·ln(I/(I − 1))`), else RK4 at 1 µs,
//! f64, interpolated times (Izhikevich RS, `I = 10` from −65 mV).
//! Accuracy: spike-count error and the mean / max |t − t_true| over the spikes both runs have
//! (k-th to k-th). Speed: updates per second of 100 000 such neurons on one thread.

use super::error::TradeoffError;
use super::table::{Cell, Column, Table, mark_front, write_trade};
use crate::bench::BenchError;
use crate::report::svg::{Axis, Chart, Marker, PALETTE, Series, panels};
use neurotac_core::io::{AtomicFileSet, csv};
use neurotac_experiments::menu::Menu;
use neurotac_experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision};
use neurotac_experiments::threads::with_threads;
use neurotac_neurons::Integrator;
use serde::Serialize;
use std::fmt::Write;
use std::path::Path;

/// What to sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct NeuronTradeoffConfig {
    /// Time steps (s). Default 10 µs … 1 ms.
    pub dts_s: Vec<f64>,
    /// Simulated time of each accuracy run (s). Default 1.
    pub duration_s: f64,
    /// Neurons in each speed run. Default 100 000.
    pub speed_neurons: usize,
    /// Steps in each speed run (best of three runs is kept). Default 100.
    pub speed_steps: u64,
}

impl Default for NeuronTradeoffConfig {
    fn default() -> Self {
        Self {
            dts_s: vec![1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3],
            duration_s: 1.0,
            speed_neurons: 100_000,
            speed_steps: 100,
        }
    }
}

/// One measured point.
#[derive(Debug, Clone, Serialize)]
pub struct NeuronTradeoffRow {
    /// Model.
    pub model: NeuronKind,
    /// Integrator name.
    pub integrator: &'static str,
    /// Precision.
    pub precision: Precision,
    /// `true` for interpolated spike times, `false` for grid times.
    pub interpolate: bool,
    /// Time step (s).
    pub dt_s: f64,
    /// Spikes fired.
    pub spikes: usize,
    /// Spikes of the truth.
    pub true_spikes: usize,
    /// `|spikes − true_spikes|`.
    pub count_error: usize,
    /// Mean |t − t_true| over matched spikes (s); `None` without spikes.
    pub mean_time_error_s: Option<f64>,
    /// Max |t − t_true| over matched spikes (s); `None` without spikes.
    pub max_time_error_s: Option<f64>,
    /// Neuron updates per second, one thread.
    pub updates_per_s: f64,
    /// On the model's Pareto front (no other point with the right spike count is both faster
    /// and more accurate).
    pub pareto: bool,
}

/// The reference spike times of `kind` over `duration_s` (see the module docs).
pub fn truth(kind: NeuronKind, duration_s: f64) -> Result<Vec<f64>, BenchError> {
    if let Some(times) = kind.exact_spike_times(duration_s) {
        return Ok(times);
    }
    let setup = NeuronSetup {
        integrator: Integrator::Rk4,
        interpolate: true,
        ..NeuronSetup::single(kind, Precision::F64)
    };
    Ok(setup.spike_times(kind.benchmark_current(), 1e-6, duration_s)?)
}

/// Measures every point of the sweep (speed on one thread).
pub fn neuron_tradeoff(
    config: &NeuronTradeoffConfig,
) -> Result<Vec<NeuronTradeoffRow>, BenchError> {
    let mut rows = Vec::new();
    for &kind in NeuronKind::ALL {
        let reference = truth(kind, config.duration_s)?;
        let current = kind.benchmark_current();
        for &integrator in kind.integrators() {
            for precision in [Precision::F32, Precision::F64] {
                for interpolate in [false, true] {
                    for &dt_s in &config.dts_s {
                        let single = NeuronSetup {
                            integrator,
                            interpolate,
                            ..NeuronSetup::single(kind, precision)
                        };
                        let times = single.spike_times(current, dt_s, config.duration_s)?;
                        let matched = times.len().min(reference.len());
                        let errors: Vec<f64> = times
                            .iter()
                            .zip(&reference)
                            .map(|(a, b)| (a - b).abs())
                            .collect();
                        let speed_setup = NeuronSetup {
                            integrator,
                            interpolate,
                            ..NeuronSetup::benchmark(kind, precision)
                        };
                        let mut best = f64::INFINITY;
                        for _ in 0..3 {
                            let (_, wall) = with_threads(1, || {
                                speed_setup.run_constant(
                                    config.speed_neurons,
                                    current,
                                    dt_s,
                                    config.speed_steps,
                                )
                            })??;
                            best = best.min(wall);
                        }
                        rows.push(NeuronTradeoffRow {
                            model: kind,
                            integrator: integrator.name(),
                            precision,
                            interpolate,
                            dt_s,
                            spikes: times.len(),
                            true_spikes: reference.len(),
                            count_error: times.len().abs_diff(reference.len()),
                            mean_time_error_s: (matched > 0)
                                .then(|| errors.iter().sum::<f64>() / matched as f64),
                            max_time_error_s: (matched > 0)
                                .then(|| errors.iter().copied().fold(0.0, f64::max)),
                            updates_per_s: config.speed_neurons as f64 * config.speed_steps as f64
                                / best,
                            pareto: false,
                        });
                    }
                }
            }
        }
    }
    mark_pareto(&mut rows);
    Ok(rows)
}

/// Marks, per model, the points no other correct-count point beats on both speed and error.
fn mark_pareto(rows: &mut [NeuronTradeoffRow]) {
    for &model in NeuronKind::ALL {
        mark_front(
            rows,
            |r| {
                (r.model == model && r.count_error == 0)
                    .then_some(r.mean_time_error_s.map(|e| (r.updates_per_s, e)))
                    .flatten()
            },
            |row, on_front| {
                if row.model == model {
                    row.pareto = on_front;
                }
            },
        );
    }
}

/// The quick settings: three time steps and smaller speed runs (a few seconds).
pub fn quick(config: &mut NeuronTradeoffConfig) {
    config.dts_s = vec![1e-5, 1e-4, 1e-3];
    config.speed_neurons = 20_000;
}

/// Measures the sweep of `config` and adds `neurons.{csv,md,svg,png}` in `out` to `files`.
pub fn report(
    config: &NeuronTradeoffConfig,
    out: &Path,
    files: &mut AtomicFileSet,
) -> Result<Vec<NeuronTradeoffRow>, TradeoffError> {
    if !(config.duration_s.is_finite() && config.duration_s > 0.0) {
        return Err(TradeoffError::InvalidParameter {
            what: "--duration",
            value: config.duration_s,
            expected: "finite and > 0",
        });
    }
    let rows = neuron_tradeoff(config)?;
    write_trade(
        files,
        out,
        "neurons",
        to_csv(&rows),
        &to_markdown(&rows, config.speed_neurons),
        &to_svg(&rows),
    )?;
    Ok(rows)
}

fn stamp(r: &NeuronTradeoffRow) -> &'static str {
    if r.interpolate {
        "interpolated"
    } else {
        "grid"
    }
}

/// The columns: the CSV splits the spike counts and adds the count error and the front mark,
/// the Markdown table shows the counts as `spikes (truth)`.
const COLUMNS: [Column; 13] = [
    Column::both("model"),
    Column::both("integrator"),
    Column::both("precision"),
    Column::named("spike_times", "spike times"),
    Column::named("dt_s", "dt (s)"),
    Column::csv_only("spikes"),
    Column::csv_only("true_spikes"),
    Column::markdown_only("spikes (truth)"),
    Column::csv_only("count_error"),
    Column::named("mean_time_error_s", "mean error (s)"),
    Column::named("max_time_error_s", "max error (s)"),
    Column::named("updates_per_s", "updates/s"),
    Column::csv_only("pareto"),
];

/// A spike-time error: every digit in the CSV (empty without one), four significant digits in
/// the Markdown table (`—` without one).
fn error_cell(error: Option<f64>) -> Cell {
    match error {
        Some(e) => Cell::split(format!("{e:e}"), format!("{e:.3e}")),
        None => Cell::split("", "—"),
    }
}

/// The cells of one row, in [`COLUMNS`] order.
fn cells(r: &NeuronTradeoffRow) -> [Cell; 13] {
    [
        r.model.name().into(),
        r.integrator.into(),
        r.precision.name().into(),
        stamp(r).into(),
        format!("{:e}", r.dt_s).into(),
        r.spikes.to_string().into(),
        r.true_spikes.to_string().into(),
        format!("{} ({})", r.spikes, r.true_spikes).into(),
        r.count_error.to_string().into(),
        error_cell(r.mean_time_error_s),
        error_cell(r.max_time_error_s),
        Cell::split(
            format!("{:e}", r.updates_per_s),
            format!("{:.2e}", r.updates_per_s),
        ),
        r.pareto.to_string().into(),
    ]
}

/// The table of `rows`, in the order given.
fn table<'a>(rows: impl IntoIterator<Item = &'a NeuronTradeoffRow>) -> Table {
    let mut table = Table::new(COLUMNS);
    for r in rows {
        table.push(cells(r));
    }
    table
}

/// CSV with one line per point.
pub fn to_csv(rows: &[NeuronTradeoffRow]) -> Result<String, csv::Error> {
    table(rows).to_csv()
}

/// The Pareto front of each model as a Markdown table, fastest first within a model.
pub fn pareto_table(rows: &[NeuronTradeoffRow]) -> String {
    let mut front: Vec<&NeuronTradeoffRow> = rows.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| {
        a.model
            .name()
            .cmp(b.model.name())
            .then(b.updates_per_s.total_cmp(&a.updates_per_s))
    });
    table(front).to_markdown()
}

/// A Markdown report: the Pareto front of each model, then every point (`speed_neurons`: the
/// population size of the speed runs).
pub fn to_markdown(rows: &[NeuronTradeoffRow], speed_neurons: usize) -> String {
    let mut out = String::from("# Neuron simulation: speed ↔ accuracy\n\n");
    let _ = write!(
        out,
        "Truth: LIF closed form (I = 1.04); Izhikevich RS (I = 10) by RK4 at 1 µs. Speed: {speed_neurons} neurons for 100 steps on one thread, the fastest of three runs (a short run that stays in cache; `neurotac bench neurons` measures a 1 s run, 10 000 steps at dt = 0.1 ms, once, on every core, so its per-thread figure is lower on a loaded machine).\n\n"
    );
    out.push_str("## Pareto front (no other point with the right spike count is both faster and more accurate)\n\n");
    out.push_str(&pareto_table(rows));
    out.push_str("\n## Every point\n\n");
    out.push_str(&table(rows).to_markdown());
    out
}

/// One panel per model (LIF, Izhikevich): mean spike-time error against updates/s, one series
/// per integrator × precision × stamping; points along a series are the time steps.
pub fn to_svg(rows: &[NeuronTradeoffRow]) -> String {
    let charts: Vec<Chart> = NeuronKind::ALL
        .iter()
        .map(|&kind| {
            let mut series = Vec::new();
            for (c, &integrator) in kind.integrators().iter().enumerate() {
                for precision in [Precision::F64, Precision::F32] {
                    for interpolate in [false, true] {
                        let points = rows
                            .iter()
                            .filter(|r| {
                                r.model == kind
                                    && r.integrator == integrator.name()
                                    && r.precision == precision
                                    && r.interpolate == interpolate
                            })
                            .filter_map(|r| r.mean_time_error_s.map(|e| (r.updates_per_s, e)))
                            .collect();
                        series.push(Series {
                            label: format!(
                                "{} {} {}",
                                integrator.name(),
                                precision.name(),
                                if interpolate { "interp" } else { "grid" }
                            ),
                            points,
                            color: PALETTE[c % PALETTE.len()].to_owned(),
                            marker: if interpolate {
                                Marker::Square
                            } else {
                                Marker::Circle
                            },
                            filled: precision == Precision::F64,
                            line: true,
                            y_ranges: Vec::new(),
                        });
                    }
                }
            }
            Chart {
                title: format!("{}: spike-time error vs speed (points: dt)", kind.name()),
                x: Axis::log("neuron updates per second (1 thread)"),
                y: Axis::log("mean spike-time error (s)"),
                series,
            }
        })
        .collect();
    panels(&charts, 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tradeoff::table::columns_written_differently;

    #[test]
    fn sweep_measures_known_truths_and_finds_a_front() {
        let config = NeuronTradeoffConfig {
            dts_s: vec![1e-4, 5e-4],
            duration_s: 0.2,
            speed_neurons: 2_000,
            speed_steps: 5,
        };
        let rows = neuron_tradeoff(&config).unwrap();
        // LIF: 4 integrators, Izhikevich: 5 (every model: its report integrators); × 2
        // precisions × 2 stampings × 2 dts.
        let of = |kind| rows.iter().filter(|r| r.model == kind).count();
        assert_eq!(of(NeuronKind::Lif), 4 * 2 * 2 * 2);
        assert_eq!(of(NeuronKind::Izhikevich), 5 * 2 * 2 * 2);
        let all: usize = NeuronKind::ALL.iter().map(|k| k.integrators().len()).sum();
        assert_eq!(rows.len(), all * 2 * 2 * 2);
        let lif_exact_grid = rows
            .iter()
            .find(|r| {
                r.model == NeuronKind::Lif
                    && r.integrator == "exact"
                    && !r.interpolate
                    && r.precision == Precision::F64
                    && r.dt_s == 1e-4
            })
            .unwrap();
        // 0.2 s / 32.58 ms = 6 spikes; grid stamps lag the truth by less than a step.
        assert_eq!((lif_exact_grid.spikes, lif_exact_grid.true_spikes), (6, 6));
        let max = lif_exact_grid.max_time_error_s.unwrap();
        assert!(max > 0.0 && max < 1e-4 * 6.0, "{max}");
        // Interpolation is far more accurate than grid stamping for the same integrator.
        let interp = rows
            .iter()
            .find(|r| {
                r.model == NeuronKind::Lif
                    && r.integrator == "exact"
                    && r.interpolate
                    && r.precision == Precision::F64
                    && r.dt_s == 1e-4
            })
            .unwrap();
        assert!(
            interp.mean_time_error_s.unwrap() < lif_exact_grid.mean_time_error_s.unwrap() / 10.0
        );
        for &kind in NeuronKind::ALL {
            assert!(
                rows.iter().any(|r| r.model == kind && r.pareto),
                "{kind:?} has a front"
            );
        }
        assert!(
            rows.iter()
                .all(|r| r.updates_per_s.is_finite() && r.updates_per_s > 0.0)
        );
        let csv = to_csv(&rows).unwrap();
        assert_eq!(csv.lines().count(), rows.len() + 1);
        assert!(to_markdown(&rows, 1000).contains("## Pareto front"));
        assert!(to_svg(&rows).contains("lif: spike-time error vs speed"));
    }

    /// Hand-made rows: both models, both precisions and stampings, a missed spike count, a run
    /// without matched spikes (no errors) and front points out of speed order.
    fn rows() -> Vec<NeuronTradeoffRow> {
        let (lif, izh) = (NeuronKind::Lif, NeuronKind::Izhikevich);
        let (f32, f64) = (Precision::F32, Precision::F64);
        // (model, integrator, precision, interpolated), dt, (spikes, truth), (mean, max) error,
        // updates/s, on the front
        #[rustfmt::skip]
        let points = [
            ((lif, "rk2", f64, true), 2e-5, (6, 6), Some((1e-9, 2.5e-9)), 5e7, true),
            ((lif, "exact", f64, false), 1e-4, (6, 6), Some((4.6e-5, 9.75e-5)), 1.234_567_89e8, true),
            ((lif, "euler", f32, false), 1e-3, (5, 6), Some((2.5e-4, 9.99e-4)), 4.5e8, false),
            ((izh, "rk4", f64, false), 5e-5, (0, 12), None, 2.000_5e7, false),
            ((izh, "euler", f32, true), 1e-5, (12, 12), Some((1.234_567e-6, 0.0)), 3.25e6, true),
        ];
        points
            .into_iter()
            .map(|(setup, dt_s, spikes, errors, updates_per_s, pareto)| {
                let (model, integrator, precision, interpolate) = setup;
                NeuronTradeoffRow {
                    model,
                    integrator,
                    precision,
                    interpolate,
                    dt_s,
                    spikes: spikes.0,
                    true_spikes: spikes.1,
                    count_error: spikes.0.abs_diff(spikes.1),
                    mean_time_error_s: errors.map(|e: (f64, f64)| e.0),
                    max_time_error_s: errors.map(|e| e.1),
                    updates_per_s,
                    pareto,
                }
            })
            .collect()
    }

    /// The formats of the CSV, the Markdown report and the Pareto table, pinned on hand-made rows.
    const CSV: &str = "model,integrator,precision,spike_times,dt_s,spikes,true_spikes,count_error,mean_time_error_s,max_time_error_s,updates_per_s,pareto
lif,rk2,f64,interpolated,2e-5,6,6,0,1e-9,2.5e-9,5e7,true
lif,exact,f64,grid,1e-4,6,6,0,4.6e-5,9.75e-5,1.23456789e8,true
lif,euler,f32,grid,1e-3,5,6,1,2.5e-4,9.99e-4,4.5e8,false
izhikevich,rk4,f64,grid,5e-5,0,12,12,,,2.0005e7,false
izhikevich,euler,f32,interpolated,1e-5,12,12,0,1.234567e-6,0e0,3.25e6,true
";
    const PARETO: &str = "| model | integrator | precision | spike times | dt (s) | spikes (truth) | mean error (s) | max error (s) | updates/s |
|---|---|---|---|---|---|---|---|---|
| izhikevich | euler | f32 | interpolated | 1e-5 | 12 (12) | 1.235e-6 | 0.000e0 | 3.25e6 |
| lif | exact | f64 | grid | 1e-4 | 6 (6) | 4.600e-5 | 9.750e-5 | 1.23e8 |
| lif | rk2 | f64 | interpolated | 2e-5 | 6 (6) | 1.000e-9 | 2.500e-9 | 5.00e7 |
";
    const MD: &str = "# Neuron simulation: speed ↔ accuracy

Truth: LIF closed form (I = 1.04); Izhikevich RS (I = 10) by RK4 at 1 µs. Speed: 1234 neurons for 100 steps on one thread, the fastest of three runs (a short run that stays in cache; `neurotac bench neurons` measures a 1 s run, 10 000 steps at dt = 0.1 ms, once, on every core, so its per-thread figure is lower on a loaded machine).

## Pareto front (no other point with the right spike count is both faster and more accurate)

| model | integrator | precision | spike times | dt (s) | spikes (truth) | mean error (s) | max error (s) | updates/s |
|---|---|---|---|---|---|---|---|---|
| izhikevich | euler | f32 | interpolated | 1e-5 | 12 (12) | 1.235e-6 | 0.000e0 | 3.25e6 |
| lif | exact | f64 | grid | 1e-4 | 6 (6) | 4.600e-5 | 9.750e-5 | 1.23e8 |
| lif | rk2 | f64 | interpolated | 2e-5 | 6 (6) | 1.000e-9 | 2.500e-9 | 5.00e7 |

## Every point

| model | integrator | precision | spike times | dt (s) | spikes (truth) | mean error (s) | max error (s) | updates/s |
|---|---|---|---|---|---|---|---|---|
| lif | rk2 | f64 | interpolated | 2e-5 | 6 (6) | 1.000e-9 | 2.500e-9 | 5.00e7 |
| lif | exact | f64 | grid | 1e-4 | 6 (6) | 4.600e-5 | 9.750e-5 | 1.23e8 |
| lif | euler | f32 | grid | 1e-3 | 5 (6) | 2.500e-4 | 9.990e-4 | 4.50e8 |
| izhikevich | rk4 | f64 | grid | 5e-5 | 0 (12) | — | — | 2.00e7 |
| izhikevich | euler | f32 | interpolated | 1e-5 | 12 (12) | 1.235e-6 | 0.000e0 | 3.25e6 |
";

    #[test]
    fn the_tables_keep_their_format() {
        let rows = rows();
        assert_eq!(to_csv(&rows).unwrap(), CSV);
        assert_eq!(pareto_table(&rows), PARETO);
        assert_eq!(to_markdown(&rows, 1234), MD);
    }

    /// The CSV and the report's table of every point show the same cells, except that the
    /// Markdown table rounds the errors and the speed.
    #[test]
    fn the_csv_and_markdown_tables_have_the_same_cells() {
        let rows = rows();
        let report = to_markdown(&rows, 1234);
        let (_, every_point) = report.split_once("## Every point").unwrap();
        assert_eq!(
            columns_written_differently(&COLUMNS, &to_csv(&rows).unwrap(), every_point),
            ["mean_time_error_s", "max_time_error_s", "updates_per_s"]
        );
    }
}
