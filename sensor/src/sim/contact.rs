//! The skin-on-texture contact, solved once per texture (spec §2.2 step 2, and the non-linear
//! partial contact of §8: the skin's sag grows with the gap until it meets the floor).
//!
//! **Model.** The 1 mm skin pressed on a texture is a membrane of tension T on a Winkler
//! foundation (the gel, stiffness k per area) under the nominal contact pressure q, resting on
//! the rigid texture height h(x, y). Its surface z_s(x, y) solves the obstacle problem
//!
//! ```text
//! T·∇²z_s − k·(z_s − ⟨z_s⟩) = q   where z_s > h   (free skin sags into gaps),
//! z_s = h, contact pressure p = q + k·(z_s − ⟨z_s⟩) − T·∇²z_s ≥ 0   where it touches,
//! ```
//!
//! on one periodic cell. A free membrane over a gap g sags q·g²/(8T) (Timoshenko &
//! Woinowsky-Krieger, membrane under uniform pressure), so the sag grows as g² until the skin
//! meets the gap floor at the bump height: the **non-linear partial contact** of the fine
//! grids (skin on the bump tops only, nearly flat) and the coarse ones (skin draped to the
//! floor). The tension is set by the calibrated conformity gap g₀, the gap over which the free
//! skin sags 1 mm: T = q·g₀²/(8 · 1 mm). The foundation limits the sag of very wide gaps to
//! about q/k.
//!
//! **Solver.** Projected successive over-relaxation (Cryer 1971) on the cell grid, ω =
//! 2/(1 + sin(π/N)), from a flat skin resting on the highest point, until the largest update
//! is below 10⁻⁷ mm. Deterministic (fixed sweep order), once per texture.
//!
//! **What the rest of the simulator uses.** The conformed surface z_s (the pins feel its
//! low-passed slope, [`super::texture`]), the contact pressure p (the local traction
//! μ_k·p under each pin, [`super::mechanics`]), and two friction measures
//! ([`super::texture::Surface`]): the real contact area relative to a flat plate,
//! A/A₀ = erf(√2·p̄/(E*·h'_rms)) over the contacted fraction at its mean pressure p̄ (Persson
//! 2001; the 1 mm skin spreads the membrane's edge line loads over the tops), and the mean slope
//! ⟨|∂z_s/∂X|⟩ of the draped skin, which scales the hysteresis friction
//! μ_hys = tan δ·⟨|∂z_s/∂X|⟩ (Greenwood & Tabor 1958).

use neurotac_core::special::erfc;

/// Skin surface sag (mm) that defines the conformity gap g₀: T = q·g₀²/(8 · this).
const REFERENCE_SAG_MM: f64 = 1.0;

/// The solved contact of one periodic texture cell.
#[derive(Debug, Clone, PartialEq)]
pub struct SkinContact {
    /// Conformed skin surface z_s (mm), row-major `nx × ny`.
    pub surface_mm: Vec<f64>,
    /// Contact pressure on the skin (MPa = N/mm²), 0 where the skin is free.
    pub pressure_mpa: Vec<f64>,
    /// Fraction of the cell in contact.
    pub contact_fraction: f64,
    /// Mean |∂z_s/∂X| of the conformed skin along the slide.
    pub mean_abs_slope: f64,
    /// Deepest sag of the skin below the highest texture point (mm).
    pub max_sag_mm: f64,
    /// Mean sag of the skin below the highest texture point over the cell (mm): how much less
    /// the dome is compressed than on a plate at the tops' level ([`super::layer::Press`]).
    pub mean_sag_mm: f64,
    /// Real contact area relative to the same skin on a flat plate (Persson 2001).
    pub real_area_ratio: f64,
    /// Sweeps the solver took.
    pub sweeps: usize,
}

/// The physical constants of a contact solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// Nominal pressure q (MPa).
    pub pressure_mpa: f64,
    /// Membrane tension T (N/mm).
    pub tension_n_mm: f64,
    /// Foundation stiffness k (N/mm³).
    pub foundation_n_mm3: f64,
    /// E*·h'_rms of the real-contact-area law (MPa).
    pub area_scale_mpa: f64,
}

impl ContactLaw {
    /// The law of `contact` parameters under nominal pressure `pressure_mpa`.
    pub fn new(contact: &super::params::ContactParams, pressure_mpa: f64) -> Self {
        let g0 = contact.gap_conformity_mm;
        Self {
            pressure_mpa,
            tension_n_mm: pressure_mpa * g0 * g0 / (8.0 * REFERENCE_SAG_MM),
            foundation_n_mm3: contact.foundation_stiffness_n_mm3,
            area_scale_mpa: contact.skin_modulus_mpa * contact.micro_slope_rms,
        }
    }

    /// Real contact area fraction A/A₀ of skin pressed at `p_mpa` (Persson 2001).
    pub fn area_fraction(&self, p_mpa: f64) -> f64 {
        1.0 - erfc(std::f64::consts::SQRT_2 * p_mpa.max(0.0) / self.area_scale_mpa)
    }
}

/// Solves the contact of the skin on heights `h` (mm, row-major `nx × ny`, periodic, spacing
/// `dx × dy` mm) under `law` (see the module docs).
pub fn solve(
    h: &[f64],
    (nx, ny): (usize, usize),
    (dx, dy): (f64, f64),
    law: &ContactLaw,
) -> SkinContact {
    assert_eq!(h.len(), nx * ny, "height field size");
    let (t, k, q) = (law.tension_n_mm, law.foundation_n_mm3, law.pressure_mpa);
    let (ax, ay) = (t / (dx * dx), t / (dy * dy));
    let diag = 2.0 * ax + 2.0 * ay + k;
    let top = h.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut z = vec![top; nx * ny];
    let n = nx.max(ny) as f64;
    let omega = 2.0 / (1.0 + (std::f64::consts::PI / n).sin());
    let max_sweeps = (40.0 * n) as usize + 200;
    let mut mean = top;
    let mut sweeps = 0;
    let sweep = Sweep {
        h,
        nx,
        ny,
        ax,
        ay,
        diag,
        q,
        omega,
    };
    while sweeps < max_sweeps {
        sweeps += 1;
        let change = sweep.run(&mut z, k * mean);
        // Summed in cell order after the sweep: the same additions as a running sum.
        let sum: f64 = z.iter().fold(0.0, |s, &v| s + v);
        mean = sum / (nx * ny) as f64;
        if change < 1e-7 {
            break;
        }
    }
    // Contact pressure and the friction measures.
    let mut pressure = vec![0.0; nx * ny];
    let (mut in_contact, mut slope) = (0usize, 0.0);
    for j in 0..ny {
        let (jn, js) = ((j + 1) % ny, (j + ny - 1) % ny);
        for i in 0..nx {
            let (ie, iw) = ((i + 1) % nx, (i + nx - 1) % nx);
            let c = j * nx + i;
            slope += (z[j * nx + ie] - z[j * nx + iw]).abs() / (2.0 * dx);
            if z[c] - h[c] < 1e-9 {
                let laplace = ax * (z[j * nx + ie] + z[j * nx + iw] - 2.0 * z[c])
                    + ay * (z[jn * nx + i] + z[js * nx + i] - 2.0 * z[c]);
                let p = (q + k * (z[c] - mean) - laplace).max(0.0);
                pressure[c] = p;
                in_contact += 1;
            }
        }
    }
    let cells = (nx * ny) as f64;
    // The 1 mm skin spreads the membrane's edge line loads over the contacted tops, so the real
    // area is taken at the mean contact pressure q/(contact fraction).
    let fraction = in_contact as f64 / cells;
    let area = fraction * law.area_fraction(q / fraction.max(1e-9));
    let bottom = z.iter().copied().fold(f64::INFINITY, f64::min);
    let mean_sag_mm = top - z.iter().sum::<f64>() / cells;
    SkinContact {
        mean_sag_mm,
        real_area_ratio: area / law.area_fraction(q),
        contact_fraction: fraction,
        mean_abs_slope: slope / cells,
        max_sag_mm: top - bottom,
        surface_mm: z,
        pressure_mpa: pressure,
        sweeps,
    }
}

/// One projected SOR sweep of [`solve`] over the periodic `nx × ny` cell grid.
///
/// The sweep is Gauss–Seidel in cell order (row by row, west to east): a cell reads its west
/// and south neighbours already updated in this sweep (the previous sweep's values across the
/// periodic seam) and its east and north ones not yet updated. Each cell therefore depends
/// only on its west and south neighbours, so the sweep runs rows in bands of [`BAND`], each row
/// one cell behind the one below it (a wavefront): every cell reads exactly the values it reads
/// in cell order and does the same arithmetic, so the result is bit for bit the same, while
/// the band's rows are independent chains the processor overlaps (a cell's update is a chain
/// of dependent additions, products and a division).
struct Sweep<'a> {
    h: &'a [f64],
    nx: usize,
    ny: usize,
    ax: f64,
    ay: f64,
    diag: f64,
    q: f64,
    omega: f64,
}

/// Rows updated together by [`Sweep::run`].
const BAND: usize = 8;

impl Sweep<'_> {
    /// Updates `z` in place (`k_mean`: k times the previous sweep's mean height); returns the
    /// largest change of a cell.
    fn run(&self, z: &mut [f64], k_mean: f64) -> f64 {
        let (nx, ny) = (self.nx, self.ny);
        // One largest change per row of the band (a maximum in any order is the same).
        let mut change = [0.0f64; BAND];
        for j0 in (0..ny).step_by(BAND) {
            let rows = BAND.min(ny - j0);
            for step in 0..nx + rows - 1 {
                // Row j0 + r is at cell step − r.
                let active = &mut change[..rows.min(step + 1)];
                for (r, row_change) in active
                    .iter_mut()
                    .enumerate()
                    .skip(step.saturating_sub(nx - 1))
                {
                    let (i, j) = (step - r, j0 + r);
                    *row_change = row_change.max(self.cell(z, i, j, k_mean));
                }
            }
        }
        change.into_iter().fold(0.0, f64::max)
    }

    /// Updates cell `(i, j)`; returns the size of its change.
    #[inline(always)]
    fn cell(&self, z: &mut [f64], i: usize, j: usize, k_mean: f64) -> f64 {
        let (nx, ny) = (self.nx, self.ny);
        let row = j * nx;
        let north = if j + 1 == ny { 0 } else { row + nx };
        let south = if j == 0 { (ny - 1) * nx } else { row - nx };
        let east = if i + 1 == nx { row } else { row + i + 1 };
        let west = if i == 0 { row + nx - 1 } else { row + i - 1 };
        let c = row + i;
        let gs = (self.ax * (z[east] + z[west]) + self.ay * (z[north + i] + z[south + i]) + k_mean
            - self.q)
            / self.diag;
        let new = (z[c] + self.omega * (gs - z[c])).max(self.h[c]);
        let change = (new - z[c]).abs();
        z[c] = new;
        change
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::ContactParams;

    /// Ridges across the slide: a 1-D gap of width `gap` between supports of width `top`.
    fn ridges(gap: f64, top: f64, n: usize) -> (Vec<f64>, f64) {
        let period = gap + top;
        let dx = period / n as f64;
        let h = (0..n * 4)
            .map(|c| {
                let x = ((c % n) as f64 + 0.5) * dx;
                if x < top { 1.0 } else { 0.0 }
            })
            .collect();
        (h, dx)
    }

    #[test]
    fn a_narrow_gap_sags_like_a_membrane_and_a_wide_one_meets_the_floor() {
        let c = ContactParams::default();
        let law = ContactLaw {
            foundation_n_mm3: 0.0,
            ..ContactLaw::new(&c, 0.008)
        };
        // Free membrane: sag q·g²/(8T) = (g/g₀)² mm below the supports.
        let g = 1.5;
        let (h, dx) = ridges(g, 1.0, 64);
        let s = solve(&h, (64, 4), (dx, 1.0), &law);
        let expected = (g / c.gap_conformity_mm).powi(2);
        assert!(
            (s.max_sag_mm - expected).abs() < 0.05 * expected,
            "{} vs {expected}",
            s.max_sag_mm
        );
        // Load balance: the mean contact pressure is q.
        let mean_p = s.pressure_mpa.iter().sum::<f64>() / s.pressure_mpa.len() as f64;
        assert!((mean_p / 0.008 - 1.0).abs() < 0.02, "{mean_p}");
        // A gap wider than g₀ drapes the skin onto the floor: sag = bump height, and the floor
        // carries part of the load.
        let (h, dx) = ridges(2.0 * c.gap_conformity_mm, 1.0, 64);
        let wide = solve(&h, (64, 4), (dx, 1.0), &law);
        assert!((wide.max_sag_mm - 1.0).abs() < 1e-6, "{}", wide.max_sag_mm);
        let floor_load: f64 = h
            .iter()
            .zip(&wide.pressure_mpa)
            .filter(|(h, _)| **h == 0.0)
            .map(|(_, p)| p)
            .sum();
        assert!(floor_load > 0.0);
    }

    /// The sweep in plain cell order with modular neighbours (the solver's definition):
    /// the conformed surface and the sweep count.
    fn cell_order_reference(
        h: &[f64],
        (nx, ny): (usize, usize),
        (dx, dy): (f64, f64),
        law: &ContactLaw,
    ) -> (Vec<f64>, usize) {
        let (t, k, q) = (law.tension_n_mm, law.foundation_n_mm3, law.pressure_mpa);
        let (ax, ay) = (t / (dx * dx), t / (dy * dy));
        let diag = 2.0 * ax + 2.0 * ay + k;
        let top = h.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut z = vec![top; nx * ny];
        let n = nx.max(ny) as f64;
        let omega = 2.0 / (1.0 + (std::f64::consts::PI / n).sin());
        let max_sweeps = (40.0 * n) as usize + 200;
        let (mut mean, mut sweeps) = (top, 0);
        while sweeps < max_sweeps {
            sweeps += 1;
            let (mut change, mut sum) = (0.0f64, 0.0);
            for j in 0..ny {
                let (jn, js) = ((j + 1) % ny, (j + ny - 1) % ny);
                for i in 0..nx {
                    let (ie, iw) = ((i + 1) % nx, (i + nx - 1) % nx);
                    let c = j * nx + i;
                    let gs = (ax * (z[j * nx + ie] + z[j * nx + iw])
                        + ay * (z[jn * nx + i] + z[js * nx + i])
                        + k * mean
                        - q)
                        / diag;
                    let new = (z[c] + omega * (gs - z[c])).max(h[c]);
                    change = change.max((new - z[c]).abs());
                    z[c] = new;
                    sum += new;
                }
            }
            mean = sum / (nx * ny) as f64;
            if change < 1e-7 {
                break;
            }
        }
        (z, sweeps)
    }

    #[test]
    fn the_banded_sweep_is_bit_identical_to_cell_order() {
        let law = ContactLaw::new(&ContactParams::default(), 0.008);
        // Shapes around the band height and the periodic seams: single rows and columns,
        // two rows (north and south are the same row), a partial last band.
        for (nx, ny) in [
            (1, 1),
            (1, 5),
            (7, 1),
            (2, 2),
            (5, 2),
            (9, 8),
            (12, 9),
            (33, 21),
        ] {
            let h: Vec<f64> = (0..nx * ny)
                .map(|c| {
                    let x = (c % nx) as f64 / nx as f64;
                    let y = (c / nx) as f64 / ny as f64;
                    ((7.0 * x).sin() * (3.0 * y + 1.0).cos()).max(0.0) * 0.8
                })
                .collect();
            let (z, sweeps) = cell_order_reference(&h, (nx, ny), (0.3, 0.2), &law);
            let s = solve(&h, (nx, ny), (0.3, 0.2), &law);
            assert_eq!(s.sweeps, sweeps, "{nx} × {ny}");
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&s.surface_mm), bits(&z), "{nx} × {ny}");
        }
    }

    #[test]
    fn sag_rises_monotonically_with_the_gap_and_saturates() {
        let c = ContactParams {
            gap_conformity_mm: 3.0,
            ..ContactParams::default()
        };
        let law = ContactLaw::new(&c, 0.008);
        let sags: Vec<f64> = [0.5, 1.0, 2.0, 3.0, 4.0, 6.0]
            .iter()
            .map(|&g| {
                let (h, dx) = ridges(g, g, 64);
                solve(&h, (64, 4), (dx, 1.0), &law).max_sag_mm
            })
            .collect();
        assert!(sags.windows(2).all(|w| w[1] >= w[0] - 1e-9), "{sags:?}");
        assert!(sags[0] < 0.05 && (sags[5] - 1.0).abs() < 1e-6, "{sags:?}");
    }
}
