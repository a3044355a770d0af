//! Textures: the 11 bump grids and the 20 natural textures as height fields, put in contact
//! with the skin once per texture and filtered into the fields the pins feel (spec §2.1,
//! §2.2 steps 1–3, §2.4; issue 12 items 1–3, 7).
//!
//! A texture becomes a [`TextureField`] and a [`Surface`] through [`Texture::prepare`]:
//! 1. the skin-on-texture contact is solved ([`super::contact`]): the conformed skin surface
//!    z_s (sag into the gaps growing with the gap until it meets the floor) and the contact
//!    pressure p;
//! 2. the field holds, at every point, the deflection `w₀ = F⁻¹[T(k)·F[z_s]]` (zero mean;
//!    `T(k) = (1 + kz)·e^(−kz)`), its gradient (spectral derivative), and the **local
//!    traction** fluctuation `τ̃ = F⁻¹[T(k)·F[μ_k·p]]` (zero mean): the tangential load under
//!    one pin as bump edges pass, transmitted through the same elastic layer — not averaged
//!    over the contact patch. The contact weight χ(r) is applied later, in the sensor frame
//!    ([`super::mechanics`]);
//! 3. the friction of a grid follows from the contact: adhesion scales with the real contact
//!    area (Persson 2001); the deformation term grows with the slope of the draped skin: at
//!    rest the skin must be lifted out of the gaps over the bump edges (geometric
//!    interlocking, μ = tan θ, Tabor's asperity-angle model), while sliding only the hysteretic
//!    fraction tan δ of that work is lost (Greenwood & Tabor 1958). So μ_s, μ_k and the onset
//!    snap μ_s − μ_k differ between textures:
//!    `μ_k = μ_k,adh·A/A_flat + tan δ·⟨|∂z_s/∂X|⟩`, `μ_s = μ_k,adh·(1 + e)·A/A_flat + ⟨|∂z_s/∂X|⟩`.
//!
//! Fields are built once per texture and shared by all its trials: the physical sample is the
//! same object every slide.
//!
//! Natural textures follow the spec's §2.4 table: a periodic weave, self-affine roughness
//! (spectrum ∝ (1 + (kξ)²)^−(1+H)), sparse discrete features, the compliance κ_m scaling every
//! height, friction and the micro-slip rate. **The numbers are physical priors (\[A\] in the spec),
//! never fitted to classification results.** The random parts are drawn from a seed derived from
//! the texture's name only, so a texture is the same sample in every dataset.

use super::contact::{ContactLaw, SkinContact, solve};
use super::error::SimulationError;
use super::fft::{Complex, fft2, frequency_index};
use super::params::{ContactParams, PeriodRule, SimParams};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

/// The periodic part of a natural texture along the slide (spec §2.4 "periodic part").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Weave {
    /// No periodic part.
    None,
    /// Ridges across the slide: `a·cos(2πX/p)`.
    Rib,
    /// Plain weave or knit (crossing threads): `a·cos(2πX/p)·cos(2πY/p)`.
    Plain,
    /// Twill: diagonal ribs, `a·cos(2π(X + Y)/p)`.
    Twill,
    /// Hexagonal net: three cosines at 120°.
    Hexagonal,
    /// Wood grain: ridges across the slide at random spacings in [p/1.5, 2p].
    Grain,
    /// Overlapping scales (sequins): a saw-tooth of steps of height a, period p.
    Scales,
    /// Quasi-periodic motif (lace): a cosine grid at p plus a second at p·φ (golden ratio).
    Motif,
    /// Wales across the slide (corduroy): rectified ridges `a·|cos(πX/p)|`.
    Wales,
}

/// Sparse discrete features: discs scattered as a Poisson process (spec §2.4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Features {
    /// Features per cm².
    pub density_per_cm2: f64,
    /// Disc diameter (mm).
    pub diameter_mm: f64,
    /// Height (mm); negative for holes and pores.
    pub height_mm: f64,
}

/// One natural texture's physical priors (a row of the spec's §2.4 table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NaturalTexture {
    /// Name as in the paper's Table II (lower case).
    pub name: &'static str,
    /// Periodic part.
    pub weave: Weave,
    /// Period p_w of the periodic part (mm).
    pub period_mm: f64,
    /// Amplitude a_w of the periodic part (mm).
    pub amplitude_mm: f64,
    /// RMS height of the random part (mm).
    pub roughness_rms_mm: f64,
    /// Correlation length ξ of the random part (mm).
    pub correlation_mm: f64,
    /// Hurst exponent H of the random part.
    pub hurst: f64,
    /// Discrete features, if any.
    pub features: Option<Features>,
    /// Compliance κ_m: fraction of the geometric height that reaches the skin.
    pub compliance: f64,
    /// Static friction μ_s against the skin.
    pub mu_static: f64,
    /// Kinetic friction μ_k.
    pub mu_kinetic: f64,
    /// Micro-slip rate λ_ms at 15 mm/s (s⁻¹).
    pub microslip_rate_hz: f64,
    /// Velocity-weakening speed v_c (mm/s), `μ(v) = μ_k + (μ_s − μ_k)·e^(−|v|/v_c)`; 0 = none.
    pub weakening_speed_mm_s: f64,
}

const fn natural(
    name: &'static str,
    weave: Weave,
    (period_mm, amplitude_mm): (f64, f64),
    (roughness_rms_mm, correlation_mm, hurst): (f64, f64, f64),
    features: Option<Features>,
    compliance: f64,
    (mu_static, mu_kinetic, microslip_rate_hz): (f64, f64, f64),
) -> NaturalTexture {
    NaturalTexture {
        name,
        weave,
        period_mm,
        amplitude_mm,
        roughness_rms_mm,
        correlation_mm,
        hurst,
        features,
        compliance,
        mu_static,
        mu_kinetic,
        microslip_rate_hz,
        weakening_speed_mm_s: 0.0,
    }
}

const fn features(density_per_cm2: f64, diameter_mm: f64, height_mm: f64) -> Option<Features> {
    Some(Features {
        density_per_cm2,
        diameter_mm,
        height_mm,
    })
}

/// The 20 natural textures of the paper (Table II order) with the spec's §2.4 priors; where
/// each column's values come from is listed under `natural.*` in
/// [`PARAMETER_SOURCES`](super::params::PARAMETER_SOURCES) (and so in every parameter file's
/// `sources`). Friction spans 0.25–1.6 and compliance 0.05–1, so the textures differ mostly by
/// their onset snap and stick-slip, as the spec expects; only the coarse weaves (wool, lace,
/// tweed, metallic mesh, sequins, embroidery) move the pins periodically. Where
/// the table gives a range the middle is used; an unstated Hurst exponent is 0.8; "hairy",
/// "pile" and "fibre flicks" are represented by the roughness and the micro-slip rate alone.
/// Columns: name, weave, (p_w, a_w) in mm, (h_rms in mm, ξ in mm, H), features (per cm²,
/// diameter mm, height mm), κ_m, (μ_s, μ_k, λ_ms in s⁻¹).
#[rustfmt::skip]
pub const NATURAL_TEXTURES: [NaturalTexture; 20] = {
    use Weave::*;
    let mut acrylic = natural("acrylic", None, (0.0, 0.0), (0.0005, 0.1, 0.8), Option::None, 1.0, (1.6, 1.1, 5.0));
    // "strong v-weakening": stick-slip at the slide speed needs (μ_s − μ_k)·N/(k_t·v_c) > τ.
    acrylic.weakening_speed_mm_s = 15.0;
    [
        natural("foam", None, (0.0, 0.0), (0.15, 0.5, 0.6), features(60.0, 0.6, -0.3), 0.1, (1.3, 0.9, 40.0)),
        natural("plywood", Grain, (1.5, 0.02), (0.01, 0.3, 0.7), Option::None, 1.0, (0.7, 0.5, 20.0)),
        natural("mdf", None, (0.0, 0.0), (0.008, 0.2, 0.8), Option::None, 1.0, (0.8, 0.6, 15.0)),
        acrylic,
        natural("wool", Plain, (3.5, 0.4), (0.15, 1.0, 0.5), Option::None, 0.3, (0.8, 0.6, 30.0)),
        natural("fake fur", None, (0.0, 0.0), (0.5, 2.0, 0.8), Option::None, 0.05, (0.6, 0.5, 50.0)),
        natural("liquid satin", Plain, (0.35, 0.01), (0.01, 0.3, 0.8), Option::None, 0.6, (0.35, 0.25, 5.0)),
        natural("shimmer organza", Plain, (0.25, 0.02), (0.015, 0.2, 0.8), Option::None, 0.8, (0.45, 0.35, 10.0)),
        natural("tweed", Twill, (2.0, 0.25), (0.12, 0.8, 0.5), features(0.5, 3.0, 0.3), 0.5, (0.8, 0.6, 30.0)),
        natural("lace", Motif, (6.0, 0.3), (0.05, 1.0, 0.8), features(2.0, 2.0, -0.3), 0.6, (0.6, 0.45, 20.0)),
        natural("flarefree net", Hexagonal, (1.2, 0.08), (0.0, 1.0, 0.8), Option::None, 0.8, (0.5, 0.4, 15.0)),
        natural("embroidered cotton", Plain, (0.5, 0.04), (0.03, 0.3, 0.8), features(1.56, 3.0, 0.5), 0.6, (0.7, 0.55, 20.0)),
        natural("shirt canvas", Plain, (0.6, 0.06), (0.03, 0.3, 0.8), Option::None, 0.7, (0.65, 0.5, 15.0)),
        natural("fairydust organza", Plain, (0.25, 0.02), (0.015, 0.2, 0.8), features(5.0, 1.0, 0.05), 0.8, (0.45, 0.35, 15.0)),
        natural("sequins allover", Scales, (3.5, 0.25), (0.0, 1.0, 0.8), Option::None, 0.9, (0.35, 0.25, 10.0)),
        natural("metallic mesh", Plain, (2.5, 0.5), (0.02, 0.5, 0.8), Option::None, 1.0, (0.45, 0.35, 10.0)),
        natural("felt", None, (0.0, 0.0), (0.06, 0.4, 0.6), Option::None, 0.4, (0.9, 0.7, 30.0)),
        natural("needlecord", Wales, (1.6, 0.35), (0.05, 0.3, 0.8), Option::None, 0.5, (0.7, 0.55, 20.0)),
        natural("fleece", None, (0.0, 0.0), (0.2, 1.5, 0.5), Option::None, 0.1, (0.7, 0.55, 35.0)),
        natural("microdot foil", Plain, (0.45, 0.02), (0.002, 0.1, 0.8), Option::None, 1.0, (0.5, 0.4, 10.0)),
    ]
};

/// The 11 bump-grid sizes of the paper (mm).
pub const GRID_SIZES_MM: [f64; 11] = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0];

/// A surface the sensor slides over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Texture {
    /// A 3D-printed grid of cylinders of size d (mm); d = 0 is the flat plate.
    Grid {
        /// Size d (mm), see [`PeriodRule`].
        size_mm: f64,
    },
    /// One of the 20 natural textures.
    Natural(&'static NaturalTexture),
}

/// Friction, micro-slip and contact facts of a texture against the skin (spec §2.2 step 5,
/// §2.4; issue 12 item 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Static friction μ_s (before the recording's shared factor and drift).
    pub mu_static: f64,
    /// Kinetic friction μ_k.
    pub mu_kinetic: f64,
    /// Micro-slip rate at 15 mm/s (s⁻¹).
    pub microslip_rate_hz: f64,
    /// Velocity-weakening speed (mm/s); 0 = none.
    pub weakening_speed_mm_s: f64,
    /// Real contact area relative to a flat plate (1 for the plate).
    pub real_area_ratio: f64,
    /// Mean slope ⟨|∂z_s/∂X|⟩ of the draped skin.
    pub mean_abs_slope: f64,
    /// Deepest sag of the skin into the texture (mm).
    pub max_sag_mm: f64,
    /// Fraction of the skin in contact.
    pub contact_fraction: f64,
}

impl Texture {
    /// The bump grid of size `size_mm` (0…5 mm; the paper's sizes are [`GRID_SIZES_MM`]).
    pub fn grid(size_mm: f64) -> Result<Self, SimulationError> {
        if !(size_mm.is_finite() && (0.0..=5.0).contains(&size_mm)) {
            return Err(SimulationError::InvalidParameter {
                field: "texture.size_mm",
                value: size_mm,
                expected: "a grid size in [0, 5] mm",
            });
        }
        Ok(Texture::Grid { size_mm })
    }

    /// A texture by name: `grid <d> mm` / `<d> mm` for a bump grid, or a natural texture's name
    /// (case-insensitive, as in [`NATURAL_TEXTURES`]).
    pub fn from_name(name: &str) -> Result<Self, SimulationError> {
        let lower = name.trim().to_lowercase();
        let number = lower
            .strip_prefix("grid")
            .unwrap_or(&lower)
            .trim()
            .trim_end_matches("mm")
            .trim();
        if let Ok(size) = number.parse::<f64>() {
            return Self::grid(size);
        }
        NATURAL_TEXTURES
            .iter()
            .find(|t| t.name == lower)
            .map(Texture::Natural)
            .ok_or_else(|| SimulationError::UnknownTexture {
                name: name.to_owned(),
                known: NATURAL_TEXTURES.map(|t| t.name).join(", "),
            })
    }

    /// The texture's name (`grid 2.5 mm`, `felt`, …); [`from_name`](Self::from_name) reads it.
    pub fn name(&self) -> String {
        match self {
            Texture::Grid { size_mm } => format!("grid {size_mm:.1} mm"),
            Texture::Natural(t) => t.name.to_owned(),
        }
    }

    /// The spatial period along the slide of a grid (mm): 2d or d by the period rule; `None` for
    /// the flat plate and natural textures.
    pub fn grid_period_mm(&self, rule: PeriodRule) -> Option<f64> {
        match *self {
            Texture::Grid { size_mm } if size_mm > 0.0 => Some(match rule {
                PeriodRule::Gap => 2.0 * size_mm,
                PeriodRule::CentreToCentre => size_mm,
            }),
            _ => None,
        }
    }

    /// Solves the skin's contact on this texture under the nominal pressure `pressure_mpa`
    /// and builds its field and surface (see the module docs). Deterministic; once per
    /// texture.
    pub fn prepare(&self, params: &SimParams, pressure_mpa: f64) -> (TextureField, Surface) {
        let c = &params.contact;
        let law = ContactLaw::new(c, pressure_mpa);
        match *self {
            Texture::Grid { size_mm } if size_mm > 0.0 => {
                let (h, n, dx) = grid_heights(size_mm, c);
                let contact = solve(&h, (n, n), (dx, dx), &law);
                let adhesion = c.adhesion_mu_kinetic * contact.real_area_ratio;
                let hysteresis = c.loss_tangent * contact.mean_abs_slope;
                let interlocking = contact.mean_abs_slope;
                let mu_kinetic = adhesion + hysteresis;
                let surface = Surface {
                    mu_static: adhesion * (1.0 + c.static_excess) + interlocking,
                    mu_kinetic,
                    microslip_rate_hz: 0.0,
                    weakening_speed_mm_s: 0.0,
                    ..contact_facts(&contact)
                };
                let field = TextureField::from_contact(&contact, mu_kinetic, (n, n), (dx, dx), c);
                (field, surface)
            }
            Texture::Grid { .. } => (
                TextureField::flat(),
                Surface {
                    mu_static: c.adhesion_mu_kinetic * (1.0 + c.static_excess),
                    mu_kinetic: c.adhesion_mu_kinetic,
                    microslip_rate_hz: 0.0,
                    weakening_speed_mm_s: 0.0,
                    real_area_ratio: 1.0,
                    mean_abs_slope: 0.0,
                    max_sag_mm: 0.0,
                    contact_fraction: 1.0,
                },
            ),
            Texture::Natural(t) => {
                let h = natural_heights(t);
                let (nx, ny, dx) = (NATURAL_NX, NATURAL_NY, NATURAL_DX_MM);
                let contact = solve(&h, (nx, ny), (dx, dx), &law);
                let surface = Surface {
                    mu_static: t.mu_static,
                    mu_kinetic: t.mu_kinetic,
                    microslip_rate_hz: t.microslip_rate_hz,
                    weakening_speed_mm_s: t.weakening_speed_mm_s,
                    ..contact_facts(&contact)
                };
                let field =
                    TextureField::from_contact(&contact, t.mu_kinetic, (nx, ny), (dx, dx), c);
                (field, surface)
            }
        }
    }
}

/// The contact facts of a [`Surface`] (friction left at zero).
fn contact_facts(contact: &SkinContact) -> Surface {
    Surface {
        mu_static: 0.0,
        mu_kinetic: 0.0,
        microslip_rate_hz: 0.0,
        weakening_speed_mm_s: 0.0,
        real_area_ratio: contact.real_area_ratio,
        mean_abs_slope: contact.mean_abs_slope,
        max_sag_mm: contact.max_sag_mm,
        contact_fraction: contact.contact_fraction,
    }
}

/// Cells per grid period (a power of two).
const GRID_CELLS: usize = 64;
/// Sample spacing of natural fields (mm) and their size (a power of two each way).
const NATURAL_DX_MM: f64 = 0.25;
const NATURAL_NX: usize = 512;
const NATURAL_NY: usize = 256;

/// A periodic field of skin deflection and slopes (see the module docs), sampled bilinearly.
#[derive(Debug, Clone)]
pub struct TextureField {
    nx: usize,
    ny: usize,
    dx_mm: f64,
    dy_mm: f64,
    /// Per point: `[w₀, ∂w₀/∂X, ∂w₀/∂Y, τ̃]`.
    values: Vec<[f32; 4]>,
    /// Per point: the contact pressure over its mean, p/⟨p⟩ (unfiltered: the interface law
    /// acts at the surface), for the partial-slip front ([`super::slip_front`]).
    pressure_ratio: Vec<f32>,
    flat: bool,
}

/// The field at one point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FieldSample {
    /// Skin deflection w₀ before contact weighting (mm).
    pub w: f64,
    /// ∂w₀/∂X.
    pub dw_dx: f64,
    /// ∂w₀/∂Y.
    pub dw_dy: f64,
    /// Local traction fluctuation τ̃ under the point (MPa = N/mm²), zero mean.
    pub traction_mpa: f64,
}

impl TextureField {
    /// `true` for a texture without height (the flat plate): every sample is zero.
    pub fn is_flat(&self) -> bool {
        self.flat
    }

    /// The field at world point `(x_mm, y_mm)` (periodic, bilinear).
    #[inline]
    pub fn sample(&self, x_mm: f64, y_mm: f64) -> FieldSample {
        if self.flat {
            return FieldSample::default();
        }
        let (fx, fy) = (x_mm / self.dx_mm, y_mm / self.dy_mm);
        let (flx, fly) = (fx.floor(), fy.floor());
        let (tx, ty) = ((fx - flx) as f32, (fy - fly) as f32);
        let ix = (flx as i64).rem_euclid(self.nx as i64) as usize;
        let iy = (fly as i64).rem_euclid(self.ny as i64) as usize;
        let (jx, jy) = ((ix + 1) % self.nx, (iy + 1) % self.ny);
        let v = |x: usize, y: usize| &self.values[y * self.nx + x];
        let (a, b, c, d) = (v(ix, iy), v(jx, iy), v(ix, jy), v(jx, jy));
        let mut out = [0f32; 4];
        for k in 0..4 {
            let top = a[k] + tx * (b[k] - a[k]);
            let bottom = c[k] + tx * (d[k] - c[k]);
            out[k] = top + ty * (bottom - top);
        }
        FieldSample {
            w: out[0] as f64,
            dw_dx: out[1] as f64,
            dw_dy: out[2] as f64,
            traction_mpa: out[3] as f64,
        }
    }

    /// The contact pressure at world point `(x_mm, y_mm)` over the mean contact pressure
    /// (periodic, bilinear; 1 everywhere on the flat plate, 0 where the skin is free).
    #[inline]
    pub fn pressure_ratio(&self, x_mm: f64, y_mm: f64) -> f64 {
        if self.flat {
            return 1.0;
        }
        let (fx, fy) = (x_mm / self.dx_mm, y_mm / self.dy_mm);
        let (flx, fly) = (fx.floor(), fy.floor());
        let (tx, ty) = ((fx - flx) as f32, (fy - fly) as f32);
        let ix = (flx as i64).rem_euclid(self.nx as i64) as usize;
        let iy = (fly as i64).rem_euclid(self.ny as i64) as usize;
        let (jx, jy) = ((ix + 1) % self.nx, (iy + 1) % self.ny);
        let v = |x: usize, y: usize| self.pressure_ratio[y * self.nx + x];
        let top = v(ix, iy) + tx * (v(jx, iy) - v(ix, iy));
        let bottom = v(ix, jy) + tx * (v(jx, jy) - v(ix, jy));
        (top + ty * (bottom - top)) as f64
    }

    /// Largest |w₀| (mm), for diagnostics.
    pub fn max_deflection_mm(&self) -> f64 {
        self.values
            .iter()
            .map(|v| v[0].abs() as f64)
            .fold(0.0, f64::max)
    }

    /// The field of the flat plate: no height, uniform pressure.
    pub(crate) fn flat() -> Self {
        Self {
            nx: 1,
            ny: 1,
            dx_mm: 1.0,
            dy_mm: 1.0,
            values: vec![[0.0; 4]],
            pressure_ratio: vec![1.0],
            flat: true,
        }
    }

    /// The field of a solved contact: the conformed surface and the local traction
    /// `mu_kinetic·p`, both passed through T(k) with their means removed.
    fn from_contact(
        contact: &SkinContact,
        mu_kinetic: f64,
        dims: (usize, usize),
        spacing: (f64, f64),
        params: &ContactParams,
    ) -> Self {
        let traction: Vec<f64> = contact
            .pressure_mpa
            .iter()
            .map(|p| mu_kinetic * p)
            .collect();
        let mut field = Self::from_surface(&contact.surface_mm, &traction, dims, spacing, params);
        let mean = contact.pressure_mpa.iter().sum::<f64>() / contact.pressure_mpa.len() as f64;
        field.pressure_ratio = contact
            .pressure_mpa
            .iter()
            .map(|&p| if mean > 0.0 { (p / mean) as f32 } else { 1.0 })
            .collect();
        field
    }

    /// Filters the skin surface `z` and the traction `tau` (row-major `nx × ny`, spacing
    /// `dx × dy` mm, periodic) by the elastic layer: removes the means, applies T(k) to both,
    /// and spectral derivatives for the deflection's gradient.
    fn from_surface(
        z: &[f64],
        tau: &[f64],
        (nx, ny): (usize, usize),
        (dx_mm, dy_mm): (f64, f64),
        contact: &ContactParams,
    ) -> Self {
        let mut spectrum: Vec<Complex> = z.iter().map(|&v| (v, 0.0)).collect();
        fft2(&mut spectrum, nx, ny, false);
        spectrum[0] = (0.0, 0.0);
        let mut traction: Vec<Complex> = tau.iter().map(|&v| (v, 0.0)).collect();
        fft2(&mut traction, nx, ny, false);
        traction[0] = (0.0, 0.0);
        let z_depth = contact.skin_depth_mm;
        let (lx, ly) = (nx as f64 * dx_mm, ny as f64 * dy_mm);
        let mut channels: [Vec<Complex>; 4] = std::array::from_fn(|_| vec![(0.0, 0.0); nx * ny]);
        for j in 0..ny {
            let ky = TAU * frequency_index(j, ny) / ly;
            for i in 0..nx {
                let kx = TAU * frequency_index(i, nx) / lx;
                let k = (kx * kx + ky * ky).sqrt();
                let t = (1.0 + k * z_depth) * (-k * z_depth).exp();
                let n = j * nx + i;
                let (re, im) = spectrum[n];
                channels[0][n] = (t * re, t * im);
                // ∂/∂X multiplies by i·kx: (re + i·im)·i·kx = (−im·kx) + i·(re·kx).
                channels[1][n] = (-t * im * kx, t * re * kx);
                channels[2][n] = (-t * im * ky, t * re * ky);
                let (tr, ti) = traction[n];
                channels[3][n] = (t * tr, t * ti);
            }
        }
        // Nyquist bins of odd derivatives have no consistent sign: drop them.
        for j in 0..ny {
            channels[1][j * nx + nx / 2] = (0.0, 0.0);
        }
        for i in 0..nx {
            channels[2][(ny / 2) * nx + i] = (0.0, 0.0);
        }
        for c in channels.iter_mut() {
            fft2(c, nx, ny, true);
        }
        let values = (0..nx * ny)
            .map(|n| std::array::from_fn(|c| channels[c][n].0 as f32))
            .collect();
        Self {
            nx,
            ny,
            dx_mm,
            dy_mm,
            values,
            pressure_ratio: vec![1.0; nx * ny],
            flat: false,
        }
    }
}

/// The height field of one period of the grid of size `size_mm` (d > 0): cylinder
/// coverage of each of `GRID_CELLS²` cells (4 × 4 supersampling) times the bump height.
/// Returns (heights, cells per side, cell size in mm).
fn grid_heights(size_mm: f64, contact: &ContactParams) -> (Vec<f64>, usize, f64) {
    let (period, diameter) = match contact.period_rule {
        PeriodRule::Gap => (2.0 * size_mm, size_mm),
        PeriodRule::CentreToCentre => (size_mm, 0.5 * size_mm),
    };
    let n = GRID_CELLS;
    let dx = period / n as f64;
    let sub = 4;
    let r2 = (0.5 * diameter).powi(2);
    let mut h = vec![0.0; n * n];
    for j in 0..n {
        for i in 0..n {
            let mut inside = 0;
            for sj in 0..sub {
                for si in 0..sub {
                    let x = (i as f64 + (si as f64 + 0.5) / sub as f64) * dx - 0.5 * period;
                    let y = (j as f64 + (sj as f64 + 0.5) / sub as f64) * dx - 0.5 * period;
                    inside += usize::from(x * x + y * y <= r2);
                }
            }
            h[j * n + i] = contact.bump_height_mm * inside as f64 / (sub * sub) as f64;
        }
    }
    (h, n, dx)
}

/// A seed from a texture name (FNV-1a), so each natural texture is one fixed sample.
fn name_seed(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fn weave_height(t: &NaturalTexture, x: f64, y: f64, grain: &[f64]) -> f64 {
    let (p, a) = (t.period_mm, t.amplitude_mm);
    if p <= 0.0 || a == 0.0 {
        return 0.0;
    }
    let k = TAU / p;
    match t.weave {
        Weave::None => 0.0,
        Weave::Rib => a * (k * x).cos(),
        Weave::Plain => a * (k * x).cos() * (k * y).cos(),
        Weave::Twill => a * (k * (x + y) / 2f64.sqrt()).cos(),
        Weave::Hexagonal => {
            let mut s = 0.0;
            for m in 0..3 {
                let angle = m as f64 * TAU / 3.0;
                s += (k * (x * angle.cos() + y * angle.sin())).cos();
            }
            a * s / 3.0
        }
        Weave::Grain => {
            // Ridges at the (sorted) random positions in `grain`, each a cosine bump of width p/2.
            let i = grain.partition_point(|&g| g < x);
            let near = [i.wrapping_sub(1), i]
                .into_iter()
                .filter_map(|j| grain.get(j))
                .map(|&g| (x - g).abs())
                .fold(f64::INFINITY, f64::min);
            if near < 0.25 * p {
                a * (0.5 + 0.5 * (TAU * near / (0.5 * p)).cos())
            } else {
                0.0
            }
        }
        Weave::Scales => {
            // Rows of overlapping discs, alternate rows offset by half a period: a saw-tooth.
            let row = (y / p).floor();
            let phase = (x / p + 0.5 * row).rem_euclid(1.0);
            a * phase
        }
        Weave::Motif => {
            let golden = 0.5 * (1.0 + 5f64.sqrt());
            a * 0.5
                * ((k * x).cos() * (k * y).cos() + (k * x / golden).cos() * (k * y / golden).cos())
        }
        Weave::Wales => a * (PI * x / p).cos().abs(),
    }
}

/// The height field of a natural texture (`NATURAL_NX × NATURAL_NY` at `NATURAL_DX_MM`),
/// every height scaled by its compliance κ_m.
fn natural_heights(t: &NaturalTexture) -> Vec<f64> {
    let (nx, ny, dx) = (NATURAL_NX, NATURAL_NY, NATURAL_DX_MM);
    let (lx, ly) = (nx as f64 * dx, ny as f64 * dx);
    let mut rng = ChaCha8Rng::seed_from_u64(name_seed(t.name));
    let mut h = vec![0.0; nx * ny];
    // Periodic weave.
    let mut grain = Vec::new();
    if t.weave == Weave::Grain {
        let mut x = 0.0;
        while x < lx {
            grain.push(x);
            x += t.period_mm * (2.0 / 3.0 + (4.0 / 3.0) * rng.random::<f64>());
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            h[j * nx + i] = weave_height(t, i as f64 * dx, j as f64 * dx, &grain);
        }
    }
    // Self-affine roughness: white noise shaped by the square root of the spectrum.
    if t.roughness_rms_mm > 0.0 {
        let mut noise: Vec<Complex> = (0..nx * ny).map(|_| (gaussian(&mut rng), 0.0)).collect();
        fft2(&mut noise, nx, ny, false);
        for j in 0..ny {
            let ky = TAU * frequency_index(j, ny) / ly;
            for i in 0..nx {
                let kx = TAU * frequency_index(i, nx) / lx;
                let k2 = (kx * kx + ky * ky) * t.correlation_mm * t.correlation_mm;
                let amp = (1.0 + k2).powf(-0.5 * (1.0 + t.hurst));
                let c = &mut noise[j * nx + i];
                *c = (c.0 * amp, c.1 * amp);
            }
        }
        noise[0] = (0.0, 0.0);
        fft2(&mut noise, nx, ny, true);
        let rms = (noise.iter().map(|c| c.0 * c.0).sum::<f64>() / (nx * ny) as f64).sqrt();
        if rms > 0.0 {
            for (v, c) in h.iter_mut().zip(&noise) {
                *v += t.roughness_rms_mm * c.0 / rms;
            }
        }
    }
    // Sparse features: Poisson-scattered discs with a soft edge.
    if let Some(f) = t.features {
        let expected = f.density_per_cm2 * lx * ly / 100.0;
        let count = poisson(&mut rng, expected);
        let r = 0.5 * f.diameter_mm;
        let reach = (r / dx).ceil() as isize + 1;
        for _ in 0..count {
            let (cx, cy) = (rng.random::<f64>() * lx, rng.random::<f64>() * ly);
            let (ci, cj) = ((cx / dx) as isize, (cy / dx) as isize);
            for dj in -reach..=reach {
                for di in -reach..=reach {
                    let (i, j) = (ci + di, cj + dj);
                    let (px, py) = (i as f64 * dx, j as f64 * dx);
                    let d = ((px - cx).powi(2) + (py - cy).powi(2)).sqrt();
                    let cover = (0.5 - (d - r) / dx).clamp(0.0, 1.0);
                    if cover > 0.0 {
                        let (wi, wj) = (i.rem_euclid(nx as isize), j.rem_euclid(ny as isize));
                        h[wj as usize * nx + wi as usize] += f.height_mm * cover;
                    }
                }
            }
        }
    }
    h.iter_mut().for_each(|v| *v *= t.compliance);
    h
}

/// A standard normal draw (Box–Muller).
pub(crate) fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

/// A Poisson draw of mean `mean` (inversion for small means, normal approximation above 50).
pub(crate) fn poisson(rng: &mut ChaCha8Rng, mean: f64) -> u64 {
    if mean <= 0.0 {
        return 0;
    }
    if mean > 50.0 {
        return (mean + mean.sqrt() * gaussian(rng)).round().max(0.0) as u64;
    }
    let limit = (-mean).exp();
    let (mut k, mut p) = (0u64, rng.random::<f64>());
    while p > limit {
        k += 1;
        p *= rng.random::<f64>();
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_unknown_names_are_errors() {
        assert_eq!(
            Texture::from_name("grid 2.5 mm").unwrap(),
            Texture::Grid { size_mm: 2.5 }
        );
        assert_eq!(
            Texture::from_name("5 mm").unwrap(),
            Texture::Grid { size_mm: 5.0 }
        );
        assert_eq!(Texture::from_name("Felt").unwrap().name(), "felt");
        for t in &NATURAL_TEXTURES {
            assert_eq!(Texture::from_name(t.name).unwrap().name(), t.name);
        }
        let err = Texture::from_name("velvet").unwrap_err();
        assert!(
            matches!(err, SimulationError::UnknownTexture { ref name, .. } if name == "velvet")
        );
        assert!(matches!(
            Texture::from_name("grid 7 mm"),
            Err(SimulationError::InvalidParameter {
                field: "texture.size_mm",
                ..
            })
        ));
        assert!(matches!(
            Texture::grid(-1.0),
            Err(SimulationError::InvalidParameter { .. })
        ));
    }

    fn prepared(name: &str) -> (TextureField, Surface) {
        let p = SimParams::default();
        let q = p.nominal_pressure_mpa(20.0);
        Texture::from_name(name).unwrap().prepare(&p, q)
    }

    #[test]
    fn conformed_skin_makes_fine_grids_nearly_flat_and_coarse_grids_deep_monotonically() {
        let (flat, _) = prepared("grid 0 mm");
        assert_eq!(flat.max_deflection_mm(), 0.0);
        let all: Vec<(f64, f64)> = GRID_SIZES_MM[1..]
            .iter()
            .map(|&d| {
                let (f, s) = prepared(&format!("grid {d} mm"));
                (f.max_deflection_mm(), s.max_sag_mm)
            })
            .collect();
        assert!(all[0].0 < 1e-3, "{all:?}");
        assert!(all[9].0 > 0.2 && (all[9].1 - 1.0).abs() < 1e-6, "{all:?}");
        assert!(
            all.windows(2)
                .all(|w| w[1].0 >= w[0].0 && w[1].1 >= w[0].1 - 1e-9),
            "{all:?}"
        );
    }

    #[test]
    fn friction_and_the_onset_snap_differ_between_grids() {
        // Issue 12 item 1: friction follows the contact, so the snap (μ_s − μ_k) and the stick
        // distance (μ_s) are texture-dependent.
        let surfaces: Vec<Surface> = GRID_SIZES_MM
            .iter()
            .map(|&d| prepared(&format!("grid {d} mm")).1)
            .collect();
        let snap = |s: &Surface| s.mu_static - s.mu_kinetic;
        // The draped skin interlocks with the bumps: the snap grows from the flat plate to the
        // 2.5 mm grid (fine grids barely differ: the skin hardly sags into sub-mm gaps).
        assert!(
            snap(&surfaces[5]) - snap(&surfaces[0]) > 0.02,
            "{surfaces:?}"
        );
        assert!(
            surfaces[..=5]
                .windows(2)
                .all(|w| snap(&w[1]) >= snap(&w[0])),
            "{surfaces:?}"
        );
        assert!(
            surfaces[10].mu_static > surfaces[5].mu_static,
            "{surfaces:?}"
        );
        assert!(
            surfaces
                .iter()
                .all(|s| s.mu_static >= s.mu_kinetic && s.mu_kinetic > 0.0)
        );
        // More contact once the skin reaches the floor of the coarse gaps.
        assert!(surfaces[10].contact_fraction > surfaces[2].contact_fraction);
    }

    #[test]
    fn transfer_function_matches_a_single_cosine() {
        // A cosine of wavelength λ comes out scaled by T(2π/λ) and its derivative by k.
        let c = ContactParams::default();
        let (n, lambda) = (64, 8.0);
        let dx = lambda / n as f64;
        let h: Vec<f64> = (0..n * n)
            .map(|i| (TAU * (i % n) as f64 / n as f64).cos())
            .collect();
        let f = TextureField::from_surface(&h, &h, (n, n), (dx, dx), &c);
        let k = TAU / lambda;
        let t = (1.0 + k * c.skin_depth_mm) * (-k * c.skin_depth_mm).exp();
        let s = f.sample(0.0, 1.0);
        assert!((s.w - t).abs() < 1e-5, "{} vs {t}", s.w);
        assert!(
            (s.traction_mpa - t).abs() < 1e-5,
            "{} vs {t}",
            s.traction_mpa
        );
        let q = f.sample(lambda / 4.0, 0.0);
        assert!((q.dw_dx + t * k).abs() < 1e-4, "{} vs {}", q.dw_dx, -t * k);
    }

    #[test]
    fn natural_fields_are_deterministic_and_scaled_by_compliance() {
        let (a, _) = prepared("wool");
        let (b, _) = prepared("wool");
        assert_eq!(a.sample(12.3, 4.5), b.sample(12.3, 4.5));
        let (acrylic, _) = prepared("acrylic");
        assert!(acrylic.max_deflection_mm() < 0.01);
        assert!(a.max_deflection_mm() > 0.01);
    }
}
