//! Pixel-level diagnostics of the simulator (spec §5, statistic 7): a controlled edge pass and
//! per-pixel sanity of an event stream.

use super::camera::Camera;
use super::error::SimulationError;
use super::params::SimParams;
use super::pixel::{PinMotion, PixelModel};
use crate::geometry::{DAVIS240_WIDTH, PinGeometry};
use neurotac_core::EventBuffer;

/// Per-pixel sanity of an event stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelSanity {
    /// Shortest interval between two events of one pixel (µs); `None` if no pixel fired twice.
    pub min_interval_us: Option<i64>,
    /// Every pixel's timestamps are strictly increasing.
    pub monotone_per_pixel: bool,
    /// Stream timestamps never decrease.
    pub monotone: bool,
    /// ON events / OFF events (∞ without OFF events).
    pub on_off_ratio: f64,
}

/// Checks `events` pixel by pixel (see [`PixelSanity`]).
pub fn pixel_sanity(events: &EventBuffer) -> PixelSanity {
    let w = DAVIS240_WIDTH as usize;
    let mut last = vec![i64::MIN; w * 180];
    let mut min_interval = None::<i64>;
    let mut monotone_per_pixel = true;
    let (mut on, mut off) = (0usize, 0usize);
    for e in events.iter() {
        let i = e.y as usize * w + e.x as usize;
        if last[i] != i64::MIN {
            let d = e.t.0 - last[i];
            monotone_per_pixel &= d > 0;
            min_interval = Some(min_interval.map_or(d, |m| m.min(d)));
        }
        last[i] = e.t.0;
        if e.polarity {
            on += 1;
        } else {
            off += 1;
        }
    }
    PixelSanity {
        min_interval_us: min_interval,
        monotone_per_pixel,
        monotone: events.t.windows(2).all(|p| p[0] <= p[1]),
        on_off_ratio: if off == 0 {
            f64::INFINITY
        } else {
            on as f64 / off as f64
        },
    }
}

/// A slow sweep of one pin's disc across a row of pixels.
struct Sweep {
    from_px: f32,
    span_px: f32,
    duration_s: f64,
}

impl PinMotion for Sweep {
    fn n_pins(&self) -> usize {
        1
    }
    fn displacement(&self, _pin: usize, t_s: f64) -> (f32, f32) {
        let f = (t_s / self.duration_s).clamp(0.0, 1.0) as f32;
        (self.from_px + f * self.span_px, 0.0)
    }
    fn time_to_travel(&self, _pin: usize, t_s: f64, distance_px: f32, limit_s: f64) -> f64 {
        let speed = self.span_px as f64 / self.duration_s;
        (t_s + distance_px as f64 / speed).min(limit_s)
    }
}

/// Result of [`edge_pass`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgePass {
    /// Mean ON events per pixel of the pin's path.
    pub on_per_pixel: f64,
    /// Mean OFF events per pixel.
    pub off_per_pixel: f64,
    /// ln K / C⁺ (K = I_pin/I_bg).
    pub expected_on: f64,
    /// ln K / C⁻.
    pub expected_off: f64,
    /// Pixels averaged.
    pub pixels: usize,
    /// Per-pixel sanity of the sweep's events.
    pub sanity: PixelSanity,
}

/// A full pass of a pin edge (spec §5, statistic 7): one pin's disc sweeps 16 px in 1 s across
/// the pixels around (120, 90), noise off. Each of the 7 × 3 pixels centred on the path sees
/// background → pin → background; ON and OFF counts are compared with ln K / C.
pub fn edge_pass(params: &SimParams, camera_seed: u64) -> Result<EdgePass, SimulationError> {
    params.validate()?;
    let mut p = *params;
    p.optics.patch_radius_px = p.optics.patch_radius_px.max(16.0);
    let geometry = PinGeometry {
        rings: vec![1],
        ..PinGeometry::default()
    };
    let camera = Camera::new(&p, camera_seed);
    let pins = geometry.pin_positions_px();
    let mut model = PixelModel::new(&p, &pins, &camera)?;
    let sweep = Sweep {
        from_px: -8.0,
        span_px: 16.0,
        duration_s: 1.0,
    };
    let mut raw = Vec::new();
    model.run(&camera, &sweep, 1.2, camera_seed, false, &mut raw);
    raw.sort_by_key(|e| (e.t_us, e.y, e.x));
    let events: EventBuffer = raw
        .iter()
        .map(|e| neurotac_core::Event {
            t: neurotac_core::Timestamp(e.t_us),
            x: e.x,
            y: e.y,
            polarity: e.on,
        })
        .collect();
    let (cx, cy) = (pins[0].0 as u16, pins[0].1 as u16);
    let path = |x: u16, y: u16| x + 3 >= cx && x <= cx + 3 && y + 1 >= cy && y <= cy + 1;
    let on = raw.iter().filter(|e| e.on && path(e.x, e.y)).count();
    let off = raw.iter().filter(|e| !e.on && path(e.x, e.y)).count();
    let pixels = 21;
    let ln_k = (p.optics.pin_dn / p.optics.background_dn).ln();
    Ok(EdgePass {
        on_per_pixel: on as f64 / pixels as f64,
        off_per_pixel: off as f64 / pixels as f64,
        expected_on: ln_k / p.pixel.threshold_on,
        expected_off: ln_k / p.pixel.threshold_off,
        pixels,
        sanity: pixel_sanity(&events),
    })
}
