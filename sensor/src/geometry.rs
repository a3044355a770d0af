//! The NeuroTac's geometry as the camera sees it: 49 pins on a hemispherical dome, projected
//! into the DAVIS240's 240 × 180 image (`shared/specs/simulator.md` §1.1–1.2).
//!
//! Defaults: dome radius R = 20 mm; pins on concentric rings of 1 + 8 + 16 + 24 at arc distances
//! 0, 4.5, 9 and 13.5 mm from the apex; orthographic projection at 4.5 px/mm centred on the
//! image centre (120, 90), so a pin at arc distance s lies `4.5 · R · sin(s/R)` px from the
//! centre (0, 20.1, 39.1 and 56.2 px). Ring j's pins sit at angles `2π·i/n_j`.

use serde::{Deserialize, Serialize};

/// Width of the DAVIS240 pixel array.
pub const DAVIS240_WIDTH: u16 = 240;
/// Height of the DAVIS240 pixel array.
pub const DAVIS240_HEIGHT: u16 = 180;

/// Where the pins are and how the camera images them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PinGeometry {
    /// Dome radius (mm). Default 20.
    pub dome_radius_mm: f64,
    /// Arc distance between rings (mm). Default 4.5.
    pub pin_pitch_mm: f64,
    /// Pins per ring, from the apex outwards. Default `[1, 8, 16, 24]`.
    pub rings: Vec<usize>,
    /// Image scale at the pin plane (px/mm). Default 4.5.
    pub scale_px_per_mm: f64,
    /// Image position of the apex (px). Default (120, 90).
    pub centre_px: (f64, f64),
}

impl Default for PinGeometry {
    fn default() -> Self {
        Self {
            dome_radius_mm: 20.0,
            pin_pitch_mm: 4.5,
            rings: vec![1, 8, 16, 24],
            scale_px_per_mm: 4.5,
            // The image centre: (120, 90).
            centre_px: (
                f64::from(DAVIS240_WIDTH) / 2.0,
                f64::from(DAVIS240_HEIGHT) / 2.0,
            ),
        }
    }
}

impl PinGeometry {
    /// Number of pins.
    pub fn n_pins(&self) -> usize {
        self.rings.iter().sum()
    }

    /// Pin positions in the sensor plane (mm, apex at the origin), ring by ring.
    pub fn pin_positions_mm(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::with_capacity(self.n_pins());
        for (j, &n) in self.rings.iter().enumerate() {
            let s = j as f64 * self.pin_pitch_mm;
            let r = self.dome_radius_mm * (s / self.dome_radius_mm).sin();
            for i in 0..n {
                let angle = std::f64::consts::TAU * i as f64 / n as f64;
                out.push((r * angle.cos(), r * angle.sin()));
            }
        }
        out
    }

    /// Pin positions in the image (px).
    pub fn pin_positions_px(&self) -> Vec<(f64, f64)> {
        let (cx, cy) = self.centre_px;
        self.pin_positions_mm()
            .into_iter()
            .map(|(x, y)| (cx + self.scale_px_per_mm * x, cy + self.scale_px_per_mm * y))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_pins_sit_on_four_rings_inside_the_image() {
        let g = PinGeometry::default();
        let px = g.pin_positions_px();
        assert_eq!(px.len(), 49);
        assert_eq!(px[0], (120.0, 90.0));
        let radius = |p: (f64, f64)| ((p.0 - 120.0).powi(2) + (p.1 - 90.0).powi(2)).sqrt();
        for (range, expected) in [(1..9, 20.080), (9..25, 39.147), (25..49, 56.241)] {
            for p in &px[range] {
                assert!((radius(*p) - expected).abs() < 0.01, "{p:?}");
            }
        }
        assert!(
            px.iter()
                .all(|&(x, y)| (0.0..f64::from(DAVIS240_WIDTH)).contains(&x)
                    && (0.0..f64::from(DAVIS240_HEIGHT)).contains(&y))
        );
    }
}
