//! Rendering, the DVS pixel model and pixel noise (spec §3.1–3.2), simulating only what the
//! scene needs. One file per concept:
//!
//! | concept | file | what it holds |
//! |---|---|---|
//! | a simulated event and its label | `event.rs` | [`EventLabel`], [`NOISE_LABEL`], the unsorted event |
//! | rendering (§3.1) | `render.rs` | pin discs → log intensity, lookup tables, pixel patches |
//! | DVS pixel (§3.2) | `dvs.rs` | photoreceptor low-pass, threshold crossings, refractory reset, output timing |
//! | noise (§3.2) | `noise.rs` | leak and shot noise, drawn per pixel as Poisson events |
//! | orchestration | here | [`PixelModel`], adaptive patch steps |
//!
//!
//! **Rendering** (pin discs, the closed-form pixel-area average, lookup tables): `render.rs`.
//!
//! **Patches.** Only pixels within `patch_radius_px` of a pin's rest position are simulated;
//! each belongs to its nearest pin and also sees the second-nearest one when that is within
//! the radius too (neighbouring pins are ≈ 15 px apart). Every other pixel is static
//! background: it only produces noise, drawn directly as Poisson events.
//!
//! **Pixel state** (structure of arrays): input log intensity L, filtered L̃, reference L_ref,
//! thresholds C⁺_p / C⁻_p (fixed-pattern noise from [`Camera`]), end of the refractory reset,
//! next noise time. Per step `[t₀, t₁]` of a patch:
//! 1. log conversion: `L = ln I` above I_lin, `I·ln(I_lin)/I_lin` below (v2e lin-log);
//! 2. photoreceptor low-pass `dL̃/dt = (L − L̃)/τ_p`, `τ_p = 1/(2π·f_max·clamp(I/I_max, 0.05, 1))`,
//!    integrated exactly for an input ramping linearly from L(t₀) to L(t₁) (so no ε ≤ 0.3 limit);
//! 3. events where L̃ — linear between the step's ends, as in ESIM — crosses `L_ref + C⁺_p` (ON)
//!    or `L_ref − C⁻_p` (OFF), at the interpolated crossing time;
//! 4. refractory, hardware variant: after an event crossing at t_e the pixel is held in reset
//!    (no events; L_ref follows L̃) until `t_ref` after the event's readout (step 6), then
//!    `L_ref = L̃` there — so output events of a pixel are always ≥ t_ref apart;
//! 5. noise events of the pixel (leak ON, shot ON/OFF) at their drawn times reset it the same
//!    way (v2e: L_ref ← L̃); one falling inside a reset is not emitted;
//! 6. output time `t_e + latency + Exp(jitter)` in whole µs, never earlier than the pixel's
//!    previous event + 1 µs (per-pixel order kept). The jitter is a hash of (trial, pixel,
//!    event index), so it does not depend on the step size.
//!
//! **Adaptive steps.** A patch takes the longest step such that no pin that renders into it
//! travels more than `tol / max|dL/dρ|` px, the low-pass moves L̃ by at most `tol`
//! (`Δt ≤ tol / max_p |L − L̃|/τ_p`), and `Δt ≤ max_step_s`. A patch whose pins rest and whose
//! filter has settled therefore takes `max_step_s` steps — it is not simulated in between.
//!
//! **Noise** (leak and shot noise as Poisson events): `noise.rs`.
//!
//! **Why slow pins give isolated events.** A pin edge moving fast (onset snap, hundreds of px/s)
//! fires its edge pixels within a fraction of a millisecond, so the 8-neighbour, 5 ms BA filter
//! keeps them. A pin drifting a few px/s changes an edge pixel's log intensity by only ≈ |∂L/∂x|·v
//! ≈ 0.7 px⁻¹ × 5 px/s ≈ 3.5 s⁻¹, so each crossing of C ≈ 0.2 takes ≈ 60 ms and neighbouring pixels
//! cross at times that differ by the threshold mismatch: σ_C/(|∂L/∂x|·v) ≈ 0.03/3.5 s⁻¹ ≈ 9 ms —
//! more than the BA window. Isolated events are therefore physical for slow sub-pixel motion: the
//! per-pixel threshold mismatch is a property of the sensor (σ_C = 0.03 in v2e; 2.1 % contrast
//! mismatch measured on the DVS128, Lichtsteiner et al., JSSC 2008), not a rendering artefact, and
//! the rendering is kept. `neurotac simulate check` reports the share of signal events the filter
//! keeps per grid (≈ 78 % on the flat plate and fine grids, ≈ 45 % on coarse grids, where the
//! steady motion is slow).

mod dvs;
mod event;
mod noise;
mod render;

pub(crate) use event::RawEvent;
pub use event::{EventLabel, NOISE_LABEL};

use super::camera::Camera;
use super::error::SimulationError;
use super::params::SimParams;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use render::{PIN_SLOTS, Patches, PinSlots, Tables, render_pixel};

/// Statistics of one run of the pixel model.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelRunStats {
    /// Patch steps taken (all patches).
    pub patch_steps: u64,
    /// Pixel updates (patch steps × pixels).
    pub pixel_steps: u64,
    /// Simulated pixels (in patches).
    pub patch_pixels: usize,
}

/// The pixel model with its prepared tables, patches and state (allocated once by
/// [`PixelModel::new`]; a run reuses every buffer).
#[derive(Debug, Clone)]
pub struct PixelModel {
    params: SimParams,
    tables: Tables,
    patches: Patches,
    // Per patch pixel: camera constants…
    c_on: Vec<f32>,
    c_off: Vec<f32>,
    // … and state.
    l_in: Vec<f32>,
    l_filt: Vec<f32>,
    l_ref: Vec<f32>,
    rate_old: Vec<f32>,
    reset_until: Vec<f64>,
    last_out_us: Vec<i64>,
    n_events: Vec<u32>,
    // Noise of patch pixels: CSR by pixel, with a cursor.
    noise_offsets: Vec<u32>,
    noise_t: Vec<f64>,
    noise_on: Vec<bool>,
    noise_cursor: Vec<u32>,
    next_noise: Vec<f64>,
    // Scratch of the noise draw: (patch pixel, time, ON) and one pixel's events.
    pending_noise: Vec<(usize, f64, bool)>,
    pixel_noise: Vec<(f64, bool)>,
    // Scratch of one patch step (sized for the largest patch): each pixel's L̃ at the step's
    // start, its filter rate |L − L̃|/τ_p at the end, and whether it takes the slow path.
    f_start: Vec<f32>,
    filter_rate: Vec<f32>,
    slow: Vec<bool>,
    // Pin displacements at the end of the current step, one slot per `u8` pin index.
    pin_dx: Box<PinSlots>,
    pin_dy: Box<PinSlots>,
}

/// The pins' image displacements over time (px), as seen by the pixel model.
pub trait PinMotion {
    /// Number of pins.
    fn n_pins(&self) -> usize;
    /// Displacement of `pin` at `t_s`.
    fn displacement(&self, pin: usize, t_s: f64) -> (f32, f32);
    /// The earliest time after `t_s` at which `pin` has moved `distance_px` farther along its
    /// path, or `limit_s` if that is later.
    fn time_to_travel(&self, pin: usize, t_s: f64, distance_px: f32, limit_s: f64) -> f64;
}

impl PinMotion for super::mechanics::PinTrajectories {
    fn n_pins(&self) -> usize {
        self.n_pins
    }
    fn displacement(&self, pin: usize, t_s: f64) -> (f32, f32) {
        super::mechanics::PinTrajectories::displacement(self, pin, t_s)
    }
    fn time_to_travel(&self, pin: usize, t_s: f64, distance_px: f32, limit_s: f64) -> f64 {
        super::mechanics::PinTrajectories::time_to_travel(self, pin, t_s, distance_px, limit_s)
    }
}

impl PixelModel {
    /// Prepares patches around `pins_px` (rest positions, px), lookup tables and state for
    /// `camera`. Allocates; each run reuses everything. At most 254 pins (a pin index is a
    /// `u8` label, [`NOISE_LABEL`] excluded): more is [`SimulationError::Geometry`].
    pub fn new(
        params: &SimParams,
        pins_px: &[(f64, f64)],
        camera: &Camera,
    ) -> Result<Self, SimulationError> {
        if pins_px.len() >= NOISE_LABEL as usize {
            return Err(SimulationError::Geometry {
                pins: pins_px.len(),
            });
        }
        let patches = Patches::new(
            pins_px,
            params.optics.patch_radius_px,
            camera.width,
            camera.height,
        );
        let n = patches.x.len();
        let largest = patches
            .ranges
            .iter()
            .map(|&(s, e)| e - s)
            .max()
            .unwrap_or(0);
        let at = |v: &Vec<f32>| -> Vec<f32> {
            patches
                .x
                .iter()
                .zip(&patches.y)
                .map(|(&x, &y)| v[y as usize * camera.width as usize + x as usize])
                .collect()
        };
        Ok(Self {
            params: *params,
            tables: Tables::new(params),
            c_on: at(&camera.threshold_on),
            c_off: at(&camera.threshold_off),
            patches,
            l_in: vec![0.0; n],
            l_filt: vec![0.0; n],
            l_ref: vec![0.0; n],
            rate_old: vec![0.0; n],
            reset_until: vec![f64::NEG_INFINITY; n],
            last_out_us: vec![i64::MIN; n],
            n_events: vec![0; n],
            noise_offsets: vec![0; n + 1],
            noise_t: Vec::new(),
            noise_on: Vec::new(),
            noise_cursor: vec![0; n],
            next_noise: vec![f64::INFINITY; n],
            pending_noise: Vec::new(),
            pixel_noise: Vec::new(),
            f_start: vec![0.0; largest],
            filter_rate: vec![0.0; largest],
            slow: vec![false; largest],
            pin_dx: Box::new([0.0; PIN_SLOTS]),
            pin_dy: Box::new([0.0; PIN_SLOTS]),
        })
    }

    /// Pixels simulated in patches.
    pub fn patch_pixels(&self) -> usize {
        self.patches.x.len()
    }

    /// Simulates every pixel over `[0, duration_s)` for pins moving as `motion`, appending
    /// events to `out`. `seed` drives the noise and the latency jitter.
    pub(crate) fn run(
        &mut self,
        camera: &Camera,
        motion: &impl PinMotion,
        duration_s: f64,
        seed: u64,
        with_noise: bool,
        out: &mut Vec<RawEvent>,
    ) -> PixelRunStats {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        if with_noise {
            self.draw_noise(camera, duration_s, &mut rng, out);
        } else {
            self.noise_offsets.fill(0);
            self.noise_t.clear();
            self.noise_on.clear();
            self.next_noise.fill(f64::INFINITY);
        }
        let tol = self.params.solver.step_tolerance as f32;
        let max_step = self.params.solver.max_step_s;
        let travel = tol / self.tables.max_slope;
        let mut stats = PixelRunStats {
            patch_pixels: self.patches.x.len(),
            ..Default::default()
        };
        for patch in 0..self.patches.ranges.len() {
            let (start, end) = self.patches.ranges[patch];
            if start == end {
                continue;
            }
            self.update_pins(patch, motion, 0.0);
            self.init_patch(patch, seed);
            let mut t = 0.0;
            let mut max_rate = 0.0f32;
            while t < duration_s {
                let mut t1 = (t + max_step).min(duration_s);
                if max_rate > 0.0 {
                    t1 = t1.min(t + (tol / max_rate) as f64);
                }
                for &pin in &self.patches.pins[patch] {
                    t1 = motion.time_to_travel(pin, t, travel, t1);
                }
                let t1 = t1.max(t + 1e-6).min(duration_s);
                self.update_pins(patch, motion, t1);
                max_rate = self.step(patch, t, t1, seed, out);
                stats.patch_steps += 1;
                stats.pixel_steps += (end - start) as u64;
                t = t1;
            }
        }
        stats
    }

    /// Log intensity and photoreceptor rate of patch pixel `j` of pin `own`'s patch, for the
    /// pins at their current displacements ([`render_pixel`]).
    #[inline(always)]
    pub(super) fn render(&self, j: usize, own: usize) -> (f32, f32) {
        render_pixel(
            &self.tables,
            &self.patches,
            (&*self.pin_dx, &*self.pin_dy),
            j,
            own,
        )
    }

    fn update_pins(&mut self, patch: usize, motion: &impl PinMotion, t: f64) {
        for &pin in &self.patches.pins[patch] {
            let (dx, dy) = motion.displacement(pin, t);
            self.pin_dx[pin] = dx;
            self.pin_dy[pin] = dy;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn more_pins_than_labels_is_a_geometry_error() {
        let params = SimParams::default();
        let camera = Camera::new(&params, 1);
        let pins: Vec<(f64, f64)> = (0..255).map(|i| (i as f64 % 240.0, 90.0)).collect();
        let err = PixelModel::new(&params, &pins, &camera).unwrap_err();
        assert!(
            matches!(err, SimulationError::Geometry { pins: 255 }),
            "{err}"
        );
        assert!(PixelModel::new(&params, &pins[..254], &camera).is_ok());
    }
}
