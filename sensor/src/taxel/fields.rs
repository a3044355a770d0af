//! Receptive fields: which taxel (if any) a pixel event belongs to, with moving centres.
//!
//! A field is a disc of radius `r` around its centre; an event belongs to the nearest centre
//! whose disc contains it (ties: the lower taxel index), else to none and is dropped. Centres
//! move (re-centring) but never farther than `max_shift` from their home, so a static table of
//! candidate taxels per 8 × 8-pixel cell — those whose disc can reach the cell — answers every
//! lookup with a few distance tests. On top of it, a per-pixel label memo
//! ([`ReceptiveFields::assign_cached`]) answers repeated lookups with one read; moving a centre
//! forgets only the labels inside its old or new disc that may have changed.

use super::layout::{TaxelLayout, dist};
use crate::error::{TransductionError, check_in_sensor};
use crate::stage::Stage;
use neurotac_core::{Event, EventBuffer};

const CELL: usize = 8;
/// Label memo: the pixel belongs to no taxel.
const NO_TAXEL: u16 = u16::MAX;
/// Label memo: not known (never looked up, or near a centre that moved since).
const UNKNOWN: u16 = u16::MAX - 1;
/// Most taxels a layout may have: the taxel indices stay below the memo's two markers.
const MAX_TAXELS: usize = UNKNOWN as usize;

/// A pixel event assigned to a taxel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaxelPixelEvent {
    /// The event.
    pub event: Event,
    /// Its taxel.
    pub taxel: u16,
}

/// The receptive fields of all taxels.
#[derive(Debug, Clone)]
pub struct ReceptiveFields {
    home: Vec<(f64, f64)>,
    centres: Vec<(f64, f64)>,
    radius: f64,
    max_shift: f64,
    width: u16,
    height: u16,
    cols: usize,
    cell_offsets: Vec<u32>,
    cell_taxels: Vec<u16>,
    /// Per pixel (row-major): [`Self::assign`]'s answer at the current centres ([`NO_TAXEL`]
    /// for none), or [`UNKNOWN`].
    labels: Vec<u16>,
}

impl ReceptiveFields {
    /// Fields of radius `radius_px` around `layout`'s centres in a `width × height` image;
    /// centres may later move up to `max_shift_px` from home. The layout is validated first
    /// (inside the image, no overlapping fields, at most 65 534 taxels).
    pub fn new(
        layout: &TaxelLayout,
        radius_px: f64,
        max_shift_px: f64,
        width: u16,
        height: u16,
    ) -> Result<Self, TransductionError> {
        if !(radius_px.is_finite() && radius_px > 0.0) {
            return Err(TransductionError::InvalidParameter {
                what: "receptive-field radius (px)",
                value: radius_px,
                expected: "finite and > 0",
            });
        }
        if !(max_shift_px.is_finite() && max_shift_px >= 0.0) {
            return Err(TransductionError::InvalidParameter {
                what: "maximum centre shift (px)",
                value: max_shift_px,
                expected: "finite and ≥ 0",
            });
        }
        if layout.len() > MAX_TAXELS {
            return Err(TransductionError::LayoutCount {
                expected: MAX_TAXELS,
                got: layout.len(),
            });
        }
        layout.validate(radius_px, None, width, height)?;
        let (cols, rows) = (
            (width as usize).div_ceil(CELL),
            (height as usize).div_ceil(CELL),
        );
        let reach = radius_px + max_shift_px;
        let mut cell_offsets = vec![0u32];
        let mut cell_taxels = Vec::new();
        for cy in 0..rows {
            for cx in 0..cols {
                let (x0, y0) = ((cx * CELL) as f64, (cy * CELL) as f64);
                let (x1, y1) = (x0 + CELL as f64 - 1.0, y0 + CELL as f64 - 1.0);
                for (t, &(hx, hy)) in layout.centres().iter().enumerate() {
                    // Distance from the home centre to the nearest pixel of the cell.
                    let d = dist((hx, hy), (hx.clamp(x0, x1), hy.clamp(y0, y1)));
                    if d <= reach {
                        cell_taxels.push(t as u16);
                    }
                }
                cell_offsets.push(cell_taxels.len() as u32);
            }
        }
        Ok(Self {
            home: layout.centres().to_vec(),
            centres: layout.centres().to_vec(),
            radius: radius_px,
            max_shift: max_shift_px,
            width,
            height,
            cols,
            cell_offsets,
            cell_taxels,
            labels: vec![UNKNOWN; width as usize * height as usize],
        })
    }

    /// The taxel of pixel `(x, y)`, if any (`(x, y)` must be inside the image).
    #[inline]
    pub fn assign(&self, x: u16, y: u16) -> Option<u16> {
        let cell = (y as usize / CELL) * self.cols + x as usize / CELL;
        let (a, b) = (
            self.cell_offsets[cell] as usize,
            self.cell_offsets[cell + 1] as usize,
        );
        let (px, py) = (x as f64, y as f64);
        let mut best = None;
        let mut best_d2 = self.radius * self.radius;
        for &t in &self.cell_taxels[a..b] {
            let (cx, cy) = self.centres[t as usize];
            let d2 = (px - cx) * (px - cx) + (py - cy) * (py - cy);
            if d2 < best_d2 || (d2 == best_d2 && best.is_none()) {
                best_d2 = d2;
                best = Some(t);
            }
        }
        best
    }

    /// [`Self::assign`], memoised per pixel: the first lookup of a pixel (and the first after a
    /// centre near it moved) computes and stores the answer, later ones read it.
    #[inline]
    pub fn assign_cached(&mut self, x: u16, y: u16) -> Option<u16> {
        let p = y as usize * self.width as usize + x as usize;
        match self.labels[p] {
            NO_TAXEL => None,
            UNKNOWN => {
                let taxel = self.assign(x, y);
                self.labels[p] = taxel.unwrap_or(NO_TAXEL);
                taxel
            }
            taxel => Some(taxel),
        }
    }

    /// Keeps the label memo true while taxel `t` moves from `old` to `new`. Only pixels inside
    /// the old or the new disc can change hands; of those, a label stays if it is still
    /// [`Self::assign`]'s answer for certain, and is forgotten otherwise:
    /// - labelled `t`, and at most as far from `new` as from `old`: `t` only got closer, the
    ///   other candidates did not move, so `t` still wins;
    /// - labelled something else (another taxel, none, unknown) and outside the new disc: the
    ///   candidates holding the pixel are those of before minus `t`, which was not the winner.
    ///
    /// The distances are computed as in [`Self::assign`], so "inside" means the same there.
    fn relabel_after_move(&mut self, t: u16, old: (f64, f64), new: (f64, f64)) {
        let r = self.radius;
        // The square around both discs, one pixel wider than rounding could need. Centres lie
        // inside the image, so the span is never empty; casts saturate.
        let span = |a: f64, b: f64, len: u16| {
            let low = (a.min(b) - r).floor() - 1.0;
            let high = (a.max(b) + r).ceil() + 1.0;
            (low.max(0.0) as usize, (high as usize).min(len as usize - 1))
        };
        let ((x0, x1), (y0, y1)) = (
            span(old.0, new.0, self.width),
            span(old.1, new.1, self.height),
        );
        let width = self.width as usize;
        for y in y0..=y1 {
            let py = y as f64;
            let dy2_new = (py - new.1) * (py - new.1);
            let dy2_old = (py - old.1) * (py - old.1);
            let row = &mut self.labels[y * width + x0..=y * width + x1];
            for (x, label) in (x0..).zip(row) {
                let px = x as f64;
                let d2_new = (px - new.0) * (px - new.0) + dy2_new;
                let d2_old = (px - old.0) * (px - old.0) + dy2_old;
                let inside_new = d2_new <= r * r;
                let still_true = if *label == t {
                    inside_new && d2_new <= d2_old
                } else {
                    !inside_new
                };
                if !still_true {
                    *label = UNKNOWN;
                }
            }
        }
    }

    /// Current centres.
    pub fn centres(&self) -> &[(f64, f64)] {
        &self.centres
    }

    /// Home (initial) centres.
    pub fn home(&self) -> &[(f64, f64)] {
        &self.home
    }

    /// Field radius (px).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Moves taxel `t`'s centre towards `target`, limited to `max_shift` from home, to the image,
    /// and to positions at least `2·radius` from every other centre (else it stays). Returns
    /// whether it moved.
    pub fn move_centre(&mut self, t: usize, target: (f64, f64)) -> bool {
        let home = self.home[t];
        let mut p = target;
        let shift = dist(home, p);
        if shift > self.max_shift {
            let k = self.max_shift / shift;
            p = (home.0 + (p.0 - home.0) * k, home.1 + (p.1 - home.1) * k);
        }
        p = (
            p.0.clamp(0.0, self.width as f64 - 1.0),
            p.1.clamp(0.0, self.height as f64 - 1.0),
        );
        let collides = self
            .centres
            .iter()
            .enumerate()
            .any(|(u, &c)| u != t && dist(c, p) < 2.0 * self.radius);
        if collides || !p.0.is_finite() || !p.1.is_finite() {
            return false;
        }
        self.relabel_after_move(t as u16, self.centres[t], p);
        self.centres[t] = p;
        true
    }

    /// Checks that `(x, y)` is inside the image.
    pub(crate) fn check(&self, index: u64, e: &Event) -> Result<(), TransductionError> {
        check_in_sensor(index, e.x, e.y, self.width, self.height)
    }
}

/// Stage: keeps the events inside some receptive field, labelled with their taxel.
#[derive(Debug, Clone)]
pub struct ReceptiveFieldMask {
    /// The fields (their centres may be moved between pushes).
    pub fields: ReceptiveFields,
    index: u64,
}

impl ReceptiveFieldMask {
    /// A mask over `fields`.
    pub fn new(fields: ReceptiveFields) -> Self {
        Self { fields, index: 0 }
    }
}

impl Stage for ReceptiveFieldMask {
    type Input = EventBuffer;
    type Output = Vec<TaxelPixelEvent>;

    fn push(
        &mut self,
        input: &EventBuffer,
        out: &mut Vec<TaxelPixelEvent>,
    ) -> Result<(), TransductionError> {
        for event in input.iter() {
            self.fields.check(self.index, &event)?;
            self.index += 1;
            if let Some(taxel) = self.fields.assign_cached(event.x, event.y) {
                out.push(TaxelPixelEvent { event, taxel });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition over every centre: the nearest whose disc holds the pixel, ties to the
    /// lower index.
    fn brute_force(fields: &ReceptiveFields, x: u16, y: u16) -> Option<u16> {
        let (px, py) = (x as f64, y as f64);
        let r2 = fields.radius() * fields.radius();
        let mut best: Option<(f64, u16)> = None;
        for (t, &(cx, cy)) in fields.centres().iter().enumerate() {
            let d2 = (px - cx) * (px - cx) + (py - cy) * (py - cy);
            if d2 <= r2 && best.is_none_or(|(b, _)| d2 < b) {
                best = Some((d2, t as u16));
            }
        }
        best.map(|(_, t)| t)
    }

    /// The relabelling rules do not rely on the spacing that `move_centre` keeps: with centres
    /// forced into overlapping discs, a taxel moving away from a pixel that another disc also
    /// holds loses it.
    #[test]
    fn relabelling_is_exact_for_overlapping_discs_too() {
        let layout = TaxelLayout::new(vec![(50.0, 50.0), (70.0, 50.0)]);
        let mut fields = ReceptiveFields::new(&layout, 6.0, 20.0, 240, 180).unwrap();
        fields.centres[1] = (57.0, 50.0);
        let check_all = |fields: &mut ReceptiveFields| {
            for y in 40..60 {
                for x in 40..70 {
                    assert_eq!(
                        fields.assign_cached(x, y),
                        brute_force(fields, x, y),
                        "({x}, {y})"
                    );
                }
            }
        };
        check_all(&mut fields);
        assert_eq!(fields.assign_cached(53, 50), Some(0));
        // Taxel 0 moves 2 px left: pixel 53 is still inside its disc (5 px) but taxel 1 (4 px)
        // is now nearer.
        fields.relabel_after_move(0, (50.0, 50.0), (48.0, 50.0));
        fields.centres[0] = (48.0, 50.0);
        assert_eq!(fields.assign_cached(53, 50), Some(1));
        check_all(&mut fields);
    }

    /// Integer moves around home (often landing exactly 2·r from a neighbour, so pixels tie),
    /// each batch followed by a lookup of every pixel: the memo, filled by the previous batch,
    /// must have forgotten exactly enough.
    #[test]
    fn memoised_labels_equal_brute_force_assignment_after_moves() {
        let mut state = 42u64;
        let mut next = move |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let layouts = [
            (TaxelLayout::neurotac_default(), 6.0, 10.0),
            (
                TaxelLayout::new(vec![(50.0, 50.0), (62.0, 50.0), (56.0, 62.0), (0.0, 179.0)]),
                6.0,
                4.0,
            ),
        ];
        for (layout, radius, max_shift) in layouts {
            let mut fields = ReceptiveFields::new(&layout, radius, max_shift, 240, 180).unwrap();
            let mut moved = 0;
            for round in 0..30 {
                for _ in 0..8 {
                    let t = next(layout.len() as u64) as usize;
                    let (hx, hy) = fields.home()[t];
                    let offset = |v: u64| v as f64 - max_shift - 2.0;
                    let span = 2 * max_shift as u64 + 5;
                    let target = (hx + offset(next(span)), hy + offset(next(span)));
                    moved += fields.move_centre(t, target) as usize;
                }
                for y in 0..180 {
                    for x in 0..240 {
                        assert_eq!(
                            fields.assign_cached(x, y),
                            brute_force(&fields, x, y),
                            "round {round}, pixel ({x}, {y}), centres {:?}",
                            fields.centres()
                        );
                    }
                }
            }
            assert!(moved > 30, "{moved} moves");
        }
    }
}
