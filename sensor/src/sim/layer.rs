//! The press under position control: how deep the dome goes into a specimen, the normal force
//! and contact radius that result, and how much of the base's motion shears the skin rather
//! than a compliant texture (spec §9 "textures must differ as materials").
//!
//! **Position control.** The arm's press ends at a fixed height, `kinematics.press_depth_mm`
//! δ₀ below the set's base surface (the flat printed plate, whose level the grids' floors share;
//! the rigid specimens' surface in the natural set). A specimen whose free surface stands h
//! above the base — a grid's bump tops (1 mm), a fabric's thickness T₀ — overlaps the dome by
//! δ₀ + h. The dome starts `press_travel_mm − δ₀` above the base (the lab's loop presses from a
//! fixed start); a specimen taller than that start clearance is touched when the press starts,
//! so its overlap is the whole travel: **overlap = min(δ₀ + h, travel)** \[A\]: the start above
//! the specimen is the script's; that the lab kept one base height for a set is the reading of
//! one fixed work frame per run.
//!
//! **Normal (series compliance).** The dome and a compliant layer share the overlap,
//! δ = δ_d + δ_t, at one force N:
//!
//! ```text
//! dome:   N = N₀·(δ_d/δ₀)^{3/2}                          (Hertz, the rigid-plate calibration point)
//! layer:  N = E_t·π·R·δ_t²/T₀   for δ_t < ε_c·T₀,  rigid beyond  (a Winkler layer of modulus
//!         E_t and thickness T₀ indented by a sphere of radius R; it densifies at strain ε_c)
//! ```
//!
//! solved for δ_d by bisection. Fabrics take E_t from their Kawabata compression (KES-FB3: the
//! secant modulus 4.9 kPa / EMC between 0.5 and 50 gf/cm², and the thickness lost T₀·EMC as the
//! densification limit); foams from Gibson & Ashby (Cellular Solids, 1997: E*/E_s = (ρ*/ρ_s)²).
//! On a rigid texture with relief (a grid) the skin drapes into the gaps by the contact solve's
//! mean sag s̄ below the tops ([`super::contact`]), so the dome's own compression is δ − s̄.
//!
//! **Contact radius.** The skin touches the specimen over the region where the undeformed dome
//! would cut its surface: a = √(2R·δ_c), with δ_c the overlap on a conforming layer (the layer
//! follows the dome's shape) and the dome's compression δ − s̄ on a rigid texture. So a thick
//! fabric pressed from a fixed height touches more pins than a thin one.
//!
//! **Tangential (series shear).** The layer shears too, with stiffness k_tex = G_t·π·a²/T₀
//! (G_t = E_t/3, an isotropic estimate of a layer's through-thickness shear \[A\]); in series
//! with the skin's k_t a fraction `k_tex/(k_t + k_tex)` of the base's travel shears the skin, so
//! a soft pile or foam takes longer to reach its stick limit.

use super::params::SimParams;
use std::f64::consts::PI;

/// A compliant layer under the texture's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    /// Thickness T₀ at a light load (mm).
    pub thickness_mm: f64,
    /// Compressive modulus E_t (MPa).
    pub modulus_mpa: f64,
    /// Strain ε_c at which it densifies and stops yielding.
    pub densification_strain: f64,
    /// Loss tangent tan δ of its compression at the passing frequency (the forward shift of a
    /// sliding contact's pressure, [`super::shear_spread`]).
    pub loss_tangent: f64,
}

impl Layer {
    /// A fabric from its Kawabata compression (KES-FB3): thickness T₀ (mm), compressibility EMC
    /// and resilience RC (fractions): E_t = 4.9 kPa / EMC, densifying at EMC, and the loss
    /// tangent of a cycle that returns RC of its work, `tan δ = (1 − RC)/(2π)` (a linear
    /// viscoelastic solid loses 2π·tan δ of its peak stored energy per cycle).
    pub const fn fabric(thickness_mm: f64, compressibility: f64, resilience: f64) -> Self {
        Self {
            thickness_mm,
            modulus_mpa: 0.0049 / compressibility,
            densification_strain: compressibility,
            loss_tangent: (1.0 - resilience) / (2.0 * std::f64::consts::PI),
        }
    }

    /// Force of the layer compressed by `depth_mm` under a sphere of radius `radius_mm` (N);
    /// infinite once densified.
    fn force_n(&self, depth_mm: f64, radius_mm: f64) -> f64 {
        if depth_mm > self.densification_strain * self.thickness_mm {
            f64::INFINITY
        } else {
            self.modulus_mpa * PI * radius_mm * depth_mm * depth_mm / self.thickness_mm
        }
    }
}

/// The press of one slide: what reaches the skin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Press {
    /// Overlap of the dome with the specimen's free surface (mm): min(δ₀ + h, travel).
    pub overlap_mm: f64,
    /// Depth of the dome's own compression δ_d (mm).
    pub dome_depth_mm: f64,
    /// Normal force N (N).
    pub normal_force_n: f64,
    /// Contact radius a = √(2R·δ_c) (mm).
    pub contact_radius_mm: f64,
    /// Fraction of the base's travel that shears the skin, k_tex/(k_t + k_tex) (1: rigid).
    pub shear_share: f64,
}

impl Press {
    /// The press of the dome of `params` (its force at the reference depth, the skin's
    /// tangential stiffness) of radius `dome_radius_mm` with `overlap_mm` into a texture with
    /// `layer` whose skin drapes `mean_sag_mm` below its tops ([`solve`](Self::solve)).
    pub fn of(
        layer: Option<&Layer>,
        params: &SimParams,
        overlap_mm: f64,
        mean_sag_mm: f64,
        dome_radius_mm: f64,
    ) -> Self {
        let k = &params.kinematics;
        Self::solve(
            layer,
            (overlap_mm, mean_sag_mm),
            dome_radius_mm,
            (k.normal_force_n, k.press_depth_mm),
            params.contact.tangential_stiffness_n_mm,
        )
    }

    /// The nominal contact pressure N/(π·a²) (MPa); 0 without contact.
    pub fn nominal_pressure_mpa(&self) -> f64 {
        let area = PI * self.contact_radius_mm.powi(2);
        if area > 0.0 {
            self.normal_force_n / area
        } else {
            0.0
        }
    }

    /// The press of a dome of radius `radius_mm` overlapping a texture with `layer` (rigid for
    /// `None`) by `overlap_mm`, its skin draping `mean_sag_mm` below the texture's tops; the
    /// dome gives `force_n` at `reference_depth_mm` on a rigid plate; `skin_stiffness_n_mm` is
    /// the skin's tangential stiffness k_t.
    pub fn solve(
        layer: Option<&Layer>,
        (overlap_mm, mean_sag_mm): (f64, f64),
        radius_mm: f64,
        (force_n, reference_depth_mm): (f64, f64),
        skin_stiffness_n_mm: f64,
    ) -> Self {
        let dome = |d: f64| force_n * (d.max(0.0) / reference_depth_mm).powf(1.5);
        let radius = |depth: f64| (2.0 * radius_mm * depth.clamp(0.0, radius_mm)).sqrt();
        let overlap_mm = overlap_mm.max(0.0);
        let Some(layer) = layer else {
            let dome_depth_mm = (overlap_mm - mean_sag_mm).max(0.0);
            return Self {
                overlap_mm,
                dome_depth_mm,
                normal_force_n: dome(dome_depth_mm),
                contact_radius_mm: radius(dome_depth_mm),
                shear_share: 1.0,
            };
        };
        // dome(δ_d) rises and layer(δ − δ_d) falls with δ_d: bisect their difference.
        let (mut lo, mut hi) = (0.0, overlap_mm);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if dome(mid) < layer.force_n(overlap_mm - mid, radius_mm) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let dome_depth_mm = 0.5 * (lo + hi);
        let contact_radius_mm = radius(overlap_mm);
        let k_tex = layer.modulus_mpa / 3.0 * PI * contact_radius_mm.powi(2) / layer.thickness_mm;
        Self {
            overlap_mm,
            dome_depth_mm,
            normal_force_n: dome(dome_depth_mm),
            contact_radius_mm,
            shear_share: if k_tex > 0.0 {
                k_tex / (skin_stiffness_n_mm + k_tex)
            } else {
                0.0
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rigid_texture_takes_the_whole_press_and_a_soft_layer_shares_it() {
        let rigid = Press::solve(None, (2.0, 0.0), 20.0, (2.0, 2.0), 2.0);
        assert_eq!(
            (rigid.dome_depth_mm, rigid.normal_force_n, rigid.shear_share),
            (2.0, 2.0, 1.0)
        );
        // A thin, barely compressible fabric densifies at once: nearly the rigid press.
        let satin = Press::solve(
            Some(&Layer::fabric(0.22, 0.22, 0.5)),
            (2.0, 0.0),
            20.0,
            (2.0, 2.0),
            2.0,
        );
        assert!(
            (satin.dome_depth_mm - (2.0 - 0.22 * 0.22)).abs() < 1e-6,
            "{satin:?}"
        );
        // A deep pile takes most of it: the force falls by an order of magnitude, and the pile
        // shears more than the skin.
        let fur = Press::solve(
            Some(&Layer::fabric(20.0, 0.72, 0.4)),
            (2.0, 0.0),
            20.0,
            (2.0, 2.0),
            2.0,
        );
        assert!(fur.normal_force_n < 0.2 && fur.shear_share < 0.1, "{fur:?}");
        // Force balance at the solution.
        let layer = Layer::fabric(20.0, 0.72, 0.4);
        let f_layer = layer.force_n(2.0 - fur.dome_depth_mm, 20.0);
        assert!((f_layer - fur.normal_force_n).abs() < 1e-9 * fur.normal_force_n.max(1.0));
        // The contact radius is the geometric overlap in every case.
        assert_eq!(fur.contact_radius_mm, rigid.contact_radius_mm);
    }

    #[test]
    fn under_position_control_height_deepens_the_press_and_draping_relieves_the_dome() {
        let p = SimParams::default();
        // Grid tops stand 1 mm above the base: 3 mm of overlap; a thick pile is capped at the
        // travel (the dome starts on it).
        assert_eq!(p.overlap_mm(1.0, 2.0), 3.0);
        assert_eq!(p.overlap_mm(20.0, 2.0), p.kinematics.press_travel_mm);
        assert_eq!(p.overlap_mm(0.0, 2.0), 2.0);
        // On a rigid grid whose skin drapes 0.6 mm below the tops the dome is compressed 2.4 mm.
        let draped = Press::of(None, &p, 3.0, 0.6, 20.0);
        assert!((draped.dome_depth_mm - 2.4).abs() < 1e-12);
        assert!((draped.normal_force_n - 2.0 * 1.2f64.powf(1.5)).abs() < 1e-12);
        assert!((draped.contact_radius_mm - (2.0f64 * 20.0 * 2.4).sqrt()).abs() < 1e-12);
        // A 2 mm felt pressed from the same height overlaps 4 mm: a wider contact than the
        // rigid plate's and, once its 0.6 mm of give is used up, a larger force.
        let felt = Press::of(
            Some(&Layer::fabric(2.0, 0.3, 0.35)),
            &p,
            p.overlap_mm(2.0, 2.0),
            0.0,
            20.0,
        );
        let plate = Press::of(None, &p, 2.0, 0.0, 20.0);
        assert!(
            felt.contact_radius_mm > 1.3 * plate.contact_radius_mm,
            "{felt:?}"
        );
        assert!(felt.normal_force_n > plate.normal_force_n, "{felt:?}");
        // No overlap, no contact.
        let none = Press::of(None, &p, 0.0, 0.0, 20.0);
        assert_eq!((none.normal_force_n, none.contact_radius_mm), (0.0, 0.0));
        assert_eq!(none.nominal_pressure_mpa(), 0.0);
    }

    #[test]
    fn a_softer_or_thicker_layer_never_presses_harder() {
        let forces: Vec<f64> = [0.2, 0.5, 1.0, 2.0, 4.0, 10.0]
            .iter()
            .map(|&t| {
                Press::solve(
                    Some(&Layer::fabric(t, 0.5, 0.5)),
                    (2.0, 0.0),
                    20.0,
                    (2.0, 2.0),
                    2.0,
                )
            })
            .map(|p| p.normal_force_n)
            .collect();
        assert!(
            forces.windows(2).all(|w| w[1] <= w[0] + 1e-12),
            "{forces:?}"
        );
    }
}
