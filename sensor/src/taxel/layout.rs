//! Where the taxels are: a [`TaxelLayout`] of receptive-field centres (px), from the NeuroTac
//! default geometry, from a JSON file, or detected from a calibration recording.

use super::lattice;
use crate::error::TransductionError;
use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH, PinGeometry};
use neurotac_core::EventBuffer;
use std::path::Path;

/// Receptive-field centres in image pixels, one per taxel, in taxel order.
#[derive(Debug, Clone, PartialEq)]
pub struct TaxelLayout {
    centres: Vec<(f64, f64)>,
}

impl TaxelLayout {
    /// A layout from explicit centres (validate it with [`validate`](Self::validate)).
    pub fn new(centres: Vec<(f64, f64)>) -> Self {
        Self { centres }
    }

    /// The NeuroTac's 49 pins at the simulator's scale ([`PinGeometry::default`]): rings of
    /// 1 + 8 + 16 + 24 around the image centre.
    pub fn neurotac_default() -> Self {
        Self::from_geometry(&PinGeometry::default())
    }

    /// The pin positions of `geometry`.
    pub fn from_geometry(geometry: &PinGeometry) -> Self {
        Self {
            centres: geometry.pin_positions_px(),
        }
    }

    /// Reads a JSON list of `[x, y]` centres (px).
    pub fn from_json_file(path: &Path) -> Result<Self, TransductionError> {
        let text = std::fs::read_to_string(path).map_err(|source| TransductionError::LayoutIo {
            path: path.to_owned(),
            source,
        })?;
        let centres: Vec<[f64; 2]> =
            serde_json::from_str(&text).map_err(|source| TransductionError::LayoutJson {
                path: path.to_owned(),
                source,
            })?;
        Ok(Self {
            centres: centres.into_iter().map(|[x, y]| (x, y)).collect(),
        })
    }

    /// The layout as a JSON list of `[x, y]` centres.
    pub fn to_json(&self) -> String {
        let list: Vec<[f64; 2]> = self.centres.iter().map(|&(x, y)| [x, y]).collect();
        serde_json::to_string(&list).expect("finite floats serialise")
    }

    /// The centres.
    pub fn centres(&self) -> &[(f64, f64)] {
        &self.centres
    }

    /// Number of taxels.
    pub fn len(&self) -> usize {
        self.centres.len()
    }

    /// `true` without taxels.
    pub fn is_empty(&self) -> bool {
        self.centres.is_empty()
    }

    /// Checks the taxel count (when `required`), that every centre is finite and inside the
    /// `width × height` image, and that no two receptive fields of radius `radius_px` overlap
    /// (centres at least `2·radius_px` apart).
    pub fn validate(
        &self,
        radius_px: f64,
        required: Option<usize>,
        width: u16,
        height: u16,
    ) -> Result<(), TransductionError> {
        if let Some(expected) = required.filter(|&n| n != self.centres.len()) {
            return Err(TransductionError::LayoutCount {
                expected,
                got: self.centres.len(),
            });
        }
        for (taxel, &(x, y)) in self.centres.iter().enumerate() {
            let inside = x.is_finite()
                && y.is_finite()
                && x >= 0.0
                && y >= 0.0
                && x < width as f64
                && y < height as f64;
            if !inside {
                return Err(TransductionError::LayoutOutOfImage {
                    taxel,
                    x,
                    y,
                    width,
                    height,
                });
            }
        }
        let min_px = 2.0 * radius_px;
        for a in 0..self.centres.len() {
            for b in a + 1..self.centres.len() {
                let d = dist(self.centres[a], self.centres[b]);
                if d < min_px {
                    return Err(TransductionError::LayoutOverlap {
                        a,
                        b,
                        distance_px: d,
                        radius_px,
                        min_px,
                    });
                }
            }
        }
        Ok(())
    }

    /// Finds up to `expected` taxel centres from the pixel activity of a calibration recording
    /// (see [`LayoutDetection`]).
    pub fn detect(events: &EventBuffer, expected: usize, radius_px: f64) -> LayoutDetection {
        detect(events, expected, radius_px)
    }
}

pub(crate) fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt()
}

/// The result of [`TaxelLayout::detect`].
///
/// Method for the NeuroTac's 49 pins (`expected` = 49): fit the pin rings of
/// [`PinGeometry::default`] — image position, scale within ±20 % and rotation within ±22.5° —
/// to the events. On a sliding recording every pin moves, so the densest spots are its edges,
/// two per pin, and a search for separate density peaks finds edges instead of pins; the ring
/// lattice does not. The centres come in the default layout's order. With fewer than 3 pins
/// active (events clearly above the background) the lattice is not placed: only the active
/// pins are reported, and `found` counts them.
///
/// Any other count: count events per pixel; sum the counts over a disc of the receptive-field
/// radius around every pixel; take local maxima, strongest first, at least `2·radius` apart and
/// holding at least 10 % of the strongest peak's density; refine each to the centroid of the
/// events within its radius; order by activity. This suits pins that twitch in place only.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutDetection {
    /// The centres found.
    pub layout: TaxelLayout,
    /// How many were found (may be fewer than expected).
    pub found: usize,
    /// How many were asked for.
    pub expected: usize,
    /// How much to trust the layout, in [0, 1]. For the 49-pin lattice: the active pins whose
    /// events confirm it (a spot centred within 1 px of the lattice pin) less the active pins
    /// that contradict it, over 49. At or above
    /// [`RELIABLE_CONFIDENCE`](Self::RELIABLE_CONFIDENCE) the layout was right on simulated
    /// slides (see that constant). For other counts: separation of the weakest accepted peak from
    /// the strongest rejected one, `1 − density(next) / density(weakest)`; 0 when fewer than
    /// `expected` were found.
    pub confidence: f64,
    /// Pins whose events stand clearly above the background (lattice fit; for other counts, the
    /// peaks found).
    pub active: usize,
    /// Fraction of the recording's events inside the detected receptive fields.
    pub captured_fraction: f64,
}

/// The fewest active pins that place the 49-pin lattice: fewer do not fix its position, scale
/// and rotation.
const MIN_ACTIVE_PINS: usize = 3;

impl LayoutDetection {
    /// Confidence at and above which a detected 49-pin layout can be used without checking.
    /// Calibrated by the test `layout_accuracy` on 150 simulated slides (50 across textures ×
    /// 3 cameras with the pins off their nominal position and scale), each detected thrice:
    /// from the first second — the press and the slide's onset, when every pin moves (every
    /// layout right, all 49 centres within 3 px, confidence 1.00) —, from the first 100 ms,
    /// before the dome touches (noise only: never reliable, confidence ≤ 0.18), and with the
    /// pins magnified 1.4× (always wrong, confidence 0). The real non-tactile DAVIS240
    /// recording in `shared/data/davis240` scores 0. A window holding the press alone places
    /// the lattice from the inner rings only, where a wrongly scaled lattice can fit: use one
    /// that holds the slide's onset.
    pub const RELIABLE_CONFIDENCE: f64 = 0.2;

    /// `true` when [`confidence`](Self::confidence) reaches
    /// [`RELIABLE_CONFIDENCE`](Self::RELIABLE_CONFIDENCE).
    pub fn is_reliable(&self) -> bool {
        self.confidence >= Self::RELIABLE_CONFIDENCE
    }
}

fn detect(events: &EventBuffer, expected: usize, radius_px: f64) -> LayoutDetection {
    let r = radius_px.max(0.5);
    let geometry = PinGeometry::default();
    let (centres, found, active, confidence) = if expected == geometry.n_pins() {
        match lattice::fit(events, &geometry) {
            Some(fit) => {
                let active = fit.active.iter().filter(|&&a| a).count();
                if active >= MIN_ACTIVE_PINS {
                    (fit.centres, expected, active, fit.confidence)
                } else {
                    // Too few pins to place the lattice: report only the active ones.
                    let centres: Vec<(f64, f64)> = fit
                        .centres
                        .into_iter()
                        .zip(&fit.active)
                        .filter_map(|(c, &a)| a.then_some(c))
                        .collect();
                    (centres, active, active, 0.0)
                }
            }
            None => (Vec::new(), 0, 0, 0.0),
        }
    } else {
        let (centres, confidence) = peaks(events, expected, r);
        let found = centres.len();
        (centres, found, found, confidence)
    };
    let layout = TaxelLayout::new(centres);
    let inside = events
        .iter()
        .filter(|e| {
            layout
                .centres
                .iter()
                .any(|&c| dist(c, (e.x as f64, e.y as f64)) <= r)
        })
        .count();
    LayoutDetection {
        layout,
        found,
        expected,
        confidence,
        active,
        captured_fraction: if events.is_empty() {
            0.0
        } else {
            inside as f64 / events.len() as f64
        },
    }
}

/// Density peaks (see [`LayoutDetection`]): the centres, strongest first, and the confidence.
fn peaks(events: &EventBuffer, expected: usize, r: f64) -> (Vec<(f64, f64)>, f64) {
    let (w, h) = (DAVIS240_WIDTH as usize, DAVIS240_HEIGHT as usize);
    let mut counts = vec![0u32; w * h];
    for e in events
        .iter()
        .filter(|e| (e.x as usize) < w && (e.y as usize) < h)
    {
        counts[e.y as usize * w + e.x as usize] += 1;
    }
    let ri = r.ceil() as isize;
    let disc: Vec<(isize, isize)> = (-ri..=ri)
        .flat_map(|dy| (-ri..=ri).map(move |dx| (dx, dy)))
        .filter(|&(dx, dy)| ((dx * dx + dy * dy) as f64) <= r * r)
        .collect();
    let at = |x: isize, y: isize| {
        if x < 0 || y < 0 || x >= w as isize || y >= h as isize {
            0
        } else {
            counts[y as usize * w + x as usize]
        }
    };
    let density: Vec<u64> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            disc.iter().map(|&(dx, dy)| at(x + dx, y + dy) as u64).sum()
        })
        .collect();
    // Candidate peaks: strongest first; ties broken by position for determinism.
    let mut order: Vec<usize> = (0..w * h).filter(|&i| density[i] > 0).collect();
    order.sort_by(|&a, &b| density[b].cmp(&density[a]).then(a.cmp(&b)));
    let min_sep = 2.0 * r;
    let floor = order.first().map_or(0, |&i| density[i]).div_ceil(10);
    let mut peaks: Vec<(f64, f64, u64)> = Vec::new();
    let mut next_strength = None;
    for i in order.into_iter().take_while(|&i| density[i] >= floor) {
        let p = ((i % w) as f64, (i / w) as f64);
        if peaks.iter().any(|&(x, y, _)| dist((x, y), p) < min_sep) {
            continue;
        }
        if peaks.len() == expected {
            next_strength = Some(density[i]);
            break;
        }
        peaks.push((p.0, p.1, density[i]));
    }
    // Refine each peak to the centroid of its disc.
    let centres: Vec<(f64, f64)> = peaks
        .iter()
        .map(|&(x, y, _)| {
            let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
            for &(dx, dy) in &disc {
                let c = at(x as isize + dx, y as isize + dy) as f64;
                sx += c * (x + dx as f64);
                sy += c * (y + dy as f64);
                n += c;
            }
            if n > 0.0 { (sx / n, sy / n) } else { (x, y) }
        })
        .collect();
    let found = centres.len();
    let confidence = match (found == expected, peaks.last(), next_strength) {
        (false, _, _) | (true, None, _) => 0.0,
        (true, Some(_), None) => 1.0,
        (true, Some(&(_, _, weakest)), Some(next)) => 1.0 - next as f64 / weakest as f64,
    };
    (centres, confidence)
}
