//! Calibration of the simulator's three global parameters, each on one of the paper's three
//! intensive means and nothing else (spec §5 calibration rule):
//!
//! | parameter | anchor | target (spikes/taxel) |
//! |---|---|---|
//! | `contact.pin_shear_gain` (the onset's size on the pins) | flat plate | 4.63 |
//! | `contact.gap_conformity_mm` (sag/conformity law) | 2.5 mm grid | 9.84 |
//! | `contact.lever_mm` (lever gain) | 5 mm grid | 34.73 |
//!
//! Each anchor count is the grid's expected count over mountings ([`grid_count`]). Every value
//! moves every anchor a little — the lever sets the press's splay on the flat plate too, the
//! shear gain every grid's onset — so they are fitted by alternating bisections (lever on
//! 5 mm, the gap on 2.5 mm, the shear gain on the flat plate) until all three are within 1 % or
//! `rounds` are spent. Every other parameter, and every accuracy, confusion matrix and chosen Δt / τ /
//! cos θ, is a held-out prediction.

use super::statistics::mean;
use neurotac_experiments::datasets::{
    DatasetsError, TextureSet, TrialJob, camera_seed, jobs_for, map_trials,
};
use neurotac_sensor::sim::{
    CalibratedParameter, GRID_SIZES_MM, PAPER_INTENSIVE_MEANS, PreparedTexture, SimParams, Texture,
    taxel_spikes,
};
use serde::Serialize;

/// One fitted parameter with what it achieved.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CalibrationEntry {
    /// The parameter, its value, anchor grid and target.
    pub parameter: CalibratedParameter,
    /// Mean spikes per taxel of the anchor grid with the final parameters.
    pub achieved: f64,
}

/// The result of [`calibrate`].
#[derive(Debug, Clone, Serialize)]
pub struct Calibration {
    /// The parameters with the three calibrated fields set.
    pub params: SimParams,
    /// The three fits.
    pub entries: Vec<CalibrationEntry>,
    /// Slides simulated.
    pub slides: usize,
}

/// Mean spikes per taxel of grid `size_mm` over `trials` slides (seeded as a dataset), each on
/// a fresh mounting ([`remounted`]): the expected count of the grid, not the count of one
/// mounting, which sits ≈ 5–10 % above or below it depending on where the bump rows fall under
/// the pins. A calibration on one mounting would fit that draw.
pub fn grid_count(
    params: &SimParams,
    size_mm: f64,
    trials: usize,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<f64, DatasetsError> {
    let class = GRID_SIZES_MM
        .iter()
        .position(|&d| d == size_mm)
        .expect("one of the paper's grid sizes");
    let params = &remounted(params);
    let camera = neurotac_sensor::sim::Camera::new(params, camera_seed(seed));
    // Only the anchor grid is prepared (its contact solve changes with every fitted value);
    // the jobs keep the dataset's seeds of class `class` and point at that one texture.
    let texture = PreparedTexture::new(Texture::Grid { size_mm }, params);
    let jobs: Vec<TrialJob> = jobs_for(TextureSet::Artificial, seed, &[class], 0, trials.max(1))
        .into_iter()
        .map(|job| TrialJob { class: 0, ..job })
        .collect();
    let counts = map_trials(
        params,
        &camera,
        std::slice::from_ref(&texture),
        &jobs,
        &|_, trial| Ok(taxel_spikes(trial)?.spikes.total_spikes() as f64 / 49.0),
        progress,
    )?;
    Ok(mean(counts))
}

/// `params` with every slide on a fresh mounting (`kinematics.per_slide_offsets`): slides
/// whose average is the expectation over where a texture is mounted.
pub fn remounted(params: &SimParams) -> SimParams {
    let mut p = *params;
    p.kinematics.per_slide_offsets = true;
    p
}

/// Bisection of `set` on `[lo, hi]` until `count` is within 1 % of `target` (at most 12
/// steps); `rising` says whether the count grows with the parameter. Returns the last value
/// and its count.
fn bisect(
    params: &mut SimParams,
    set: fn(&mut SimParams, f64),
    (mut lo, mut hi): (f64, f64),
    rising: bool,
    target: f64,
    count: &mut dyn FnMut(&SimParams) -> Result<f64, DatasetsError>,
) -> Result<(f64, f64), DatasetsError> {
    let mut best = (f64::NAN, f64::NAN);
    for _ in 0..12 {
        let value = 0.5 * (lo + hi);
        set(params, value);
        let c = count(params)?;
        best = (value, c);
        if (c / target - 1.0).abs() <= 0.01 {
            break;
        }
        if (c < target) == rising {
            lo = value;
        } else {
            hi = value;
        }
    }
    set(params, best.0);
    Ok(best)
}

/// Calibrates the three parameters of `params` (see the module docs) with `trials` slides per
/// evaluation; `rounds` alternations of the three fits (≥ 1).
pub fn calibrate(
    params: &SimParams,
    trials: usize,
    seed: u64,
    rounds: usize,
    progress: &(dyn Fn() + Sync),
) -> Result<Calibration, DatasetsError> {
    params.validate()?;
    neurotac_sensor::sim::check_trials(trials.max(1), 1)?;
    let [flat, mid, coarse] = PAPER_INTENSIVE_MEANS;
    let mut p = *params;
    let mut slides = 0usize;
    // Each value moves every anchor (the lever also sets the press's splay on the flat plate;
    // the shear gain every grid's onset), so the three are fitted in turn — lever on 5 mm,
    // conformity gap on 2.5 mm, shear gain on the flat plate — until the anchors all hold.
    /// A fitted value: how to set it, its range, whether the count rises with it, its anchor
    /// (grid size, target count).
    type Fit = (fn(&mut SimParams, f64), (f64, f64), bool, (f64, f64));
    let fits: [Fit; 3] = [
        (|q, v| q.contact.lever_mm = v, (0.05, 3.0), true, coarse),
        (
            |q, v| q.contact.gap_conformity_mm = v,
            (1.0, 20.0),
            false,
            mid,
        ),
        (|q, v| q.contact.pin_shear_gain = v, (0.0, 2.0), true, flat),
    ];
    let mut count = |q: &SimParams, size_mm: f64| {
        slides += trials;
        grid_count(q, size_mm, trials, seed, progress)
    };
    let held = |achieved: f64, target: f64| (achieved / target - 1.0).abs() <= 0.01;
    let (mut flat_achieved, mut mid_achieved, mut coarse_achieved) = (f64::NAN, f64::NAN, f64::NAN);
    for _ in 0..rounds.max(1) {
        for (set, range, rising, (size_mm, target)) in fits {
            let (_, achieved) = bisect(&mut p, set, range, rising, target, &mut |q| {
                count(q, size_mm)
            })?;
            // The flat plate is fitted last: its count is what the round ends with.
            if size_mm == flat.0 {
                flat_achieved = achieved;
            }
        }
        mid_achieved = count(&p, mid.0)?;
        coarse_achieved = count(&p, coarse.0)?;
        if held(coarse_achieved, coarse.1) && held(mid_achieved, mid.1) {
            break;
        }
    }
    let achieved = [flat_achieved, mid_achieved, coarse_achieved];
    let entries = p
        .calibrated_parameters()
        .into_iter()
        .zip(achieved)
        .map(|(parameter, achieved)| CalibrationEntry {
            parameter,
            achieved,
        })
        .collect();
    Ok(Calibration {
        params: p,
        entries,
        slides,
    })
}
