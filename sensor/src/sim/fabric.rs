//! A fabric specimen's mechanics beyond its compression ([`super::layer`]): the hairs standing
//! proud of its surface, and the drag and wrinkling of the fabric on its mounting at the onset.
//!
//! **Pile hairs (fibre beam mechanics).** Hairs of length L, diameter d and Young's modulus E_f
//! stand above a pile or hairy fabric at n per mm². Outside the contact the dome's surface rises
//! as r²/2R above the overlap, so hairs reach it out to `r = √(2R·(δ + L))`
//! ([`Pile::reach_mm`]). A hair pressed at its tip buckles as a clamped–free column at
//! `P = π²·E_f·I/(4L²)`, `I = π·d⁴/64`, and keeps about that load while bent further (the
//! elastica's plateau); sliding, its tip drags with the kinetic friction, so the reached annulus
//! carries the traction `τ = n·μ_k·P` ([`Pile::traction_mpa`]) — a share of the tangential load
//! outside the contact, spreading shear to rim pins ([`super::shear_spread`]). A single hair's
//! release moves the skin by far less than a DVS pixel resolves (a force step of
//! (μ_s − μ_k)·P: ≈ 10⁻⁷ mm, [`Pile::release_displacement_mm`]), so releases are not simulated;
//! `neurotac simulate check` prints the number.
//!
//! **Mounting drag and wrinkling (KES-FB1, KES-FB2).** A fabric lies on the base plate, taped
//! along its edges `contact.fabric_mount_span_mm` from the contact \[A\]. Under the dome it is
//! held by its friction on the plate, `H = μ_fb·N` (`contact.fabric_base_friction`). Where
//! the fabric's friction on the skin exceeds that, the onset's tangential load Q drags the
//! fabric under the contact once Q > H, against the fabric around it: a strip behind stretched
//! and a strip ahead compressed (tensile stiffness per width `E_m = 4.9 N/cm / EMT`, KES-FB1's
//! strain EMT at 500 gf/cm) and two side strips sheared (in-plane shear stiffness `G_m`, KES-FB1's
//! shear rigidity G), each 2a wide over the span L_m:
//!
//! ```text
//! k_fab = (2·E_m + 2·G_m)·2a/L_m          (the strip ahead counts until it wrinkles)
//! k_fab = (E_m + 2·G_m)·2a/L_m            (after)
//! ```
//!
//! in series with the skin (k_t) and the layer's through-thickness shear (k_tex), so the skin's
//! shear rises more slowly while the fabric is dragged. The strip ahead, clamped at both ends,
//! buckles (wrinkles) when its share of the drag reaches `P_cr = 4π²·B·2a/L_m²` (B: KES-FB2
//! bending rigidity per width): its support is lost at once, the fabric under the contact jumps
//! forward and the skin's shear drops — a small twitch inside the onset, earlier for limp
//! fabrics. After the skin's first full slip the fabric's drag is held at its kinetic level
//! (not simulated further).
//!
//! Units: KES-FB1 G in gf/(cm·deg) → N/mm per radian: × 9.807·10⁻³ N/gf ÷ 10 mm/cm × 57.30
//! deg/rad; KES-FB2 B in gf·cm²/cm → N·mm (per mm of width): × 9.807·10⁻³ × 100 ÷ 10.

use std::f64::consts::PI;

/// N/mm per radian of in-plane shear per gf/(cm·deg) (KES-FB1 G).
const SHEAR_RIGIDITY_N_MM: f64 = 9.807e-3 / 10.0 * 57.2958;
/// N·mm per gf·cm²/cm (KES-FB2 B).
const BENDING_RIGIDITY_N_MM: f64 = 9.807e-3 * 100.0 / 10.0;
/// Tension per width at KES-FB1's maximum load, 500 gf/cm (N/mm).
const KES_MAX_TENSION_N_MM: f64 = 500.0 * 9.807e-3 / 10.0;

/// Hairs standing proud of a fabric's surface (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pile {
    /// Length of the hairs above the fabric's surface (mm).
    pub hair_length_mm: f64,
    /// Fibre diameter (mm).
    pub fibre_diameter_mm: f64,
    /// Fibre Young's modulus (MPa).
    pub fibre_modulus_mpa: f64,
    /// Hairs per mm² of fabric.
    pub density_per_mm2: f64,
}

impl Pile {
    /// Euler load of one hair, clamped at the fabric and free at its tip (N).
    pub fn hair_buckling_n(&self) -> f64 {
        let i = PI * self.fibre_diameter_mm.powi(4) / 64.0;
        PI * PI * self.fibre_modulus_mpa * i / (4.0 * self.hair_length_mm.powi(2))
    }

    /// Drag traction of the hairs a sliding dome bends (MPa): n·μ_k·P.
    pub fn traction_mpa(&self, mu_kinetic: f64) -> f64 {
        self.density_per_mm2 * mu_kinetic * self.hair_buckling_n()
    }

    /// Outer radius the hairs reach on a dome of radius `dome_radius_mm` overlapping the fabric
    /// by `overlap_mm` (mm): √(2R·(δ + L)), at most R.
    pub fn reach_mm(&self, overlap_mm: f64, dome_radius_mm: f64) -> f64 {
        (2.0 * dome_radius_mm * (overlap_mm + self.hair_length_mm))
            .sqrt()
            .min(dome_radius_mm)
    }

    /// Displacement of the skin at depth `depth_mm` right under one hair when its tip lets go
    /// (mm): Cerruti's `u = F·2/(4πG·z)` for the force step `F = (μ_s − μ_k)·P` on a gel of
    /// shear modulus `gel_shear_mpa`.
    pub fn release_displacement_mm(
        &self,
        (mu_static, mu_kinetic): (f64, f64),
        gel_shear_mpa: f64,
        depth_mm: f64,
    ) -> f64 {
        let force = (mu_static - mu_kinetic).max(0.0) * self.hair_buckling_n();
        2.0 * force / (4.0 * PI * gel_shear_mpa * depth_mm)
    }
}

/// A fabric's in-plane and bending properties (Kawabata KES-FB1 and FB2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FabricMechanics {
    /// KES-FB1 tensile strain EMT at 500 gf/cm (a fraction).
    pub tensile_strain: f64,
    /// KES-FB1 shear rigidity G (gf/(cm·deg)).
    pub shear_rigidity_gf_cm_deg: f64,
    /// KES-FB2 bending rigidity B (gf·cm²/cm).
    pub bending_rigidity_gf_cm2_cm: f64,
}

impl FabricMechanics {
    /// In-plane stiffness of the fabric around a dragged contact of radius `radius_mm` with the
    /// tape `span_mm` away (N/mm), before or after the strip ahead wrinkles.
    pub fn drag_stiffness_n_mm(&self, radius_mm: f64, span_mm: f64, wrinkled: bool) -> f64 {
        let tension = KES_MAX_TENSION_N_MM / self.tensile_strain;
        let shear = self.shear_rigidity_gf_cm_deg * SHEAR_RIGIDITY_N_MM;
        let strips = if wrinkled { 1.0 } else { 2.0 };
        (strips * tension + 2.0 * shear) * 2.0 * radius_mm / span_mm
    }

    /// The strip ahead's share of the drag force before it wrinkles.
    pub fn compressed_share(&self) -> f64 {
        let tension = KES_MAX_TENSION_N_MM / self.tensile_strain;
        let shear = self.shear_rigidity_gf_cm_deg * SHEAR_RIGIDITY_N_MM;
        tension / (2.0 * tension + 2.0 * shear)
    }

    /// The load at which the strip ahead (2a wide, clamped at both ends `span_mm` apart)
    /// buckles (N): 4π²·B·2a/L².
    pub fn wrinkle_load_n(&self, radius_mm: f64, span_mm: f64) -> f64 {
        4.0 * PI * PI * self.bending_rigidity_gf_cm2_cm * BENDING_RIGIDITY_N_MM * 2.0 * radius_mm
            / (span_mm * span_mm)
    }
}

/// The drag of a fabric over one onset (see the module docs): how much of the base's travel
/// shears the skin, and the twitch when the fabric ahead wrinkles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FabricDrag {
    /// Friction that holds the fabric on the plate, H = μ_fb·N (N).
    hold_n: f64,
    /// Skin and layer in series (N/mm): (1/k_t + 1/k_tex)⁻¹.
    chain_n_mm: f64,
    /// The skin's tangential stiffness k_t (N/mm).
    skin_n_mm: f64,
    /// The fabric's in-plane stiffness before and after wrinkling (N/mm).
    fabric_n_mm: (f64, f64),
    /// The drag force on the strip ahead at which it wrinkles (N).
    wrinkle_n: f64,
    /// The strip ahead's share of the drag force.
    compressed_share: f64,
    /// Whether the strip ahead has wrinkled.
    wrinkled: bool,
}

impl FabricDrag {
    /// The drag of `fabric` under a contact of radius `radius_mm` pressed with `normal_force_n`,
    /// the tape `span_mm` away, held with friction `base_friction`; the skin's stiffness
    /// `skin_n_mm` and the share of the base's travel that reaches the skin through the layer
    /// `shear_share` (`None` for no fabric, or one whose plate friction holds it).
    pub fn new(
        fabric: &FabricMechanics,
        (radius_mm, normal_force_n): (f64, f64),
        (span_mm, base_friction): (f64, f64),
        (skin_n_mm, shear_share): (f64, f64),
    ) -> Self {
        Self {
            hold_n: base_friction * normal_force_n,
            // share = k_c/k_t with k_c the chain's stiffness.
            chain_n_mm: shear_share * skin_n_mm,
            skin_n_mm,
            fabric_n_mm: (
                fabric.drag_stiffness_n_mm(radius_mm, span_mm, false),
                fabric.drag_stiffness_n_mm(radius_mm, span_mm, true),
            ),
            wrinkle_n: fabric.wrinkle_load_n(radius_mm, span_mm),
            compressed_share: fabric.compressed_share(),
            wrinkled: false,
        }
    }

    /// The fabric's stiffness now.
    fn fabric(&self) -> f64 {
        if self.wrinkled {
            self.fabric_n_mm.1
        } else {
            self.fabric_n_mm.0
        }
    }

    /// The share of the base's travel that shears the skin at skin shear `s_mm`: the chain's
    /// while the plate holds the fabric, less while it is dragged.
    pub fn share(&self, s_mm: f64) -> f64 {
        let chain = self.chain_n_mm / self.skin_n_mm;
        if self.skin_n_mm * s_mm <= self.hold_n {
            chain
        } else {
            1.0 / (self.skin_n_mm / self.chain_n_mm + self.skin_n_mm / self.fabric())
        }
    }

    /// Wrinkles the strip ahead if its share of the drag at skin shear `s_mm` reaches its
    /// buckling load; returns the skin shear after the fabric's jump (the base's travel into
    /// the chain held fixed), or `s_mm` if nothing happened.
    pub fn wrinkle(&mut self, s_mm: f64) -> f64 {
        let q = self.skin_n_mm * s_mm;
        let drag = q - self.hold_n;
        if self.wrinkled || drag <= 0.0 || drag * self.compressed_share < self.wrinkle_n {
            return s_mm;
        }
        let travel = q / self.chain_n_mm + drag / self.fabric_n_mm.0;
        self.wrinkled = true;
        let (kc, kf) = (self.chain_n_mm, self.fabric_n_mm.1);
        // travel = Q'/k_c + (Q' − H)/k_f'.
        let q_new = (travel + self.hold_n / kf) / (1.0 / kc + 1.0 / kf);
        q_new / self.skin_n_mm
    }

    /// Whether the strip ahead has wrinkled.
    pub fn wrinkled(&self) -> bool {
        self.wrinkled
    }

    /// How far the fabric under the contact has been dragged at skin shear `s_mm` (mm).
    pub fn drag_mm(&self, s_mm: f64) -> f64 {
        (self.skin_n_mm * s_mm - self.hold_n).max(0.0) / self.fabric()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHIRTING: FabricMechanics = FabricMechanics {
        tensile_strain: 0.05,
        shear_rigidity_gf_cm_deg: 1.0,
        bending_rigidity_gf_cm2_cm: 0.1,
    };

    #[test]
    fn a_hair_buckles_at_eulers_load_and_its_release_is_far_below_a_pixel() {
        let fur = Pile {
            hair_length_mm: 3.0,
            fibre_diameter_mm: 0.03,
            fibre_modulus_mpa: 3000.0,
            density_per_mm2: 50.0,
        };
        let i = PI * 0.03f64.powi(4) / 64.0;
        let p = PI * PI * 3000.0 * i / (4.0 * 9.0);
        assert!((fur.hair_buckling_n() - p).abs() < 1e-15);
        assert!((fur.traction_mpa(0.5) - 50.0 * 0.5 * p).abs() < 1e-15);
        // Hairs reach beyond the contact radius √(2Rδ).
        assert!(fur.reach_mm(2.0, 20.0) > (2.0f64 * 20.0 * 2.0).sqrt());
        assert_eq!(fur.reach_mm(30.0, 20.0), 20.0);
        // 0.1 px at 4.5 px/mm is 0.02 mm: a release is orders of magnitude smaller.
        assert!(fur.release_displacement_mm((1.2, 1.0), 0.01, 1.25) < 1e-4);
    }

    #[test]
    fn a_dragged_fabric_slows_the_skin_and_wrinkling_drops_its_shear() {
        let mut drag = FabricDrag::new(&SHIRTING, (9.0, 2.0), (30.0, 0.3), (2.0, 0.9));
        // Held by the plate up to 0.6 N (s = 0.3 mm): the chain's share.
        assert!((drag.share(0.29) - 0.9).abs() < 1e-12);
        let dragged = drag.share(0.31);
        assert!(dragged < 0.9 && dragged > 0.0, "{dragged}");
        // The strip ahead wrinkles once its share of the drag reaches P_cr: the skin's shear
        // drops, and the softer fabric lets the skin shear more slowly still.
        let p_cr = SHIRTING.wrinkle_load_n(9.0, 30.0);
        let s_at = (0.6 + p_cr / SHIRTING.compressed_share()) / 2.0;
        assert_eq!(drag.wrinkle(s_at - 1e-6), s_at - 1e-6);
        let after = drag.wrinkle(s_at + 1e-6);
        assert!(drag.wrinkled() && after < s_at, "{after} vs {s_at}");
        assert!(drag.share(after) < dragged);
        // Stiffer cloth wrinkles later.
        let canvas = FabricMechanics {
            bending_rigidity_gf_cm2_cm: 0.5,
            ..SHIRTING
        };
        assert!(canvas.wrinkle_load_n(9.0, 30.0) > 4.0 * p_cr);
    }
}
