//! The camera's fixed-pattern noise (spec §3.2): per-pixel ON/OFF thresholds and leak rates,
//! drawn once per camera.

use super::params::SimParams;
use super::random::gaussian;
use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The camera's fixed-pattern noise: per-pixel thresholds and leak rates, drawn once per
/// camera (the same physical sensor records every trial of a dataset).
#[derive(Debug, Clone)]
pub struct Camera {
    pub(crate) width: u16,
    pub(crate) height: u16,
    pub(crate) threshold_on: Vec<f32>,
    pub(crate) threshold_off: Vec<f32>,
    pub(crate) leak_rate_hz: Vec<f32>,
    /// The seed the camera was drawn from; it also names the rig (texture mountings, the
    /// recording's friction factor, [`super::Mounting`]).
    pub(crate) rig_seed: u64,
}

impl Camera {
    /// A DAVIS240 whose pixel thresholds `C ~ N(C̄, σ_C)` (clipped at ≥ 0.01) and leak rates
    /// are drawn from `seed`.
    pub fn new(params: &SimParams, seed: u64) -> Self {
        let (width, height) = (DAVIS240_WIDTH, DAVIS240_HEIGHT);
        let n = width as usize * height as usize;
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x005e_edca_3e7a_u64);
        let p = &params.pixel;
        let mut threshold_on = Vec::with_capacity(n);
        let mut threshold_off = Vec::with_capacity(n);
        let mut leak_rate_hz = Vec::with_capacity(n);
        for _ in 0..n {
            threshold_on
                .push((p.threshold_on + p.threshold_sd * gaussian(&mut rng)).max(0.01) as f32);
            threshold_off
                .push((p.threshold_off + p.threshold_sd * gaussian(&mut rng)).max(0.01) as f32);
            let spread = 10f64.powf(params.noise.leak_spread_decades * gaussian(&mut rng));
            leak_rate_hz.push((params.noise.leak_rate_hz * spread) as f32);
        }
        Self {
            width,
            height,
            threshold_on,
            threshold_off,
            leak_rate_hz,
            rig_seed: seed,
        }
    }

    /// Image width (px).
    pub fn width(&self) -> u16 {
        self.width
    }

    /// Image height (px).
    pub fn height(&self) -> u16 {
        self.height
    }
}
