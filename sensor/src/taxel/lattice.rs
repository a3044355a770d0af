//! Fitting the NeuroTac's pin lattice to the events of a calibration recording.
//!
//! A sliding or pressed sensor moves every pin by a few pixels, so each pin's events form a
//! smeared crescent pair (leading ON edge, trailing OFF edge) rather than a blob at its centre;
//! local maxima of event density then fall on pin edges, two per pin. The pins' arrangement,
//! however, is known: the rings of [`PinGeometry`] (`1 + 8 + 16 + 24`), seen by the camera up to
//! an unknown image position, scale and rotation. [`fit`] finds those three by maximising the
//! events under the lattice's pins:
//!
//! 1. count events per pixel, each pixel capped at [`PIXEL_CAP`] (hot pixels and busy edges
//!    weigh no more than a pixel a pin edge crossed once or twice);
//! 2. box-sum the capped counts over `(2·BLOB_HALF_PX + 1)²` pixels (a pin tip plus its motion);
//! 3. score every lattice `(centre, scale, rotation)` by the box sums at its 49 pins: coarse grid
//!    (3 px, 0.15 px/mm, 3°) over the plausible range, then a fine search (0.5 px, 0.02 px/mm,
//!    0.5°) around the best coarse lattice;
//! 4. refine to sub-pixel: centroid of the capped counts within `BLOB_HALF_PX` of each active
//!    pin, and the similarity transform (least squares) that maps the lattice onto those
//!    centroids; twice.
//!
//! The fit's quality ([`LatticeFit::confidence`]): a pin is *active* when its box sum stands
//! clearly above the background's, and *confirmed* when, moreover, its events form a spot
//! (denser on the pin than in the ring around it) whose centroid lies within 1 px of the lattice
//! pin. The confidence is `(confirmed − (active − confirmed)) / 49`, at least 0: the pins whose
//! own events confirm the lattice less those that contradict it. A right lattice confirms nearly
//! every active pin; a wrong one (pins spaced otherwise, a scene without pins) contradicts about
//! as many as it confirms.

use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH, PinGeometry};
use neurotac_core::EventBuffer;

/// A pixel's event count is capped here before scoring.
const PIXEL_CAP: u32 = 4;
/// Half-width of the box summed around a lattice pin (px): pin tip radius ≈ 3 px plus motion.
const BLOB_HALF_PX: i32 = 4;
/// An active pin is confirmed when its events' centroid lies this close to the lattice (px).
const CONFIRM_PX: f64 = 1.0;
/// A confirmed pin's events are at least this many times denser on it than around it.
const SPOT_CONTRAST: f64 = 2.0;
/// Padding around the image in the density map, so lattice pins off the image score 0 without
/// bounds checks (px; more than the largest ring radius at the largest scale).
const PAD: i32 = 80;
/// Scale search range (px/mm) around the nominal 4.5: ±20 %.
const SCALE_RANGE: (f64, f64) = (3.6, 5.4);
/// Rotation search range (degrees): the ring lattice repeats every 45°.
const ROTATION_DEG: f64 = 22.5;

/// The lattice that best explains a calibration recording.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LatticeFit {
    /// Pin centres (px), in [`PinGeometry::pin_positions_mm`] order.
    pub centres: Vec<(f64, f64)>,
    /// Per pin: is its box sum clearly above the background (see module doc)?
    pub active: Vec<bool>,
    /// `max(0, 2·confirmed − active) / pins`, in [0, 1] (see module doc).
    pub confidence: f64,
}

/// The capped, box-summed event density on a padded grid.
struct Density {
    w: i32,
    h: i32,
    boxed: Vec<u32>,
    capped: Vec<u32>,
    total: u64,
}

impl Density {
    fn new(events: &EventBuffer) -> Self {
        let (iw, ih) = (i32::from(DAVIS240_WIDTH), i32::from(DAVIS240_HEIGHT));
        let (w, h) = (iw + 2 * PAD, ih + 2 * PAD);
        let mut capped = vec![0u32; (w * h) as usize];
        for e in events
            .iter()
            .filter(|e| i32::from(e.x) < iw && i32::from(e.y) < ih)
        {
            let i = ((i32::from(e.y) + PAD) * w + i32::from(e.x) + PAD) as usize;
            capped[i] = (capped[i] + 1).min(PIXEL_CAP);
        }
        let total = capped.iter().map(|&c| u64::from(c)).sum();
        // Summed-area table, then box sums.
        let (wu, hu) = (w as usize, h as usize);
        let mut sat = vec![0u32; (wu + 1) * (hu + 1)];
        for y in 0..hu {
            let mut row = 0u32;
            for x in 0..wu {
                row += capped[y * wu + x];
                sat[(y + 1) * (wu + 1) + x + 1] = sat[y * (wu + 1) + x + 1] + row;
            }
        }
        let b = BLOB_HALF_PX;
        let mut boxed = vec![0u32; wu * hu];
        for y in 0..h {
            for x in 0..w {
                let (x0, x1) = ((x - b).max(0) as usize, (x + b + 1).min(w) as usize);
                let (y0, y1) = ((y - b).max(0) as usize, (y + b + 1).min(h) as usize);
                let s = |xx: usize, yy: usize| sat[yy * (wu + 1) + xx];
                boxed[(y * w + x) as usize] = s(x1, y1) + s(x0, y0) - s(x0, y1) - s(x1, y0);
            }
        }
        Self {
            w,
            h,
            boxed,
            capped,
            total,
        }
    }

    /// Box sum at image pixel (x, y) (0 outside the padded grid).
    fn at(&self, x: i32, y: i32) -> u32 {
        let (px, py) = (x + PAD, y + PAD);
        if px < 0 || py < 0 || px >= self.w || py >= self.h {
            0
        } else {
            self.boxed[(py * self.w + px) as usize]
        }
    }

    /// Box sum bilinearly interpolated at image point `p`.
    fn at_f(&self, p: (f64, f64)) -> f64 {
        let (fx, fy) = (p.0.floor(), p.1.floor());
        let (ax, ay) = (p.0 - fx, p.1 - fy);
        let (x, y) = (fx as i32, fy as i32);
        let v = |dx: i32, dy: i32| f64::from(self.at(x + dx, y + dy));
        (1.0 - ay) * ((1.0 - ax) * v(0, 0) + ax * v(1, 0))
            + ay * ((1.0 - ax) * v(0, 1) + ax * v(1, 1))
    }

    /// Capped count at image pixel (x, y).
    fn capped(&self, x: i32, y: i32) -> u32 {
        let (px, py) = (x + PAD, y + PAD);
        if px < 0 || py < 0 || px >= self.w || py >= self.h {
            0
        } else {
            self.capped[(py * self.w + px) as usize]
        }
    }
}

/// A similarity transform of the lattice: image centre (px), scale (px/mm), rotation (rad).
#[derive(Debug, Clone, Copy)]
struct Pose {
    cx: f64,
    cy: f64,
    scale: f64,
    angle: f64,
}

impl Pose {
    fn place(&self, mm: &[(f64, f64)]) -> Vec<(f64, f64)> {
        let (s, c) = self.angle.sin_cos();
        mm.iter()
            .map(|&(x, y)| {
                (
                    self.cx + self.scale * (c * x - s * y),
                    self.cy + self.scale * (s * x + c * y),
                )
            })
            .collect()
    }
}

/// Fits `geometry`'s pin rings to `events` (see the module doc); `None` without events.
pub(crate) fn fit(events: &EventBuffer, geometry: &PinGeometry) -> Option<LatticeFit> {
    let d = Density::new(events);
    if d.total == 0 {
        return None;
    }
    let mm = geometry.pin_positions_mm();
    let best = coarse_search(&d, &mm);
    let pose = fine_search(&d, &mm, best);
    let pose = refine(&d, &mm, pose);
    let centres = pose.place(&mm);
    let active = activity(&d, &centres);
    let n_active = active.iter().filter(|&&a| a).count();
    let confirmed = confirmed(&d, &centres, &active);
    Some(LatticeFit {
        confidence: (2 * confirmed).saturating_sub(n_active) as f64 / mm.len() as f64,
        active,
        centres,
    })
}

/// Best pose on the coarse grid; ties keep the first in scan order (deterministic).
fn coarse_search(d: &Density, mm: &[(f64, f64)]) -> Pose {
    let (iw, ih) = (f64::from(DAVIS240_WIDTH), f64::from(DAVIS240_HEIGHT));
    let mut best = (
        0u64,
        Pose {
            cx: iw / 2.0,
            cy: ih / 2.0,
            scale: 4.5,
            angle: 0.0,
        },
    );
    let n_rot = (2.0 * ROTATION_DEG / 3.0).round() as i32;
    let n_scale = ((SCALE_RANGE.1 - SCALE_RANGE.0) / 0.15).round() as i32;
    for r in 0..=n_rot {
        let angle = (-ROTATION_DEG + 3.0 * f64::from(r)).to_radians();
        for k in 0..=n_scale {
            let scale = SCALE_RANGE.0 + 0.15 * f64::from(k);
            let offsets: Vec<(i32, i32)> = Pose {
                cx: 0.0,
                cy: 0.0,
                scale,
                angle,
            }
            .place(mm)
            .into_iter()
            .map(|(x, y)| (x.round() as i32, y.round() as i32))
            .collect();
            // Centres that keep the lattice's middle inside the image; every pin then lies
            // inside the padded grid (|offset| < PAD), so plain indexing is in bounds.
            let reach = offsets
                .iter()
                .map(|&(x, y)| x.abs().max(y.abs()))
                .max()
                .unwrap_or(0);
            if reach >= PAD {
                continue;
            }
            let linear: Vec<usize> = offsets
                .iter()
                .map(|&(dx, dy)| ((dy + PAD) * d.w + dx + PAD) as usize)
                .collect();
            let lo = reach / 2;
            for cy in (lo..=(ih as i32 - lo)).step_by(3) {
                for cx in (lo..=(iw as i32 - lo)).step_by(3) {
                    let base = (cy * d.w + cx) as usize;
                    let score: u64 = linear.iter().map(|&o| u64::from(d.boxed[base + o])).sum();
                    if score > best.0 {
                        best = (
                            score,
                            Pose {
                                cx: f64::from(cx),
                                cy: f64::from(cy),
                                scale,
                                angle,
                            },
                        );
                    }
                }
            }
        }
    }
    best.1
}

/// Best pose on a fine grid around `around`.
fn fine_search(d: &Density, mm: &[(f64, f64)], around: Pose) -> Pose {
    let score = |p: &Pose| -> f64 { p.place(mm).into_iter().map(|q| d.at_f(q)).sum() };
    let mut best = (score(&around), around);
    for r in -6..=6 {
        let angle = around.angle + (0.5 * f64::from(r)).to_radians();
        for k in -5..=5 {
            let scale = around.scale + 0.02 * f64::from(k);
            for j in -4..=4 {
                for i in -4..=4 {
                    let p = Pose {
                        cx: around.cx + 0.5 * f64::from(i),
                        cy: around.cy + 0.5 * f64::from(j),
                        scale,
                        angle,
                    };
                    let s = score(&p);
                    if s > best.0 {
                        best = (s, p);
                    }
                }
            }
        }
    }
    best.1
}

/// Sub-pixel refinement: pin centroids, then the least-squares similarity transform onto them.
fn refine(d: &Density, mm: &[(f64, f64)], mut pose: Pose) -> Pose {
    for _ in 0..2 {
        let placed = pose.place(mm);
        let active = activity(d, &placed);
        let pairs: Vec<PinMatch> = placed
            .iter()
            .zip(mm)
            .zip(&active)
            .filter(|(_, a)| **a)
            .filter_map(|((&p, &m), _)| centroid(d, p).map(|c| (m, c)))
            .collect();
        // Three pins fix a similarity transform robustly enough; fewer keep the pose.
        match similarity(&pairs) {
            Some(p) if pairs.len() >= 3 => pose = p,
            _ => break,
        }
    }
    pose
}

/// A pin's lattice position (mm) and where its events put it in the image (px).
type PinMatch = ((f64, f64), (f64, f64));

/// The least-squares similarity transform mapping the `mm` points onto the `px` points.
fn similarity(pairs: &[PinMatch]) -> Option<Pose> {
    let n = pairs.len() as f64;
    if pairs.is_empty() {
        return None;
    }
    let (mut mx, mut my, mut qx, mut qy) = (0.0, 0.0, 0.0, 0.0);
    for &((ax, ay), (bx, by)) in pairs {
        mx += ax / n;
        my += ay / n;
        qx += bx / n;
        qy += by / n;
    }
    let (mut a, mut b, mut norm) = (0.0, 0.0, 0.0);
    for &((ax, ay), (bx, by)) in pairs {
        let (ux, uy, vx, vy) = (ax - mx, ay - my, bx - qx, by - qy);
        a += ux * vx + uy * vy;
        b += ux * vy - uy * vx;
        norm += ux * ux + uy * uy;
    }
    if norm <= 0.0 {
        return None;
    }
    let (sa, sb) = (a / norm, b / norm);
    let scale = sa.hypot(sb);
    let angle = sb.atan2(sa);
    let (s, c) = angle.sin_cos();
    Some(Pose {
        cx: qx - scale * (c * mx - s * my),
        cy: qy - scale * (s * mx + c * my),
        scale,
        angle,
    })
}

/// Which pins are active: box sum above the background's expected box sum (the capped events
/// outside every pin box spread uniformly) by three standard deviations and three events.
fn activity(d: &Density, centres: &[(f64, f64)]) -> Vec<bool> {
    let sums: Vec<u32> = centres
        .iter()
        .map(|&(x, y)| d.at(x.round() as i32, y.round() as i32))
        .collect();
    let side = f64::from(2 * BLOB_HALF_PX + 1);
    let pixels = f64::from(DAVIS240_WIDTH) * f64::from(DAVIS240_HEIGHT);
    let under: f64 = sums.iter().map(|&s| f64::from(s)).sum();
    let outside_area = (pixels - centres.len() as f64 * side * side).max(side * side);
    let background = ((d.total as f64 - under).max(0.0) / outside_area) * side * side;
    let threshold = background + 3.0 * background.sqrt() + 3.0;
    sums.iter().map(|&s| f64::from(s) >= threshold).collect()
}

/// The centroid of the capped counts within `BLOB_HALF_PX` of `p` (`None` without events).
fn centroid(d: &Density, p: (f64, f64)) -> Option<(f64, f64)> {
    let (x0, y0) = (p.0.round() as i32, p.1.round() as i32);
    let b = BLOB_HALF_PX;
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in y0 - b..=y0 + b {
        for x in x0 - b..=x0 + b {
            let c = f64::from(d.capped(x, y));
            sx += c * f64::from(x);
            sy += c * f64::from(y);
            n += c;
        }
    }
    (n > 0.0).then(|| (sx / n, sy / n))
}

/// `true` when the events around `p` form a spot: the mean capped count within
/// `BLOB_HALF_PX` of `p` is at least [`SPOT_CONTRAST`] times the mean over the ring between
/// `BLOB_HALF_PX + 2` and `BLOB_HALF_PX + 4` px (between a pin's tip and its neighbours'); a
/// busy region of a scene without pins is as dense there as at `p`.
fn isolated(d: &Density, p: (f64, f64)) -> bool {
    let (x0, y0) = (p.0.round() as i32, p.1.round() as i32);
    let (inner_r, ring) = (
        f64::from(BLOB_HALF_PX),
        (f64::from(BLOB_HALF_PX + 2), f64::from(BLOB_HALF_PX + 4)),
    );
    let reach = BLOB_HALF_PX + 4;
    let (mut inner, mut n_inner, mut outer, mut n_outer) = (0.0, 0.0, 0.0, 0.0);
    for y in y0 - reach..=y0 + reach {
        for x in x0 - reach..=x0 + reach {
            let r = (f64::from(x) - p.0).hypot(f64::from(y) - p.1);
            let c = f64::from(d.capped(x, y));
            if r <= inner_r {
                inner += c;
                n_inner += 1.0;
            } else if r > ring.0 && r <= ring.1 {
                outer += c;
                n_outer += 1.0;
            }
        }
    }
    inner / n_inner >= SPOT_CONTRAST * outer / n_outer
}

/// How many active pins are confirmed: their events' centroid within [`CONFIRM_PX`] of the
/// lattice pin and forming a spot ([`isolated`]).
fn confirmed(d: &Density, centres: &[(f64, f64)], active: &[bool]) -> usize {
    centres
        .iter()
        .zip(active)
        .filter(|(_, a)| **a)
        .filter(|&(&p, _)| {
            centroid(d, p).is_some_and(|c| (c.0 - p.0).hypot(c.1 - p.1) <= CONFIRM_PX)
                && isolated(d, p)
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_core::{Event, Timestamp};

    /// Every pin of `pose` flickers: a 5 × 5 px spot, 20 times.
    fn spots(pose: Pose) -> (EventBuffer, Vec<(f64, f64)>) {
        let pins = pose.place(&PinGeometry::default().pin_positions_mm());
        let mut events = EventBuffer::new();
        for round in 0..20i64 {
            for &(x, y) in &pins {
                for (dx, dy) in (-2..=2).flat_map(|dy| (-2..=2).map(move |dx| (dx, dy))) {
                    events.push(Event {
                        t: Timestamp(round),
                        x: (x.round() as i32 + dx) as u16,
                        y: (y.round() as i32 + dy) as u16,
                        polarity: true,
                    });
                }
            }
        }
        (events, pins)
    }

    #[test]
    fn a_shifted_rescaled_rotated_lattice_is_found_in_pin_order() {
        let pose = Pose {
            cx: 127.0,
            cy: 84.0,
            scale: 4.1,
            angle: 12f64.to_radians(),
        };
        let (events, truth) = spots(pose);
        let fit = fit(&events, &PinGeometry::default()).unwrap();
        for (found, true_pin) in fit.centres.iter().zip(&truth) {
            let err = (found.0 - true_pin.0).hypot(found.1 - true_pin.1);
            assert!(err < 0.75, "{found:?} vs {true_pin:?}");
        }
        assert!(fit.active.iter().all(|&a| a));
        assert!(fit.confidence > 0.9, "{}", fit.confidence);
        // The same events again: the same fit, bit for bit.
        assert_eq!(super::fit(&events, &PinGeometry::default()).unwrap(), fit);
    }

    #[test]
    fn no_events_no_fit() {
        assert!(fit(&EventBuffer::new(), &PinGeometry::default()).is_none());
    }
}
