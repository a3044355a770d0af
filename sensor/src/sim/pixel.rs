//! Rendering and the DVS pixel model (spec §3.1–3.2), simulating only what the scene needs.
//!
//! **Rendering.** A pin is a bright disc on a dark background:
//! `I = I_bg + (I_pin − I_bg)·Σ_i S(‖p − c_i(t)‖)`, `S(ρ) = ½·erfc((ρ − r_d)/(√2·σ))`. The
//! spec's 3 × 3 supersampled pixel-area average is replaced by its closed-form equivalent: a
//! unit pixel box has variance 1/12, so σ² = w² + 1/12. S is tabulated against ρ².
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
//! **Noise.** Leak events are drawn as Poisson events at the per-pixel rate
//! `r_leak·10^(spread·N(0,1))` (drawn once per camera) rather than as a drift of L_ref: over a
//! 4.5 s trial a static pixel's drift yields at most one leak event, at the same mean rate.
//! Shot noise is Poisson at `r_shot`, half ON, half OFF. Hot pixels are not modelled.

use super::camera::Camera;
use super::params::SimParams;
use neurotac_core::special::erfc;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Label of noise events (see [`EventLabel`]).
pub const NOISE_LABEL: u8 = u8::MAX;

/// Ground truth of one pixel event: the pin whose motion caused it, or noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EventLabel(pub u8);

impl EventLabel {
    /// The noise label.
    pub const NOISE: EventLabel = EventLabel(NOISE_LABEL);

    /// `true` for a noise event.
    pub fn is_noise(self) -> bool {
        self.0 == NOISE_LABEL
    }

    /// The source pin of a signal event.
    pub fn pin(self) -> Option<usize> {
        (!self.is_noise()).then_some(self.0 as usize)
    }
}

/// One simulated event before sorting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct RawEvent {
    pub t_us: i64,
    pub y: u16,
    pub x: u16,
    pub on: bool,
    pub label: u8,
}

/// Lookup tables of the rendering and the photoreceptor.
#[derive(Debug, Clone)]
struct Tables {
    /// S against ρ², step `rho2_step`.
    coverage: Vec<f32>,
    rho2_inv_step: f32,
    /// L and 1/τ_p against total coverage S ∈ [0, 2].
    log_intensity: Vec<f32>,
    inv_tau: Vec<f32>,
    s_inv_step: f32,
    /// Largest |dL/dρ| of one pin (per px).
    max_slope: f32,
}

const COVERAGE_ENTRIES: usize = 4096;
const LOG_ENTRIES: usize = 2048;

impl Tables {
    fn new(params: &SimParams) -> Self {
        let o = &params.optics;
        let sigma = (o.edge_blur_px * o.edge_blur_px + 1.0 / 12.0).sqrt();
        let rho_max = o.pin_radius_px + 7.0 * sigma;
        let rho2_step = rho_max * rho_max / (COVERAGE_ENTRIES - 2) as f64;
        let s = |rho: f64| 0.5 * erfc((rho - o.pin_radius_px) / (std::f64::consts::SQRT_2 * sigma));
        let coverage: Vec<f32> = (0..COVERAGE_ENTRIES)
            .map(|i| {
                if i >= COVERAGE_ENTRIES - 2 {
                    0.0
                } else {
                    s((i as f64 * rho2_step).sqrt()) as f32
                }
            })
            .collect();
        let lin = |i: f64| {
            if i > o.linear_below_dn {
                i.ln()
            } else {
                i * o.linear_below_dn.ln() / o.linear_below_dn
            }
        };
        let intensity = |cov: f64| o.background_dn + (o.pin_dn - o.background_dn) * cov;
        let f_max = params.pixel.bandwidth_hz;
        let s_step = 2.0 / (LOG_ENTRIES - 1) as f64;
        let log_intensity = (0..LOG_ENTRIES)
            .map(|i| lin(intensity(i as f64 * s_step)) as f32)
            .collect();
        let inv_tau = (0..LOG_ENTRIES)
            .map(|i| {
                let rel = (intensity(i as f64 * s_step) / o.full_scale_dn).clamp(0.05, 1.0);
                (std::f64::consts::TAU * f_max * rel) as f32
            })
            .collect();
        // Steepest slope of L along ρ for one pin.
        let mut max_slope = 0.0f64;
        let n = 2000;
        for i in 0..n {
            let (r0, r1) = (
                rho_max * i as f64 / n as f64,
                rho_max * (i + 1) as f64 / n as f64,
            );
            let d = (lin(intensity(s(r1))) - lin(intensity(s(r0)))).abs() / (r1 - r0);
            max_slope = max_slope.max(d);
        }
        Self {
            coverage,
            rho2_inv_step: (1.0 / rho2_step) as f32,
            log_intensity,
            inv_tau,
            s_inv_step: (1.0 / s_step) as f32,
            max_slope: max_slope as f32,
        }
    }

    #[inline(always)]
    fn coverage(&self, rho2: f32) -> f32 {
        let x = (rho2 * self.rho2_inv_step).min((COVERAGE_ENTRIES - 2) as f32);
        let i = x as usize;
        let f = x - i as f32;
        let (a, b) = (self.coverage[i], self.coverage[i + 1]);
        a + f * (b - a)
    }

    #[inline(always)]
    fn log_and_rate(&self, cover: f32) -> (f32, f32) {
        let x = (cover * self.s_inv_step).min((LOG_ENTRIES - 2) as f32);
        let i = x as usize;
        let f = x - i as f32;
        let (l0, l1) = (self.log_intensity[i], self.log_intensity[i + 1]);
        let (r0, r1) = (self.inv_tau[i], self.inv_tau[i + 1]);
        (l0 + f * (l1 - l0), r0 + f * (r1 - r0))
    }
}

/// Which pixels are simulated and which pins render into them (fixed by the geometry).
#[derive(Debug, Clone)]
struct Patches {
    /// Pixel index range of each patch (patch = its owner pin).
    ranges: Vec<(usize, usize)>,
    /// Pins rendering into each patch (owner first).
    pins: Vec<Vec<usize>>,
    /// Per pixel: coordinates.
    x: Vec<u16>,
    y: Vec<u16>,
    /// Per pixel: offset from the owner pin's rest centre, and from the second pin's (or far
    /// away when there is none).
    own_dx: Vec<f32>,
    own_dy: Vec<f32>,
    other: Vec<u8>,
    other_dx: Vec<f32>,
    other_dy: Vec<f32>,
    /// Per image pixel: index into the patch arrays, or `u32::MAX`.
    index_of: Vec<u32>,
}

impl Patches {
    fn new(pins_px: &[(f64, f64)], radius: f64, width: u16, height: u16) -> Self {
        let n_pins = pins_px.len();
        let mut per_pin: Vec<Vec<(u16, u16, u8)>> = vec![Vec::new(); n_pins];
        for y in 0..height {
            for x in 0..width {
                let (mut best, mut second) = ((f64::INFINITY, 0usize), (f64::INFINITY, 0usize));
                for (i, &(cx, cy)) in pins_px.iter().enumerate() {
                    let d = ((x as f64 - cx).powi(2) + (y as f64 - cy).powi(2)).sqrt();
                    if d < best.0 {
                        second = best;
                        best = (d, i);
                    } else if d < second.0 {
                        second = (d, i);
                    }
                }
                if best.0 <= radius {
                    let other = if second.0 <= radius {
                        second.1 as u8
                    } else {
                        NOISE_LABEL
                    };
                    per_pin[best.1].push((x, y, other));
                }
            }
        }
        let mut p = Patches {
            ranges: Vec::with_capacity(n_pins),
            pins: Vec::with_capacity(n_pins),
            x: Vec::new(),
            y: Vec::new(),
            own_dx: Vec::new(),
            own_dy: Vec::new(),
            other: Vec::new(),
            other_dx: Vec::new(),
            other_dy: Vec::new(),
            index_of: vec![u32::MAX; width as usize * height as usize],
        };
        for (pin, pixels) in per_pin.iter().enumerate() {
            let start = p.x.len();
            let mut pins = vec![pin];
            let (cx, cy) = pins_px[pin];
            for &(x, y, other) in pixels {
                p.index_of[y as usize * width as usize + x as usize] = p.x.len() as u32;
                p.x.push(x);
                p.y.push(y);
                p.own_dx.push((x as f64 - cx) as f32);
                p.own_dy.push((y as f64 - cy) as f32);
                p.other.push(other);
                if other == NOISE_LABEL {
                    p.other_dx.push(1e4);
                    p.other_dy.push(1e4);
                } else {
                    let (ox, oy) = pins_px[other as usize];
                    p.other_dx.push((x as f64 - ox) as f32);
                    p.other_dy.push((y as f64 - oy) as f32);
                    if !pins.contains(&(other as usize)) {
                        pins.push(other as usize);
                    }
                }
            }
            p.ranges.push((start, p.x.len()));
            p.pins.push(pins);
        }
        p
    }
}

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
    // Pin displacements at the end of the current step.
    pin_dx: Vec<f32>,
    pin_dy: Vec<f32>,
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

/// e^(−x) for x ≥ 0 in f32, inlined (absolute error < 3·10⁻⁷; flushes to ≈ 2⁻¹²⁵ beyond
/// x ≈ 86): 2^(−x·log₂e) split into an exponent and a degree-6 polynomial of the fraction.
#[inline(always)]
fn exp_neg(x: f32) -> f32 {
    let y = (-x * std::f32::consts::LOG2_E).max(-125.0);
    let n = (y + 0.5).floor();
    let f = y - n;
    // 2^f on [−½, ½]: Taylor series of e^(f·ln 2), degree 6 (remainder < 1.3·10⁻⁷).
    let l = std::f32::consts::LN_2 * f;
    let p = 1.0
        + l * (1.0
            + l * (0.5
                + l * (1.0 / 6.0 + l * (1.0 / 24.0 + l * (1.0 / 120.0 + l * (1.0 / 720.0))))));
    p * f32::from_bits((((n as i32) + 127) as u32) << 23)
}

/// SplitMix64 finaliser: a well-mixed hash of a 64-bit value.
#[inline]
pub(crate) fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl PixelModel {
    /// Prepares patches around `pins_px` (rest positions, px), lookup tables and state for
    /// `camera`. Allocates; each run reuses everything.
    pub fn new(params: &SimParams, pins_px: &[(f64, f64)], camera: &Camera) -> Self {
        let patches = Patches::new(
            pins_px,
            params.optics.patch_radius_px,
            camera.width,
            camera.height,
        );
        let n = patches.x.len();
        let at = |v: &Vec<f32>| -> Vec<f32> {
            patches
                .x
                .iter()
                .zip(&patches.y)
                .map(|(&x, &y)| v[y as usize * camera.width as usize + x as usize])
                .collect()
        };
        Self {
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
            pin_dx: vec![0.0; pins_px.len()],
            pin_dy: vec![0.0; pins_px.len()],
        }
    }

    /// Pixels simulated in patches.
    pub fn patch_pixels(&self) -> usize {
        self.patches.x.len()
    }

    /// Draws the noise of every pixel over `[0, duration_s)`: events of background pixels go
    /// straight to `out`, those of patch pixels into the per-pixel queues.
    fn draw_noise(
        &mut self,
        camera: &Camera,
        duration_s: f64,
        rng: &mut ChaCha8Rng,
        out: &mut Vec<RawEvent>,
    ) {
        let shot = self.params.noise.shot_rate_hz;
        let t_ref = self.params.pixel.refractory_s;
        let width = camera.width as usize;
        self.noise_t.clear();
        self.noise_on.clear();
        let mut pending = std::mem::take(&mut self.pending_noise);
        let mut times = std::mem::take(&mut self.pixel_noise);
        pending.clear();
        for (pixel, &leak) in camera.leak_rate_hz.iter().enumerate() {
            let rate = leak as f64 + shot;
            if rate <= 0.0 {
                continue;
            }
            times.clear();
            let mut t = 0.0;
            loop {
                t += -(1.0 - rng.random::<f64>()).ln() / rate;
                if t >= duration_s {
                    break;
                }
                // ON for leak, or for half of the shot noise.
                let u = rng.random::<f64>() * rate;
                let on = u < leak as f64 + 0.5 * shot;
                // Whole µs; a pixel in reset after its previous event cannot fire.
                let t = (t * 1e6).round() / 1e6;
                if times
                    .last()
                    .is_none_or(|&(last, _)| t - last >= t_ref - 1e-9)
                {
                    times.push((t, on));
                }
            }
            if times.is_empty() {
                continue;
            }
            let patch_index = self.patches.index_of[pixel];
            if patch_index == u32::MAX {
                let (x, y) = ((pixel % width) as u16, (pixel / width) as u16);
                out.extend(times.iter().map(|&(t, on)| RawEvent {
                    t_us: (t * 1e6).round() as i64,
                    y,
                    x,
                    on,
                    label: NOISE_LABEL,
                }));
            } else {
                pending.extend(times.iter().map(|&(t, on)| (patch_index as usize, t, on)));
            }
        }
        // CSR by patch pixel (pending is in image order, so sort by patch index, stable in time).
        pending.sort_by_key(|&(j, _, _)| j);
        self.noise_offsets.fill(0);
        for &(j, _, _) in &pending {
            self.noise_offsets[j + 1] += 1;
        }
        for j in 0..self.noise_offsets.len() - 1 {
            self.noise_offsets[j + 1] += self.noise_offsets[j];
        }
        for &(_, t, on) in &pending {
            self.noise_t.push(t);
            self.noise_on.push(on);
        }
        self.pending_noise = pending;
        self.pixel_noise = times;
        for j in 0..self.next_noise.len() {
            let start = self.noise_offsets[j];
            self.noise_cursor[j] = start;
            self.next_noise[j] = if start < self.noise_offsets[j + 1] {
                self.noise_t[start as usize]
            } else {
                f64::INFINITY
            };
        }
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
            self.init_patch(patch);
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

    fn update_pins(&mut self, patch: usize, motion: &impl PinMotion, t: f64) {
        for &pin in &self.patches.pins[patch] {
            let (dx, dy) = motion.displacement(pin, t);
            self.pin_dx[pin] = dx;
            self.pin_dy[pin] = dy;
        }
    }

    #[inline(always)]
    fn render(&self, j: usize, own: usize) -> (f32, f32) {
        let p = &self.patches;
        let (ex, ey) = (
            p.own_dx[j] - self.pin_dx[own],
            p.own_dy[j] - self.pin_dy[own],
        );
        let mut cover = self.tables.coverage(ex * ex + ey * ey);
        let other = p.other[j];
        if other != NOISE_LABEL {
            let o = other as usize;
            let (fx, fy) = (
                p.other_dx[j] - self.pin_dx[o],
                p.other_dy[j] - self.pin_dy[o],
            );
            cover += self.tables.coverage(fx * fx + fy * fy);
        }
        self.tables.log_and_rate(cover)
    }

    fn init_patch(&mut self, patch: usize) {
        let (start, end) = self.patches.ranges[patch];
        for j in start..end {
            let (l, rate) = self.render(j, patch);
            self.l_in[j] = l;
            self.l_filt[j] = l;
            self.l_ref[j] = l;
            self.rate_old[j] = rate;
            self.reset_until[j] = f64::NEG_INFINITY;
            self.last_out_us[j] = i64::MIN;
            self.n_events[j] = 0;
        }
    }

    fn patch_owner(&self, j: usize) -> usize {
        self.patches.ranges.partition_point(|&(_, end)| end <= j)
    }

    /// One step of the pixels of `patch` (= its owner pin) from `t0` to `t1`; returns the largest filter rate
    /// |L − L̃|/τ_p at `t1`.
    fn step(&mut self, patch: usize, t0: f64, t1: f64, seed: u64, out: &mut Vec<RawEvent>) -> f32 {
        let (start, end) = self.patches.ranges[patch];
        let dt = (t1 - t0) as f32;
        let mut max_rate = 0.0f32;
        for j in start..end {
            let (l_new, rate) = self.render(j, patch);
            let l_old = self.l_in[j];
            let f_old = self.l_filt[j];
            let x = dt * 0.5 * (rate + self.rate_old[j]);
            let a = exp_neg(x);
            // g = (1 − e^(−x))/x; its series below x = 0.1 (both computed: a select, not a
            // branch, which mispredicts on mixed bright and dark pixels).
            let series = 1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0)));
            let direct = (1.0 - a) / x.max(0.1);
            let g = if x > 0.1 { direct } else { series };
            // Exact first-order response to an input ramping from l_old to l_new.
            let f_new = l_new - (l_new - l_old) * g + (f_old - l_old) * a;
            max_rate = max_rate.max((l_new - f_new).abs() * rate);
            let r = self.l_ref[j];
            if f_new - r >= self.c_on[j]
                || r - f_new >= self.c_off[j]
                || self.reset_until[j] > t0
                || self.next_noise[j] < t1
            {
                self.events(j, t0, t1, f_old, f_new, seed, out);
            }
            self.l_in[j] = l_new;
            self.l_filt[j] = f_new;
            self.rate_old[j] = rate;
        }
        max_rate
    }

    /// The slow path of one pixel over one step: threshold crossings, refractory resets and
    /// noise events, in time order. L̃ is linear from `f0` at `t0` to `f1` at `t1`.
    #[allow(clippy::too_many_arguments)]
    #[cold]
    fn events(
        &mut self,
        j: usize,
        t0: f64,
        t1: f64,
        f0: f32,
        f1: f32,
        seed: u64,
        out: &mut Vec<RawEvent>,
    ) {
        let t_ref = self.params.pixel.refractory_s;
        let dt = t1 - t0;
        let slope = (f1 - f0) as f64 / dt;
        let at = |t: f64| (f0 as f64 + slope * (t - t0)) as f32;
        let mut ta = t0;
        loop {
            if self.reset_until[j] > ta {
                // Held in reset: no events, noise included.
                let until = self.reset_until[j];
                while self.next_noise[j] < until.min(t1) {
                    self.advance_noise(j);
                }
                if until >= t1 {
                    self.l_ref[j] = f1;
                    return;
                }
                ta = until;
                self.l_ref[j] = at(ta);
                self.reset_until[j] = f64::NEG_INFINITY;
            }
            let tn = self.next_noise[j];
            let tb = tn.min(t1);
            let r = self.l_ref[j];
            let fb = at(tb);
            let crossing = if fb - r >= self.c_on[j] && slope > 0.0 {
                Some((true, r + self.c_on[j]))
            } else if r - fb >= self.c_off[j] && slope < 0.0 {
                Some((false, r - self.c_off[j]))
            } else {
                None
            };
            if let Some((on, level)) = crossing {
                let te = (t0 + (level - f0) as f64 / slope).clamp(ta, tb);
                let t_out = self.emit(j, te, on, seed, out);
                self.l_ref[j] = level;
                self.hold_reset(j, t_out, t_ref);
                ta = te;
                continue;
            }
            if tn < t1 {
                let idx = self.noise_cursor[j] as usize;
                let on = self.noise_on[idx];
                let t_out = self.push(j, tn, on, NOISE_LABEL, out);
                self.n_events[j] += 1;
                self.advance_noise(j);
                self.l_ref[j] = at(tn);
                self.hold_reset(j, t_out, t_ref);
                ta = tn;
                continue;
            }
            return;
        }
    }

    /// Holds pixel `j` in reset until `t_ref` after its event's readout at `t_out`.
    fn hold_reset(&mut self, j: usize, t_out: f64, t_ref: f64) {
        self.reset_until[j] = if t_ref > 0.0 {
            t_out + t_ref
        } else {
            f64::NEG_INFINITY
        };
    }

    fn advance_noise(&mut self, j: usize) {
        let c = self.noise_cursor[j] + 1;
        self.noise_cursor[j] = c;
        self.next_noise[j] = if c < self.noise_offsets[j + 1] {
            self.noise_t[c as usize]
        } else {
            f64::INFINITY
        };
    }

    /// Emits a signal event crossing at `te`; returns its output time (s).
    fn emit(&mut self, j: usize, te: f64, on: bool, seed: u64, out: &mut Vec<RawEvent>) -> f64 {
        let p = &self.params.pixel;
        let k = self.n_events[j];
        self.n_events[j] = k + 1;
        let h = mix64(seed ^ mix64(((j as u64) << 32) | k as u64));
        let u = ((h >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        let t = te + p.latency_s - p.latency_jitter_s * u.ln();
        let owner = self.patch_owner(j) as u8;
        let label = self.signal_source(j, owner);
        self.push(j, t, on, label, out)
    }

    /// The pin an event of pixel `j` is attributed to: the one contributing more light now.
    fn signal_source(&self, j: usize, owner: u8) -> u8 {
        let p = &self.patches;
        let other = p.other[j];
        if other == NOISE_LABEL {
            return owner;
        }
        let (o, w) = (other as usize, owner as usize);
        let d_own = (p.own_dx[j] - self.pin_dx[w]).powi(2) + (p.own_dy[j] - self.pin_dy[w]).powi(2);
        let d_other =
            (p.other_dx[j] - self.pin_dx[o]).powi(2) + (p.other_dy[j] - self.pin_dy[o]).powi(2);
        if d_other < d_own { other } else { owner }
    }

    /// Outputs an event of pixel `j` at `t` (whole µs, after the pixel's previous event);
    /// returns the output time (s).
    fn push(&mut self, j: usize, t: f64, on: bool, label: u8, out: &mut Vec<RawEvent>) -> f64 {
        let t_us = ((t * 1e6).round() as i64).max(self.last_out_us[j].saturating_add(1));
        self.last_out_us[j] = t_us;
        out.push(RawEvent {
            t_us,
            y: self.patches.y[j],
            x: self.patches.x[j],
            on,
            label,
        });
        t_us as f64 / 1e6
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_exponential_matches_the_library() {
        for i in 0..20_000 {
            let x = i as f32 * 0.005;
            let (a, b) = (exp_neg(x), (-x).exp());
            // Absolute error (what the low-pass sees) and relative error (f32 rounding of
            // x·log₂e grows with x).
            assert!((a - b).abs() <= 3e-7, "{x}: {a} vs {b}");
            assert!(x > 80.0 || (a - b).abs() <= 1e-5 * b, "{x}: {a} vs {b}");
        }
        assert!(exp_neg(1e6) < 1e-37);
    }
}
