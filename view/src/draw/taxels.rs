//! The taxel panel: a hexagon per taxel at its home position (the sensor's layout, scaled to
//! fit), filled by its spike rate on the sequential colour map and labelled with its number
//! (its row in the raster), with a colour bar in Hz.
//!
//! The scale tops at the smallest 1–2–5 value (10, 20, 50, 100, … Hz) at or above the highest
//! rate and at least 10 Hz, so a quiet sensor does not look busy and rates above the top
//! cannot occur. Hexagons have a circumradius of half the nearest-neighbour spacing: they never
//! overlap.

use std::fmt::{self, Write};

use super::colour::{NO_CLASS, sequential};
use super::svg::{AXIS_STYLE, Area, LABEL_STYLE, TITLE_STYLE, finite_or, nice_ceil};
use crate::frame::Frame;

/// The colour bar's lowest top (Hz).
const MIN_TOP_HZ: f64 = 10.0;

/// The panel: title, hexagons with a `<title>` each, colour bar.
pub(super) fn panel(out: &mut String, frame: &Frame, area: Area) -> fmt::Result {
    write!(
        out,
        r#"<text x="{:.1}" y="{:.1}" {TITLE_STYLE}>taxel spike rates over the last {:.2} s</text>"#,
        area.x,
        area.y - 8.0,
        finite_or(frame.rate_window_s, 0.0),
    )?;
    let finite = |&(x, y): &(f64, f64)| x.is_finite() && y.is_finite();
    let homes = || frame.taxel_home.iter().copied().filter(finite);
    let (mut x_min, mut x_max, mut y_min, mut y_max) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in homes() {
        (x_min, x_max) = (x_min.min(x), x_max.max(x));
        (y_min, y_max) = (y_min.min(y), y_max.max(y));
    }
    if x_min > x_max {
        return write!(
            out,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" {LABEL_STYLE}>no taxels</text>"#,
            area.x + area.w / 2.0,
            area.y + area.h / 2.0
        );
    }
    // Nearest-neighbour spacing (px of the image); one taxel alone gets a unit spacing.
    let mut spacing = f64::MAX;
    for (i, (xa, ya)) in homes().enumerate() {
        for (xb, yb) in homes().skip(i + 1) {
            let d = (xa - xb).hypot(ya - yb);
            if d > 1e-9 {
                spacing = spacing.min(d);
            }
        }
    }
    if spacing == f64::MAX {
        spacing = (x_max - x_min).max(y_max - y_min).max(1.0);
    }
    let scale = (area.w / (x_max - x_min + spacing)).min(area.h / (y_max - y_min + spacing));
    let (cx, cy) = (area.x + area.w / 2.0, area.y + area.h / 2.0);
    let (mx, my) = ((x_min + x_max) / 2.0, (y_min + y_max) / 2.0);
    let radius = 0.5 * spacing * scale;

    let top_hz = nice_ceil(
        frame
            .taxel_rate_hz
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .fold(MIN_TOP_HZ, f64::max),
    );
    out.push_str(r##"<g stroke="#ffffff" stroke-width="1">"##);
    for (i, &(x, y)) in frame.taxel_home.iter().enumerate() {
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        let (px, py) = (cx + (x - mx) * scale, cy + (y - my) * scale);
        out.push_str(r#"<polygon class="taxel" points=""#);
        for corner in 0..6 {
            // Pointy-top hexagon: corners at 30° + k·60°.
            let angle = (30.0 + 60.0 * corner as f64).to_radians();
            write!(
                out,
                "{}{:.1},{:.1}",
                if corner == 0 { "" } else { " " },
                px + radius * angle.cos(),
                py + radius * angle.sin()
            )?;
        }
        match frame
            .taxel_rate_hz
            .get(i)
            .copied()
            .filter(|r| r.is_finite())
        {
            Some(rate) => write!(
                out,
                r#"" fill="{}"><title>taxel {i}: {rate:.1} Hz</title></polygon>"#,
                sequential(rate / top_hz)
            )?,
            None => write!(
                out,
                r#"" fill="{NO_CLASS}"><title>taxel {i}: no rate</title></polygon>"#
            )?,
        }
    }
    out.push_str("</g>");
    numbers(out, frame, radius, |x, y| {
        (cx + (x - mx) * scale, cy + (y - my) * scale)
    })?;
    colour_bar(out, area, top_hz)
}

/// Each taxel's number (its row in the raster) at the centre of its hexagon, dark on a white
/// halo so that it reads on every colour of the map; left out when the hexagons are too small
/// to hold it.
fn numbers(
    out: &mut String,
    frame: &Frame,
    radius: f64,
    at: impl Fn(f64, f64) -> (f64, f64),
) -> fmt::Result {
    let size = (0.8 * radius).min(11.0);
    if size < 5.0 {
        return Ok(());
    }
    write!(
        out,
        r##"<g class="taxel-numbers" font-size="{size:.1}" text-anchor="middle" fill="#222" stroke="#ffffff" stroke-width="2" paint-order="stroke">"##
    )?;
    for (i, &(x, y)) in frame.taxel_home.iter().enumerate() {
        if x.is_finite() && y.is_finite() {
            let (px, py) = at(x, y);
            write!(
                out,
                r#"<text x="{px:.1}" y="{:.1}">{i}</text>"#,
                py + 0.35 * size
            )?;
        }
    }
    out.push_str("</g>");
    Ok(())
}

/// A horizontal colour bar under the hexagons, 0 to `top_hz`, three ticks.
fn colour_bar(out: &mut String, area: Area, top_hz: f64) -> fmt::Result {
    let (x0, w, y, h) = (area.x + 30.0, area.w - 60.0, area.y + area.h + 22.0, 8.0);
    out.push_str(r#"<defs><linearGradient id="neurotac-rate-scale" x1="0" x2="1" y1="0" y2="0">"#);
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        write!(
            out,
            r#"<stop offset="{t:.1}" stop-color="{}"/>"#,
            sequential(t)
        )?;
    }
    write!(
        out,
        r#"</linearGradient></defs><rect x="{x0:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" fill="url(#neurotac-rate-scale)"/><g {AXIS_STYLE}>"#
    )?;
    for k in 0..=2 {
        let x = x0 + w * k as f64 / 2.0;
        write!(
            out,
            r#"<line x1="{x:.1}" x2="{x:.1}" y1="{:.1}" y2="{:.1}"/>"#,
            y + h,
            y + h + 3.0
        )?;
    }
    out.push_str("</g>");
    for k in 0..=2 {
        let x = x0 + w * k as f64 / 2.0;
        write!(
            out,
            r#"<text x="{x:.1}" y="{:.1}" text-anchor="middle" {LABEL_STYLE}>{:.0}{}</text>"#,
            y + h + 14.0,
            top_hz * k as f64 / 2.0,
            if k == 2 { " Hz" } else { "" }
        )?;
    }
    Ok(())
}
