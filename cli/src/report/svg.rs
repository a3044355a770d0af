//! Minimal SVG charts (scatter and line series on linear or log axes), written as plain text so
//! that figures need no font or graphics library. Used by the trade-off reports and the
//! paper-style figures.

use std::fmt::Write;

/// One axis: label, scale and range.
#[derive(Debug, Clone)]
pub struct Axis {
    /// Label under (x) or beside (y) the axis.
    pub label: String,
    /// Logarithmic (base 10) scale.
    pub log: bool,
    /// Fixed range; `None` fits the data.
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// A linear axis fitted to the data.
    pub fn linear(label: &str) -> Self {
        Self {
            label: label.to_owned(),
            log: false,
            range: None,
        }
    }

    /// A log axis fitted to the data.
    pub fn log(label: &str) -> Self {
        Self {
            label: label.to_owned(),
            log: true,
            range: None,
        }
    }
}

/// Marker shape of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// No marker (line only).
    None,
    /// Circle.
    Circle,
    /// Square.
    Square,
    /// Triangle.
    Triangle,
    /// A short vertical tick (spike rasters).
    Tick,
}

/// A named set of points.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// `(x, y)` points; non-finite points, and non-positive ones on log axes, are skipped.
    pub points: Vec<(f64, f64)>,
    /// CSS colour.
    pub color: String,
    /// Marker shape.
    pub marker: Marker,
    /// Filled (true) or hollow marker.
    pub filled: bool,
    /// Join the points with a line, in order.
    pub line: bool,
    /// An error bar `(low, high)` on `y` for each point, in order (empty: none).
    pub y_ranges: Vec<(f64, f64)>,
}

/// A palette of 10 distinguishable colours (Tableau 10).
pub const PALETTE: [&str; 10] = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
    "#9c755f", "#bab0ac",
];

/// A chart: title, axes and series.
#[derive(Debug, Clone)]
pub struct Chart {
    /// Title above the plot.
    pub title: String,
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// The data.
    pub series: Vec<Series>,
}

const W: f64 = 640.0;
const H: f64 = 420.0;
const LEFT: f64 = 70.0;
const RIGHT: f64 = 190.0;
const TOP: f64 = 36.0;
const BOTTOM: f64 = 52.0;

pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Range of an axis over the usable values, padded a little.
fn fit(values: impl Iterator<Item = f64>, axis: &Axis) -> (f64, f64) {
    if let Some(r) = axis.range {
        return r;
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!axis.log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if axis.log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if axis.log {
        (
            10f64.powf(lo.log10().floor()),
            10f64.powf(hi.log10().ceil().max(lo.log10().floor() + 1.0)),
        )
    } else if lo == hi {
        (lo - 1.0, hi + 1.0)
    } else {
        let pad = (hi - lo) * 0.05;
        (lo - pad, hi + pad)
    }
}

/// Tick positions: decades on log axes, 1–2–5 steps on linear ones.
fn ticks((lo, hi): (f64, f64), log: bool) -> Vec<f64> {
    if log {
        let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        let step = ((b - a) as f64 / 8.0).ceil().max(1.0) as i32;
        return (a..=b)
            .step_by(step as usize)
            .map(|e| 10f64.powi(e))
            .filter(|t| *t >= lo * 0.999 && *t <= hi * 1.001)
            .collect();
    }
    let raw = (hi - lo) / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn tick_label(v: f64, log: bool) -> String {
    if log {
        let e = v.log10().round() as i32;
        return match e {
            0 => "1".into(),
            1 => "10".into(),
            _ => format!("1e{e}"),
        };
    }
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    }
}

fn marker_svg(out: &mut String, m: Marker, x: f64, y: f64, color: &str, filled: bool) {
    let fill = if filled { color } else { "white" };
    let _ = match m {
        Marker::None => Ok(()),
        Marker::Tick => write!(
            out,
            r#"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="{color}" stroke-width="1"/>"#,
            y - 3.5,
            y + 3.5
        ),
        Marker::Circle => write!(
            out,
            r#"<circle cx="{x:.1}" cy="{y:.1}" r="4" fill="{fill}" stroke="{color}" stroke-width="1.5"/>"#
        ),
        Marker::Square => write!(
            out,
            r#"<rect x="{:.1}" y="{:.1}" width="7" height="7" fill="{fill}" stroke="{color}" stroke-width="1.5"/>"#,
            x - 3.5,
            y - 3.5
        ),
        Marker::Triangle => write!(
            out,
            r#"<polygon points="{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}" fill="{fill}" stroke="{color}" stroke-width="1.5"/>"#,
            x,
            y - 4.5,
            x - 4.5,
            y + 4.0,
            x + 4.5,
            y + 4.0
        ),
    };
}

impl Chart {
    /// The chart as an SVG group of size 640 × 420 at offset `(dx, dy)`.
    fn group(&self, dx: f64, dy: f64) -> String {
        let usable = |axis: &Axis, v: f64| v.is_finite() && (!axis.log || v > 0.0);
        let points = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let xr = fit(
            points().filter(|p| usable(&self.y, p.1)).map(|p| p.0),
            &self.x,
        );
        let yr = fit(
            points().filter(|p| usable(&self.x, p.0)).map(|p| p.1),
            &self.y,
        );
        let map = |v: f64, (lo, hi): (f64, f64), log: bool| {
            if log {
                (v.log10() - lo.log10()) / (hi.log10() - lo.log10())
            } else {
                (v - lo) / (hi - lo)
            }
        };
        let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
        let px = |v: f64| LEFT + map(v, xr, self.x.log) * pw;
        let py = |v: f64| TOP + (1.0 - map(v, yr, self.y.log)) * ph;
        let mut g = format!(
            r#"<g transform="translate({dx},{dy})" font-family="sans-serif" font-size="11">"#
        );
        let _ = write!(
            g,
            r#"<text x="{:.1}" y="20" font-size="14" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            escape(&self.title)
        );
        let _ = write!(
            g,
            r##"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="#333"/>"##
        );
        for t in ticks(xr, self.x.log) {
            let x = px(t);
            let _ = write!(
                g,
                r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
                TOP + ph,
                TOP + ph + 15.0,
                tick_label(t, self.x.log)
            );
        }
        for t in ticks(yr, self.y.log) {
            let y = py(t);
            let _ = write!(
                g,
                r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
                LEFT + pw,
                LEFT - 5.0,
                y + 4.0,
                tick_label(t, self.y.log)
            );
        }
        let _ = write!(
            g,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            H - 12.0,
            escape(&self.x.label)
        );
        let _ = write!(
            g,
            r#"<text transform="translate(16,{:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
            TOP + ph / 2.0,
            escape(&self.y.label)
        );
        for (k, s) in self.series.iter().enumerate() {
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| usable(&self.x, p.0) && usable(&self.y, p.1))
                .map(|(x, y)| (px(x), py(y)))
                .collect();
            if s.line && pts.len() > 1 {
                let path: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
                let _ = write!(
                    g,
                    r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.5"/>"#,
                    path.join(" "),
                    s.color
                );
            }
            for (&(x, _), &(low, high)) in s.points.iter().zip(&s.y_ranges) {
                if !(usable(&self.x, x) && usable(&self.y, low) && usable(&self.y, high)) {
                    continue;
                }
                let (x, y0, y1) = (px(x), py(low), py(high));
                let _ = write!(
                    g,
                    r#"<path d="M{:.1},{y0:.1}H{:.1}M{x:.1},{y0:.1}V{y1:.1}M{:.1},{y1:.1}H{:.1}" stroke="{}" stroke-width="1" fill="none"/>"#,
                    x - 3.0,
                    x + 3.0,
                    x - 3.0,
                    x + 3.0,
                    s.color
                );
            }
            for &(x, y) in &pts {
                marker_svg(&mut g, s.marker, x, y, &s.color, s.filled);
            }
            let ly = TOP + 8.0 + 16.0 * k as f64;
            let lx = W - RIGHT + 12.0;
            if s.line {
                let _ = write!(
                    g,
                    r#"<line x1="{lx}" y1="{ly}" x2="{:.1}" y2="{ly}" stroke="{}" stroke-width="1.5"/>"#,
                    lx + 16.0,
                    s.color
                );
            }
            marker_svg(&mut g, s.marker, lx + 8.0, ly, &s.color, s.filled);
            let _ = write!(
                g,
                r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
                lx + 22.0,
                ly + 4.0,
                escape(&s.label)
            );
        }
        g.push_str("</g>");
        g
    }

    /// This chart alone as an SVG document.
    pub fn to_svg(&self) -> String {
        panels(std::slice::from_ref(self), 1)
    }
}

/// Several charts in a grid of `columns` columns, as one SVG document.
pub fn panels(charts: &[Chart], columns: usize) -> String {
    let columns = columns.max(1);
    let rows = charts.len().div_ceil(columns).max(1);
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}"><rect width="100%" height="100%" fill="white"/>"#,
        W * columns as f64,
        H * rows as f64,
        W * columns as f64,
        H * rows as f64
    );
    for (i, c) in charts.iter().enumerate() {
        svg.push_str(&c.group(W * (i % columns) as f64, H * (i / columns) as f64));
    }
    svg.push_str("</svg>\n");
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_decades_on_log_axes_and_round_on_linear_ones() {
        assert_eq!(
            ticks((1e-6, 1e-2), true),
            vec![1e-6, 1e-5, 1e-4, 1e-3, 1e-2]
        );
        assert_eq!(
            ticks((0.0, 1.0), false),
            vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
        );
        assert_eq!(tick_label(1e-3, true), "1e-3");
        assert_eq!(tick_label(0.25, false), "0.25");
    }

    #[test]
    fn charts_skip_unplottable_points_and_escape_text() {
        let chart = Chart {
            title: "a < b & c".into(),
            x: Axis::log("updates/s"),
            y: Axis::log("error (s)"),
            series: vec![Series {
                label: "rk4".into(),
                points: vec![(1e9, 1e-6), (2e9, 0.0), (f64::NAN, 1.0), (3e9, 1e-4)],
                color: PALETTE[0].into(),
                marker: Marker::Circle,
                filled: true,
                line: true,
                y_ranges: Vec::new(),
            }],
        };
        let svg = chart.to_svg();
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
        assert!(svg.contains("a &lt; b &amp; c"));
        // Two plottable points plus the legend marker.
        assert_eq!(svg.matches("<circle").count(), 3);
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }
}
