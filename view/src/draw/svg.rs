//! What every panel of the drawing writes with: its [`Area`], the shared styles, XML escaping,
//! compact number formatting and 1–2–5 axis steps.

use std::borrow::Cow;
use std::fmt::{self, Write};

/// A rectangle of the figure (px).
#[derive(Debug, Clone, Copy)]
pub(super) struct Area {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) w: f64,
    pub(super) h: f64,
}

/// Panel titles.
pub(super) const TITLE_STYLE: &str = r##"font-size="11" fill="#444""##;
/// Axis labels and notes.
pub(super) const LABEL_STYLE: &str = r##"font-size="10" fill="#777""##;
/// Axis lines and ticks.
pub(super) const AXIS_STYLE: &str = r##"stroke="#999" stroke-width="0.6" fill="none""##;

/// Text escaped for XML content and attribute values; characters XML 1.0 cannot hold (most
/// control characters) become U+FFFD.
pub(super) struct Esc<'a>(pub(super) &'a str);

impl fmt::Display for Esc<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut rest = self.0;
        while let Some(i) = rest.find(|c: char| {
            matches!(c, '&' | '<' | '>' | '"' | '\'')
                || (c < ' ' && !matches!(c, '\t' | '\n' | '\r'))
                || c == '\u{fffe}'
                || c == '\u{ffff}'
        }) {
            f.write_str(&rest[..i])?;
            let c = rest[i..].chars().next().unwrap_or('\u{fffd}');
            f.write_str(match c {
                '&' => "&amp;",
                '<' => "&lt;",
                '>' => "&gt;",
                '"' => "&quot;",
                '\'' => "&apos;",
                _ => "\u{fffd}",
            })?;
            rest = &rest[i + c.len_utf8()..];
        }
        f.write_str(rest)
    }
}

/// `s` cut to at most `max_chars` characters by replacing its middle with `…`, so names that
/// differ only at the end (`natural texture 12`, a file's number) stay apart.
pub(super) fn clipped(s: &str, max_chars: usize) -> Cow<'_, str> {
    let chars = s.chars().count();
    if chars <= max_chars {
        return Cow::Borrowed(s);
    }
    let head = max_chars.saturating_sub(1) / 2;
    let tail = max_chars.saturating_sub(1) - head;
    let byte_at = |n: usize| s.char_indices().nth(n).map_or(s.len(), |(i, _)| i);
    Cow::Owned(format!(
        "{}…{}",
        &s[..byte_at(head)],
        &s[byte_at(chars - tail)..]
    ))
}

/// A count with its thousands grouped by spaces (`12 034`).
pub(super) struct Count(pub(super) u64);

impl fmt::Display for Count {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let digits = self.0.to_string();
        for (i, d) in digits.chars().enumerate() {
            if i > 0 && (digits.len() - i).is_multiple_of(3) {
                f.write_char(' ')?;
            }
            f.write_char(d)?;
        }
        Ok(())
    }
}

/// `x` with one decimal, as `{:.1}` writes it (up to how exact halves round), made
/// for the thousands of coordinates of a frame: a stack buffer instead of float formatting.
/// Not finite or beyond ±10¹⁵ falls back to `{:.1}`.
pub(super) struct F1(pub(super) f64);

impl fmt::Display for F1 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let tenths = (self.0 * 10.0).round();
        if !tenths.is_finite() || tenths.abs() >= 1e16 {
            return write!(f, "{:.1}", self.0);
        }
        let mut tenths = tenths as i64;
        let mut buf = [0u8; 24];
        let mut at = buf.len();
        let negative = tenths < 0;
        tenths = tenths.abs();
        at -= 1;
        buf[at] = b'0' + (tenths % 10) as u8;
        at -= 1;
        buf[at] = b'.';
        let mut whole = tenths / 10;
        loop {
            at -= 1;
            buf[at] = b'0' + (whole % 10) as u8;
            whole /= 10;
            if whole == 0 {
                break;
            }
        }
        if negative {
            at -= 1;
            buf[at] = b'-';
        }
        // Only ASCII digits, '.' and '-' were written.
        f.write_str(std::str::from_utf8(&buf[at..]).unwrap_or("0.0"))
    }
}

/// `x`, or `fallback` when `x` is NaN or infinite.
pub(super) fn finite_or(x: f64, fallback: f64) -> f64 {
    if x.is_finite() { x } else { fallback }
}

/// The 1–2–5 step that cuts `span` (> 0) into at most `max_ticks` intervals.
pub(super) fn nice_step(span: f64, max_ticks: usize) -> f64 {
    let raw = span / max_ticks.max(1) as f64;
    let magnitude = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|&step| step >= raw)
        .unwrap_or(10.0 * magnitude)
}

/// The smallest 1–2–5 value (1, 2, 5, 10, 20, …) at or above `x` (> 0).
pub(super) fn nice_ceil(x: f64) -> f64 {
    let magnitude = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|&v| v >= x * (1.0 - 1e-9))
        .unwrap_or(10.0 * magnitude)
}

/// Decimals that show a multiple of `step` exactly (0 for steps ≥ 1).
pub(super) fn decimals_for(step: f64) -> usize {
    if step >= 1.0 {
        0
    } else {
        (-step.log10() - 1e-9).ceil().clamp(0.0, 6.0) as usize
    }
}
