//! How the contact's tangential load reaches the pins: the skin's displacement under the
//! contact's traction, carried by the gel — in place of a fixed spread φ(r) (spec §2.2 step 4,
//! which assumed `φ = e^(−(r/1.5a)²)` for every texture).
//!
//! **Gel.** An incompressible elastic half-space (ν = ½: the silicone gel). A tangential point
//! force Q_x on its surface displaces a point Δ = (Δx, Δy) away and z deep by Cerruti's solution
//! (Johnson, *Contact Mechanics*, 1985, §2.2; for ν = ½ it is exactly twice Kelvin's
//! full-space solution, the free surface acting as a mirror):
//!
//! ```text
//! u_x = Q_x/(4πGρ)·(1 + Δx²/ρ²),   u_y = Q_x/(4πGρ)·Δx·Δy/ρ²,   ρ² = Δx² + Δy² + z²
//! ```
//!
//! The pins hang from the skin's inner face, `contact.skin_depth_mm` below the contact (the same
//! depth the skin's low-pass T(k) uses). Summed over the contact's traction q(x, y), this gives
//! each pin's displacement for a unit load; it is scaled by the displacement of the apex under
//! a fully stuck contact, so that a pin at the apex of a stuck contact moves exactly with the
//! lumped shear s (the convention of the fixed spread it replaces).
//!
//! **Traction.** Two distributions, for a load Q = k_t·s:
//! - *stuck* (Mindlin, Johnson §7.1): `q = Q/(2πa·√(a² − r²))`, which displaces the whole
//!   contact uniformly;
//! - *sliding* (Amontons on the contact pressure, Johnson §7.2): `q = μ·p`. On a rigid texture p
//!   is Hertzian, `∝ √(1 − r²/a²)`, and a sliding contact's centre moves 1.5 times as far as a
//!   stuck one's under the same load. On a compliant layer sliding is a flow of the layer's
//!   material through the contact: material entering at the leading edge is compressed, leaving
//!   at the trailing edge it recovers late, so its pressure is shifted forward (Hunter, J. Appl.
//!   Mech. 1961, for rolling on a viscoelastic solid; Greenwood & Tabor, Proc. Phys. Soc. 1958,
//!   for the hysteresis it costs). For a Kelvin–Voigt Winkler layer under the dome,
//!   `p ∝ w + τ_r·Dw/Dt` with `Dw/Dt = v·x/R` and `v·τ_r = a·tan δ` at the passing frequency v/a,
//!   so `p ∝ 1 − r²/a² + ε·x/a` with **ε = 2·tan δ_layer · δ_t/δ** (the layer's share of the
//!   overlap, [`super::layer::Press`]): a Hertzian pressure about a centre shifted forward by
//!   ε·a/2 over a radius `a·√(1 + ε²/4)`. Leading pins (+x) then move more than trailing ones,
//!   by an amount set by compliance × loss — nothing on a rigid texture.
//!
//! While the onset's slip front grows, the slipped share of the contact `f = 1 − (1 − s/s_s)^β`
//! (the stick zone's area, [`super::slip_front`]) carries the sliding traction and the rest the
//! stuck one: a pin's displacement per unit shear blends the two profiles by f, and follows the
//! sliding profile from the first full slip on.
//!
//! **Pile outside the contact** ([`super::fabric::Pile`]): hairs standing proud of a fabric's
//! surface touch the dome beyond the contact radius and drag on it while it slides; they carry a
//! share of the load over the annulus they reach, spreading shear to rim pins no contact
//! touches.

use std::f64::consts::{FRAC_PI_2, TAU};

/// Quadrature: polar angles and rings per traction distribution.
const ANGLES: usize = 48;
const RINGS: usize = 24;

/// What the spread depends on: the contact, the forward shift of its sliding pressure, the pile
/// reaching beyond it, and the pins' depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpreadContact {
    /// Contact radius a (mm); no contact for 0.
    pub radius_mm: f64,
    /// Forward shift ε of the sliding pressure `p ∝ 1 − r²/a² + ε·x/a` (0 on a rigid texture).
    pub forward_shift: f64,
    /// The pile beyond the contact: its outer radius (mm) and the share of the load it carries.
    pub pile: Option<(f64, f64)>,
    /// Depth of the pins below the contact surface (mm).
    pub depth_mm: f64,
}

/// Each pin's displacement per unit lumped shear, stuck and sliding (see the module docs),
/// solved once per slide (buffers reused).
#[derive(Debug, Clone, Default)]
pub struct ShearSpread {
    stuck: Vec<(f64, f64)>,
    sliding: Vec<(f64, f64)>,
    /// Scratch: the traction's point loads (x, y, weight).
    loads: Vec<(f64, f64, f64)>,
}

impl ShearSpread {
    /// Solves the two profiles for pins at `pins_mm` (sensor plane) under `contact`.
    pub fn solve(&mut self, pins_mm: &[(f64, f64)], contact: &SpreadContact) {
        let a = contact.radius_mm;
        self.stuck.clear();
        self.sliding.clear();
        if a <= 0.0 {
            self.stuck.resize(pins_mm.len(), (0.0, 0.0));
            self.sliding.resize(pins_mm.len(), (0.0, 0.0));
            return;
        }
        let z = contact.depth_mm;
        let pile_share = contact.pile.map_or(0.0, |(_, share)| share);
        // Stuck: Mindlin's q = Q/(2πa√(a² − r²)); with r = a·sin θ, q·dA = Q/(2π)·sin θ dθ dψ.
        self.loads.clear();
        polar_loads(&mut self.loads, (0.0, 0.0), a, |theta| theta.sin());
        scale_loads(&mut self.loads, 1.0 - pile_share);
        let apex = displacement(&self.loads, (0.0, 0.0), z).0;
        let pile = contact
            .pile
            .map(|(outer, _)| annulus_loads(a, outer, pile_share));
        self.loads.extend(pile.iter().flatten());
        for &p in pins_mm {
            let (ux, uy) = displacement(&self.loads, p, z);
            self.stuck.push((ux / apex, uy / apex));
        }
        // Sliding: Hertzian about the forward-shifted centre, R' = a·√(1 + ε²/4); with
        // r' = R'·sin θ, q·dA ∝ sin θ·cos² θ dθ dψ.
        let eps = contact.forward_shift;
        let centre = (0.5 * eps * a, 0.0);
        self.loads.clear();
        polar_loads(
            &mut self.loads,
            centre,
            a * (1.0 + 0.25 * eps * eps).sqrt(),
            |theta| theta.sin() * theta.cos().powi(2),
        );
        scale_loads(&mut self.loads, 1.0 - pile_share);
        self.loads.extend(pile.iter().flatten());
        for &p in pins_mm {
            let (ux, uy) = displacement(&self.loads, p, z);
            self.sliding.push((ux / apex, uy / apex));
        }
    }

    /// The displacement (x, y) of `pin` per unit lumped shear when a share `slipped` of the
    /// contact slides (0: all stuck, 1: sliding).
    #[inline]
    pub fn at(&self, pin: usize, slipped: f64) -> (f64, f64) {
        let (s, d) = (self.stuck[pin], self.sliding[pin]);
        (s.0 + slipped * (d.0 - s.0), s.1 + slipped * (d.1 - s.1))
    }

    /// The sliding profile of `pin`.
    pub fn sliding(&self, pin: usize) -> (f64, f64) {
        self.sliding[pin]
    }
}

/// Point loads of an axisymmetric traction on the disc of radius `radius` about `centre`, in
/// the substitution r = radius·sin θ (θ ∈ [0, π/2]) with weight `weight(θ)`·dθ·dψ, normalised to
/// a unit total.
fn polar_loads(
    out: &mut Vec<(f64, f64, f64)>,
    centre: (f64, f64),
    radius: f64,
    weight: impl Fn(f64) -> f64,
) {
    let start = out.len();
    let (d_theta, d_psi) = (FRAC_PI_2 / RINGS as f64, TAU / ANGLES as f64);
    for i in 0..RINGS {
        let theta = (i as f64 + 0.5) * d_theta;
        let (r, w) = (radius * theta.sin(), weight(theta));
        for j in 0..ANGLES {
            // Rings alternate half an angle step, so no two rings line up.
            let psi = (j as f64 + 0.5 * (i % 2) as f64) * d_psi;
            out.push((centre.0 + r * psi.cos(), centre.1 + r * psi.sin(), w));
        }
    }
    let total: f64 = out[start..].iter().map(|l| l.2).sum();
    for l in &mut out[start..] {
        l.2 /= total;
    }
}

/// A uniform traction on the annulus from `inner` to `outer` (mm) carrying `share` of the load.
fn annulus_loads(inner: f64, outer: f64, share: f64) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::with_capacity(RINGS * ANGLES);
    if outer <= inner || share <= 0.0 {
        return out;
    }
    let (dr, d_psi) = ((outer - inner) / RINGS as f64, TAU / ANGLES as f64);
    for i in 0..RINGS {
        let r = inner + (i as f64 + 0.5) * dr;
        for j in 0..ANGLES {
            let psi = (j as f64 + 0.5 * (i % 2) as f64) * d_psi;
            out.push((r * psi.cos(), r * psi.sin(), r * dr * d_psi));
        }
    }
    let total: f64 = out.iter().map(|l| l.2).sum();
    for l in &mut out {
        l.2 *= share / total;
    }
    out
}

fn scale_loads(loads: &mut [(f64, f64, f64)], factor: f64) {
    for l in loads {
        l.2 *= factor;
    }
}

/// Displacement at depth `z` below `point` under x-directed point loads (Cerruti, ν = ½), up to
/// the common factor 1/(4πG).
fn displacement(loads: &[(f64, f64, f64)], point: (f64, f64), z: f64) -> (f64, f64) {
    let (mut ux, mut uy) = (0.0, 0.0);
    for &(x, y, w) in loads {
        let (dx, dy) = (point.0 - x, point.1 - y);
        let rho2 = dx * dx + dy * dy + z * z;
        let inv = 1.0 / rho2.sqrt();
        ux += w * inv * (1.0 + dx * dx / rho2);
        uy += w * inv * dx * dy / rho2;
    }
    (ux, uy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The apex's sliding displacement over its stuck one on a Hertzian contact of radius `a`,
    /// at the surface.
    fn hertz_apex_ratio(a: f64) -> f64 {
        let mut spread = ShearSpread::default();
        spread.solve(
            &[(0.0, 0.0)],
            &SpreadContact {
                radius_mm: a,
                forward_shift: 0.0,
                pile: None,
                depth_mm: 1e-3 * a,
            },
        );
        spread.sliding(0).0
    }

    fn contact(eps: f64, pile: Option<(f64, f64)>) -> SpreadContact {
        SpreadContact {
            radius_mm: 9.0,
            forward_shift: eps,
            pile,
            depth_mm: 1.25,
        }
    }

    fn ring(r: f64) -> Vec<(f64, f64)> {
        (0..8)
            .map(|k| {
                let a = k as f64 * PI / 4.0;
                (r * a.cos(), r * a.sin())
            })
            .collect()
    }

    #[test]
    fn a_stuck_contact_moves_as_a_whole_and_the_gel_carries_it_beyond() {
        let mut s = ShearSpread::default();
        let pins: Vec<(f64, f64)> = (0..13).map(|i| (i as f64, 0.0)).collect();
        s.solve(&pins, &contact(0.0, None));
        assert!((s.at(0, 0.0).0 - 1.0).abs() < 1e-12);
        // Mindlin: uniform inside the contact (at the pins' depth, to a few per cent away from
        // the edge, where the traction's edge singularity lies partly beside the pin) ...
        for i in 1..8 {
            assert!(
                (s.at(i, 0.0).0 - 1.0).abs() < 0.07,
                "{i}: {:?}",
                s.at(i, 0.0)
            );
        }
        // ... and decaying outside it, monotonically.
        let outside: Vec<f64> = (9..13).map(|i| s.at(i, 0.0).0).collect();
        assert!(
            outside.windows(2).all(|w| w[1] < w[0]) && outside[3] < 0.8,
            "{outside:?}"
        );
        // Along the load, no sideways motion; symmetric pins move alike.
        assert!(s.at(5, 0.0).1.abs() < 1e-9);
    }

    #[test]
    fn sliding_moves_the_apex_of_a_hertzian_contact_half_as_far_again() {
        // Johnson 1985 §7.2: full sliding (q = μp) displaces the centre 3(2 − ν)/(16Ga)·Q,
        // sticking (2 − ν)/(8Ga)·Q: a ratio of 1.5 at the surface.
        let ratio = hertz_apex_ratio(9.0);
        assert!((ratio - 1.5).abs() < 0.02, "{ratio}");
    }

    #[test]
    fn a_compliant_layer_moves_leading_pins_more_than_trailing_ones() {
        let pins = [(6.0, 0.0), (-6.0, 0.0), (0.0, 6.0), (0.0, -6.0)];
        let mut rigid = ShearSpread::default();
        rigid.solve(&pins, &contact(0.0, None));
        let (lead, trail) = (rigid.sliding(0).0, rigid.sliding(1).0);
        assert!((lead - trail).abs() < 1e-9, "{lead} {trail}");
        let mut soft = ShearSpread::default();
        soft.solve(&pins, &contact(0.3, None));
        let (lead, trail) = (soft.sliding(0).0, soft.sliding(1).0);
        assert!(lead > 1.1 * trail, "{lead} {trail}");
        // Sideways pins stay mirror images.
        assert!((soft.sliding(2).0 - soft.sliding(3).0).abs() < 1e-9);
        assert!((soft.sliding(2).1 + soft.sliding(3).1).abs() < 1e-9);
        // Stuck, the shift does not matter.
        assert!((soft.at(0, 0.0).0 - soft.at(1, 0.0).0).abs() < 1e-9);
    }

    #[test]
    fn pile_beyond_the_contact_shears_the_rim_pins() {
        let rim = ring(12.9);
        let mut bare = ShearSpread::default();
        bare.solve(&rim, &contact(0.0, None));
        let mut hairy = ShearSpread::default();
        hairy.solve(&rim, &contact(0.0, Some((15.0, 0.3))));
        for k in 0..rim.len() {
            assert!(hairy.sliding(k).0 > bare.sliding(k).0, "pin {k}");
        }
        // No contact: nothing moves.
        let mut none = ShearSpread::default();
        none.solve(
            &rim,
            &SpreadContact {
                radius_mm: 0.0,
                ..contact(0.0, None)
            },
        );
        assert_eq!(none.at(0, 0.5), (0.0, 0.0));
    }
}
