//! The decisions panel (only with a recogniser): per coding, its latest decision — class
//! name (`tie` when the nearest samples tie), vote-share bar, a ✓ once stable — and a timeline
//! strip over the slide with a rect per decision (coloured by class, ties grey) and the final
//! decision marked; under the rows a legend of class colours.
//!
//! All codings share the strip's time axis, from the slide start to the latest decision of
//! any coding.

use std::borrow::Cow;
use std::fmt::{self, Write};

use super::colour::{NO_CLASS, Rgb, class_colour};
use super::svg::{AXIS_STYLE, Area, Esc, LABEL_STYLE, TITLE_STYLE, clipped, finite_or};
use crate::frame::{DecisionPoint, Frame};

/// Height of one coding's row (name line + strip).
const ROW_H: f64 = 44.0;
/// Height of a legend line.
const LEGEND_LINE_H: f64 = 14.0;
/// Legend columns.
const LEGEND_COLUMNS: usize = 3;

/// The panel; nothing when the frame has no decisions.
pub(super) fn panel(out: &mut String, frame: &Frame, area: Area) -> fmt::Result {
    if frame.decisions.is_empty() {
        return write!(
            out,
            r#"<text x="{:.1}" y="{:.1}" {LABEL_STYLE}>no recogniser: its decisions show here with --train DATASET</text>"#,
            area.x,
            area.y - 8.0
        );
    }
    let name = |point: &DecisionPoint| -> Cow<'_, str> {
        if point.tie {
            Cow::Borrowed("tie")
        } else {
            match frame.class_names.get(point.class) {
                Some(name) => clipped(name, 18),
                None => Cow::Owned(format!("class {}", point.class)),
            }
        }
    };
    let colour = |point: &DecisionPoint| -> Rgb {
        if point.tie {
            NO_CLASS
        } else {
            class_colour(point.class)
        }
    };
    let t_max_s = frame
        .decisions
        .iter()
        .flat_map(|c| c.history.iter().chain(&c.final_decision))
        .map(|p| finite_or(p.t_s, 0.0))
        .fold(0.1, f64::max);
    // The strip leaves room at its right end for the final decision's mark.
    let strip_w = area.w - 4.0;
    let x_at = |t_s: f64| area.x + strip_w * (finite_or(t_s, 0.0) / t_max_s).clamp(0.0, 1.0);

    out.push_str(r#"<g class="decisions">"#);
    write!(
        out,
        r#"<text x="{:.1}" y="{:.1}" {TITLE_STYLE}>recogniser decisions over the slide</text>"#,
        area.x,
        area.y - 8.0
    )?;
    let mut y = area.y + 12.0;
    for coding in &frame.decisions {
        write!(
            out,
            r##"<text x="{:.1}" y="{y:.1}" font-size="11" fill="#333">{}</text>"##,
            area.x,
            Esc(&clipped(&coding.coding, 14))
        )?;
        match coding.final_decision.as_ref().or(coding.history.last()) {
            None => write!(
                out,
                r#"<text x="{:.1}" y="{y:.1}" {LABEL_STYLE}>no decision yet</text>"#,
                area.x + 95.0
            )?,
            Some(latest) => {
                let share = finite_or(latest.vote_share, 0.0).clamp(0.0, 1.0);
                let c = colour(latest);
                write!(
                    out,
                    r##"<rect x="{:.1}" y="{:.1}" width="8" height="8" fill="{c}"/><text x="{:.1}" y="{y:.1}" font-size="11" fill="#222">{}</text><rect x="{:.1}" y="{:.1}" width="70" height="7" fill="#eeeeee"/><rect x="{:.1}" y="{:.1}" width="{:.1}" height="7" fill="{c}"/><text x="{:.1}" y="{y:.1}" {LABEL_STYLE}>{:.0} %</text>"##,
                    area.x + 95.0,
                    y - 8.0,
                    area.x + 107.0,
                    Esc(&name(latest)),
                    area.x + 225.0,
                    y - 7.0,
                    area.x + 225.0,
                    y - 7.0,
                    70.0 * share,
                    area.x + 299.0,
                    100.0 * share,
                )?;
                if latest.stable {
                    write!(
                        out,
                        r##"<text class="stable" x="{:.1}" y="{y:.1}" font-size="11" fill="#2e7d32">✓<title>stable</title></text>"##,
                        area.x + area.w - 8.0
                    )?;
                }
            }
        }
        // The timeline strip.
        let (strip_y, strip_h) = (y + 7.0, 10.0);
        write!(
            out,
            r##"<rect x="{:.1}" y="{strip_y:.1}" width="{strip_w:.1}" height="{strip_h:.1}" fill="#f4f4f4"/>"##,
            area.x
        )?;
        // One rect per run of windows with the same decision (a slide has hundreds of
        // windows but few changes, and the page redraws this up to 100 times a second).
        let same =
            |a: &DecisionPoint, b: &DecisionPoint| a.tie == b.tie && (a.tie || a.class == b.class);
        let mut previous_s = 0.0;
        for run in coding.history.chunk_by(same) {
            let (first, last) = (&run[0], &run[run.len() - 1]);
            let (x0, x1) = (x_at(previous_s), x_at(last.t_s));
            let from_s = previous_s;
            previous_s = finite_or(last.t_s, previous_s);
            write!(
                out,
                r#"<rect class="decision-run" x="{:.1}" y="{strip_y:.1}" width="{:.1}" height="{strip_h:.1}" fill="{}"><title>{:.2}–{:.2} s: {}</title></rect>"#,
                x0.min(x1),
                (x1 - x0).abs().max(1.5),
                colour(first),
                from_s,
                finite_or(last.t_s, 0.0),
                Esc(&name(first)),
            )?;
        }
        if let Some(last) = &coding.final_decision {
            let x = x_at(last.t_s);
            write!(
                out,
                r##"<path class="final-decision" d="M{x:.1} {:.1}l-3.5 5h7z" fill="#222"><title>final at {:.2} s: {}</title></path>"##,
                strip_y + strip_h + 1.0,
                finite_or(last.t_s, 0.0),
                Esc(&name(last)),
            )?;
        }
        y += ROW_H;
    }
    // The strips' time axis, under the last one.
    let axis_y = y - ROW_H + 24.0;
    write!(
        out,
        r#"<text x="{:.1}" y="{:.1}" {LABEL_STYLE}>0</text><text x="{:.1}" y="{:.1}" text-anchor="middle" {LABEL_STYLE}>time in the slide (s); ▲ final decision</text><text x="{:.1}" y="{:.1}" text-anchor="end" {LABEL_STYLE}>{t_max_s:.2}</text>"#,
        area.x,
        axis_y + 10.0,
        area.x + area.w / 2.0,
        axis_y + 10.0,
        area.x + strip_w,
        axis_y + 10.0,
    )?;
    legend(out, frame, area, axis_y + 30.0)?;
    out.push_str("</g>");
    Ok(())
}

/// Class swatches and names in columns from `top`, cut (with a count) at the panel's bottom.
fn legend(out: &mut String, frame: &Frame, area: Area, top: f64) -> fmt::Result {
    if frame.class_names.is_empty() {
        return Ok(());
    }
    write!(
        out,
        r#"<line x1="{:.1}" x2="{:.1}" y1="{:.1}" y2="{:.1}" {AXIS_STYLE} stroke-opacity="0.5"/>"#,
        area.x,
        area.x + area.w,
        top - 12.0,
        top - 12.0
    )?;
    let column_w = area.w / LEGEND_COLUMNS as f64;
    let lines_fit = ((area.y + area.h - top) / LEGEND_LINE_H).floor().max(1.0) as usize;
    let shown = frame.class_names.len().min(lines_fit * LEGEND_COLUMNS);
    for (k, class_name) in frame.class_names.iter().enumerate().take(shown) {
        let (column, line) = (k % LEGEND_COLUMNS, k / LEGEND_COLUMNS);
        let (x, y) = (
            area.x + column as f64 * column_w,
            top + line as f64 * LEGEND_LINE_H,
        );
        write!(
            out,
            r#"<rect x="{x:.1}" y="{:.1}" width="8" height="8" fill="{}"/><text x="{:.1}" y="{y:.1}" {LABEL_STYLE}>{}</text>"#,
            y - 8.0,
            class_colour(k),
            x + 12.0,
            Esc(&clipped(class_name, 17)),
        )?;
    }
    if shown < frame.class_names.len() {
        write!(
            out,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end" {LABEL_STYLE}>… and {} more</text>"#,
            area.x + area.w,
            area.y + area.h + 10.0,
            frame.class_names.len() - shown
        )?;
    }
    Ok(())
}
