//! The partial-slip front of the onset: which parts of the contact let go first, and how each
//! pin's skin shear follows (spec §9 "Needed: a distributed onset").
//!
//! **Theory.** A contact loaded tangentially does not slip at once. In Cattaneo–Mindlin's
//! solution for a smooth sphere (Johnson, *Contact Mechanics*, 1985, §7.2) slip starts at the
//! edge of the contact, where the pressure falls to zero, and an annulus of slip grows inward
//! as the tangential load Q rises (stick radius c = a·(1 − Q/μP)^{1/3}) until the whole
//! contact slides at Q = μP. Fingertips show the same front travelling from the periphery
//! inward during the incipient-slip phase (Delhaye, Lefèvre & Thonnard, J. R. Soc. Interface
//! 2014), and a TacTip's pins move ahead of gross slip (James, Pestell & Lepora, RA-L 2018).
//! On a textured surface the pressure is not Hertzian: the skin rests on bump tops, drapes
//! into gaps or touches a floor, so *where* it slips first follows the solved contact
//! pressure field ([`super::contact`]), not the distance from the centre.
//!
//! **Model: the stick zone is the strongest part of the contact.** By the Ciavarella–Jäger
//! principle (Ciavarella, Int. J. Solids Struct. 1998; Jäger, J. Tribol. 1998) the stick zone
//! at tangential load Q is the contact area of the same bodies at the reduced normal load
//! P − Q/μ: the part of the contact that would still touch under a lighter press, i.e. the
//! most strongly held part. For a sphere its area shrinks as A_stick/A = (1 − Q/μP)^β with
//! β = 2/3 (Cattaneo–Mindlin: (c/a)² = (1 − Q/μP)^{2/3}); a fingertip pad measured by André,
//! Lefèvre & Thonnard (J. R. Soc. Interface 2011) loses its stuck area linearly, β = 1
//! (`contact.stick_area_exponent`). On any pressure field we rank the contact's points by
//! their capacity c(x) (below) and let the stick zone be the strongest fraction of the area;
//! a point whose stronger points cover the area fraction u(x) slips when
//!
//! ```text
//! (1 − Q/Q_s)^β = u(x)   ⇔   θ(x) = Q/Q_s = 1 − u(x)^{1/β}
//! ```
//!
//! which is exactly Cattaneo–Mindlin's front on a Hertzian contact (u = r²/a², θ = 1 − (r/a)³)
//! and follows bump tops, draped flanks and floors on a texture. The lumped spring-slider of
//! [`super::mechanics`] gives the load fraction Q/Q_s as s/s_s (its shear over its stick limit).
//!
//! **Pins.** A pin feels the skin under its footprint (radius `contact.pin_footprint_radius_mm`):
//! [`FOOTPRINT_POINTS`] elements at fixed points around it. Before the first full slip each
//! element's shear follows the common shear s while it sticks; when the front reaches it
//! (s ≥ θ·s_s) it slips, its traction drops from the static to the kinetic level and its shear
//! relaxes towards `(μ_k/μ_s)·θ·s_s` with the slip time τ — each pin twitches back when the
//! front passes under it. After the first full slip every element relaxes to the lumped shear
//! (with τ), which then governs sliding, stick-slip and the recoil at the stop exactly as
//! before. A pin with no contact under its footprint feels the contact-wide mean shear, carried
//! by the gel (the shear spread φ(r) of [`super::mechanics`] still applies to every pin).

use super::texture::TextureField;
use std::f64::consts::PI;

/// Elements under one pin's footprint: the centre and two rings (1 + 5 + 10).
pub const FOOTPRINT_POINTS: usize = 16;

/// Elements that stand for the whole contact (pins with no contact under them).
const CONTACT_QUANTILES: usize = 32;

/// Sampling of the contact disc: points per contact radius.
const DISC_POINTS_PER_RADIUS: usize = 24;

/// The contact a slide starts from: its geometry and the interface law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactState {
    /// Contact radius a (mm).
    pub radius_mm: f64,
    /// Normal force N (N).
    pub normal_force_n: f64,
    /// E*·h'_rms of the real-area law (MPa).
    pub area_scale_mpa: f64,
    /// Texture offset of the sensor frame's origin: world X = x + offset.0, Y = y + offset.1 (mm).
    pub offset_mm: (f64, f64),
    /// Radius of a pin's footprint on the skin (mm).
    pub footprint_radius_mm: f64,
}

impl ContactState {
    /// Real-area fraction at pressure `p_mpa` (Persson 2001).
    fn area(&self, p_mpa: f64) -> f64 {
        1.0 - neurotac_core::special::erfc(
            std::f64::consts::SQRT_2 * p_mpa.max(0.0) / self.area_scale_mpa,
        )
    }

    /// Capacity at sensor-plane point (x, y): the real-area fraction A(p) under the local
    /// pressure, up to a constant factor (μ_s·q/A(q)) that no rank depends on.
    fn capacity(&self, field: &TextureField, x: f64, y: f64) -> f64 {
        let a = self.radius_mm;
        let r2 = x * x + y * y;
        if r2 >= a * a {
            return 0.0;
        }
        let p0 = 3.0 * self.normal_force_n / (2.0 * PI * a * a);
        let rho = field.pressure_ratio(x + self.offset_mm.0, y + self.offset_mm.1);
        let p = p0 * (1.0 - r2 / (a * a)).sqrt() * rho;
        if p <= 0.0 {
            return 0.0;
        }
        self.area(p)
    }
}

/// Where the slip front reaches each pin: per pin, the load fractions θ of its footprint's
/// elements in contact (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct SlipFront {
    /// `[pin · FOOTPRINT_POINTS + k]`: θ of element k, or NaN where it is not in contact.
    thresholds: Vec<f64>,
    /// θ quantiles of the whole contact (for pins with no contact under them).
    contact: Vec<f64>,
    /// Scratch: capacities of the disc samples, sorted.
    sorted: Vec<f64>,
    /// The stick-area exponent β.
    exponent: f64,
}

impl SlipFront {
    /// Solves the front for pins at `pins_mm` (sensor plane) on the contact `state` over
    /// `field` (buffers reused).
    pub fn solve(
        &mut self,
        pins_mm: &[(f64, f64)],
        state: &ContactState,
        field: &TextureField,
        stick_area_exponent: f64,
    ) {
        self.exponent = stick_area_exponent;
        let a = state.radius_mm;
        let h = a / DISC_POINTS_PER_RADIUS as f64;
        let n = DISC_POINTS_PER_RADIUS as i64;
        self.sorted.clear();
        for j in -n..=n {
            for i in -n..=n {
                let c = state.capacity(field, i as f64 * h, j as f64 * h);
                if c > 0.0 {
                    self.sorted.push(c);
                }
            }
        }
        self.sorted.sort_unstable_by(f64::total_cmp);
        self.thresholds.clear();
        for &(px, py) in pins_mm {
            for k in 0..FOOTPRINT_POINTS {
                let (dx, dy) = footprint_offset(k, state.footprint_radius_mm);
                let c = state.capacity(field, px + dx, py + dy);
                self.thresholds
                    .push(if c > 0.0 { self.fraction(c) } else { f64::NAN });
            }
        }
        self.contact.clear();
        let m = self.sorted.len();
        if m > 0 {
            for q in 0..CONTACT_QUANTILES {
                let c = self.sorted
                    [((q as f64 + 0.5) / CONTACT_QUANTILES as f64 * m as f64) as usize % m];
                self.contact.push(self.fraction(c));
            }
        }
    }

    /// Forgets the last solve (a slide without the front: every pin follows the lumped shear),
    /// keeping the buffers.
    pub fn clear(&mut self) {
        self.thresholds.clear();
        self.contact.clear();
    }

    /// θ of an element of capacity `c`: `1 − u^{1/β}`, u the area fraction of the disc samples
    /// stronger than `c` (ties count half).
    fn fraction(&self, c: f64) -> f64 {
        let n = self.sorted.len();
        if n == 0 {
            return 0.0;
        }
        let below = self.sorted.partition_point(|&v| v < c);
        let not_above = self.sorted.partition_point(|&v| v <= c);
        let stronger = (n - not_above) as f64 + 0.5 * (not_above - below) as f64;
        (1.0 - (stronger / n as f64).powf(1.0 / self.exponent)).clamp(0.0, 1.0)
    }

    /// The load fraction at which the front reaches `pin`: the median θ of its footprint's
    /// elements in contact, or `None` for a pin with no contact under it.
    pub fn pin_threshold(&self, pin: usize) -> Option<f64> {
        let mut v = [0.0; FOOTPRINT_POINTS];
        let mut n = 0;
        for &t in &self.thresholds[pin * FOOTPRINT_POINTS..(pin + 1) * FOOTPRINT_POINTS] {
            if !t.is_nan() {
                v[n] = t;
                n += 1;
            }
        }
        if n == 0 {
            return None;
        }
        v[..n].sort_unstable_by(f64::total_cmp);
        Some(v[n / 2])
    }

    /// Pins the front was solved for.
    pub fn n_pins(&self) -> usize {
        self.thresholds.len() / FOOTPRINT_POINTS
    }
}

/// Offset of footprint element `k` from its pin's centre: the centre, five points at half the
/// radius, ten on the rim.
fn footprint_offset(k: usize, radius_mm: f64) -> (f64, f64) {
    let (r, angle) = match k {
        0 => (0.0, 0.0),
        1..=5 => (0.5 * radius_mm, (k - 1) as f64 * 2.0 * PI / 5.0),
        _ => (radius_mm, (k - 6) as f64 * 2.0 * PI / 10.0 + PI / 10.0),
    };
    (r * angle.cos(), r * angle.sin())
}

/// The skin shear each pin feels over one slide, stepped at the mechanics' sampling interval
/// (see the module docs; reusable buffers).
#[derive(Debug, Clone, Default)]
pub struct PinShear {
    /// `[pin · FOOTPRINT_POINTS + k]` element shear (mm); the contact-wide elements follow.
    shear: Vec<f64>,
    /// Per element: has it slipped during the onset.
    slipped: Vec<bool>,
    /// Per element: its θ (NaN: not in contact).
    thresholds: Vec<f64>,
    /// Per pin: whether it has contact under it (else it feels the contact-wide mean).
    pin_in_contact: Vec<bool>,
    n_pins: usize,
    /// The first full slip has happened.
    full_slip: bool,
    /// Every element has relaxed onto the lumped shear: pins follow it directly.
    settled: bool,
}

impl PinShear {
    /// Starts a slide from rest on the front `front`.
    pub fn start(&mut self, front: &SlipFront) {
        self.n_pins = front.n_pins();
        self.thresholds.clear();
        self.thresholds.extend_from_slice(&front.thresholds);
        self.thresholds.extend_from_slice(&front.contact);
        self.pin_in_contact.clear();
        self.pin_in_contact.extend((0..self.n_pins).map(|p| {
            front.thresholds[p * FOOTPRINT_POINTS..(p + 1) * FOOTPRINT_POINTS]
                .iter()
                .any(|t| !t.is_nan())
        }));
        let n = self.thresholds.len();
        self.shear.clear();
        self.shear.resize(n, 0.0);
        self.slipped.clear();
        self.slipped.resize(n, false);
        self.full_slip = front.contact.is_empty();
        self.settled = self.full_slip;
    }

    /// Advances by one sample: `s` is the lumped shear now, `s_static` its stick limit,
    /// `kinetic_ratio` = μ_k/μ_s, `stuck` whether the lumped contact still sticks, `relax` =
    /// e^(−Δt/τ) over the sample.
    pub fn step(&mut self, s: f64, s_static: f64, kinetic_ratio: f64, stuck: bool, relax: f64) {
        if self.settled {
            return;
        }
        if !stuck {
            self.full_slip = true;
        }
        if self.full_slip {
            let mut gap = 0.0f64;
            for e in self.shear.iter_mut() {
                *e = s + (*e - s) * relax;
                gap = gap.max((*e - s).abs());
            }
            self.settled = gap < 1e-7;
            return;
        }
        for ((e, slipped), &theta) in self
            .shear
            .iter_mut()
            .zip(self.slipped.iter_mut())
            .zip(&self.thresholds)
        {
            if theta.is_nan() {
                continue;
            }
            if !*slipped && s >= theta * s_static {
                *slipped = true;
            }
            if *slipped {
                let target = kinetic_ratio * theta * s_static;
                *e = target + (*e - target) * relax;
            } else {
                *e = s;
            }
        }
    }

    /// The shear `pin` feels now (mm); `s` is the lumped shear (followed once settled).
    pub fn pin(&self, pin: usize, s: f64) -> f64 {
        if self.settled {
            return s;
        }
        let range = if self.pin_in_contact[pin] {
            pin * FOOTPRINT_POINTS..(pin + 1) * FOOTPRINT_POINTS
        } else {
            self.n_pins * FOOTPRINT_POINTS..self.shear.len()
        };
        let (mut sum, mut n) = (0.0, 0usize);
        for k in range {
            if !self.thresholds[k].is_nan() {
                sum += self.shear[k];
                n += 1;
            }
        }
        if n == 0 { s } else { sum / n as f64 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat_state() -> ContactState {
        ContactState {
            radius_mm: 8.94,
            normal_force_n: 2.0,
            area_scale_mpa: 0.28,
            offset_mm: (0.0, 0.0),
            footprint_radius_mm: 0.75,
        }
    }

    #[test]
    fn on_a_smooth_dome_the_front_runs_from_the_edge_inward() {
        let state = flat_state();
        let pins: Vec<(f64, f64)> = (0..9).map(|i| (i as f64, 0.0)).collect();
        let mut front = SlipFront::default();
        front.solve(&pins, &state, &TextureField::flat(), 2.0 / 3.0);
        let theta: Vec<f64> = (0..9).map(|p| front.pin_threshold(p).unwrap()).collect();
        assert!(theta.windows(2).all(|w| w[1] < w[0]), "{theta:?}");
        // Cattaneo–Mindlin: θ = 1 − (r/a)³ (the footprint's median, within the disc sampling).
        for (r, t) in theta.iter().enumerate() {
            let expected = 1.0 - (r as f64 / state.radius_mm).powi(3);
            assert!((t - expected).abs() < 0.03, "r = {r}: {t} vs {expected}");
        }
        // Outside the contact there is nothing to slip.
        front.solve(&[(12.0, 0.0)], &state, &TextureField::flat(), 2.0 / 3.0);
        assert_eq!(front.pin_threshold(0), None);
    }

    #[test]
    fn the_stick_zone_is_the_strongest_fraction_of_the_area() {
        // Four samples of capacities 1…4, each standing for a quarter of the area (a sample's
        // own quarter counts half: its midpoint). With β = 1 the weakest slips when the stick
        // area has shrunk to 7/8, the strongest when it is 1/8 ...
        let front = SlipFront {
            sorted: vec![1.0, 2.0, 3.0, 4.0],
            exponent: 1.0,
            ..SlipFront::default()
        };
        assert!((front.fraction(1.0) - 0.125).abs() < 1e-12);
        assert!((front.fraction(3.0) - 0.625).abs() < 1e-12);
        assert!((front.fraction(4.0) - 0.875).abs() < 1e-12);
        // ... and with Cattaneo–Mindlin's β = 2/3 later in the loading: θ = 1 − u^{3/2}.
        let cm = SlipFront {
            exponent: 2.0 / 3.0,
            ..front
        };
        assert!((cm.fraction(1.0) - (1.0 - 0.875f64.powf(1.5))).abs() < 1e-12);
    }

    #[test]
    fn each_element_sticks_until_the_front_reaches_it_then_drops_to_its_kinetic_share() {
        let state = flat_state();
        let mut front = SlipFront::default();
        front.solve(
            &[(0.0, 0.0), (8.0, 0.0)],
            &state,
            &TextureField::flat(),
            2.0 / 3.0,
        );
        let edge = front.pin_threshold(1).unwrap();
        let mut shear = PinShear::default();
        shear.start(&front);
        let s_static = 1.0;
        let (mut s, mut peak_edge, mut at_edge_slip) = (0.0, 0.0f64, None);
        while s < 0.99 {
            s += 0.005;
            shear.step(s, s_static, 0.7, true, 0.9);
            peak_edge = peak_edge.max(shear.pin(1, s));
            if at_edge_slip.is_none() && s > edge + 0.1 {
                at_edge_slip = Some(shear.pin(1, s));
            }
            // The centre sticks until the very end: it moves with the lumped shear.
            if s < 0.95 {
                assert!((shear.pin(0, s) - s).abs() < 1e-9, "{s}");
            }
        }
        // The edge pin stopped rising near its threshold and fell back towards 0.7·θ.
        assert!(peak_edge < edge + 0.05, "{peak_edge} vs {edge}");
        assert!(at_edge_slip.unwrap() < peak_edge);
        // Full slip: everything relaxes onto the lumped shear and then follows it exactly.
        for _ in 0..400 {
            shear.step(0.85, s_static, 0.7, false, 0.9);
        }
        assert_eq!(shear.pin(1, 0.85), 0.85);
        assert_eq!(shear.pin(0, 0.42), 0.42);
    }
}
