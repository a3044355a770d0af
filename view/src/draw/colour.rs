//! The drawing's colours: a perceptual sequential map for rates, a categorical palette for
//! classes, and the event image's ON/OFF colours.
//!
//! The sequential map is computed in OKLab (Ottosson 2020), the perceptual space whose
//! lightness `L` tracks perceived brightness: `L` rises linearly from dark to light while the
//! hue turns from violet through blue and teal to yellow (the path viridis takes), so equal rate
//! steps look like equal colour steps and the map reads in greyscale too. Colours outside sRGB
//! keep their lightness and hue and lose chroma until they fit.

use std::fmt;

/// An sRGB colour, 8 bits per channel; `Display` writes `#rrggbb`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Rgb(pub u8, pub u8, pub u8);

impl fmt::Display for Rgb {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

impl Rgb {
    /// `self` moved towards `to` by `share` in `[0, 1]` (per channel, in sRGB).
    pub(crate) fn mix(self, to: Rgb, share: f32) -> Rgb {
        let share = if share.is_finite() {
            share.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let m = |a: u8, b: u8| (a as f32 + (b as f32 - a as f32) * share).round() as u8;
        Rgb(m(self.0, to.0), m(self.1, to.1), m(self.2, to.2))
    }
}

/// The event image's background (no recent event).
pub(crate) const EVENT_BACKGROUND: Rgb = Rgb(14, 16, 24);
/// A pixel whose last event was ON, at full intensity (warm white-yellow).
pub(crate) const EVENT_ON: Rgb = Rgb(255, 214, 92);
/// A pixel whose last event was OFF, at full intensity (blue).
pub(crate) const EVENT_OFF: Rgb = Rgb(64, 140, 255);
/// A tie (no class) and anything without data.
pub(crate) const NO_CLASS: Rgb = Rgb(190, 190, 190);

/// The class colours, in class order (Okabe–Ito's colour-blind-safe eight, less its black and
/// yellow, then six of Tol's muted colours); class `k` takes colour `k mod 12`, so past 12
/// classes colours repeat and the names in the legend and the rows tell the classes apart.
const CLASS_PALETTE: [Rgb; 12] = [
    Rgb(0x00, 0x72, 0xb2),
    Rgb(0xe6, 0x9f, 0x00),
    Rgb(0x00, 0x9e, 0x73),
    Rgb(0xd5, 0x5e, 0x00),
    Rgb(0xcc, 0x79, 0xa7),
    Rgb(0x56, 0xb4, 0xe9),
    Rgb(0x88, 0x22, 0x55),
    Rgb(0x44, 0xaa, 0x99),
    Rgb(0x99, 0x99, 0x33),
    Rgb(0x33, 0x22, 0x88),
    Rgb(0xaa, 0x44, 0x99),
    Rgb(0x66, 0x66, 0x66),
];

/// Class `k`'s colour (see [`CLASS_PALETTE`]).
pub(crate) fn class_colour(class: usize) -> Rgb {
    CLASS_PALETTE[class % CLASS_PALETTE.len()]
}

/// The sequential map at `t` in `[0, 1]` (clamped; not finite → 0): dark violet → blue → teal
/// → green → yellow, with OKLab lightness rising linearly from 0.30 to 0.92.
pub(crate) fn sequential(t: f64) -> Rgb {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let lightness = 0.30 + 0.62 * t;
    // Chroma dips in the middle (teal) and peaks at the yellow end, as viridis' does.
    let chroma = 0.15 - 0.24 * t + 0.28 * t * t;
    let hue = (320.0 - 215.0 * t).to_radians();
    oklch_to_srgb(lightness, chroma, hue)
}

/// OKLCh (lightness, chroma, hue in radians) → sRGB; out-of-gamut colours lose chroma
/// (bisection) until they fit.
fn oklch_to_srgb(lightness: f64, chroma: f64, hue: f64) -> Rgb {
    let at = |c: f64| oklab_to_linear_srgb(lightness, c * hue.cos(), c * hue.sin());
    let in_gamut = |rgb: [f64; 3]| rgb.iter().all(|v| (-1e-9..=1.0 + 1e-9).contains(v));
    let mut rgb = at(chroma);
    if !in_gamut(rgb) {
        let (mut lo, mut hi) = (0.0, chroma);
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            if in_gamut(at(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        rgb = at(lo);
    }
    let encode = |v: f64| {
        let v = v.clamp(0.0, 1.0);
        let s = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    Rgb(encode(rgb[0]), encode(rgb[1]), encode(rgb[2]))
}

/// OKLab → linear sRGB (Ottosson's published matrices).
fn oklab_to_linear_srgb(l: f64, a: f64, b: f64) -> [f64; 3] {
    let l_ = l + 0.396_337_777_4 * a + 0.215_803_757_3 * b;
    let m_ = l - 0.105_561_345_8 * a - 0.063_854_172_8 * b;
    let s_ = l - 0.089_484_177_5 * a - 1.291_485_548_0 * b;
    let (l3, m3, s3) = (l_ * l_ * l_, m_ * m_ * m_, s_ * s_ * s_);
    [
        4.076_741_662_1 * l3 - 3.307_711_591_3 * m3 + 0.230_969_929_2 * s3,
        -1.268_438_004_6 * l3 + 2.609_757_401_1 * m3 - 0.341_319_396_5 * s3,
        -0.004_196_086_3 * l3 - 0.703_418_614_7 * m3 + 1.707_614_701_0 * s3,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative luminance (WCAG) of an sRGB colour.
    fn luminance(c: Rgb) -> f64 {
        let lin = |v: u8| {
            let v = v as f64 / 255.0;
            if v <= 0.040_45 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        0.2126 * lin(c.0) + 0.7152 * lin(c.1) + 0.0722 * lin(c.2)
    }

    #[test]
    fn rate_colours_get_lighter_as_the_rate_rises_from_violet_to_yellow() {
        let steps: Vec<Rgb> = (0..=20).map(|i| sequential(i as f64 / 20.0)).collect();
        for pair in steps.windows(2) {
            assert!(
                luminance(pair[1]) > luminance(pair[0]),
                "{} is not lighter than {}",
                pair[1],
                pair[0]
            );
        }
        let (low, high) = (steps[0], steps[20]);
        assert!(
            low.2 > low.1 && low.0 > low.1,
            "low end {low} is not violet"
        );
        assert!(
            high.0 > 200 && high.1 > 200 && high.2 < 120,
            "high end {high} is not yellow"
        );
        assert_eq!(sequential(f64::NAN), sequential(0.0));
        assert_eq!(sequential(7.0), sequential(1.0));
    }
}
