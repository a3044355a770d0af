//! Bayesian optimisation of the spatiotemporal coding's (τ, cos θ): a Gaussian process with
//! expected improvement (EI), deterministic for a seed, maximising leave-one-out accuracy.
//!
//! # The search
//! - **Domain**: a grid, τ from `tau_min_s` to `tau_max_s` in `tau_step_s` (paper: 10–100 ms; 1 ms
//!   steps) × cos θ from 0 to 1 in `cos_step` (0.01). Coordinates are scaled to [0, 1]².
//! - **Surrogate**: GP with a Matérn-5/2 kernel `k(r) = (1 + √5·r + 5r²/3)·e^{−√5·r}`,
//!   `r = ‖Δx‖/ℓ`, unit signal variance on standardised accuracies, noise variance `noise`
//!   (accuracy is a step function of the parameters). Hyperparameters are fixed, so every
//!   observation adds one row to the Cholesky factor `L` and one row to `V = L⁻¹·K(X, grid)`:
//!   the posterior on the whole grid is `μ = Vᵀ·L⁻¹(y − ȳ)/s_y`, `σ² = 1 − Σ V²`, `O(n·m)` per epoch.
//! - **Acquisition**: `EI = (μ − f* − ξ)·Φ(z) + σ·φ(z)`, `z = (μ − f* − ξ)/σ`, maximised over the
//!   grid points not yet evaluated (ties: the lowest grid index, τ-major).
//! - **Start**: `initial` distinct grid points drawn with ChaCha8 from `seed`; then one EI point
//!   per epoch, `epochs` evaluations in all (paper: 1000), fewer if the grid is exhausted.
//!
//! Everything is sequential except inside the objective, so the trace is the same for a seed
//! at any thread count, and at any rank count when the objective's matrices are split over
//! ranks ([`VanRossumObjective::on_ranks`]): the optimiser runs identically on every rank.
//! [`VanRossumObjective`] caches `LL²`/`SP²` per τ (least recently used first out), so every
//! cos θ at a known τ costs only a matrix combination and a LOO pass.

use crate::error::ExperimentError;
use crate::neuron_setup::Precision;
use crate::protocols::Accuracy;
use ndarray::Array2;
use neurotac_core::coding::TraceRecord;
use neurotac_core::distance::{VanRossum, VanRossumMatrices, trace_matrices};
use neurotac_core::special::erfc;
use neurotac_core::{Knn, MultiSpikeTrain, OneProcess, Ranks};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use std::sync::Arc;

/// Settings of the search; defaults follow the paper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BayesConfig {
    /// Objective evaluations in all, initial ones included. Default 1000.
    pub epochs: usize,
    /// Random initial evaluations. Default 10.
    pub initial: usize,
    /// Seed of the initial design. Default 1.
    pub seed: u64,
    /// Smallest τ (s). Default 0.010.
    pub tau_min_s: f64,
    /// Largest τ (s). Default 0.100.
    pub tau_max_s: f64,
    /// τ grid step (s). Default 0.001.
    pub tau_step_s: f64,
    /// cos θ grid step in [0, 1]. Default 0.01.
    pub cos_step: f64,
    /// Matérn length scale in scaled coordinates. Default 0.2.
    pub length_scale: f64,
    /// GP noise variance (standardised units). Default 10⁻³.
    pub noise: f64,
    /// EI exploration margin ξ (standardised units). Default 0.01.
    pub xi: f64,
}

impl Default for BayesConfig {
    fn default() -> Self {
        Self {
            epochs: 1000,
            initial: 10,
            seed: 1,
            tau_min_s: 0.010,
            tau_max_s: 0.100,
            tau_step_s: 0.001,
            cos_step: 0.01,
            length_scale: 0.2,
            noise: 1e-3,
            xi: 0.01,
        }
    }
}

/// One evaluation of the search.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BayesStep {
    /// Evaluation number, from 0.
    pub epoch: usize,
    /// τ evaluated (s).
    pub tau_s: f64,
    /// cos θ evaluated.
    pub cos: f64,
    /// Objective at this point.
    pub value: f64,
    /// Best objective so far.
    pub best_value: f64,
    /// τ of the best so far (s).
    pub best_tau_s: f64,
    /// cos θ of the best so far.
    pub best_cos: f64,
}

/// The outcome: the convergence trace and the optimum (the first point reaching the best value).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BayesResult {
    /// One entry per evaluation.
    pub trace: Vec<BayesStep>,
    /// Best τ (s).
    pub best_tau_s: f64,
    /// Index of the best τ in the τ grid (the key of [`VanRossumObjective`]'s cache).
    pub best_tau_index: usize,
    /// Best cos θ.
    pub best_cos: f64,
    /// Best objective value.
    pub best_value: f64,
}

fn grid(min: f64, max: f64, step: f64) -> Vec<f64> {
    let n = grid_len(min, max, step) as usize;
    (0..n).map(|i| on_grid(min + i as f64 * step)).collect()
}

/// `x` rounded to 12 decimals, so that a grid point is the double nearest to its decimal value
/// (0.01 + 18 × 0.005 is 0.1, not 0.09999999999999999) and prints in its shortest form.
fn on_grid(x: f64) -> f64 {
    (x * 1e12).round() / 1e12
}

/// Refuses a configuration outside its domain, or whose grid and epochs exceed the optimiser's
/// budget (at most 10⁴ values per axis, 2 × 10⁸ grid values over the epochs), before anything
/// is allocated; [`bayes_optimise`] checks it first.
pub fn check(config: &BayesConfig) -> Result<(), ExperimentError> {
    let bad = |what, value, expected| {
        Err(ExperimentError::InvalidParameter {
            what,
            value,
            expected,
        })
    };
    if !(config.tau_min_s > 0.0 && config.tau_min_s.is_finite()) {
        return bad("tau_min_s", config.tau_min_s, "finite and > 0");
    }
    if !(config.tau_max_s >= config.tau_min_s && config.tau_max_s.is_finite()) {
        return bad("tau_max_s", config.tau_max_s, "finite and ≥ tau_min_s");
    }
    if !(config.tau_step_s > 0.0 && config.tau_step_s.is_finite()) {
        return bad("tau_step_s", config.tau_step_s, "finite and > 0");
    }
    if !(config.cos_step > 0.0 && config.cos_step <= 1.0) {
        return bad("cos_step", config.cos_step, "in (0, 1]");
    }
    if !(config.length_scale > 0.0 && config.length_scale.is_finite()) {
        return bad("length_scale", config.length_scale, "finite and > 0");
    }
    if !(config.noise > 0.0 && config.noise.is_finite()) {
        return bad("noise", config.noise, "finite and > 0");
    }
    if !(config.xi >= 0.0 && config.xi.is_finite()) {
        return bad("xi", config.xi, "finite and ≥ 0");
    }
    if config.epochs == 0 || config.initial == 0 {
        return bad("epochs/initial", 0.0, "≥ 1");
    }
    // The grid and the optimiser's rows (one per epoch, one value per grid point) are sized by
    // these numbers: bounded before anything is allocated.
    let n_tau = grid_len(config.tau_min_s, config.tau_max_s, config.tau_step_s);
    if n_tau > MAX_GRID_AXIS {
        return bad(
            "tau_step_s",
            config.tau_step_s,
            "at most 10⁴ τ values on the grid ((tau_max − tau_min) / tau_step + 1)",
        );
    }
    let n_cos = grid_len(0.0, 1.0, config.cos_step);
    if n_cos > MAX_GRID_AXIS {
        return bad(
            "cos_step",
            config.cos_step,
            "at most 10⁴ cos θ values on the grid (≥ 10⁻⁴)",
        );
    }
    let points = n_tau * n_cos;
    if points * (config.epochs as f64).min(points) > MAX_GRID_WORK {
        return bad(
            "epochs",
            config.epochs as f64,
            "at most 2 × 10⁸ grid values over the epochs (epochs × τ values × cos θ values: a coarser grid or fewer epochs)",
        );
    }
    Ok(())
}

/// The most values on one axis of the (τ, cos θ) grid.
const MAX_GRID_AXIS: f64 = 1e4;

/// The most grid values the optimiser keeps over its epochs (one row of the whole grid per
/// epoch: 2 × 10⁸ values is 1.6 GB).
const MAX_GRID_WORK: f64 = 2e8;

/// The number of points of [`grid`]`(min, max, step)`, in floating point (so an absurd step
/// is counted, not wrapped).
fn grid_len(min: f64, max: f64, step: f64) -> f64 {
    ((max - min) / step + 1e-9).floor() + 1.0
}

/// Expected improvement of a normal `(mean, sd)` over `best + xi` (maximisation).
fn expected_improvement(mean: f64, sd: f64, best: f64, xi: f64) -> f64 {
    let imp = mean - best - xi;
    if sd <= 1e-12 {
        return imp.max(0.0);
    }
    let z = imp / sd;
    let cdf = 0.5 * erfc(-z / std::f64::consts::SQRT_2);
    let pdf = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
    imp * cdf + sd * pdf
}

/// Maximises `objective(tau_index, tau_s, cos)` over the grid of `config`.
pub fn bayes_optimise<F>(
    config: &BayesConfig,
    mut objective: F,
) -> Result<BayesResult, ExperimentError>
where
    F: FnMut(usize, f64, f64) -> Result<f64, ExperimentError>,
{
    check(config)?;
    let taus = grid(config.tau_min_s, config.tau_max_s, config.tau_step_s);
    let coss = grid(0.0, 1.0, config.cos_step);
    let (nt, nc) = (taus.len(), coss.len());
    let m = nt * nc;
    let scaled = |g: usize| -> (f64, f64) {
        let (i, j) = (g / nc, g % nc);
        (
            if nt > 1 {
                i as f64 / (nt - 1) as f64
            } else {
                0.0
            },
            if nc > 1 {
                j as f64 / (nc - 1) as f64
            } else {
                0.0
            },
        )
    };
    let points: Vec<(f64, f64)> = (0..m).map(scaled).collect();
    let kernel = |a: (f64, f64), b: (f64, f64)| -> f64 {
        let r = ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt() / config.length_scale;
        let s5r = 5f64.sqrt() * r;
        (1.0 + s5r + 5.0 * r * r / 3.0) * (-s5r).exp()
    };
    let mut evaluated = vec![false; m];
    let mut chosen: Vec<usize> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut chol: Vec<Vec<f64>> = Vec::new();
    let mut v_rows: Vec<Vec<f64>> = Vec::new();
    let mut variance = vec![1.0f64; m];
    let mut trace = Vec::new();
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let mut best: Option<(f64, usize)> = None;
    let epochs = config.epochs.min(m);
    for epoch in 0..epochs {
        let g = if epoch < config.initial.min(m) {
            loop {
                let g = rng.random_range(0..m);
                if !evaluated[g] {
                    break g;
                }
            }
        } else {
            // Posterior mean on the grid from standardised values.
            let n = values.len();
            let mean_y = values.iter().sum::<f64>() / n as f64;
            let sd_y = (values.iter().map(|y| (y - mean_y).powi(2)).sum::<f64>() / n as f64).sqrt();
            let sd_y = if sd_y > 0.0 { sd_y } else { 1.0 };
            let mut z = vec![0.0; n];
            for i in 0..n {
                let s: f64 = (0..i).map(|k| chol[i][k] * z[k]).sum();
                z[i] = ((values[i] - mean_y) / sd_y - s) / chol[i][i];
            }
            let mut mean = vec![0.0f64; m];
            for (row, &zi) in v_rows.iter().zip(&z) {
                for (mu, &v) in mean.iter_mut().zip(row) {
                    *mu += v * zi;
                }
            }
            let f_best = (best.expect("initial points evaluated").0 - mean_y) / sd_y;
            let mut pick = None;
            let mut pick_ei = f64::NEG_INFINITY;
            for x in (0..m).filter(|&x| !evaluated[x]) {
                let ei =
                    expected_improvement(mean[x], variance[x].max(0.0).sqrt(), f_best, config.xi);
                if ei > pick_ei {
                    pick_ei = ei;
                    pick = Some(x);
                }
            }
            pick.expect("epochs ≤ grid size leaves a point")
        };
        let (ti, ci) = (g / nc, g % nc);
        let value = objective(ti, taus[ti], coss[ci])?;
        if !value.is_finite() {
            return Err(ExperimentError::InvalidParameter {
                what: "objective value",
                value,
                expected: "finite",
            });
        }
        // Grow the Cholesky factor and V by one row.
        let kvec: Vec<f64> = chosen
            .iter()
            .map(|&c| kernel(points[c], points[g]))
            .collect();
        let mut l = vec![0.0; chosen.len()];
        for i in 0..chosen.len() {
            let s: f64 = (0..i).map(|k| chol[i][k] * l[k]).sum();
            l[i] = (kvec[i] - s) / chol[i][i];
        }
        let diag = (1.0 + config.noise - l.iter().map(|x| x * x).sum::<f64>())
            .max(1e-12)
            .sqrt();
        let mut v_new: Vec<f64> = points.iter().map(|&p| kernel(p, points[g])).collect();
        for (li, row) in l.iter().zip(&v_rows) {
            for (v, &r) in v_new.iter_mut().zip(row) {
                *v -= li * r;
            }
        }
        for (v, var) in v_new.iter_mut().zip(variance.iter_mut()) {
            *v /= diag;
            *var -= *v * *v;
        }
        l.push(diag);
        chol.push(l);
        v_rows.push(v_new);
        evaluated[g] = true;
        chosen.push(g);
        values.push(value);
        if best.is_none_or(|(b, _)| value > b) {
            best = Some((value, g));
        }
        let (bv, bg) = best.expect("just set");
        trace.push(BayesStep {
            epoch,
            tau_s: taus[ti],
            cos: coss[ci],
            value,
            best_value: bv,
            best_tau_s: taus[bg / nc],
            best_cos: coss[bg % nc],
        });
    }
    let (best_value, bg) = best.expect("at least one epoch");
    Ok(BayesResult {
        trace,
        best_tau_s: taus[bg / nc],
        best_tau_index: bg / nc,
        best_cos: coss[bg % nc],
        best_value,
    })
}

/// What the Van Rossum matrices of a search are computed from.
#[derive(Debug, Clone, Copy)]
pub enum VanRossumInput<'a> {
    /// The exact distance from the spike trains ([`VanRossum::matrices`]).
    Exact(&'a [MultiSpikeTrain]),
    /// The trace-sampled distance from the samples' synaptic trace records
    /// ([`trace_matrices`]), with its arithmetic in `precision`.
    Traces {
        /// One record per sample, all at the same trace step.
        records: &'a [TraceRecord],
        /// `f64` or `f32` arithmetic.
        precision: Precision,
    },
}

impl VanRossumInput<'_> {
    /// `LL²` and `SP²` at `tau_s`.
    ///
    /// Split over `ranks` (`&OneProcess` for one process) ([`VanRossum::matrices`],
    /// [`trace_matrices`]): every rank returns the one-process matrices. Collective.
    pub fn matrices(
        &self,
        tau_s: f64,
        ranks: &dyn Ranks,
    ) -> Result<VanRossumMatrices, ExperimentError> {
        Ok(match *self {
            VanRossumInput::Exact(trains) => VanRossum::new(tau_s)?.matrices(trains, ranks)?,
            VanRossumInput::Traces {
                records,
                precision: Precision::F64,
            } => trace_matrices::<f64>(records, tau_s, ranks)?,
            VanRossumInput::Traces {
                records,
                precision: Precision::F32,
            } => trace_matrices::<f32>(records, tau_s, ranks)?,
        })
    }
}

/// Leave-one-out KNN accuracy of the Van Rossum distance at (τ, cos θ), with `LL²`/`SP²`
/// cached per τ grid index (at most `capacity` matrices, least recently used evicted).
///
/// On several ranks ([`on_ranks`](Self::on_ranks)) every matrix is computed by all of them
/// together ([`VanRossumInput::matrices`]) and every rank gets the same matrices, so the
/// same accuracies: [`bayes_optimise`] then runs identically on every rank, and the ranks stay
/// in lock step (every rank misses the cache at the same evaluations, so they all join the
/// same collectives).
pub struct VanRossumObjective<'a> {
    input: VanRossumInput<'a>,
    labels: &'a [usize],
    knn: Knn,
    capacity: usize,
    ranks: &'a dyn Ranks,
    /// `(tau index, matrices)`, most recently used last.
    cache: Vec<(usize, Arc<VanRossumMatrices>)>,
    /// `D²(c)` of the last evaluation (reused, not reallocated, by the next).
    squared: Array2<f64>,
    /// Matrices computed so far (cache misses).
    pub matrices_computed: usize,
}

impl<'a> VanRossumObjective<'a> {
    /// An objective over `input`'s samples labelled `labels`, keeping up to `capacity` τ
    /// matrices, computed in this process alone.
    pub fn new(input: VanRossumInput<'a>, labels: &'a [usize], knn: Knn, capacity: usize) -> Self {
        Self {
            input,
            labels,
            knn,
            capacity: capacity.max(1),
            ranks: &OneProcess,
            cache: Vec::new(),
            squared: Array2::zeros((0, 0)),
            matrices_computed: 0,
        }
    }

    /// The objective with its matrices computed over `ranks`: every rank must then make the
    /// same calls, in the same order (as [`bayes_optimise`] does for a seed).
    pub fn on_ranks(self, ranks: &'a dyn Ranks) -> Self {
        Self { ranks, ..self }
    }

    /// The `LL²`/`SP²` matrices at grid τ index `tau_index` (value `tau_s`), from the cache or
    /// computed (and cached).
    pub fn matrices(
        &mut self,
        tau_index: usize,
        tau_s: f64,
    ) -> Result<Arc<VanRossumMatrices>, ExperimentError> {
        if let Some(p) = self.cache.iter().position(|(t, _)| *t == tau_index) {
            let entry = self.cache.remove(p);
            let m = entry.1.clone();
            self.cache.push(entry);
            return Ok(m);
        }
        let m = Arc::new(self.input.matrices(tau_s, self.ranks)?);
        self.matrices_computed += 1;
        if self.cache.len() == self.capacity {
            self.cache.remove(0);
        }
        self.cache.push((tau_index, m.clone()));
        Ok(m)
    }

    /// The LOO accuracy at grid τ index `tau_index` (value `tau_s`) and `cos`.
    pub fn accuracy(
        &mut self,
        tau_index: usize,
        tau_s: f64,
        cos: f64,
    ) -> Result<f64, ExperimentError> {
        let matrices = self.matrices(tau_index, tau_s)?;
        matrices.squared_into(cos, &mut self.squared)?;
        let predicted = self.knn.leave_one_out(self.squared.view(), self.labels)?;
        Ok(Accuracy::of(&predicted, self.labels).mean)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_points_print_as_their_decimal_values() {
        let taus = grid(0.01, 0.1, 0.005);
        assert_eq!(taus.len(), 19);
        assert_eq!(taus[18].to_string(), "0.1");
        assert_eq!((taus[18] * 1e3).to_string(), "100");
        assert_eq!(taus[5].to_string(), "0.035");
        assert!(
            grid(0.0, 1.0, 0.01)
                .iter()
                .all(|c| c.to_string().len() <= 4)
        );
    }

    #[test]
    fn a_grid_too_fine_to_hold_is_refused_before_anything_is_allocated() {
        let paper = BayesConfig {
            tau_step_s: 0.001,
            cos_step: 0.01,
            ..BayesConfig::default()
        };
        assert!(check(&paper).is_ok(), "the paper's 1 ms × 0.01 grid");
        for (config, field) in [
            (
                BayesConfig {
                    tau_step_s: 1e-300,
                    ..paper
                },
                "tau_step_s",
            ),
            (
                BayesConfig {
                    tau_step_s: 1e-7,
                    ..paper
                },
                "tau_step_s",
            ),
            (
                BayesConfig {
                    cos_step: 1e-300,
                    ..paper
                },
                "cos_step",
            ),
            (
                BayesConfig {
                    cos_step: 1e-3,
                    tau_step_s: 1e-5,
                    ..paper
                },
                "epochs",
            ),
        ] {
            let e = bayes_optimise(&config, |_, _, _| Ok(0.5)).unwrap_err();
            assert!(
                matches!(e, ExperimentError::InvalidParameter { what, .. } if what == field),
                "{e}"
            );
        }
    }

    #[test]
    fn erfc_and_ei_known_values() {
        assert!((erfc(0.0) - 1.0).abs() < 1e-7);
        assert!((erfc(1.0) - 0.157_299_207).abs() < 1e-7);
        assert!((erfc(-1.0) - 1.842_700_793).abs() < 1e-7);
        // EI of N(0, 1) over 0 is φ(0) = 0.398 942 28.
        assert!((expected_improvement(0.0, 1.0, 0.0, 0.0) - 0.398_942_28).abs() < 1e-7);
        assert_eq!(expected_improvement(2.0, 0.0, 1.0, 0.5), 0.5);
    }

    #[test]
    fn finds_the_peak_of_a_smooth_objective_deterministically() {
        let config = BayesConfig {
            epochs: 60,
            seed: 3,
            ..Default::default()
        };
        let peak =
            |tau: f64, cos: f64| -((tau - 0.076) / 0.03).powi(2) - ((cos - 0.4) / 0.3).powi(2);
        let run = || bayes_optimise(&config, |_, t, c| Ok(peak(t, c))).unwrap();
        let r = run();
        assert_eq!(r.trace.len(), 60);
        assert!(
            (r.best_tau_s - 0.076).abs() <= 0.006 && (r.best_cos - 0.4).abs() <= 0.06,
            "{r:?}"
        );
        assert!(
            r.trace
                .windows(2)
                .all(|w| w[1].best_value >= w[0].best_value)
        );
        assert_eq!(run(), r);
        let other =
            bayes_optimise(&BayesConfig { seed: 4, ..config }, |_, t, c| Ok(peak(t, c))).unwrap();
        assert_ne!(other.trace[0], r.trace[0]);
    }

    #[test]
    fn bad_configs_and_objectives_are_errors() {
        let bad = BayesConfig {
            tau_min_s: -1.0,
            ..Default::default()
        };
        assert!(bayes_optimise(&bad, |_, _, _| Ok(0.0)).is_err());
        let small = BayesConfig {
            epochs: 3,
            ..Default::default()
        };
        assert!(bayes_optimise(&small, |_, _, _| Ok(f64::NAN)).is_err());
        // A grid smaller than the epochs stops when exhausted.
        let tiny = BayesConfig {
            tau_min_s: 0.01,
            tau_max_s: 0.011,
            cos_step: 0.5,
            epochs: 100,
            ..Default::default()
        };
        assert_eq!(
            bayes_optimise(&tiny, |_, t, c| Ok(t + c))
                .unwrap()
                .trace
                .len(),
            6
        );
    }
}
