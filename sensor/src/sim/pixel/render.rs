//! Rendering (spec §3.1): a pin is a bright disc on a dark background,
//! `I = I_bg + (I_pin − I_bg)·Σ_i S(‖p − c_i(t)‖)`, `S(ρ) = ½·erfc((ρ − r_d)/(√2·σ))`, with the
//! pixel-area average in closed form (σ² = w² + 1/12); lookup tables of S against ρ² and of the
//! lin-log intensity and photoreceptor rate against coverage; and the pixel patches around the
//! pins (each pixel sees its nearest pin and the second-nearest within the patch radius).

use super::event::NOISE_LABEL;
use crate::sim::params::SimParams;
use neurotac_core::special::erfc;

/// The integer value of a whole-numbered `x` with |x| < 2²², through the bits of
/// `x + 1.5·2²³` (exact there, one unit per ulp): unlike `as`, which saturates and is
/// converted one lane at a time, this stays in vector lanes.
#[inline(always)]
pub(super) fn integral_to_i32(x: f32) -> i32 {
    const MAGIC: f32 = 12_582_912.0; // 1.5·2²³, bits 0x4B40_0000
    (x + MAGIC).to_bits() as i32 - MAGIC.to_bits() as i32
}

/// Lookup tables of the rendering and the photoreceptor.
#[derive(Debug, Clone)]
pub(super) struct Tables {
    /// S against ρ², step `rho2_step` (fixed size, so lookups need no bounds checks and the
    /// pixel loop vectorises).
    pub(super) coverage: Box<[f32; COVERAGE_ENTRIES]>,
    pub(super) rho2_inv_step: f32,
    /// L and 1/τ_p against total coverage S ∈ [0, 2].
    pub(super) log_intensity: Box<[f32; LOG_ENTRIES]>,
    pub(super) inv_tau: Box<[f32; LOG_ENTRIES]>,
    pub(super) s_inv_step: f32,
    /// Largest |dL/dρ| of one pin (per px).
    pub(super) max_slope: f32,
}

const COVERAGE_ENTRIES: usize = 4096;
const LOG_ENTRIES: usize = 2048;

impl Tables {
    pub(super) fn new(params: &SimParams) -> Self {
        let o = &params.optics;
        let sigma = (o.edge_blur_px * o.edge_blur_px + 1.0 / 12.0).sqrt();
        let rho_max = o.pin_radius_px + 7.0 * sigma;
        let rho2_step = rho_max * rho_max / (COVERAGE_ENTRIES - 2) as f64;
        let s = |rho: f64| 0.5 * erfc((rho - o.pin_radius_px) / (std::f64::consts::SQRT_2 * sigma));
        let coverage = Box::new(std::array::from_fn(|i| {
            if i >= COVERAGE_ENTRIES - 2 {
                0.0
            } else {
                s((i as f64 * rho2_step).sqrt()) as f32
            }
        }));
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
        let log_intensity = Box::new(std::array::from_fn(|i| {
            lin(intensity(i as f64 * s_step)) as f32
        }));
        let inv_tau = Box::new(std::array::from_fn(|i| {
            let rel = (intensity(i as f64 * s_step) / o.full_scale_dn).clamp(0.05, 1.0);
            (std::f64::consts::TAU * f_max * rel) as f32
        }));
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
    pub(super) fn coverage(&self, rho2: f32) -> f32 {
        let x = (rho2 * self.rho2_inv_step).min((COVERAGE_ENTRIES - 2) as f32);
        // x ≥ 0, so its floor is its truncation and the index clamp changes nothing; the
        // clamp proves both lookups in range.
        let floor = x.floor();
        let i = integral_to_i32(floor).clamp(0, (COVERAGE_ENTRIES - 2) as i32) as usize;
        let f = x - floor;
        let (a, b) = (self.coverage[i], self.coverage[i + 1]);
        a + f * (b - a)
    }

    #[inline(always)]
    pub(super) fn log_and_rate(&self, cover: f32) -> (f32, f32) {
        let x = (cover * self.s_inv_step).min((LOG_ENTRIES - 2) as f32);
        let floor = x.floor();
        let i = integral_to_i32(floor).clamp(0, (LOG_ENTRIES - 2) as i32) as usize;
        let f = x - floor;
        let (l0, l1) = (self.log_intensity[i], self.log_intensity[i + 1]);
        let (r0, r1) = (self.inv_tau[i], self.inv_tau[i + 1]);
        (l0 + f * (l1 - l0), r0 + f * (r1 - r0))
    }
}

/// Which pixels are simulated and which pins render into them (fixed by the geometry).
///
/// Within a patch, the pixels only their owner pin renders into come first, then those a
/// second pin reaches too (`second[patch]` is where they start), so each part runs its own
/// loop without per-pixel choices. A pixel's random draws are keyed by its `seed_index`: its
/// rank in image order among all patch pixels (patch by patch), whatever its position.
#[derive(Debug, Clone)]
pub(super) struct Patches {
    /// Pixel index range of each patch (patch = its owner pin).
    pub(super) ranges: Vec<(usize, usize)>,
    /// Per patch: the first pixel that a second pin renders into too.
    pub(super) second: Vec<usize>,
    /// Per pixel: the index its random draws are keyed by.
    pub(super) seed_index: Vec<u32>,
    /// Pins rendering into each patch (owner first).
    pub(super) pins: Vec<Vec<usize>>,
    /// Per pixel: coordinates.
    pub(super) x: Vec<u16>,
    pub(super) y: Vec<u16>,
    /// Per pixel: offset from the owner pin's rest centre, and from the second pin's (or far
    /// away when there is none).
    pub(super) own_dx: Vec<f32>,
    pub(super) own_dy: Vec<f32>,
    pub(super) other: Vec<u8>,
    pub(super) other_dx: Vec<f32>,
    pub(super) other_dy: Vec<f32>,
    /// Per image pixel: index into the patch arrays, or `u32::MAX`.
    pub(super) index_of: Vec<u32>,
}

impl Patches {
    pub(super) fn new(pins_px: &[(f64, f64)], radius: f64, width: u16, height: u16) -> Self {
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
            second: Vec::with_capacity(n_pins),
            seed_index: Vec::new(),
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
            // Lone pixels first; the stable sort keeps image order within each part.
            let mut order: Vec<_> = pixels.iter().enumerate().collect();
            order.sort_by_key(|&(_, &(_, _, other))| other != NOISE_LABEL);
            let lone = pixels.iter().filter(|q| q.2 == NOISE_LABEL).count();
            p.second.push(start + lone);
            for (rank, &(x, y, other)) in order {
                p.seed_index.push((start + rank) as u32);
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

/// Pin slots of the per-pin displacement arrays the renderer reads: one per possible `u8` pin
/// index, so a lookup needs no bounds check. Slot [`NOISE_LABEL`] (the "second pin" of a pixel
/// that has none) always stays at rest; such a pixel's offset from it is far beyond the disc,
/// so it adds exactly zero coverage.
pub(super) const PIN_SLOTS: usize = 256;

/// Per-pin image displacements (px), one slot per `u8` pin index ([`PIN_SLOTS`]).
pub(super) type PinSlots = [f32; PIN_SLOTS];

/// Log intensity and photoreceptor rate of a pixel at offset `own` (px) from its owner pin's
/// current centre and `other` from its second pin's: the two pins' coverages summed, through
/// the tables. A pixel without a second pin has `other` far away, whose coverage is exactly 0.
#[inline(always)]
pub(super) fn render_offsets(tables: &Tables, own: (f32, f32), other: (f32, f32)) -> (f32, f32) {
    let cover = tables.coverage(own.0 * own.0 + own.1 * own.1)
        + tables.coverage(other.0 * other.0 + other.1 * other.1);
    tables.log_and_rate(cover)
}

/// [`render_offsets`] for a pixel that only its owner pin renders into.
#[inline(always)]
pub(super) fn render_offset(tables: &Tables, own: (f32, f32)) -> (f32, f32) {
    tables.log_and_rate(tables.coverage(own.0 * own.0 + own.1 * own.1))
}

/// Log intensity and photoreceptor rate of patch pixel `j` of pin `own`'s patch, for pins
/// displaced by (`pin_dx`, `pin_dy`) (px, per pin slot) ([`render_offsets`]).
#[inline(always)]
pub(super) fn render_pixel(
    tables: &Tables,
    p: &Patches,
    (pin_dx, pin_dy): (&PinSlots, &PinSlots),
    j: usize,
    own: usize,
) -> (f32, f32) {
    let o = p.other[j] as usize;
    render_offsets(
        tables,
        (p.own_dx[j] - pin_dx[own], p.own_dy[j] - pin_dy[own]),
        (p.other_dx[j] - pin_dx[o], p.other_dy[j] - pin_dy[o]),
    )
}
