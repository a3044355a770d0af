//! Calibration of the simulator's one free parameter, G_lever, on the 5 mm grid (spec §5).

use super::mean;
use crate::datasets::{
    DatasetsError, TextureSet, camera_seed, jobs_for, map_trials, prepare_textures,
};
use neurotac_sensor::sim::{Camera, SimParams, taxel_spikes};
use serde::Serialize;

/// The result of [`calibrate_lever`].
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Calibration {
    /// The calibrated `contact.lever_mm` (mm).
    pub lever_mm: f64,
    /// Mean spikes per taxel of the 5 mm grid with it.
    pub spikes_per_taxel: f64,
    /// The target (the paper's 34.73).
    pub target: f64,
    /// Bisection steps taken.
    pub iterations: usize,
}

/// Mean spikes per taxel of the 5 mm grid over `trials` slides (seeded as a dataset).
pub fn coarse_grid_count(
    params: &SimParams,
    trials: usize,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<f64, DatasetsError> {
    let camera = Camera::new(params, camera_seed(seed));
    let jobs = jobs_for(TextureSet::Artificial, seed, &[10], 0, trials.max(1));
    let textures = prepare_textures(params, TextureSet::Artificial);
    let counts = map_trials(
        params,
        &camera,
        &textures,
        &jobs,
        &|_, trial| Ok(taxel_spikes(trial)?.spikes.total_spikes() as f64 / 49.0),
        progress,
    )?;
    Ok(mean(counts))
}

/// Calibrates the one free parameter, G_lever (`contact.lever_mm`), against the 5 mm grid's
/// intensive count alone (spec §5: "calibrate only G_lever"): bisection on [0.1, 1.5] mm
/// until the mean over `trials` slides is within 1 % of `target` (at most 12 steps).
pub fn calibrate_lever(
    params: &SimParams,
    trials: usize,
    seed: u64,
    target: f64,
    progress: &(dyn Fn() + Sync),
) -> Result<Calibration, DatasetsError> {
    let (mut lo, mut hi) = (0.1, 1.5);
    let mut best = (params.contact.lever_mm, f64::NAN);
    let mut iterations = 0;
    while iterations < 12 {
        iterations += 1;
        let lever = 0.5 * (lo + hi);
        let mut p = *params;
        p.contact.lever_mm = lever;
        let count = coarse_grid_count(&p, trials, seed, progress)?;
        best = (lever, count);
        if (count / target - 1.0).abs() <= 0.01 {
            break;
        }
        if count < target {
            lo = lever;
        } else {
            hi = lever;
        }
    }
    Ok(Calibration {
        lever_mm: best.0,
        spikes_per_taxel: best.1,
        target,
        iterations,
    })
}
