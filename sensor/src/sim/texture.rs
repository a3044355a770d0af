//! Textures: the 11 bump grids and the 20 natural textures as height fields, put in contact
//! with the skin once per texture and filtered into the fields the pins feel (spec §2.1,
//! §2.2 steps 1–3, §2.4, and what §8 asks for: friction that follows the contact, a partial
//! contact whose sag grows with the gap, a pin-scale tangential channel at the bump edges).
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
//!    `μ_k = μ_k,adh·A/A_flat + tan δ·⟨|∂z_s/∂X|⟩`, `μ_s = μ_k,adh·(1 + e)·A/A_flat + ⟨|∂z_s/∂X|⟩`;
//!    while sliding, the skin catches on each row of bumps (`contact.edge_catches_per_period`);
//! 4. the field also keeps the contact pressure over its mean, unfiltered, for the onset's
//!    partial-slip front ([`super::slip_front`]).
//!
//! Fields are built once per texture and shared by all its trials: the physical sample is the
//! same object every slide.
//!
//! Natural textures ([`super::natural`]) are height fields with their own friction priors and
//! compliant layers; a layer sets the force, so the pressure their contact is solved at.

use super::contact::{ContactLaw, SkinContact, solve};
use super::error::SimulationError;
use super::fabric::{FabricMechanics, Pile};
use super::fft::{Complex, fft2, frequency_index};
use super::layer::{Layer, Press};
use super::natural::{
    NATURAL_DX_MM, NATURAL_NX, NATURAL_NY, NATURAL_TEXTURES, NaturalTexture, natural_heights,
};
use super::params::{ContactParams, PeriodRule, SimParams};
use std::f64::consts::TAU;

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
/// §2.4; friction follows the contact, §8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Static friction μ_s (before the recording's shared factor and drift).
    pub mu_static: f64,
    /// Kinetic friction μ_k.
    pub mu_kinetic: f64,
    /// Micro-slip rate at 15 mm/s (s⁻¹), Poisson in slip distance (natural textures).
    pub microslip_rate_hz: f64,
    /// Slip distance between edge catches (mm): a catch each time a row of bumps passes, locked
    /// to the texture (grids; `None` elsewhere).
    pub catch_period_mm: Option<f64>,
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
    /// Height of the specimen's free surface above the set's base (mm): a grid's bump height,
    /// a layer's thickness, 0 for the flat plate and rigid sheets (position control,
    /// [`super::layer`]).
    pub height_mm: f64,
    /// Mean sag of the skin below the texture's tops at the nominal press (mm).
    pub mean_sag_mm: f64,
    /// The compliant layer in series with the dome (`None`: rigid), [`super::layer`].
    pub layer: Option<Layer>,
    /// A fabric's in-plane and bending mechanics (mounting drag, wrinkling), [`super::fabric`].
    pub fabric: Option<FabricMechanics>,
    /// Hairs standing proud of the surface, [`super::fabric`].
    pub pile: Option<Pile>,
    /// Relative spread of the friction prior between specimens (0: friction follows from the
    /// contact, as on the printed grids).
    pub friction_spread: f64,
}

impl Surface {
    /// The press of a dome of radius `dome_radius_mm` whose press ends `depth_mm` below the
    /// set's base, on this surface (position control, [`super::layer`]).
    pub fn press(&self, params: &SimParams, depth_mm: f64, dome_radius_mm: f64) -> Press {
        Press::of(
            self.layer.as_ref(),
            params,
            params.overlap_mm(self.height_mm, depth_mm),
            self.mean_sag_mm,
            dome_radius_mm,
        )
    }
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

    /// Height of this texture's free surface above its set's base (mm): the bump height of a
    /// grid, a natural texture's layer thickness, 0 for the flat plate and rigid sheets.
    pub fn height_mm(&self, contact: &ContactParams) -> f64 {
        match self {
            Texture::Grid { size_mm } if *size_mm > 0.0 => contact.bump_height_mm,
            Texture::Grid { .. } => 0.0,
            Texture::Natural(t) => t.layer.map_or(0.0, |l| l.thickness_mm),
        }
    }

    /// Solves the skin's contact on this texture under the nominal press (position control,
    /// [`super::layer`]) and builds its field and surface (see the module docs).
    /// Deterministic; once per texture.
    ///
    /// On a grid the press and the contact depend on each other — the skin's sag into the
    /// gaps relieves the dome, and the dome's force sets the pressure the skin sags under — so
    /// the contact is solved [`PRESS_ITERATIONS`] times, each at the press the last one implies
    /// (the sag barely depends on the pressure: the skin's tension scales with it).
    pub fn prepare(&self, params: &SimParams, dome_radius_mm: f64) -> (TextureField, Surface) {
        let c = &params.contact;
        let height_mm = self.height_mm(c);
        let overlap = params.overlap_mm(height_mm, params.kinematics.press_depth_mm);
        match *self {
            Texture::Grid { size_mm } if size_mm > 0.0 => {
                let (h, n, dx) = grid_heights(size_mm, c);
                let mut sag = 0.0;
                let mut contact = None;
                for _ in 0..PRESS_ITERATIONS {
                    let press = Press::of(None, params, overlap, sag, dome_radius_mm);
                    let law =
                        ContactLaw::new(c, contact_pressure_mpa(&press, params, dome_radius_mm));
                    let solved = solve(&h, (n, n), (dx, dx), &law);
                    sag = solved.mean_sag_mm;
                    contact = Some(solved);
                }
                let contact = contact.expect("at least one iteration");
                let adhesion = c.adhesion_mu_kinetic * contact.real_area_ratio;
                let hysteresis = c.loss_tangent * contact.mean_abs_slope;
                let interlocking = contact.mean_abs_slope;
                let mu_kinetic = adhesion + hysteresis;
                let period = self.grid_period_mm(c.period_rule).expect("a grid");
                let surface = Surface {
                    mu_static: adhesion * (1.0 + c.static_excess) + interlocking,
                    mu_kinetic,
                    microslip_rate_hz: 0.0,
                    catch_period_mm: (c.edge_catches_per_period > 0.0)
                        .then(|| period / c.edge_catches_per_period),
                    weakening_speed_mm_s: 0.0,
                    height_mm,
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
                    ..contact_facts_flat()
                },
            ),
            Texture::Natural(t) => {
                // A compliant layer sets the force, so the pressure the contact is solved at.
                let press = Press::of(t.layer.as_ref(), params, overlap, 0.0, dome_radius_mm);
                let law = ContactLaw::new(c, contact_pressure_mpa(&press, params, dome_radius_mm));
                let h = natural_heights(t);
                let (nx, ny, dx) = (NATURAL_NX, NATURAL_NY, NATURAL_DX_MM);
                let contact = solve(&h, (nx, ny), (dx, dx), &law);
                let surface = Surface {
                    mu_static: t.mu_static,
                    mu_kinetic: t.mu_kinetic,
                    microslip_rate_hz: t.microslip_rate_hz,
                    weakening_speed_mm_s: t.weakening_speed_mm_s,
                    layer: t.layer,
                    friction_spread: t.material.friction_spread,
                    fabric: t.material.fabric,
                    pile: t.material.pile,
                    height_mm,
                    // The layer conforms: the relief's sag does not relieve the dome.
                    mean_sag_mm: 0.0,
                    ..contact_facts(&contact)
                };
                let field =
                    TextureField::from_contact(&contact, t.mu_kinetic, (nx, ny), (dx, dx), c);
                (field, surface)
            }
        }
    }
}

/// The pressure a texture's contact is solved at: the press's nominal pressure, or — for a
/// texture the press never reaches (no travel) — the rigid plate's at the reference depth, so
/// its surface facts stay defined.
fn contact_pressure_mpa(press: &Press, params: &SimParams, dome_radius_mm: f64) -> f64 {
    let q = press.nominal_pressure_mpa();
    if q > 0.0 {
        return q;
    }
    let k = &params.kinematics;
    Press::of(None, params, k.press_depth_mm, 0.0, dome_radius_mm).nominal_pressure_mpa()
}

/// Contact solves of a grid's [`Texture::prepare`]: the press and the skin's sag settle within
/// a millimetre's thousandth after two.
pub const PRESS_ITERATIONS: usize = 2;

/// The contact facts of a [`Surface`] (friction left at zero).
fn contact_facts(contact: &SkinContact) -> Surface {
    Surface {
        real_area_ratio: contact.real_area_ratio,
        mean_abs_slope: contact.mean_abs_slope,
        max_sag_mm: contact.max_sag_mm,
        mean_sag_mm: contact.mean_sag_mm,
        contact_fraction: contact.contact_fraction,
        ..contact_facts_flat()
    }
}

/// The contact facts of the flat plate (friction left at zero).
fn contact_facts_flat() -> Surface {
    Surface {
        real_area_ratio: 1.0,
        mean_abs_slope: 0.0,
        max_sag_mm: 0.0,
        mean_sag_mm: 0.0,
        height_mm: 0.0,
        contact_fraction: 1.0,
        mu_static: 0.0,
        mu_kinetic: 0.0,
        microslip_rate_hz: 0.0,
        catch_period_mm: None,
        weakening_speed_mm_s: 0.0,
        layer: None,
        fabric: None,
        pile: None,
        friction_spread: 0.0,
    }
}

/// The slide speed the micro-slip rates are stated at (mm/s, the paper's).
pub const REFERENCE_SPEED_MM_S: f64 = 15.0;

/// Cells per grid period (a power of two).
const GRID_CELLS: usize = 64;

/// `i` modulo `n` in `0..n` (Euclidean): a mask when `n` is a power of two (every field's
/// grid is; the same value without a division), else `rem_euclid`.
#[inline]
fn wrap(i: i64, n: usize) -> usize {
    if n.is_power_of_two() {
        (i & (n as i64 - 1)) as usize
    } else {
        i.rem_euclid(n as i64) as usize
    }
}

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
        let ([ia, ib, ic, id], tx, ty) = self.corners(x_mm, y_mm);
        let (a, b, c, d) = (
            &self.values[ia],
            &self.values[ib],
            &self.values[ic],
            &self.values[id],
        );
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
        let ([a, b, c, d], tx, ty) = self.corners(x_mm, y_mm);
        let v = &self.pressure_ratio;
        let top = v[a] + tx * (v[b] - v[a]);
        let bottom = v[c] + tx * (v[d] - v[c]);
        (top + ty * (bottom - top)) as f64
    }

    /// The four grid points around world point `(x_mm, y_mm)` (periodic; indices of
    /// (x, y), (x+1, y), (x, y+1), (x+1, y+1)) and the bilinear weights along x and y.
    #[inline]
    fn corners(&self, x_mm: f64, y_mm: f64) -> ([usize; 4], f32, f32) {
        let (fx, fy) = (x_mm / self.dx_mm, y_mm / self.dy_mm);
        let (flx, fly) = (fx.floor(), fy.floor());
        let (tx, ty) = ((fx - flx) as f32, (fy - fly) as f32);
        let (ix, iy) = (wrap(flx as i64, self.nx), wrap(fly as i64, self.ny));
        let next = |i: usize, n: usize| if i + 1 == n { 0 } else { i + 1 };
        let (jx, jy) = (next(ix, self.nx), next(iy, self.ny));
        let at = |x: usize, y: usize| y * self.nx + x;
        ([at(ix, iy), at(jx, iy), at(ix, jy), at(jx, jy)], tx, ty)
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
        let mean = contact.pressure_mpa.iter().sum::<f64>() / contact.pressure_mpa.len() as f64;
        let pressure_ratio = contact
            .pressure_mpa
            .iter()
            .map(|&p| if mean > 0.0 { (p / mean) as f32 } else { 1.0 })
            .collect();
        let z = &contact.surface_mm;
        Self::from_surface(z, &traction, pressure_ratio, dims, spacing, params)
    }

    /// Filters the skin surface `z` and the traction `tau` (row-major `nx × ny`, spacing
    /// `dx × dy` mm, periodic) by the elastic layer: removes the means, applies T(k) to both,
    /// and spectral derivatives for the deflection's gradient; `pressure_ratio` (p/⟨p⟩, same
    /// grid) is kept as it is.
    fn from_surface(
        z: &[f64],
        tau: &[f64],
        pressure_ratio: Vec<f32>,
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
            pressure_ratio,
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
        Texture::from_name(name).unwrap().prepare(&p, 20.0)
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
        // Friction follows the contact (spec §8), so the snap (μ_s − μ_k) and the stick
        // distance (μ_s) are texture-dependent.
        let surfaces: Vec<Surface> = GRID_SIZES_MM
            .iter()
            .map(|&d| prepared(&format!("grid {d} mm")).1)
            .collect();
        let snap = |s: &Surface| s.mu_static - s.mu_kinetic;
        // The draped skin interlocks with the bumps: the snap grows from the finest grid to the
        // 2.5 mm grid (fine grids barely differ: the skin hardly sags into sub-mm gaps) and
        // ends above the flat plate's.
        assert!(
            snap(&surfaces[5]) - snap(&surfaces[0]) > 0.02,
            "{surfaces:?}"
        );
        assert!(
            surfaces[1..=5]
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
        let f = TextureField::from_surface(&h, &h, vec![1.0; n * n], (n, n), (dx, dx), &c);
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
