//! A compliant texture in series with the dome: how much of the commanded press reaches the
//! skin, the normal force that results, and how much of the base's motion shears the skin
//! rather than the texture (spec §9 "textures must differ as materials").
//!
//! **Normal (series compliance).** The arm presses the dome a depth δ into the texture's free
//! surface; the dome and a compliant layer share it, δ = δ_d + δ_t, at one force N:
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
//! The contact radius stays the geometric overlap a = √(2Rδ): the skin touches the layer over
//! the whole footprint, but presses it with the force N.
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
}

impl Layer {
    /// A fabric from its Kawabata compression: thickness T₀ (mm) and compressibility EMC
    /// (a fraction): E_t = 4.9 kPa / EMC, densifying at EMC.
    pub const fn fabric(thickness_mm: f64, compressibility: f64) -> Self {
        Self {
            thickness_mm,
            modulus_mpa: 0.0049 / compressibility,
            densification_strain: compressibility,
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
    /// Depth of the dome's own indentation δ_d (mm).
    pub dome_depth_mm: f64,
    /// Normal force N (N).
    pub normal_force_n: f64,
    /// Contact radius a = √(2Rδ) (mm).
    pub contact_radius_mm: f64,
    /// Fraction of the base's travel that shears the skin, k_tex/(k_t + k_tex) (1: rigid).
    pub shear_share: f64,
}

impl Press {
    /// The press of the dome of `params` (its force at the mean press depth, the skin's
    /// tangential stiffness) of radius `dome_radius_mm`, commanded `depth_mm` deep into a
    /// texture with `layer` ([`solve`](Self::solve)).
    pub fn of(
        layer: Option<&Layer>,
        params: &SimParams,
        depth_mm: f64,
        dome_radius_mm: f64,
    ) -> Self {
        let k = &params.kinematics;
        Self::solve(
            layer,
            depth_mm,
            dome_radius_mm,
            (k.normal_force_n, k.press_depth_mm),
            params.contact.tangential_stiffness_n_mm,
        )
    }

    /// The nominal contact pressure N/(π·a²) (MPa).
    pub fn nominal_pressure_mpa(&self) -> f64 {
        self.normal_force_n / (PI * self.contact_radius_mm.powi(2))
    }

    /// The press of a dome of radius `radius_mm` commanded `depth_mm` deep into a texture with
    /// `layer` (rigid for `None`); the dome gives `force_n` at `reference_depth_mm` on a rigid
    /// plate; `skin_stiffness_n_mm` is the skin's tangential stiffness k_t.
    pub fn solve(
        layer: Option<&Layer>,
        depth_mm: f64,
        radius_mm: f64,
        (force_n, reference_depth_mm): (f64, f64),
        skin_stiffness_n_mm: f64,
    ) -> Self {
        let dome = |d: f64| force_n * (d.max(0.0) / reference_depth_mm).powf(1.5);
        let contact_radius_mm = (2.0 * radius_mm * depth_mm.max(0.0)).sqrt();
        let Some(layer) = layer else {
            return Self {
                dome_depth_mm: depth_mm,
                normal_force_n: dome(depth_mm),
                contact_radius_mm,
                shear_share: 1.0,
            };
        };
        // dome(δ_d) rises and layer(δ − δ_d) falls with δ_d: bisect their difference.
        let (mut lo, mut hi) = (0.0, depth_mm.max(0.0));
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if dome(mid) < layer.force_n(depth_mm - mid, radius_mm) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let dome_depth_mm = 0.5 * (lo + hi);
        let k_tex = layer.modulus_mpa / 3.0 * PI * contact_radius_mm.powi(2) / layer.thickness_mm;
        Self {
            dome_depth_mm,
            normal_force_n: dome(dome_depth_mm),
            contact_radius_mm,
            shear_share: k_tex / (skin_stiffness_n_mm + k_tex),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rigid_texture_takes_the_whole_press_and_a_soft_layer_shares_it() {
        let rigid = Press::solve(None, 2.0, 20.0, (2.0, 2.0), 2.0);
        assert_eq!(
            (rigid.dome_depth_mm, rigid.normal_force_n, rigid.shear_share),
            (2.0, 2.0, 1.0)
        );
        // A thin, barely compressible fabric densifies at once: nearly the rigid press.
        let satin = Press::solve(Some(&Layer::fabric(0.22, 0.22)), 2.0, 20.0, (2.0, 2.0), 2.0);
        assert!(
            (satin.dome_depth_mm - (2.0 - 0.22 * 0.22)).abs() < 1e-6,
            "{satin:?}"
        );
        // A deep pile takes most of it: the force falls by an order of magnitude, and the pile
        // shears more than the skin.
        let fur = Press::solve(Some(&Layer::fabric(20.0, 0.72)), 2.0, 20.0, (2.0, 2.0), 2.0);
        assert!(fur.normal_force_n < 0.2 && fur.shear_share < 0.1, "{fur:?}");
        // Force balance at the solution.
        let layer = Layer::fabric(20.0, 0.72);
        let f_layer = layer.force_n(2.0 - fur.dome_depth_mm, 20.0);
        assert!((f_layer - fur.normal_force_n).abs() < 1e-9 * fur.normal_force_n.max(1.0));
        // The contact radius is the geometric overlap in every case.
        assert_eq!(fur.contact_radius_mm, rigid.contact_radius_mm);
    }

    #[test]
    fn a_softer_or_thicker_layer_never_presses_harder() {
        let forces: Vec<f64> = [0.2, 0.5, 1.0, 2.0, 4.0, 10.0]
            .iter()
            .map(|&t| Press::solve(Some(&Layer::fabric(t, 0.5)), 2.0, 20.0, (2.0, 2.0), 2.0))
            .map(|p| p.normal_force_n)
            .collect();
        assert!(
            forces.windows(2).all(|w| w[1] <= w[0] + 1e-12),
            "{forces:?}"
        );
    }
}
