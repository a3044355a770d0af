//! The speed ↔ accuracy trade of the multi-unit Van Rossum distance: the trace-sampled distance
//! (the traces a simulated network advances at step dt through its synapse filter) against the
//! exact one (the Markage recursion), as dt shrinks.
//!
//! Error: the relative difference `|D_dt − D| / D` over every pair of distinct samples with
//! `D > 0` (mean and max). Time: wall and CPU time of the whole N × N matrix.

use super::{Table, TradeoffError, error_series, mark_front, write_trade};
use crate::coding::sample_duration_ms;
use crate::error::ExperimentError;
use crate::report::svg::{Axis, Chart, Marker, panels};
use crate::timing::{Timing, timed};
use neurotac_core::distance::{VanRossum, check_cos, trace_sampled_matrices};
use neurotac_core::{MultiSpikeTrain, SpikeDataset};
use std::path::Path;

/// What to sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct VrTradeoffConfig {
    /// Kernel time constant τ (s). Default 0.076 (the paper's best).
    pub tau_s: f64,
    /// cos θ in [0, 1]. Default 0.4.
    pub cos: f64,
    /// Time steps to try (s). Default 10, 5, 2, 1, 0.5 ms.
    pub dts_s: Vec<f64>,
    /// Use at most the first this many samples (the sampled matrices cost N²·steps).
    /// Default 100.
    pub samples: usize,
}

impl Default for VrTradeoffConfig {
    fn default() -> Self {
        Self {
            tau_s: 0.076,
            cos: 0.4,
            dts_s: vec![0.01, 0.005, 0.002, 0.001, 0.0005],
            samples: 100,
        }
    }
}

/// One time step.
#[derive(Debug, Clone, serde::Serialize)]
pub struct VrTradeoffRow {
    /// Time step (s).
    pub dt_s: f64,
    /// Time of the trace-sampled matrix.
    pub timing: Timing,
    /// Mean relative error of the distance over the pairs.
    pub mean_relative_error: f64,
    /// Max relative error of the distance over the pairs.
    pub max_relative_error: f64,
    /// No other time step is both faster (wall) and more accurate (mean error).
    pub pareto: bool,
}

/// The measured sweep.
#[derive(Debug, Clone, serde::Serialize)]
pub struct VrTradeoff {
    /// Samples used.
    pub samples: usize,
    /// τ (s).
    pub tau_s: f64,
    /// cos θ.
    pub cos: f64,
    /// Time of the exact matrix.
    pub exact: Timing,
    /// One row per time step, in the order given.
    pub rows: Vec<VrTradeoffRow>,
}

/// Measures the sweep on the first `config.samples` of `observations`, sampling the traces over
/// `[0, duration_s)`.
pub fn vr_tradeoff(
    observations: &[MultiSpikeTrain],
    duration_s: f64,
    config: &VrTradeoffConfig,
) -> Result<VrTradeoff, ExperimentError> {
    check_cos(config.cos)?;
    let obs = &observations[..config.samples.min(observations.len())];
    let n = obs.len();
    if n < 2 {
        return Err(ExperimentError::InvalidParameter {
            what: "samples",
            value: n as f64,
            expected: "at least 2 (distances are between pairs)",
        });
    }
    let vr = VanRossum::new(config.tau_s)?;
    let (exact, exact_time) = timed(|| vr.matrices(obs)?.squared(config.cos));
    let exact = exact?;
    let mut rows = Vec::new();
    for &dt_s in &config.dts_s {
        let (sampled, timing) = timed(|| {
            trace_sampled_matrices(obs, config.tau_s, dt_s, duration_s)?.squared(config.cos)
        });
        let sampled = sampled?;
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
            dt_s,
            timing,
            mean_relative_error: if pairs > 0 {
                sum_rel / pairs as f64
            } else {
                0.0
            },
            max_relative_error: max_rel,
            pareto: false,
        });
    }
    mark_front(
        &mut rows,
        |r| Some((1.0 / r.timing.wall_s, r.mean_relative_error)),
        |r, on_front| r.pareto = on_front,
    );
    Ok(VrTradeoff {
        samples: n,
        tau_s: config.tau_s,
        cos: config.cos,
        exact: exact_time,
        rows,
    })
}

/// The quick settings: 30 samples, three time steps.
pub fn quick(config: &mut VrTradeoffConfig) {
    config.samples = 30;
    config.dts_s = vec![0.01, 0.005, 0.002];
}

/// Measures the sweep on `data` (sample duration: `duration_s`, else as
/// [`sample_duration_ms`]).
pub fn measure(
    data: &SpikeDataset,
    duration_s: Option<f64>,
    config: &VrTradeoffConfig,
) -> Result<VrTradeoff, ExperimentError> {
    let duration_s = sample_duration_ms(data, duration_s)? as f64 / 1e3;
    vr_tradeoff(data.observations(), duration_s, config)
}

/// [`measure`]s the sweep and writes `vr.{csv,md,svg,png}` to `out`.
pub fn report(
    data: &SpikeDataset,
    duration_s: Option<f64>,
    config: &VrTradeoffConfig,
    out: &Path,
) -> Result<VrTradeoff, TradeoffError> {
    let sweep = measure(data, duration_s, config)?;
    write_trade(
        out,
        "vr",
        &to_csv(&sweep),
        &to_markdown(&sweep),
        &to_svg(&sweep),
    )?;
    Ok(sweep)
}

/// CSV: one line per time step, then the exact matrix (`dt_s` empty, errors 0).
pub fn to_csv(sweep: &VrTradeoff) -> String {
    let mut table = Table::new(&[
        "dt_s",
        "wall_s",
        "cpu_s",
        "mean_relative_error",
        "max_relative_error",
        "pareto",
    ]);
    let cpu = |t: &Timing| t.cpu_s.map_or(String::new(), |c| format!("{c}"));
    for r in &sweep.rows {
        table.push(vec![
            format!("{:e}", r.dt_s),
            format!("{:e}", r.timing.wall_s),
            cpu(&r.timing),
            format!("{:e}", r.mean_relative_error),
            format!("{:e}", r.max_relative_error),
            r.pareto.to_string(),
        ]);
    }
    let exact = [
        String::new(),
        format!("{:e}", sweep.exact.wall_s),
        cpu(&sweep.exact),
    ];
    table.push([&exact[..], &["0".into(), "0".into(), String::new()]].concat());
    table.to_csv()
}

/// The exact distance, then `rows`, as a Markdown table.
fn table<'a>(sweep: &VrTradeoff, rows: impl IntoIterator<Item = &'a VrTradeoffRow>) -> String {
    let mut table = Table::new(&[
        "method",
        "dt (s)",
        "mean rel. error",
        "max rel. error",
        "time",
    ]);
    let exact = ["exact (Markage)", "—", "0", "0"].map(String::from);
    table.push([&exact[..], &[sweep.exact.to_string()]].concat());
    for r in rows {
        table.push(vec![
            "trace-sampled".into(),
            r.dt_s.to_string(),
            format!("{:.3e}", r.mean_relative_error),
            format!("{:.3e}", r.max_relative_error),
            r.timing.to_string(),
        ]);
    }
    table.to_markdown()
}

/// The exact distance and the Pareto front of the time steps as a Markdown table.
pub fn pareto_table(sweep: &VrTradeoff) -> String {
    let mut front: Vec<&VrTradeoffRow> = sweep.rows.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| a.timing.wall_s.total_cmp(&b.timing.wall_s));
    table(sweep, front)
}

/// A Markdown report: every time step against the exact distance.
pub fn to_markdown(sweep: &VrTradeoff) -> String {
    let mut out = format!(
        "# Van Rossum distance: trace-sampled vs exact\n\n{} samples, τ = {} s, cos θ = {}.\n\n",
        sweep.samples, sweep.tau_s, sweep.cos
    );
    out.push_str(&table(sweep, &sweep.rows));
    out
}

/// Mean and max relative error against wall time, one point per time step.
pub fn to_svg(sweep: &VrTradeoff) -> String {
    let series = |label: &str, c: usize, marker, error: fn(&VrTradeoffRow) -> f64| {
        let points = sweep.rows.iter().map(|r| (r.timing.wall_s, error(r)));
        error_series(label, c, marker, points.collect())
    };
    let chart = Chart {
        title: format!(
            "trace-sampled Van Rossum vs exact ({} samples; points: dt; exact: {:.3} s)",
            sweep.samples, sweep.exact.wall_s
        ),
        x: Axis::log("wall time of the N × N matrix (s)"),
        y: Axis::log("relative error of the distance"),
        series: vec![
            series("mean", 0, Marker::Circle, |r| r.mean_relative_error),
            series("max", 1, Marker::Square, |r| r.max_relative_error),
        ],
    };
    panels(&[chart], 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::datasets::synthetic::{SyntheticConfig, synthetic_dataset};

    #[test]
    fn error_shrinks_with_dt_and_the_front_is_marked() {
        let data = synthetic_dataset(&SyntheticConfig {
            samples: 6,
            classes: 2,
            channels: 4,
            duration_s: 1.0,
            ..SyntheticConfig::default()
        });
        let config = VrTradeoffConfig {
            dts_s: vec![0.01, 0.001],
            samples: 5,
            ..VrTradeoffConfig::default()
        };
        let sweep = vr_tradeoff(data.observations(), 1.0, &config).unwrap();
        assert_eq!((sweep.samples, sweep.rows.len()), (5, 2));
        let (coarse, fine) = (&sweep.rows[0], &sweep.rows[1]);
        assert!(fine.mean_relative_error < coarse.mean_relative_error / 3.0);
        assert!(coarse.max_relative_error >= coarse.mean_relative_error);
        // The finer step is the more accurate one: it is always on the front.
        assert!(fine.pareto);
        assert_eq!(to_csv(&sweep).lines().count(), 1 + 2 + 1);
        assert!(pareto_table(&sweep).contains("| exact (Markage) |"));
        assert!(to_svg(&sweep).contains("<svg"));
        let too_few = VrTradeoffConfig {
            samples: 1,
            ..config
        };
        assert!(matches!(
            vr_tradeoff(data.observations(), 1.0, &too_few),
            Err(ExperimentError::InvalidParameter {
                what: "samples",
                ..
            })
        ));
    }
}
