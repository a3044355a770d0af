//! Contact mechanics of one recording: the press, stick-slip shear and the 49 pin-tip
//! displacements in the image (spec §2.1, §2.2 steps 4–6).
//!
//! **Timeline** ([`super::kinematics::Recording`]): the loop's latencies, the press (the arm moves
//! `press_travel_mm` down at the linear speed), the dwell, the slide (`distance_mm` with a
//! trapezoidal speed profile), the end of logging.
//!
//! **Press** ([`super::layer`]): position control gives each slide its overlap δ, force N,
//! contact radius a and the share of the base's travel that shears the skin. The dome touches
//! the specimen once the press has covered `travel − δ`; from there the contact grows as
//! `a(t) = a·√(overlap(t)/δ)`, and every pin it covers splays radially as the skin flattens by
//! the dome's share of the overlap: `u = −G_lever·(r/R)·(δ_d/δ)·χ(r; a(t))·r̂` (spec §7's
//! indentation burst).
//!
//! **Shear** (lumped spring-slider, state: shear s, slip velocity v_p, stuck flag), integrated at
//! `shear_dt_s` from the slide's start:
//! - stick: `ds/dt = share·v_b` until `s ≥ s_s = μ_s·N/k_t` — slower while a fabric is dragged on
//!   its mounting, and with a drop when the fabric ahead wrinkles ([`super::fabric`]);
//! - slip: `ds/dt = share·v_b − v_p`, where v_p follows `(s − S(v_p))/τ` with lag
//!   `slip_inertia_s`, `S(v) = μ(v)·N/k_t`, `μ(v) = μ_k + (μ_s − μ_k)·e^(−|v|/v_c)` with velocity
//!   weakening, else μ_k; re-stick when v_p reaches 0. Without weakening the steady slip is
//!   `s → s_k + τ·v`; at the stop s recoils to s_k within about τ (the offset burst).
//! - micro-slips (natural textures): Poisson at rate `λ_ms·v_p/(15 mm/s)` while slipping, each
//!   releasing δ ~ U(δ_min, δ_max) that reloads with time constant τ_ms; on a grid, a catch each
//!   time a row of bumps passes, its slip scaled by how deep the skin sinks into the gaps.
//! - friction: the texture's μ_s, μ_k ([`Surface`], from its contact) times one factor per
//!   slide, shared by μ_s and μ_k so their ratio (the snap) is a texture property
//!   ([`super::mounting`]).
//!
//! **Local traction (pin-scale tangential channel).** Each pin also sees the traction under
//! itself, not averaged over the patch: `δu_i = g_pin·χ_i·τ̃(X_i)/κ`, the local traction
//! fluctuation of the texture field (μ_k·p through the elastic layer, [`super::texture`]) over
//! the skin's shear stiffness per area κ = G_skin/t_skin. It changes at v/p as bump edges pass
//! under the pin.
//!
//! **Onset front** ([`super::slip_front`]): before the first full slip each pin feels its own
//! shear s_i — the base's travel while its footprint sticks, a twitch back when the partial-slip
//! front reaches it — and after it the lumped s.
//!
//! **Pins** (sensor plane, mm; χ(r) the contact weight `contact_weight` below, φ_i the pin's
//! displacement per unit shear through the gel, stuck or sliding, [`super::shear_spread`]):
//! `u_i = G_lever·∇w(x_i) + g_pin·φ_i·(s_i + micro) + g_pin·χ_i·τ̃/κ·x̂ + β·w(x_i)·r̂_i + splay`,
//! with `w = χ·w₀(X, Y)` sampled at the world point under the pin. The world point follows the
//! contact patch, not the base: `X = x + x_b − s + x_phase`, `Y = y + y₀` — while the skin
//! sticks, the texture does not move under it (a refinement of the spec's `X = x + x_b`).
//! Image displacement = k·u_i (px). The lift after the slide is outside the recording
//! ([`super::kinematics`]).

use super::fabric::FabricDrag;
use super::layer::Press;
use super::mounting::TrialDraw;
use super::params::SimParams;
use super::shear_spread::{ShearSpread, SpreadContact};
use super::slip_front::{ContactState, PinShear, SlipFront};
use super::texture::{Surface, TextureField};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Pin-tip positions over a trial, sampled every `dt_s`, as image displacements from rest
/// (px), one contiguous series per pin; plus the cumulative path length of each pin (px).
#[derive(Debug, Clone, Default)]
pub struct PinTrajectories {
    /// Sampling interval (s).
    pub dt_s: f64,
    /// Samples per pin.
    pub n_samples: usize,
    /// Pins.
    pub n_pins: usize,
    /// x displacement (px), `[pin · n_samples + k]`.
    pub dx_px: Vec<f32>,
    /// y displacement (px).
    pub dy_px: Vec<f32>,
    /// Cumulative path length (px).
    pub arc_px: Vec<f32>,
    /// Shear seen by the pins at each sample (mm), for diagnostics.
    pub shear_mm: Vec<f32>,
    /// Whether each pin is in contact (χ(r) > 0.5).
    pub in_contact: Vec<bool>,
    /// Per pin: the fraction of the full-slip load at which the partial-slip front reaches it
    /// ([`super::slip_front`]); `None` for a pin with no contact under it or without the front.
    pub slip_front: Vec<Option<f64>>,
    /// Stick limit s_s = μ_s·N/k_t of this slide (mm).
    pub stick_limit_mm: f64,
    /// Time of the first full slip (s from the recording start), if it happened.
    pub full_slip_s: Option<f64>,
    /// The press of this slide.
    pub press: Option<Press>,
    /// How the slide's load reached the pins and what the specimen did at the onset.
    pub contact: ContactFacts,
}

/// How a slide's tangential load reached the pins, and what a fabric specimen did at its
/// onset ([`super::shear_spread`], [`super::fabric`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactFacts {
    /// Forward shift ε of the sliding pressure (0 on a rigid texture).
    pub forward_shift: f64,
    /// Pile hairs beyond the contact: their reach (mm) and their share of the load.
    pub pile: Option<(f64, f64)>,
    /// How far the fabric had been dragged when the skin first slipped (mm; `None`: no fabric).
    pub fabric_drag_mm: Option<f64>,
    /// When the fabric ahead of the contact wrinkled (s from the recording start).
    pub wrinkle_s: Option<f64>,
}

impl PinTrajectories {
    /// Displacement of `pin` at time `t_s` (linear between samples).
    #[inline]
    pub fn displacement(&self, pin: usize, t_s: f64) -> (f32, f32) {
        let (k, f) = self.locate(t_s);
        let base = pin * self.n_samples + k;
        let (x0, y0) = (self.dx_px[base], self.dy_px[base]);
        if f == 0.0 {
            return (x0, y0);
        }
        (
            x0 + f * (self.dx_px[base + 1] - x0),
            y0 + f * (self.dy_px[base + 1] - y0),
        )
    }

    /// Path length of `pin` up to `t_s` (px).
    #[inline]
    pub fn arc(&self, pin: usize, t_s: f64) -> f32 {
        let (k, f) = self.locate(t_s);
        let base = pin * self.n_samples + k;
        let a = self.arc_px[base];
        if f == 0.0 {
            a
        } else {
            a + f * (self.arc_px[base + 1] - a)
        }
    }

    /// The earliest time after `t_s` at which `pin` has travelled `distance_px` more, if before
    /// `limit_s`.
    ///
    /// The first sample after `t_s` that reaches the target distance, lies at or after
    /// `limit_s`, or is past the end: a monotone predicate of the sample index (the path length
    /// never decreases), found by a galloping search — a pin at rest is not scanned sample by
    /// sample up to the limit.
    pub fn time_to_travel(&self, pin: usize, t_s: f64, distance_px: f32, limit_s: f64) -> f64 {
        let target = self.arc(pin, t_s) + distance_px;
        let series = &self.arc_px[pin * self.n_samples..(pin + 1) * self.n_samples];
        let (k0, _) = self.locate(t_s);
        let last = self.n_samples - 1;
        let stops = |k: usize| k > last || k as f64 * self.dt_s >= limit_s || series[k] >= target;
        // Gallop: the predicate is false at `lo` (or lo = k0) and true at `hi`.
        let (mut lo, mut hi, mut stride) = (k0, k0 + 1, 1);
        while !stops(hi) {
            lo = hi;
            stride *= 2;
            hi = (hi + stride).min(last + 1);
        }
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if stops(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let k = hi;
        if k > last || k as f64 * self.dt_s >= limit_s {
            return limit_s;
        }
        let (a0, a1) = (series[k - 1], series[k]);
        let f = ((target - a0) / (a1 - a0)).clamp(0.0, 1.0) as f64;
        ((k - 1) as f64 + f) * self.dt_s
    }

    /// Fills the cumulative path lengths from the displacements: the step lengths of each pin
    /// first (independent, so they vectorise), then their running sum in sample order.
    fn accumulate_arcs(&mut self) {
        let n = self.n_samples;
        if n == 0 {
            return;
        }
        for ((arc, dx), dy) in self
            .arc_px
            .chunks_exact_mut(n)
            .zip(self.dx_px.chunks_exact(n))
            .zip(self.dy_px.chunks_exact(n))
        {
            arc[0] = 0.0;
            for (a, (x, y)) in arc[1..].iter_mut().zip(dx.windows(2).zip(dy.windows(2))) {
                let (ddx, ddy) = (x[1] - x[0], y[1] - y[0]);
                *a = (ddx * ddx + ddy * ddy).sqrt();
            }
            for k in 1..n {
                arc[k] += arc[k - 1];
            }
        }
    }

    #[inline]
    fn locate(&self, t_s: f64) -> (usize, f32) {
        let x = (t_s / self.dt_s).max(0.0);
        let k = x as usize;
        if k + 1 >= self.n_samples {
            (self.n_samples - 1, 0.0)
        } else {
            (k, (x - k as f64) as f32)
        }
    }

    /// Per pin, when the slip front released it between `from_s` (the motion start) and
    /// `to_s` (the full slip): the first sample at which the pin moves along the slide at less
    /// than half the rate it moved at while all of its footprint stuck (its displacement per
    /// unit of lumped shear over 2 ms, the largest over the first 10 ms of motion, before the
    /// weakest part of a contact lets go). `to_s` if it never slows so much before.
    pub fn release_times(&self, from_s: f64, to_s: f64) -> Vec<f64> {
        let last = self.n_samples.saturating_sub(1);
        let lo = ((from_s / self.dt_s).max(0.0) as usize).min(last);
        let hi = ((to_s / self.dt_s).max(0.0) as usize).min(last);
        let early = lo + ((0.01 / self.dt_s) as usize).max(2);
        // Over 2 ms steps: per-sample differences of a slow start are rounding.
        let step = ((0.002 / self.dt_s) as usize).max(1);
        (0..self.n_pins)
            .map(|pin| {
                let series = &self.dx_px[pin * self.n_samples..(pin + 1) * self.n_samples];
                let rate = |k: usize| {
                    let j = (k + step).min(last);
                    let ds = (self.shear_mm[j] - self.shear_mm[k]) as f64;
                    (ds > 1e-4).then(|| (series[j] - series[k]) as f64 / ds)
                };
                let stuck_rate = (lo..early.min(hi))
                    .filter_map(rate)
                    .fold(0.0f64, |m, r| m.max(r.abs()));
                (lo..hi)
                    .find(|&k| {
                        stuck_rate > 0.0 && rate(k).is_some_and(|r| r.abs() < 0.5 * stuck_rate)
                    })
                    .unwrap_or(hi) as f64
                    * self.dt_s
            })
            .collect()
    }

    /// Largest displacement of any pin from rest (px).
    pub fn max_displacement_px(&self) -> f64 {
        self.dx_px
            .iter()
            .zip(&self.dy_px)
            .map(|(x, y)| (x * x + y * y).sqrt() as f64)
            .fold(0.0, f64::max)
    }
}

/// Per-trial constants of one pin: position, distance from the apex, radial unit vector,
/// contact weight χ and its derivative χ' (at the final contact radius).
#[derive(Debug, Clone, Copy)]
struct PinConstants {
    x: f64,
    y: f64,
    r: f64,
    rx: f64,
    ry: f64,
    chi: f64,
    dchi: f64,
}

/// The contact weight χ of a point at distance `r` from the apex under a contact of radius
/// `a` with an edge of width `w`, and its derivative dχ/dr: a smooth indicator of |r| < a,
/// `χ = σ((a − r)/w) − σ((−a − r)/w)` with σ the logistic function — 0 everywhere without
/// contact (a = 0), the logistic edge `1/(1 + e^((r − a)/w))` once a ≫ w.
#[inline]
fn contact_weight(r: f64, a: f64, w: f64) -> (f64, f64) {
    let sigma = |x: f64| 1.0 / (1.0 + (-x).exp());
    let (near, far) = (sigma((a - r) / w), sigma((-a - r) / w));
    (near - far, (-near * (1.0 - near) + far * (1.0 - far)) / w)
}

/// Reusable buffers and pin geometry for computing trajectories (allocated once).
#[derive(Debug, Clone)]
pub struct Mechanics {
    pins_mm: Vec<(f64, f64)>,
    pin_constants: Vec<PinConstants>,
    front: SlipFront,
    pin_shear: PinShear,
    spread: ShearSpread,
    dome_radius_mm: f64,
    scale_px_per_mm: f64,
}

impl Mechanics {
    /// Mechanics for pins at `pins_mm` (sensor plane) on a dome of radius `dome_radius_mm`,
    /// imaged at `scale_px_per_mm`.
    pub fn new(pins_mm: Vec<(f64, f64)>, dome_radius_mm: f64, scale_px_per_mm: f64) -> Self {
        Self {
            pin_constants: Vec::with_capacity(pins_mm.len()),
            front: SlipFront::default(),
            pin_shear: PinShear::default(),
            spread: ShearSpread::default(),
            pins_mm,
            dome_radius_mm,
            scale_px_per_mm,
        }
    }

    /// Computes the trajectories of one trial into `out` (buffers reused).
    pub fn run(
        &mut self,
        params: &SimParams,
        field: &TextureField,
        surface: &Surface,
        draw: &TrialDraw,
        rng: &mut ChaCha8Rng,
        out: &mut PinTrajectories,
    ) {
        let c = &params.contact;
        let rec = draw.recording;
        let local_gain = c.pin_shear_gain / c.skin_shear_stiffness_n_mm3;
        let dt = params.solver.mechanics_dt_s;
        let n_samples = (rec.end_s / dt).ceil() as usize + 2;
        let n_pins = self.pins_mm.len();
        let press = surface.press(params, draw.press_depth_mm, self.dome_radius_mm);
        let a = press.contact_radius_mm;
        let normal = press.normal_force_n;
        let shear_share = press.shear_share;
        let n_over_kt = normal / c.tangential_stiffness_n_mm;
        let edge = c.contact_edge_mm;

        self.pin_constants.clear();
        for &(x, y) in &self.pins_mm {
            let r = (x * x + y * y).sqrt();
            let (rx, ry) = if r > 1e-9 { (x / r, y / r) } else { (0.0, 0.0) };
            let (chi, dchi) = contact_weight(r, a, edge);
            self.pin_constants.push(PinConstants {
                x,
                y,
                r,
                rx,
                ry,
                chi,
                dchi,
            });
        }

        out.dt_s = dt;
        out.n_samples = n_samples;
        out.n_pins = n_pins;
        for v in [&mut out.dx_px, &mut out.dy_px, &mut out.arc_px] {
            v.clear();
            v.resize(n_pins * n_samples, 0.0);
        }
        out.shear_mm.clear();
        out.shear_mm.resize(n_samples, 0.0);
        out.in_contact.clear();
        out.in_contact
            .extend(self.pin_constants.iter().map(|pin| pin.chi > 0.5));
        out.press = Some(press);

        // Shear state.
        let s_static = draw.mu_static * n_over_kt;
        let s_kinetic = draw.mu_kinetic * n_over_kt;
        out.stick_limit_mm = s_static;
        out.full_slip_s = None;
        out.slip_front.clear();
        if c.partial_slip && a > 0.0 {
            let state = ContactState {
                radius_mm: a,
                normal_force_n: normal,
                area_scale_mpa: c.skin_modulus_mpa * c.micro_slope_rms,
                offset_mm: (draw.start_phase_mm, draw.lateral_offset_mm),
                footprint_radius_mm: c.pin_footprint_radius_mm,
            };
            self.front
                .solve(&self.pins_mm, &state, field, c.stick_area_exponent);
            out.slip_front
                .extend((0..n_pins).map(|p| self.front.pin_threshold(p)));
        } else {
            self.front.clear();
            out.slip_front.resize(n_pins, None);
        }
        self.pin_shear.start(&self.front);
        // How the load spreads to the pins: the layer's forward shift and the pile's reach.
        let forward_shift = match (surface.layer, press.overlap_mm > 0.0) {
            (Some(layer), true) => {
                2.0 * layer.loss_tangent * (press.overlap_mm - press.dome_depth_mm)
                    / press.overlap_mm
            }
            _ => 0.0,
        };
        let pile = surface.pile.and_then(|pile| {
            let outer = pile.reach_mm(press.overlap_mm, self.dome_radius_mm);
            let hairs =
                pile.traction_mpa(draw.mu_kinetic) * std::f64::consts::PI * (outer * outer - a * a);
            (a > 0.0 && outer > a).then(|| (outer, hairs / (hairs + draw.mu_kinetic * normal)))
        });
        self.spread.solve(
            &self.pins_mm,
            &SpreadContact {
                radius_mm: a,
                forward_shift,
                pile,
                depth_mm: c.skin_depth_mm,
            },
        );
        // A fabric dragged on its mounting during the onset (before the first full slip).
        out.contact = ContactFacts {
            forward_shift,
            pile,
            fabric_drag_mm: None,
            wrinkle_s: None,
        };
        let mut drag = surface
            .fabric
            .filter(|_| a > 0.0 && shear_share > 0.0)
            .map(|fabric| {
                FabricDrag::new(
                    &fabric,
                    (a, normal),
                    (c.fabric_mount_span_mm, c.fabric_base_friction),
                    (c.tangential_stiffness_n_mm, shear_share),
                )
            });
        let kinetic_ratio = if draw.mu_static > 0.0 {
            draw.mu_kinetic / draw.mu_static
        } else {
            1.0
        };
        let relax = (-dt / c.slip_time_s).exp();
        let weakening = surface.weakening_speed_mm_s;
        let slip_level = |v: f64| {
            if weakening > 0.0 {
                (draw.mu_kinetic
                    + (draw.mu_static - draw.mu_kinetic) * (-v.abs() / weakening).exp())
                    * n_over_kt
            } else {
                s_kinetic
            }
        };
        let (mut s, mut vp, mut stuck, mut micro) = (0.0f64, 0.0f64, true, 0.0f64);
        let sub = (dt / params.solver.shear_dt_s).ceil().max(1.0) as usize;
        let h = dt / sub as f64;
        let inertia = (-h / c.slip_inertia_s).exp();
        let micro_decay = (-h / c.microslip_time_s).exp();
        let micro_rate_per_mm = surface.microslip_rate_hz / super::texture::REFERENCE_SPEED_MM_S;
        // Edge catches: one each time the patch has slipped past another row of bumps, from the
        // mounting's phase.
        let mut next_catch = surface
            .catch_period_mm
            .map_or(f64::INFINITY, |p| p - draw.start_phase_mm.rem_euclid(p));
        let mut slid = 0.0;
        let release = |micro: &mut f64, rng: &mut ChaCha8Rng, scale: f64| {
            let u = rng.random::<f64>();
            *micro -= scale * (c.microslip_min_mm + u * (c.microslip_max_mm - c.microslip_min_mm));
        };
        // A bump edge catches the skin as deeply as the skin sinks into the gaps: a full
        // catch once it drapes to the floor, none on a grid it only rests on.
        let catch_scale = (surface.max_sag_mm / c.bump_height_mm).min(1.0);
        let mut slipped_once = false;
        // The press: the dome starts `clearance` above the specimen's surface and its contact
        // grows as √(overlap) until the press ends; the skin flattens against the specimen by
        // the dome's share of the overlap, splaying the pins it covers (spec §7).
        let travel = params.kinematics.press_travel_mm;
        let clearance = travel - press.overlap_mm;
        let splay_gain = if press.overlap_mm > 0.0 {
            c.lever_mm * (press.dome_depth_mm / press.overlap_mm) / self.dome_radius_mm
        } else {
            0.0
        };
        let press_end = rec.press_end_s();
        let mut t = 0.0;
        let scale = self.scale_px_per_mm;
        for n in 0..n_samples {
            if n > 0 {
                for _ in 0..sub {
                    let (_, base_speed) = rec.slide_at(t + 0.5 * h);
                    let vb = shear_share * base_speed;
                    if stuck {
                        match drag.as_mut().filter(|_| !slipped_once) {
                            Some(drag) => {
                                s += drag.share(s) * base_speed * h;
                                let was = drag.wrinkled();
                                s = drag.wrinkle(s);
                                if !was && drag.wrinkled() {
                                    out.contact.wrinkle_s = Some(t + h);
                                }
                            }
                            None => s += vb * h,
                        }
                        if s >= s_static && vb > 0.0 {
                            stuck = false;
                            if !slipped_once {
                                out.contact.fabric_drag_mm = drag.map(|d| d.drag_mm(s));
                            }
                            slipped_once = true;
                        }
                    } else {
                        let target = (s - slip_level(vp)) / c.slip_time_s;
                        vp = target + (vp - target) * inertia;
                        if vp <= 0.0 {
                            vp = 0.0;
                            stuck = true;
                        }
                        s += (vb - vp) * h;
                        // Micro-slips: Poisson in slip distance.
                        if micro_rate_per_mm > 0.0
                            && rng.random::<f64>() < micro_rate_per_mm * vp * h
                        {
                            release(&mut micro, rng, 1.0);
                        }
                        slid += vp * h;
                        if slid >= next_catch {
                            next_catch += surface.catch_period_mm.unwrap_or(f64::INFINITY);
                            release(&mut micro, rng, catch_scale);
                        }
                    }
                    micro *= micro_decay;
                    t += h;
                }
            }
            if !stuck && out.full_slip_s.is_none() {
                out.full_slip_s = Some(t);
            }
            self.pin_shear
                .step(s, s_static, kinetic_ratio, stuck, relax);
            let (xb, _) = rec.slide_at(t);
            let patch_x = xb - s + draw.start_phase_mm;
            out.shear_mm[n] = (s + micro) as f32;
            // While pressing, the contact radius of the overlap so far.
            let radius_now = (t < press_end && press.overlap_mm > 0.0).then(|| {
                let overlap = (rec.press_travel_at(t) - clearance).max(0.0);
                a * (overlap / press.overlap_mm).sqrt()
            });
            // The share of the contact that slides: the slip front's, up to the first full slip.
            let slipped = if out.full_slip_s.is_some() {
                1.0
            } else if c.partial_slip && s_static > 0.0 {
                1.0 - (1.0 - (s / s_static).clamp(0.0, 1.0)).powf(c.stick_area_exponent)
            } else {
                0.0
            };
            for (i, pin) in self.pin_constants.iter().enumerate() {
                let (chi, dchi) =
                    radius_now.map_or((pin.chi, pin.dchi), |r| contact_weight(pin.r, r, edge));
                let s_pin = c.pin_shear_gain * (self.pin_shear.pin(i, s) + micro);
                let (spread_x, spread_y) = self.spread.at(i, slipped);
                let splay = splay_gain * pin.r * chi;
                let mut ux = spread_x * s_pin - splay * pin.rx;
                let mut uy = spread_y * s_pin - splay * pin.ry;
                if !field.is_flat() && chi > 1e-3 {
                    let f = field.sample(pin.x + patch_x, pin.y + draw.lateral_offset_mm);
                    let w = chi * f.w;
                    // ∇(χ·w₀) = χ∇w₀ + w₀·χ'(r)·r̂.
                    ux += c.lever_mm * (chi * f.dw_dx + f.w * dchi * pin.rx)
                        + c.bulge * w * pin.rx
                        + local_gain * chi * f.traction_mpa;
                    uy += c.lever_mm * (chi * f.dw_dy + f.w * dchi * pin.ry) + c.bulge * w * pin.ry;
                }
                let idx = i * n_samples + n;
                out.dx_px[idx] = (scale * ux) as f32;
                out.dy_px[idx] = (scale * uy) as f32;
            }
        }
        out.accumulate_arcs();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::PinGeometry;
    use crate::sim::kinematics::Recording;
    use crate::sim::texture::Texture;
    use rand::SeedableRng;

    /// The trajectories of one slide over grid `size_mm` with the default geometry, at press
    /// depth 2 mm, phase `phase_mm` and friction `mu` (μ_s, μ_k; the texture's own for `None`).
    fn slide(size_mm: f64, phase_mm: f64, mu: Option<(f64, f64)>) -> PinTrajectories {
        let p = SimParams::default();
        let g = PinGeometry::default();
        let (field, surface) = Texture::grid(size_mm)
            .unwrap()
            .prepare(&p, g.dome_radius_mm);
        let (mu_static, mu_kinetic) = mu.unwrap_or((surface.mu_static, surface.mu_kinetic));
        let draw = TrialDraw {
            lateral_offset_mm: 0.0,
            start_phase_mm: phase_mm,
            press_depth_mm: 2.0,
            mu_static,
            mu_kinetic,
            recording: Recording::nominal(&p),
        };
        let mut m = Mechanics::new(g.pin_positions_mm(), g.dome_radius_mm, g.scale_px_per_mm);
        let mut out = PinTrajectories::default();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        m.run(&p, &field, &surface, &draw, &mut rng, &mut out);
        out
    }

    #[test]
    fn galloping_travel_search_equals_the_sample_by_sample_scan() {
        // The scan it replaced: sample by sample from t_s up to the limit.
        fn scan(tr: &PinTrajectories, pin: usize, t_s: f64, distance: f32, limit_s: f64) -> f64 {
            let target = tr.arc(pin, t_s) + distance;
            let series = &tr.arc_px[pin * tr.n_samples..(pin + 1) * tr.n_samples];
            let (mut k, _) = tr.locate(t_s);
            loop {
                k += 1;
                if k > tr.n_samples - 1 || k as f64 * tr.dt_s >= limit_s {
                    return limit_s;
                }
                if series[k] >= target {
                    let (a0, a1) = (series[k - 1], series[k]);
                    let f = ((target - a0) / (a1 - a0)).clamp(0.0, 1.0) as f64;
                    return ((k - 1) as f64 + f) * tr.dt_s;
                }
            }
        }
        let tr = slide(5.0, 1.0, None);
        let end = tr.n_samples as f64 * tr.dt_s;
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..20_000 {
            let pin = rng.random_range(0..tr.n_pins);
            let t = rng.random_range(0.0..end);
            let distance = 10f32.powf(rng.random_range(-4.0..1.0));
            let limit = t + 10f64.powf(rng.random_range(-5.0..0.0));
            let (a, b) = (
                tr.time_to_travel(pin, t, distance, limit),
                scan(&tr, pin, t, distance, limit),
            );
            assert_eq!(a.to_bits(), b.to_bits(), "pin {pin} at {t}: {a} vs {b}");
        }
    }

    #[test]
    fn flat_plate_onset_sticks_then_slips_back_and_recoils_at_the_stop() {
        let p = SimParams::default();
        let out = slide(0.0, 0.0, Some((1.0, 0.7)));
        let at = |t: f64| out.shear_mm[((t / out.dt_s) as usize).min(out.n_samples - 1)] as f64;
        // N/k_t = 1 mm: stick up to s_s = 1 mm, steady s_k + τv = 0.85 mm, rest at s_k = 0.7 mm.
        let peak = out.shear_mm.iter().copied().fold(0.0f32, f32::max) as f64;
        assert!((peak - 1.0).abs() < 0.02, "{peak}");
        assert!((at(2.0) - 0.85).abs() < 0.01, "{}", at(2.0));
        let rec = Recording::nominal(&p);
        assert!((at(rec.end_s) - 0.7).abs() < 0.02);
        // Stuck, the centre pin moves g_pin·s·k = g_pin · 1 mm · 4.5 px/mm at the stick limit; as
        // the contact slips its traction turns Hertzian and the apex moves up to 1.5 times as far
        // (Cattaneo–Mindlin, [`ShearSpread`]).
        let stuck = (p.contact.pin_shear_gain * 4.5) as f32;
        let centre = (0..out.n_samples)
            .map(|k| out.dx_px[k].hypot(out.dy_px[k]))
            .fold(0.0f32, f32::max);
        assert!(
            centre > 1.02 * stuck && centre < 1.5 * stuck,
            "{centre} vs {stuck}"
        );
        // The press splays the pins it covers radially, by G_lever·r/R at most.
        let pressed = Recording::nominal(&p).slide_start_s - 0.01;
        let (sx, sy) = out.displacement(8, pressed);
        let g = PinGeometry::default();
        let (x, y) = g.pin_positions_mm()[8];
        let expected = p.contact.lever_mm * x.hypot(y) / g.dome_radius_mm * g.scale_px_per_mm;
        assert!(sx.hypot(sy) > 0.9 * expected as f32 && sx.hypot(sy) <= expected as f32 * 1.01);
        // Nothing moves before the press reaches the plate; the centre pin does not splay, so
        // it moves only once the slide starts.
        assert_eq!(out.arc(48, 0.05), 0.0);
        assert_eq!(out.arc(0, rec.slide_start_s), 0.0);
        assert!(out.arc(8, rec.slide_start_s) > 0.0);
        assert!(out.in_contact[0] && !out.in_contact[48]);
    }

    #[test]
    fn edge_catches_on_a_grid_come_once_per_row_of_bumps() {
        let p = SimParams::default();
        // A catch is a sudden drop of the pins' shear while sliding steadily (after the onset's
        // snap, before the stop's recoil), of at least the smallest micro-slip scaled by how deep
        // the skin sinks into the gaps; the patch slips ≈ 56 mm then, p = 5 mm.
        let out = slide(2.5, 1.0, None);
        let (_, surface) = Texture::grid(2.5)
            .unwrap()
            .prepare(&p, PinGeometry::default().dome_radius_mm);
        let smallest =
            (p.contact.microslip_min_mm * surface.max_sag_mm / p.contact.bump_height_mm) as f32;
        let rec = Recording::nominal(&p);
        let (from, to) = (
            ((rec.slide_start_s + 0.35) / out.dt_s) as usize,
            ((rec.slide_end_s() - 0.1) / out.dt_s) as usize,
        );
        let drops = |out: &PinTrajectories| {
            out.shear_mm[from..to]
                .windows(2)
                .filter(|w| w[1] < w[0] - 0.8 * smallest)
                .count()
        };
        assert!((9..=12).contains(&drops(&out)), "{} catches", drops(&out));
        // The flat plate has no bumps to catch on.
        assert_eq!(drops(&slide(0.0, 1.0, None)), 0);
    }
}
