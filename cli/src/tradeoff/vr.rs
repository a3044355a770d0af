//! The speed ↔ accuracy trade of the multi-unit Van Rossum distance, measured as
//! classification accuracy: the exact distance (Markage recursion) against the distance of the
//! synaptic traces a network samples at `trace_dt`, in `f64` or `f32`
//! ([`neurotac_core::distance::trace_sampled`]).
//!
//! For each method: wall and CPU time of the N × N matrix (from the readouts: trains or trace
//! records), leave-one-out KNN accuracy at (τ, cos θ), and the relative error of the distance
//! `|D_h − D| / D` over every pair of distinct samples with `D > 0` (mean and max). The Pareto
//! front is taken on (matrix speed, LOO accuracy).

use super::table::{Cell, Column, Table, mark_front};
use neurotac_core::coding::TraceRecord;
use neurotac_core::distance::check_cos;
use neurotac_core::io::csv;
use neurotac_core::{CodingError, Knn, SpikeDataset};
use neurotac_experiments::error::ExperimentError;
use neurotac_experiments::neuron_setup::Precision;
use neurotac_experiments::protocols::Accuracy;
use neurotac_experiments::search::bayes::VanRossumInput;
use neurotac_experiments::timing::{Timing, timed};
use rayon::prelude::*;

/// What to measure.
#[derive(Debug, Clone, PartialEq)]
pub struct VrTradeoffConfig {
    /// Kernel time constant τ (s). Default 0.076 (the paper's best).
    pub tau_s: f64,
    /// cos θ in [0, 1]. Default 0.4 (the paper's best).
    pub cos: f64,
    /// KNN neighbours. Default 4 (the paper's).
    pub k: usize,
    /// Trace steps to try (s). Default 0.1, 1, 5, 20 ms.
    pub trace_dts_s: Vec<f64>,
    /// Arithmetic of the traces. Default f64 and f32.
    pub precisions: Vec<Precision>,
    /// Use every `⌈N / samples⌉`-th sample (all classes keep samples); `None`: all.
    pub samples: Option<usize>,
}

impl Default for VrTradeoffConfig {
    fn default() -> Self {
        Self {
            tau_s: 0.076,
            cos: 0.4,
            k: 4,
            trace_dts_s: vec![1e-4, 1e-3, 5e-3, 2e-2],
            precisions: vec![Precision::F64, Precision::F32],
            samples: None,
        }
    }
}

/// One method.
#[derive(Debug, Clone, serde::Serialize)]
pub struct VrTradeoffRow {
    /// `exact`, or `traces`.
    pub method: &'static str,
    /// Trace step (s); `None` for the exact distance.
    pub trace_dt_s: Option<f64>,
    /// Arithmetic.
    pub precision: Precision,
    /// Time of the N × N matrix pair (`LL²`, `SP²`) from the readouts.
    pub timing: Timing,
    /// Leave-one-out KNN accuracy at (τ, cos θ).
    pub loo: Accuracy,
    /// Mean relative error of the distance over the pairs (0 for exact).
    pub mean_relative_error: f64,
    /// Max relative error of the distance over the pairs.
    pub max_relative_error: f64,
    /// No other method is both faster and more accurate.
    pub pareto: bool,
}

/// The measured trade.
#[derive(Debug, Clone, serde::Serialize)]
pub struct VrTradeoff {
    /// Samples used.
    pub samples: usize,
    /// τ (s).
    pub tau_s: f64,
    /// cos θ.
    pub cos: f64,
    /// KNN neighbours.
    pub k: usize,
    /// The exact distance first, then every trace step × precision in the order given.
    pub rows: Vec<VrTradeoffRow>,
}

/// Measures the trade on `data` (labelled; see the module docs).
pub fn measure(
    data: &SpikeDataset,
    config: &VrTradeoffConfig,
) -> Result<VrTradeoff, ExperimentError> {
    check_cos(config.cos)?;
    let stride = config
        .samples
        .map_or(1, |s| data.len().div_ceil(s.max(1)).max(1));
    let picked: Vec<usize> = (0..data.len()).step_by(stride).collect();
    let obs: Vec<_> = picked
        .iter()
        .map(|&i| data.observations()[i].clone())
        .collect();
    let labels: Vec<usize> = picked.iter().map(|&i| data.labels()[i]).collect();
    let n = obs.len();
    if n < 2 || labels.len() != n {
        return Err(ExperimentError::InvalidParameter {
            what: "labelled samples",
            value: n as f64,
            expected: "at least 2 (distances are between pairs), every one labelled",
        });
    }
    let knn = Knn::new(config.k)?;
    let evaluate = |input: VanRossumInput<'_>| -> Result<_, ExperimentError> {
        let (m, timing) = timed(|| input.matrices(config.tau_s, &neurotac_core::OneProcess));
        let d2 = m?.squared(config.cos)?;
        let loo = Accuracy::of(&knn.leave_one_out(d2.view(), &labels)?, &labels);
        Ok((d2, timing, loo))
    };
    let (exact, timing, loo) = evaluate(VanRossumInput::Exact(&obs))?;
    let mut rows = vec![VrTradeoffRow {
        method: "exact",
        trace_dt_s: None,
        precision: Precision::F64,
        timing,
        loo,
        mean_relative_error: 0.0,
        max_relative_error: 0.0,
        pareto: false,
    }];
    for &h in &config.trace_dts_s {
        let records = obs
            .par_iter()
            .map(|o| TraceRecord::of_trains(o, h))
            .collect::<Result<Vec<_>, CodingError>>()?;
        for &precision in &config.precisions {
            let input = VanRossumInput::Traces {
                records: &records,
                precision,
            };
            let (sampled, timing, loo) = evaluate(input)?;
            let (mut max_rel, mut sum_rel, mut pairs) = (0.0f64, 0.0, 0usize);
            for i in 0..n {
                for j in i + 1..n {
                    let (e, s) = (exact[[i, j]].sqrt(), sampled[[i, j]].sqrt());
                    if e > 0.0 {
                        let rel = (s - e).abs() / e;
                        max_rel = max_rel.max(rel);
                        sum_rel += rel;
                        pairs += 1;
                    }
                }
            }
            rows.push(VrTradeoffRow {
                method: "traces",
                trace_dt_s: Some(h),
                precision,
                timing,
                loo,
                mean_relative_error: sum_rel / pairs.max(1) as f64,
                max_relative_error: max_rel,
                pareto: false,
            });
        }
    }
    mark_front(
        &mut rows,
        |r| Some((1.0 / r.timing.wall_s.max(1e-9), 1.0 - r.loo.mean)),
        |r, on_front| r.pareto = on_front,
    );
    Ok(VrTradeoff {
        samples: n,
        tau_s: config.tau_s,
        cos: config.cos,
        k: config.k,
        rows,
    })
}

/// The columns: the CSV has the wall and CPU times in seconds and the front mark, the Markdown
/// table the matrix time as one text ([`Timing`]'s display), after the errors.
const COLUMNS: [Column; 10] = [
    Column::both("method"),
    Column::named("trace_dt_s", "trace dt (ms)"),
    Column::both("precision"),
    Column::csv_only("wall_s"),
    Column::csv_only("cpu_s"),
    Column::named("loo_accuracy", "LOO accuracy"),
    Column::named("mean_relative_error", "mean rel. error"),
    Column::named("max_relative_error", "max rel. error"),
    Column::markdown_only("matrix time"),
    Column::csv_only("pareto"),
];

/// A relative error: every digit in the CSV, three significant digits in the Markdown table.
fn relative_error_cell(error: f64) -> Cell {
    Cell::split(format!("{error:e}"), format!("{error:.2e}"))
}

/// The cells of one row, in [`COLUMNS`] order.
fn cells(r: &VrTradeoffRow) -> [Cell; 10] {
    [
        r.method.into(),
        match r.trace_dt_s {
            Some(h) => Cell::split(format!("{h:e}"), format!("{}", h * 1e3)),
            None => Cell::split("", "—"),
        },
        r.precision.name().into(),
        format!("{:e}", r.timing.wall_s).into(),
        r.timing
            .cpu_s
            .map_or(String::new(), |c| format!("{c}"))
            .into(),
        Cell::split(
            format!("{}", r.loo.mean),
            format!("{:.1} %", 100.0 * r.loo.mean),
        ),
        relative_error_cell(r.mean_relative_error),
        relative_error_cell(r.max_relative_error),
        r.timing.to_string().into(),
        r.pareto.to_string().into(),
    ]
}

/// The table of `rows`, in the order given.
fn table<'a>(rows: impl IntoIterator<Item = &'a VrTradeoffRow>) -> Table {
    let mut table = Table::new(COLUMNS);
    for r in rows {
        table.push(cells(r));
    }
    table
}

/// CSV: one line per method.
pub fn to_csv(sweep: &VrTradeoff) -> Result<String, csv::Error> {
    table(&sweep.rows).to_csv()
}

/// The Pareto front (fastest first) as a Markdown table.
pub fn pareto_table(sweep: &VrTradeoff) -> String {
    let mut front: Vec<&VrTradeoffRow> = sweep.rows.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| a.timing.wall_s.total_cmp(&b.timing.wall_s));
    table(front).to_markdown()
}

/// A Markdown report: every method.
pub fn to_markdown(sweep: &VrTradeoff) -> String {
    let mut out = format!(
        "# Van Rossum distance: exact vs synaptic traces\n\n{} samples, τ = {} s, cos θ = {}, \
         KNN k = {} (leave-one-out). Matrix time: `LL²` and `SP²` of all pairs from the \
         readouts (trains or trace records), {} threads.\n\n",
        sweep.samples,
        sweep.tau_s,
        sweep.cos,
        sweep.k,
        rayon::current_num_threads()
    );
    out.push_str(&table(&sweep.rows).to_markdown());
    out.push_str("\nPareto front (matrix speed, LOO accuracy):\n\n");
    out.push_str(&pareto_table(sweep));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tradeoff::table::columns_written_differently;
    use neurotac_experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};

    #[test]
    fn every_method_gets_accuracy_and_the_trace_error_shrinks_with_the_step() {
        let data = synthetic_dataset(&SyntheticConfig {
            samples: 40,
            classes: 4,
            channels: 6,
            ..SyntheticConfig::default()
        });
        let config = VrTradeoffConfig {
            trace_dts_s: vec![2e-2, 1e-3, 1e-5],
            samples: Some(20),
            ..VrTradeoffConfig::default()
        };
        let t = measure(&data, &config).unwrap();
        assert_eq!(t.samples, 20);
        assert_eq!(t.rows.len(), 1 + 3 * 2);
        assert_eq!(
            (t.rows[0].method, t.rows[0].mean_relative_error),
            ("exact", 0.0)
        );
        assert!(t.rows.iter().all(|r| r.loo.n == 20));
        assert!(t.rows.iter().any(|r| r.pareto));
        let f64_errors: Vec<f64> = t
            .rows
            .iter()
            .filter(|r| r.method == "traces" && r.precision == Precision::F64)
            .map(|r| r.mean_relative_error)
            .collect();
        assert!(
            f64_errors[0] > f64_errors[1] && f64_errors[1] > f64_errors[2],
            "{f64_errors:?}"
        );
        assert!(f64_errors[2] < 1e-3, "{f64_errors:?}");
        // At a 10 µs step the traces rank the neighbours as the exact distance does.
        assert_eq!(t.rows.last().unwrap().loo.mean, t.rows[0].loo.mean);
        assert!(
            to_csv(&t).unwrap().lines().count() == 8 && to_markdown(&t).contains("Pareto front")
        );
    }

    /// Hand-made rows: the exact distance and trace steps of both precisions, with and without
    /// a CPU time, front points out of speed order.
    fn sweep() -> VrTradeoff {
        let (f32, f64) = (Precision::F32, Precision::F64);
        // trace dt, precision, (wall, CPU) time, LOO hits of 60, (mean, max) relative error,
        // on the front
        #[rustfmt::skip]
        let points = [
            (None, f64, (0.012_345_6, Some(0.045_6)), 51, (0.0, 0.0), true),
            (Some(1e-4), f32, (0.000_987, Some(0.002)), 50, (1.234e-5, 5.678e-4), true),
            (Some(1e-3), f64, (0.003_45, Some(0.006_9)), 49, (1.234e-3, 5.678e-2), false),
            (Some(2e-2), f32, (0.5, None), 30, (0.123_45, 0.9), false),
            (Some(5e-3), f64, (0.002, None), 50, (2e-3, 1e-2), true),
        ];
        let rows = points
            .into_iter()
            .map(
                |(trace_dt_s, precision, (wall_s, cpu_s), hits, errors, pareto)| VrTradeoffRow {
                    method: if trace_dt_s.is_some() {
                        "traces"
                    } else {
                        "exact"
                    },
                    trace_dt_s,
                    precision,
                    timing: Timing {
                        wall_s,
                        cpu_s,
                        threads: 2,
                    },
                    loo: Accuracy {
                        n: 60,
                        hits,
                        mean: hits as f64 / 60.0,
                        std: 0.0,
                        wilson_low: 0.0,
                        wilson_high: 1.0,
                    },
                    mean_relative_error: errors.0,
                    max_relative_error: errors.1,
                    pareto,
                },
            )
            .collect();
        VrTradeoff {
            samples: 60,
            tau_s: 0.076,
            cos: 0.4,
            k: 4,
            rows,
        }
    }

    /// The formats of the CSV, the Markdown report and the Pareto table, pinned on hand-made rows
    /// (the Markdown report's header names the thread count as THREADS).
    const CSV: &str = "method,trace_dt_s,precision,wall_s,cpu_s,loo_accuracy,mean_relative_error,max_relative_error,pareto
exact,,f64,1.23456e-2,0.0456,0.85,0e0,0e0,true
traces,1e-4,f32,9.87e-4,0.002,0.8333333333333334,1.234e-5,5.678e-4,true
traces,1e-3,f64,3.45e-3,0.0069,0.8166666666666667,1.234e-3,5.678e-2,false
traces,2e-2,f32,5e-1,,0.5,1.2345e-1,9e-1,false
traces,5e-3,f64,2e-3,,0.8333333333333334,2e-3,1e-2,true
";
    const PARETO: &str = "| method | trace dt (ms) | precision | LOO accuracy | mean rel. error | max rel. error | matrix time |
|---|---|---|---|---|---|---|
| traces | 0.1 | f32 | 83.3 % | 1.23e-5 | 5.68e-4 | 0.001 s wall, 0.00 s CPU on 2 threads |
| traces | 5 | f64 | 83.3 % | 2.00e-3 | 1.00e-2 | 0.002 s wall on 2 threads |
| exact | — | f64 | 85.0 % | 0.00e0 | 0.00e0 | 0.012 s wall, 0.05 s CPU on 2 threads |
";
    const MD: &str = "# Van Rossum distance: exact vs synaptic traces

60 samples, τ = 0.076 s, cos θ = 0.4, KNN k = 4 (leave-one-out). Matrix time: `LL²` and `SP²` of all pairs from the readouts (trains or trace records), THREADS threads.

| method | trace dt (ms) | precision | LOO accuracy | mean rel. error | max rel. error | matrix time |
|---|---|---|---|---|---|---|
| exact | — | f64 | 85.0 % | 0.00e0 | 0.00e0 | 0.012 s wall, 0.05 s CPU on 2 threads |
| traces | 0.1 | f32 | 83.3 % | 1.23e-5 | 5.68e-4 | 0.001 s wall, 0.00 s CPU on 2 threads |
| traces | 1 | f64 | 81.7 % | 1.23e-3 | 5.68e-2 | 0.003 s wall, 0.01 s CPU on 2 threads |
| traces | 20 | f32 | 50.0 % | 1.23e-1 | 9.00e-1 | 0.500 s wall on 2 threads |
| traces | 5 | f64 | 83.3 % | 2.00e-3 | 1.00e-2 | 0.002 s wall on 2 threads |

Pareto front (matrix speed, LOO accuracy):

| method | trace dt (ms) | precision | LOO accuracy | mean rel. error | max rel. error | matrix time |
|---|---|---|---|---|---|---|
| traces | 0.1 | f32 | 83.3 % | 1.23e-5 | 5.68e-4 | 0.001 s wall, 0.00 s CPU on 2 threads |
| traces | 5 | f64 | 83.3 % | 2.00e-3 | 1.00e-2 | 0.002 s wall on 2 threads |
| exact | — | f64 | 85.0 % | 0.00e0 | 0.00e0 | 0.012 s wall, 0.05 s CPU on 2 threads |
";

    #[test]
    fn the_tables_keep_their_format() {
        let s = sweep();
        assert_eq!(to_csv(&s).unwrap(), CSV);
        assert_eq!(pareto_table(&s), PARETO);
        assert_eq!(
            to_markdown(&s),
            MD.replace("THREADS", &rayon::current_num_threads().to_string())
        );
    }

    /// The CSV and the report's table of every method show the same cells, except that the
    /// Markdown table gives the trace step in ms, the accuracy in % and rounds the errors.
    #[test]
    fn the_csv_and_markdown_tables_have_the_same_cells() {
        let s = sweep();
        assert_eq!(
            columns_written_differently(&COLUMNS, &to_csv(&s).unwrap(), &to_markdown(&s)),
            [
                "trace_dt_s",
                "loo_accuracy",
                "mean_relative_error",
                "max_relative_error"
            ]
        );
    }
}
