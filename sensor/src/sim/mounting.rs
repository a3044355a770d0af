//! What varies between the slides of a recording, hierarchically as in a real one (spec §2.1,
//! §8): a texture's [`Mounting`] — where the rig put it (lateral offset y₀, start phase), the
//! recording-wide friction factor, its specimen's friction draw and the shape of the slow
//! friction drift over its slides — is fixed for all its slides; a slide's [`TrialDraw`] adds
//! only what the arm does not repeat (positioning jitter at its stated repeatability, a
//! press-depth jitter of the same order) and the loop's timing
//! ([`super::kinematics::Recording::draw`]).
//!
//! `kinematics.mounting` picks another draw of every texture's mounting with the same camera;
//! `kinematics.per_slide_offsets` restores independent per-slide offsets (the first
//! implementation's behaviour) to study that confound.

use super::kinematics::Recording;
use super::params::SimParams;
use super::random::gaussian;
use super::texture::Surface;
use neurotac_core::seed_hash::{fnv1a, splitmix64};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What is fixed for every slide of one texture on one rig (recording): where the texture is
/// mounted under the arm, the recording-wide friction factor, and the shape of the slow
/// friction drift over the texture's slides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mounting {
    /// Lateral offset y₀ of the texture (mm).
    pub lateral_offset_mm: f64,
    /// Start phase: texture offset along the slide (mm).
    pub start_phase_mm: f64,
    /// Recording-wide friction factor 1 + σ_day·Z (shared by every texture of the rig).
    pub day_friction: f64,
    /// This specimen's draw from its texture's friction prior: 1 + spread·Z
    /// ([`Surface::friction_spread`]; 1 where the friction follows from the contact).
    pub specimen_friction: f64,
    /// Drift components: (amplitude, period in slides, phase in rad).
    pub drift: [(f64, f64, f64); 3],
}

impl Mounting {
    /// A texture's key for [`new`](Self::new): FNV-1a of its name ([`fnv1a`]).
    pub fn texture_key(name: &str) -> u64 {
        fnv1a(name.as_bytes())
    }

    /// The mounting of the texture with key `texture_key` ([`texture_key`](Self::texture_key))
    /// on the rig `rig_seed` (a pure function of both and of `kinematics.mounting`: the same
    /// texture is mounted once per recording).
    pub fn new(params: &SimParams, rig_seed: u64, texture_key: u64) -> Self {
        Self::of_specimen(params, rig_seed, texture_key, 0.0)
    }

    /// [`new`](Self::new) for a specimen whose friction is drawn from a prior of relative
    /// spread `friction_spread` (its own stream, so the offsets and drift do not change).
    pub fn of_specimen(
        params: &SimParams,
        rig_seed: u64,
        texture_key: u64,
        friction_spread: f64,
    ) -> Self {
        let k = &params.kinematics;
        let name_hash = texture_key;
        // Mounting k > 0: the same camera, every texture mounted from another draw.
        let rig_seed = match k.mounting {
            0 => rig_seed,
            m => splitmix64(rig_seed ^ splitmix64(m ^ 0x6d6f_756e_7400)),
        };
        let mut day = ChaCha8Rng::seed_from_u64(splitmix64(rig_seed ^ 0x6461_7900));
        let day_friction = (1.0 + params.contact.friction_day_sd * gaussian(&mut day)).max(0.5);
        let mut rng = ChaCha8Rng::seed_from_u64(splitmix64(rig_seed ^ splitmix64(name_hash)));
        let lateral_offset_mm = (rng.random::<f64>() - 0.5) * k.lateral_offset_range_mm;
        let start_phase_mm = rng.random::<f64>() * k.start_phase_range_mm;
        // Three sinusoids of equal amplitude: variance 3a²/2 = σ².
        let a = params.contact.friction_drift_sd * (2.0f64 / 3.0).sqrt();
        let drift = std::array::from_fn(|_| {
            let period = 50.0 + 350.0 * rng.random::<f64>();
            (a, period, std::f64::consts::TAU * rng.random::<f64>())
        });
        let mut specimen =
            ChaCha8Rng::seed_from_u64(splitmix64(rig_seed ^ splitmix64(name_hash ^ 0x7370)));
        let specimen_friction = if friction_spread > 0.0 {
            (1.0 + friction_spread * gaussian(&mut specimen)).max(0.3)
        } else {
            1.0
        };
        Self {
            lateral_offset_mm,
            start_phase_mm,
            day_friction,
            specimen_friction,
            drift,
        }
    }

    /// The friction factor of slide `slide` (recording-wide factor × specimen × slow drift).
    pub fn friction_factor(&self, slide: usize) -> f64 {
        let n = slide as f64;
        let drift: f64 = self
            .drift
            .iter()
            .map(|&(a, period, phase)| a * (std::f64::consts::TAU * n / period + phase).sin())
            .sum();
        (self.day_friction * self.specimen_friction * (1.0 + drift)).max(0.2)
    }
}

/// The per-slide physical draws (spec §2.1; variability is hierarchical, §8: what a texture
/// keeps for the whole recording is its [`Mounting`], what changes per slide is here).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrialDraw {
    /// Lateral offset y₀ of the texture (mm).
    pub lateral_offset_mm: f64,
    /// Start phase: texture offset along the slide (mm).
    pub start_phase_mm: f64,
    /// Press depth δ (mm).
    pub press_depth_mm: f64,
    /// Static friction of this slide.
    pub mu_static: f64,
    /// Kinetic friction of this slide.
    pub mu_kinetic: f64,
    /// The recording's timeline: the loop's latencies of this slide
    /// ([`Recording::draw`]).
    pub recording: Recording,
}

impl TrialDraw {
    /// Draws slide `slide` of a texture with `surface` on `mounting`: the mounting's offset and
    /// phase plus the arm's repeatability (or, with `per_slide_offsets`, fresh uniform
    /// ones), press-depth jitter, the loop's timing, friction scaled by the mounting's factor.
    pub fn draw(
        params: &SimParams,
        surface: &Surface,
        mounting: &Mounting,
        slide: usize,
        rng: &mut ChaCha8Rng,
    ) -> Self {
        let k = &params.kinematics;
        let rp = k.position_repeatability_mm;
        let (lateral_offset_mm, start_phase_mm) = if k.per_slide_offsets {
            (
                (rng.random::<f64>() - 0.5) * k.lateral_offset_range_mm,
                rng.random::<f64>() * k.start_phase_range_mm,
            )
        } else {
            (
                mounting.lateral_offset_mm + rp * gaussian(rng),
                mounting.start_phase_mm + rp * gaussian(rng),
            )
        };
        let press_depth_mm =
            (k.press_depth_mm + k.press_depth_sd_mm * gaussian(rng)).max(0.25 * k.press_depth_mm);
        let recording = Recording::draw(params, rng);
        let f = mounting.friction_factor(slide);
        Self {
            lateral_offset_mm,
            start_phase_mm,
            press_depth_mm,
            mu_static: surface.mu_static * f,
            mu_kinetic: surface.mu_kinetic * f,
            recording,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::texture::Texture;

    #[test]
    fn a_soft_texture_presses_lighter_and_its_specimen_draws_its_friction() {
        let p = SimParams::default();
        let fur = Texture::from_name("fake fur").unwrap();
        let (_, surface) = fur.prepare(&p, 20.0);
        let press = surface.press(&p, 2.0, 20.0);
        assert!(
            press.normal_force_n < 0.5 * p.kinematics.normal_force_n,
            "{press:?}"
        );
        let key = Mounting::texture_key(&fur.name());
        let factors: Vec<f64> = (0..40)
            .map(|rig| {
                Mounting::of_specimen(&p, rig, key, surface.friction_spread).specimen_friction
            })
            .collect();
        let mean = factors.iter().sum::<f64>() / 40.0;
        let sd = (factors.iter().map(|f| (f - mean).powi(2)).sum::<f64>() / 39.0).sqrt();
        assert!((0.1..0.3).contains(&sd), "{sd}");
        // Grids take their friction from the contact: no specimen factor.
        assert_eq!(Mounting::new(&p, 5, key).specimen_friction, 1.0);
    }

    #[test]
    fn mounting_is_shared_by_slides_and_jitter_is_bounded_by_the_repeatability() {
        let p = SimParams::default();
        let texture = Texture::grid(2.5).unwrap();
        let (_, surface) = texture.prepare(&p, 20.0);
        let mounting = Mounting::new(&p, 11, Mounting::texture_key(&texture.name()));
        assert_eq!(
            mounting,
            Mounting::new(&p, 11, Mounting::texture_key(&texture.name()))
        );
        assert_ne!(
            mounting,
            Mounting::new(&p, 12, Mounting::texture_key(&texture.name()))
        );
        let draws: Vec<TrialDraw> = (0..200)
            .map(|i| {
                let mut rng = ChaCha8Rng::seed_from_u64(i);
                TrialDraw::draw(&p, &surface, &mounting, i as usize, &mut rng)
            })
            .collect();
        let rp = p.kinematics.position_repeatability_mm;
        // Offsets within 5 repeatabilities of the mounting; depth and onset jitter bounded.
        assert!(
            draws
                .iter()
                .all(|d| (d.lateral_offset_mm - mounting.lateral_offset_mm).abs() < 5.0 * rp)
        );
        assert!(
            draws
                .iter()
                .all(|d| (d.start_phase_mm - mounting.start_phase_mm).abs() < 5.0 * rp)
        );
        assert!(
            draws
                .iter()
                .all(|d| (d.press_depth_mm - 2.0).abs() < 5.0 * p.kinematics.press_depth_sd_mm)
        );
        let nominal = Recording::nominal(&p).slide_start_s;
        assert!(draws.iter().all(|d| {
            (d.recording.slide_start_s - nominal).abs() < 5.0 * p.kinematics.loop_jitter_s
        }));
        // Friction: μ_s/μ_k fixed by the texture; the factor drifts slowly (neighbouring slides
        // differ far less than the drift's range).
        let ratio = surface.mu_static / surface.mu_kinetic;
        assert!(
            draws
                .iter()
                .all(|d| (d.mu_static / d.mu_kinetic - ratio).abs() < 1e-12)
        );
        let f: Vec<f64> = (0..200).map(|n| mounting.friction_factor(n)).collect();
        let step = f
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        let range =
            f.iter().copied().fold(f64::MIN, f64::max) - f.iter().copied().fold(f64::MAX, f64::min);
        assert!(step < 0.2 * range, "{step} vs {range}");
        // The switch restores independent per-slide offsets.
        let mut q = p;
        q.kinematics.per_slide_offsets = true;
        let spread: Vec<f64> = (0..50)
            .map(|i| {
                let mut rng = ChaCha8Rng::seed_from_u64(i);
                TrialDraw::draw(&q, &surface, &mounting, 0, &mut rng).lateral_offset_mm
            })
            .collect();
        let (lo, hi) = spread
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo > 3.0, "{lo} {hi}");
    }
}
