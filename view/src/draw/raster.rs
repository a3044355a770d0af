//! The raster panel: a row per taxel (taxel 0 on top) over the raster's window, a short
//! vertical line per spike, and under it, on the same time axis, the population rate.
//!
//! Every spike of [`Raster::spikes`] is drawn exactly once: one outside the window is drawn at
//! the window's edge, one of a taxel past the last row widens the raster by rows, one at a
//! time that is not a number at the left edge.

use std::fmt::{self, Write};

use super::svg::{
    AXIS_STYLE, Area, F1, LABEL_STYLE, TITLE_STYLE, decimals_for, finite_or, nice_ceil, nice_step,
};
use crate::frame::Raster;

/// Rows labelled with their taxel number: every this many (and the last).
const ROW_LABEL_EVERY: usize = 8;

/// The panel: title, spikes, rate polyline, axes.
pub(super) fn panel(
    out: &mut String,
    raster: &Raster,
    taxels: usize,
    area: Area,
    rate_area: Area,
) -> fmt::Result {
    let rows = raster
        .spikes
        .iter()
        .map(|&(taxel, _)| usize::from(taxel) + 1)
        .fold(taxels.max(1), usize::max);
    let from_s = finite_or(raster.from_s, 0.0);
    let span_s = match raster.to_s - from_s {
        s if s.is_finite() && s > 0.0 => s,
        _ => 1.0,
    };
    let x_at =
        |t_s: f64| area.x + area.w * (finite_or((t_s - from_s) / span_s, 0.0)).clamp(0.0, 1.0);
    write!(
        out,
        r#"<text x="{:.1}" y="{:.1}" {TITLE_STYLE}>taxel spikes over the last {span_s:.1} s ({rows} taxels); below, the population rate (mean per taxel)</text>"#,
        area.x,
        area.y - 8.0,
    )?;
    write!(
        out,
        r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="none" stroke="#e0e0e0" stroke-width="0.6"/>"##,
        area.x, area.y, area.w, area.h
    )?;
    // Row labels: every ROW_LABEL_EVERY-th taxel and the last (the numbers the hexagons of
    // the taxel panel carry), and the axis name.
    let row_h = area.h / rows as f64;
    let labelled =
        (0..rows).filter(|r| r % ROW_LABEL_EVERY == 0 && rows - 1 - r >= ROW_LABEL_EVERY / 2);
    for row in labelled.chain([rows - 1]) {
        write!(
            out,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end" {LABEL_STYLE}>{row}</text>"#,
            area.x - 5.0,
            area.y + (row as f64 + 0.5) * row_h + 3.5,
        )?;
    }
    write!(
        out,
        r#"<text transform="translate({:.1} {:.1}) rotate(-90)" text-anchor="middle" {LABEL_STYLE}>taxel</text>"#,
        area.x - 30.0,
        area.y + area.h / 2.0,
    )?;
    let half = (0.42 * row_h).max(0.6);
    out.push_str(r##"<g stroke="#1b1b1b" stroke-width="1">"##);
    for &(taxel, t_s) in &raster.spikes {
        let x = F1(x_at(t_s));
        let y = area.y + (f64::from(taxel) + 0.5) * row_h;
        write!(
            out,
            r#"<line class="spike" x1="{x}" x2="{x}" y1="{}" y2="{}"/>"#,
            F1(y - half),
            F1(y + half)
        )?;
    }
    out.push_str("</g>");
    rate(out, raster, span_s, rate_area)?;
    time_axis(out, from_s, span_s, rate_area)
}

/// The population rate as a polyline through its bins' centres, with a 0–top axis in Hz.
fn rate(out: &mut String, raster: &Raster, span_s: f64, area: Area) -> fmt::Result {
    let top_hz = nice_ceil(
        raster
            .population_rate_hz
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .fold(1.0, f64::max),
    );
    let bottom = area.y + area.h;
    write!(
        out,
        r#"<path d="M{:.1} {:.1}V{bottom:.1}H{:.1}" {AXIS_STYLE}/>"#,
        area.x,
        area.y,
        area.x + area.w
    )?;
    write!(
        out,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="end" {LABEL_STYLE}>{top_hz:.0} Hz</text><text x="{:.1}" y="{:.1}" text-anchor="end" {LABEL_STYLE}>0</text>"#,
        area.x - 5.0,
        area.y + 4.0,
        area.x - 5.0,
        bottom,
    )?;
    if !(raster.bin_s.is_finite() && raster.bin_s > 0.0) {
        return Ok(());
    }
    out.push_str(r##"<polyline class="population-rate" fill="none" stroke="#2b6cb0" stroke-width="1.2" stroke-linejoin="round" points=""##);
    let mut first = true;
    for (i, &rate_hz) in raster.population_rate_hz.iter().enumerate() {
        let offset_s = (i as f64 + 0.5) * raster.bin_s;
        if offset_s > span_s {
            break;
        }
        let x = area.x + area.w * offset_s / span_s;
        let y = bottom - area.h * (finite_or(rate_hz, 0.0) / top_hz).clamp(0.0, 1.0);
        write!(out, "{}{x:.1},{y:.1}", if first { "" } else { " " })?;
        first = false;
    }
    out.push_str("\"/>");
    Ok(())
}

/// Ticks and labels (s of stream time) under the rate plot.
fn time_axis(out: &mut String, from_s: f64, span_s: f64, area: Area) -> fmt::Result {
    let step = nice_step(span_s, 12);
    let decimals = decimals_for(step);
    let bottom = area.y + area.h;
    let first = (from_s / step).ceil();
    let mut ticks = String::new();
    let mut labels = String::new();
    for k in 0..=13 {
        // `+ 0.0` turns −0 into 0 for the label.
        let t = (first + k as f64) * step + 0.0;
        if t > from_s + span_s * (1.0 + 1e-9) {
            break;
        }
        let x = area.x + area.w * (t - from_s) / span_s;
        write!(ticks, "M{x:.1} {bottom:.1}v3")?;
        write!(
            labels,
            r#"<text x="{x:.1}" y="{:.1}" text-anchor="middle" {LABEL_STYLE}>{t:.decimals$}</text>"#,
            bottom + 13.0
        )?;
    }
    write!(
        out,
        r#"<path d="{ticks}" {AXIS_STYLE}/>{labels}<text x="{:.1}" y="{:.1}" text-anchor="end" {LABEL_STYLE}>t (s)</text>"#,
        area.x - 16.0,
        bottom + 13.0
    )
}
