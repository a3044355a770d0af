//! The 20 natural textures of the paper as materials (spec §2.4; §9): each a height field
//! (periodic weave, self-affine roughness, sparse features, scaled by its relief compliance
//! κ_m), a compliant layer in series with the dome ([`super::layer`]) and a friction prior
//! with a stated spread. [`NATURAL_TEXTURES`] lists them with the sources of every column.
//!
//! The random parts are drawn from a seed derived from the texture's name only, so a texture is
//! the same sample in every dataset. **The numbers are physical priors, never fitted to
//! classification results.**

use super::fabric::{FabricMechanics, Pile};
use super::fft::{Complex, fft2, frequency_index};
use super::layer::Layer;
use super::random::{gaussian, poisson};
use neurotac_core::seed_hash::fnv1a;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

/// Sample spacing of natural fields (mm) and their size (a power of two each way).
pub(crate) const NATURAL_DX_MM: f64 = 0.25;
pub(crate) const NATURAL_NX: usize = 512;
pub(crate) const NATURAL_NY: usize = 256;

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
    /// The compliant layer under the surface (`None`: rigid), [`Layer`].
    pub layer: Option<Layer>,
    /// Static friction μ_s against the skin: the prior's mean.
    pub mu_static: f64,
    /// Kinetic friction μ_k.
    pub mu_kinetic: f64,
    /// Micro-slip rate λ_ms at 15 mm/s (s⁻¹).
    pub microslip_rate_hz: f64,
    /// Velocity-weakening speed v_c (mm/s), `μ(v) = μ_k + (μ_s − μ_k)·e^(−|v|/v_c)`; 0 = none.
    pub weakening_speed_mm_s: f64,
    /// Its mechanics as a specimen: fabric properties, pile, friction spread.
    pub material: Material,
}

/// What a natural texture is as a specimen besides its surface and compression: a fabric's
/// in-plane and bending mechanics (mounting drag and wrinkling), its pile, and how much its
/// friction varies between specimens ([`super::fabric`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Kawabata KES-FB1/FB2 properties of a fabric (`None`: not a fabric).
    pub fabric: Option<FabricMechanics>,
    /// Hairs standing proud of its surface (`None`: none).
    pub pile: Option<Pile>,
    /// Relative standard deviation of its friction between specimens: each recording (rig
    /// seed) draws its specimen's μ_s and μ_k from it, sharing one factor.
    pub friction_spread: f64,
}

#[allow(clippy::too_many_arguments)]
const fn natural(
    name: &'static str,
    weave: Weave,
    (period_mm, amplitude_mm): (f64, f64),
    (roughness_rms_mm, correlation_mm, hurst): (f64, f64, f64),
    features: Option<Features>,
    compliance: f64,
    layer: Option<Layer>,
    (mu_static, mu_kinetic, microslip_rate_hz): (f64, f64, f64),
    material: Material,
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
        layer,
        mu_static,
        mu_kinetic,
        microslip_rate_hz,
        weakening_speed_mm_s: 0.0,
        material,
    }
}

const fn features(density_per_cm2: f64, diameter_mm: f64, height_mm: f64) -> Option<Features> {
    Some(Features {
        density_per_cm2,
        diameter_mm,
        height_mm,
    })
}

/// The 20 natural textures of the paper (Table II order) as materials; where each column's
/// values come from is listed under `natural.*` in
/// [`PARAMETER_SOURCES`](super::params::PARAMETER_SOURCES) (and so in every parameter file's
/// `sources`).
///
/// - **Geometry** (weave, roughness, features, κ_m): the spec's §2.4 priors; where it gives a
///   range the middle is used; an unstated Hurst exponent is 0.8.
/// - **Layer** (series compliance, [`Layer`]): fabrics from Kawabata compression (KES-FB3,
///   thickness T₀, compressibility EMC and resilience RC, middle of the typical range of each
///   fabric class); the PU foam from Gibson & Ashby (E ≈ 50 kPa, densifying at 90 % strain,
///   10 mm thick \[A\]); wood, MDF, acrylic, metal mesh and foil are rigid (GPa moduli). Where
///   two textures fall in the same fabric class their layers are the same (the organzas; tweed
///   and needlecord): no source separates them.
/// - **Friction** (μ_s, μ_k): kinetic friction of a rubber skin = adhesion on the fraction of
///   the area in contact plus the texture's ploughing friction measured with a rigid tool (Penn
///   Haptic Texture Toolkit, Culbertson et al. 2014, one value per material class), μ_s/μ_k =
///   1.2 for fabrics and foam (Temel et al. 2022: 1.14–1.24), 1.3 for smooth adhesive solids.
///   No two textures share a value.
/// - **Material** ([`Material`]): KES-FB1 tensile strain EMT and shear rigidity G, KES-FB2
///   bending rigidity B (middle of each fabric class's typical range); hairs standing proud of
///   pile and hairy fabrics (length, fibre diameter and modulus, density); each specimen's
///   friction drawn with its class's spread — 21 % for cotton fabrics (Temel et al. 2022:
///   0.90 ± 0.19), 25 % for smooth adhesive solids, 15 % for wood, 20 % where no source
///   separates a class.
/// - **Micro-slips** (λ_ms): the spec's §2.4 rates \[A\].
///
/// Columns: name, weave, (p_w, a_w) in mm, (h_rms in mm, ξ in mm, H), features (per cm²,
/// diameter mm, height mm), κ_m, layer, (μ_s, μ_k, λ_ms in s⁻¹), material.
#[rustfmt::skip]
pub const NATURAL_TEXTURES: [NaturalTexture; 20] = {
    use Weave::*;
    const RIGID: Option<Layer> = Option::None;
    /// A fabric layer from KES-FB3: thickness T₀ (mm), compressibility EMC and resilience RC.
    const fn fabric(thickness_mm: f64, compressibility: f64, resilience: f64) -> Option<Layer> {
        Some(Layer::fabric(thickness_mm, compressibility, resilience))
    }
    const FOAM: Option<Layer> = Some(Layer { thickness_mm: 10.0, modulus_mpa: 0.05, densification_strain: 0.9, loss_tangent: 0.15 });
    /// KES-FB1 tensile strain EMT and shear rigidity G (gf/(cm·deg)), KES-FB2 bending rigidity
    /// B (gf·cm²/cm).
    const fn kes(tensile_strain: f64, shear_rigidity_gf_cm_deg: f64, bending_rigidity_gf_cm2_cm: f64) -> Option<FabricMechanics> {
        Some(FabricMechanics { tensile_strain, shear_rigidity_gf_cm_deg, bending_rigidity_gf_cm2_cm })
    }
    /// Hairs: length (mm), fibre diameter (mm), fibre modulus (MPa), hairs per mm².
    const fn hairs(hair_length_mm: f64, fibre_diameter_mm: f64, fibre_modulus_mpa: f64, density_per_mm2: f64) -> Option<Pile> {
        Some(Pile { hair_length_mm, fibre_diameter_mm, fibre_modulus_mpa, density_per_mm2 })
    }
    const fn material(fabric: Option<FabricMechanics>, pile: Option<Pile>, friction_spread: f64) -> Material {
        Material { fabric, pile, friction_spread }
    }
    const SOLID: Material = material(Option::None, Option::None, 0.25);
    const WOOD: Material = material(Option::None, Option::None, 0.15);
    const CELLULAR: Material = material(Option::None, Option::None, 0.2);
    const NO_PILE: Option<Pile> = Option::None;
    let mut acrylic = natural("acrylic", None, (0.0, 0.0), (0.0005, 0.1, 0.8), Option::None, 1.0, RIGID, (1.45, 1.12, 5.0), SOLID);
    // "strong v-weakening": stick-slip at the slide speed needs (μ_s − μ_k)·N/(k_t·v_c) > τ.
    acrylic.weakening_speed_mm_s = 15.0;
    [
        natural("foam", None, (0.0, 0.0), (0.15, 0.5, 0.6), features(60.0, 0.6, -0.3), 0.1, FOAM, (1.33, 1.11, 40.0), CELLULAR),
        natural("plywood", Grain, (1.5, 0.02), (0.01, 0.3, 0.7), Option::None, 1.0, RIGID, (0.97, 0.75, 20.0), WOOD),
        natural("mdf", None, (0.0, 0.0), (0.008, 0.2, 0.8), Option::None, 1.0, RIGID, (1.03, 0.79, 15.0), WOOD),
        acrylic,
        natural("wool", Plain, (3.5, 0.4), (0.15, 1.0, 0.5), Option::None, 0.3, fabric(2.0, 0.5, 0.4), (0.76, 0.63, 30.0),
            material(kes(0.25, 0.5, 0.15), hairs(1.5, 0.025, 3000.0, 2.0), 0.2)),
        natural("fake fur", None, (0.0, 0.0), (0.5, 2.0, 0.8), Option::None, 0.05, fabric(20.0, 0.72, 0.4), (1.22, 1.02, 50.0),
            material(kes(0.2, 1.0, 1.0), hairs(3.0, 0.04, 3000.0, 20.0), 0.2)),
        natural("liquid satin", Plain, (0.35, 0.01), (0.01, 0.3, 0.8), Option::None, 0.6, fabric(0.22, 0.22, 0.5), (0.65, 0.54, 5.0),
            material(kes(0.05, 0.4, 0.03), NO_PILE, 0.2)),
        natural("shimmer organza", Plain, (0.25, 0.02), (0.015, 0.2, 0.8), Option::None, 0.8, fabric(0.14, 0.17, 0.5), (0.44, 0.37, 10.0),
            material(kes(0.03, 1.0, 0.03), NO_PILE, 0.2)),
        natural("tweed", Twill, (2.0, 0.25), (0.12, 0.8, 0.5), features(0.5, 3.0, 0.3), 0.5, fabric(1.15, 0.4, 0.45), (0.53, 0.44, 30.0),
            material(kes(0.05, 2.0, 0.2), hairs(1.0, 0.03, 3000.0, 2.0), 0.2)),
        natural("lace", Motif, (6.0, 0.3), (0.05, 1.0, 0.8), features(2.0, 2.0, -0.3), 0.6, fabric(0.55, 0.4, 0.5), (0.48, 0.40, 20.0),
            material(kes(0.2, 0.5, 0.03), NO_PILE, 0.2)),
        natural("flarefree net", Hexagonal, (1.2, 0.08), (0.0, 1.0, 0.8), Option::None, 0.8, fabric(0.35, 0.45, 0.5), (0.42, 0.35, 15.0),
            material(kes(0.3, 0.2, 0.01), NO_PILE, 0.2)),
        natural("embroidered cotton", Plain, (0.5, 0.04), (0.03, 0.3, 0.8), features(1.56, 3.0, 0.5), 0.6, fabric(0.32, 0.27, 0.5), (0.51, 0.43, 20.0),
            material(kes(0.04, 1.2, 0.1), NO_PILE, 0.21)),
        natural("shirt canvas", Plain, (0.6, 0.06), (0.03, 0.3, 0.8), Option::None, 0.7, fabric(0.75, 0.22, 0.5), (0.60, 0.50, 15.0),
            material(kes(0.03, 3.0, 0.4), NO_PILE, 0.21)),
        natural("fairydust organza", Plain, (0.25, 0.02), (0.015, 0.2, 0.8), features(5.0, 1.0, 0.05), 0.8, fabric(0.14, 0.17, 0.5), (0.45, 0.375, 15.0),
            material(kes(0.03, 1.0, 0.03), NO_PILE, 0.2)),
        natural("sequins allover", Scales, (3.5, 0.25), (0.0, 1.0, 0.8), Option::None, 0.9, fabric(0.55, 0.2, 0.5), (0.92, 0.71, 10.0),
            material(kes(0.15, 0.8, 0.2), NO_PILE, 0.2)),
        natural("metallic mesh", Plain, (2.5, 0.5), (0.02, 0.5, 0.8), Option::None, 1.0, RIGID, (0.46, 0.39, 10.0), SOLID),
        natural("felt", None, (0.0, 0.0), (0.06, 0.4, 0.6), Option::None, 0.4, fabric(2.0, 0.3, 0.35), (0.72, 0.60, 30.0),
            material(kes(0.1, 4.0, 1.0), hairs(0.5, 0.025, 3000.0, 5.0), 0.2)),
        natural("needlecord", Wales, (1.6, 0.35), (0.05, 0.3, 0.8), Option::None, 0.5, fabric(1.15, 0.4, 0.45), (0.55, 0.46, 20.0),
            material(kes(0.05, 1.5, 0.3), hairs(0.3, 0.015, 8000.0, 10.0), 0.21)),
        natural("fleece", None, (0.0, 0.0), (0.2, 1.5, 0.5), Option::None, 0.1, fabric(3.0, 0.6, 0.4), (0.58, 0.48, 35.0),
            material(kes(0.25, 0.4, 0.2), hairs(1.0, 0.015, 4000.0, 30.0), 0.2)),
        natural("microdot foil", Plain, (0.45, 0.02), (0.002, 0.1, 0.8), Option::None, 1.0, RIGID, (1.15, 0.89, 10.0), SOLID),
    ]
};

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
pub(crate) fn natural_heights(t: &NaturalTexture) -> Vec<f64> {
    let (nx, ny, dx) = (NATURAL_NX, NATURAL_NY, NATURAL_DX_MM);
    let (lx, ly) = (nx as f64 * dx, ny as f64 * dx);
    // Seeded by the name alone (FNV-1a), so each natural texture is one fixed sample.
    let mut rng = ChaCha8Rng::seed_from_u64(fnv1a(t.name.as_bytes()));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_textures_share_a_friction_prior() {
        for (i, a) in NATURAL_TEXTURES.iter().enumerate() {
            for b in &NATURAL_TEXTURES[i + 1..] {
                assert!(
                    (a.mu_static, a.mu_kinetic) != (b.mu_static, b.mu_kinetic),
                    "{} and {} share their friction",
                    a.name,
                    b.name
                );
            }
            assert!(
                a.mu_static > a.mu_kinetic && a.mu_kinetic > 0.0,
                "{}",
                a.name
            );
        }
    }

    #[test]
    fn soft_materials_have_layers_and_rigid_ones_do_not() {
        let find = |name: &str| NATURAL_TEXTURES.iter().find(|t| t.name == name).unwrap();
        for rigid in [
            "acrylic",
            "mdf",
            "plywood",
            "metallic mesh",
            "microdot foil",
        ] {
            assert!(find(rigid).layer.is_none(), "{rigid}");
        }
        // Pile and foam are far softer and thicker than a satin.
        let satin = find("liquid satin").layer.unwrap();
        for soft in ["fake fur", "fleece", "foam", "wool"] {
            let layer = find(soft).layer.unwrap();
            assert!(layer.thickness_mm > 5.0 * satin.thickness_mm, "{soft}");
        }
    }
}
