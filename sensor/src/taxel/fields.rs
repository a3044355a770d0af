//! Receptive fields: which taxel (if any) a pixel event belongs to, with moving centres.
//!
//! A field is a disc of radius `r` around its centre; an event belongs to the nearest centre
//! whose disc contains it (ties: the lower taxel index), else to none and is dropped. Centres
//! move (re-centring) but never farther than `max_shift` from their home, so a static table of
//! candidate taxels per 8 × 8-pixel cell — those whose disc can reach the cell — answers every
//! lookup with one or two distance tests, and moving a centre costs nothing.

use super::layout::{TaxelLayout, dist};
use crate::error::{TransductionError, check_in_sensor};
use crate::stage::Stage;
use neurotac_core::{Event, EventBuffer};

const CELL: usize = 8;

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
}

impl ReceptiveFields {
    /// Fields of radius `radius_px` around `layout`'s centres in a `width × height` image;
    /// centres may later move up to `max_shift_px` from home. The layout is validated first
    /// (inside the image, no overlapping fields).
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
        if layout.len() > u16::MAX as usize {
            return Err(TransductionError::LayoutCount {
                expected: u16::MAX as usize,
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
            if let Some(taxel) = self.fields.assign(event.x, event.y) {
                out.push(TaxelPixelEvent { event, taxel });
            }
        }
        Ok(())
    }
}
