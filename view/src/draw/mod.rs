//! Drawing a [`Frame`] as one standalone SVG document ([`draw_frame`]): the page shows it
//! inline and `--snapshot` writes it (or a PNG of it), so both show the same picture.
//!
//! The figure, 1200 × 650 px, white, sans-serif:
//!
//! | where | panel | module |
//! |---|---|---|
//! | top line | source, stream time, state, speed, the four stage counts | here |
//! | top left | the decaying event image (×2, ON warm, OFF blue, on dark) with the receptive fields | `events.rs` |
//! | top middle | the 49 taxels as hexagons in the sensor's layout, coloured by rate, with a colour bar | `taxels.rs` |
//! | top right | the recogniser's decisions per coding and their timeline over the slide (only with a recogniser) | `decisions.rs` |
//! | bottom | the spike raster (a row per taxel) and under it the population rate | `raster.rs` |
//! | last line | what the drawing leaves out, and the frame's notice in red | here |
//!
//! Every text from the frame is escaped for XML; numbers have fixed decimals; nothing is
//! allocated by a size the frame states without holding the data (a malformed event image is
//! drawn as an empty panel with a note).
//!
//! Elements the page and the browser test find by class: one `<line class="spike">` per raster
//! spike, one `<polygon class="taxel">` per taxel, one `<circle class="field">` per receptive
//! field, the event image as `<image class="events">`.

mod colour;
mod decisions;
mod events;
mod raster;
mod svg;
mod taxels;

use std::fmt::{self, Write};

use crate::frame::{Frame, PlayState};
use svg::{Area, Count, Esc, LABEL_STYLE, clipped, finite_or};

pub use events::event_image_png;

/// The figure's width (px).
const WIDTH: f64 = 1200.0;
/// The figure's height (px).
const HEIGHT: f64 = 650.0;

/// The event image (scaled to fit, ×2 for a DAVIS240).
const EVENTS_AREA: Area = Area {
    x: 20.0,
    y: 56.0,
    w: 480.0,
    h: 360.0,
};
/// The taxel hexagons (the colour bar goes below).
const TAXELS_AREA: Area = Area {
    x: 530.0,
    y: 56.0,
    w: 270.0,
    h: 270.0,
};
/// The decisions rows and their legend.
const DECISIONS_AREA: Area = Area {
    x: 835.0,
    y: 56.0,
    w: 345.0,
    h: 360.0,
};
/// The raster's plot area (taxel rows).
const RASTER_AREA: Area = Area {
    x: 60.0,
    y: 452.0,
    w: 1120.0,
    h: 110.0,
};
/// The population rate's plot area (same time axis as the raster, under it).
const RATE_AREA: Area = Area {
    x: 60.0,
    y: 572.0,
    w: 1120.0,
    h: 40.0,
};

/// One standalone SVG document of `frame` (see the [module doc](self) for the panels).
pub fn draw_frame(frame: &Frame) -> String {
    // About 80 bytes per spike plus the event image (≈ 4/3 of a few tens of kB) and the rest.
    let mut out = String::with_capacity(40_000 + 80 * frame.raster.spikes.len().min(1 << 20));
    // Writing into a String cannot fail.
    let _ = write_frame(&mut out, frame);
    out
}

fn write_frame(out: &mut String, frame: &Frame) -> fmt::Result {
    write!(
        out,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH:.0}" height="{HEIGHT:.0}" viewBox="0 0 {WIDTH:.0} {HEIGHT:.0}" font-family="sans-serif"><rect width="{WIDTH:.0}" height="{HEIGHT:.0}" fill="#ffffff"/>"##
    )?;
    header(out, frame)?;
    events::panel(out, frame, EVENTS_AREA)?;
    taxels::panel(out, frame, TAXELS_AREA)?;
    decisions::panel(out, frame, DECISIONS_AREA)?;
    raster::panel(
        out,
        &frame.raster,
        frame.taxel_home.len(),
        RASTER_AREA,
        RATE_AREA,
    )?;
    footer(out, frame)?;
    out.push_str("</svg>");
    Ok(())
}

/// Source, time, state, speed and the stage counts.
fn header(out: &mut String, frame: &Frame) -> fmt::Result {
    let state = match frame.state {
        PlayState::Playing => "playing",
        PlayState::Paused => "paused",
        PlayState::Ended => "ended",
        PlayState::Failed => "failed",
        PlayState::Snapshot => "snapshot",
    };
    let c = &frame.counts;
    write!(
        out,
        r##"<text class="header" x="20" y="24" font-size="13" fill="#222"><tspan font-weight="bold">{}</tspan><tspan fill="#999">  ·  </tspan>t = {:.3} s<tspan fill="#999">  ·  </tspan>{state}{}<tspan fill="#999">  ·  </tspan>{} pixel events → {} after filters → {} in fields → {} taxel spikes</text>"##,
        Esc(&clipped(&frame.source, 40)),
        finite_or(frame.t_s, 0.0),
        Speed(frame.speed.as_deref()),
        Count(c.events_in),
        Count(c.after_filters),
        Count(c.in_fields),
        Count(c.taxel_spikes),
    )?;
    write!(
        out,
        r##"<line x1="20" x2="{:.0}" y1="34.5" y2="34.5" stroke="#ddd" stroke-width="1"/>"##,
        WIDTH - 20.0
    )
}

/// ` · speed 2×` in the header; nothing without a speed (a snapshot).
struct Speed<'a>(Option<&'a str>);

impl fmt::Display for Speed<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            None => Ok(()),
            Some(speed) => write!(
                f,
                r##"<tspan fill="#999">  ·  </tspan>speed {}"##,
                Esc(&clipped(speed, 12))
            ),
        }
    }
}

/// What the drawing leaves out, and the notice (red) when there is one.
fn footer(out: &mut String, frame: &Frame) -> fmt::Result {
    let d = &frame.decimation;
    let y = HEIGHT - 8.0;
    write!(
        out,
        r#"<text class="footer" x="20" y="{y:.0}" {LABEL_STYLE}>"#
    )?;
    if d.events_since_last_frame == 0 {
        out.push_str("no new pixel events since the last frame");
    } else {
        write!(
            out,
            "event image shows {:.0} % of the {} pixel events of the last {:.0} ms of stream (each pixel's latest)",
            100.0 * finite_or(d.drawn_share, 0.0).clamp(0.0, 1.0),
            Count(d.events_since_last_frame),
            finite_or(d.stream_ms_since_last_frame, 0.0).max(0.0),
        )?;
    }
    out.push_str("; counts, rates and raster include every event");
    // 0: not measured (a snapshot has no wall clock to compare with).
    let speed = finite_or(d.speed_vs_realtime, 0.0);
    if speed > 0.0 {
        write!(out, "; stream at {speed:.1}× real time")?;
    }
    if let Some(notice) = &frame.notice {
        write!(
            out,
            r##"<tspan class="notice" fill="#c62828" font-weight="bold">  {}</tspan>"##,
            Esc(&clipped(notice, 120))
        )?;
    }
    out.push_str("</text>");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::svg::{F1, decimals_for, nice_ceil, nice_step};
    use super::*;
    use crate::frame::{
        CodingDecisions, Decimation, DecisionPoint, EventImage, Raster, StageCounts,
    };
    use neurotac_sensor::geometry::PinGeometry;

    /// A plausible frame: 49 pins in their rings, a moving blob of events, `spikes` raster
    /// spikes spread over 2 s, rates rising with the taxel index.
    fn frame_with(spikes: usize) -> Frame {
        let (width, height) = (240u16, 180u16);
        let mut intensity = vec![0.0f32; width as usize * height as usize];
        for y in 60..120 {
            for x in 80..160 {
                let v = ((x as f32 - 120.0) / 40.0).sin() * ((y as f32 - 90.0) / 30.0).cos();
                intensity[y * width as usize + x] = v.clamp(-1.0, 1.0);
            }
        }
        let pins = PinGeometry::default().pin_positions_px();
        let n = pins.len();
        let spikes: Vec<(u16, f64)> = (0..spikes)
            .map(|i| {
                (
                    (i * 7 % n) as u16,
                    8.0 + 2.0 * (i as f64 + 0.5) / spikes as f64,
                )
            })
            .collect();
        Frame {
            seq: 12,
            source: "texture_3.aedat4".into(),
            t_s: 10.0,
            counts: StageCounts {
                events_in: 1_234_567,
                after_filters: 456_789,
                in_fields: 123_456,
                taxel_spikes: 9_876,
            },
            image: EventImage {
                width,
                height,
                intensity,
                decay_ms: 30.0,
            },
            field_centres: pins.clone(),
            field_radius_px: 3.0,
            taxel_home: pins,
            taxel_rate_hz: (0..n).map(|i| i as f64 * 0.7).collect(),
            rate_window_s: 0.5,
            raster: Raster {
                from_s: 8.0,
                to_s: 10.0,
                spikes,
                population_rate_hz: (0..100)
                    .map(|i| 5.0 + (i as f64 / 8.0).sin() * 4.0)
                    .collect(),
                bin_s: 0.02,
            },
            class_names: vec![],
            decisions: vec![],
            state: PlayState::Playing,
            speed: Some("2×".into()),
            decimation: Decimation {
                events_since_last_frame: 12_034,
                stream_ms_since_last_frame: 66.0,
                drawn_share: 0.37,
                speed_vs_realtime: 4.2,
            },
            notice: None,
            oldest_new_event_due_unix_ms: None,
        }
    }

    /// `frame` with a recogniser's decisions for two codings.
    fn with_decisions(mut frame: Frame) -> Frame {
        frame.class_names = (0..11)
            .map(|k| format!("grid {:.1} mm", k as f64 * 0.5))
            .collect();
        let point = |t_s: f64, class: usize, tie: bool, stable: bool| DecisionPoint {
            t_s,
            class,
            vote_share: 0.6,
            tie,
            stable,
        };
        frame.decisions = vec![
            CodingDecisions {
                coding: "intensive".into(),
                history: vec![
                    point(0.5, 0, true, false),
                    point(1.0, 3, false, false),
                    point(1.5, 3, false, true),
                ],
                final_decision: Some(point(1.5, 3, false, true)),
            },
            CodingDecisions {
                coding: "spatial".into(),
                history: vec![point(0.5, 2, false, false), point(1.0, 5, false, false)],
                final_decision: None,
            },
        ];
        frame
    }

    fn count(svg: &str, needle: &str) -> usize {
        svg.matches(needle).count()
    }

    /// Every `<x …>` has its `</x>` (or is `<x …/>`), in order.
    fn assert_balanced(svg: &str) {
        let mut open: Vec<&str> = Vec::new();
        let mut rest = svg;
        while let Some(start) = rest.find('<') {
            let end = rest[start..].find('>').expect("unclosed tag") + start;
            let tag = &rest[start + 1..end];
            assert!(!tag.contains('<'), "a '<' inside a tag: {tag}");
            if let Some(name) = tag.strip_prefix('/') {
                assert_eq!(open.pop(), Some(name), "mismatched </{name}>");
            } else if !tag.ends_with('/') {
                open.push(tag.split(|c: char| c.is_whitespace()).next().unwrap_or(""));
            }
            rest = &rest[end + 1..];
        }
        assert!(open.is_empty(), "unclosed: {open:?}");
    }

    #[test]
    fn a_frame_is_one_balanced_svg_with_an_element_per_spike_taxel_and_field() {
        let frame = frame_with(5000);
        let svg = draw_frame(&frame);
        assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1200\""));
        assert!(svg.ends_with("</svg>"));
        assert_balanced(&svg);
        assert_eq!(count(&svg, "class=\"spike\""), 5000);
        assert_eq!(count(&svg, "class=\"taxel\""), 49);
        assert_eq!(count(&svg, "class=\"field\""), 49);
        // Every hexagon carries its taxel's number, the raster's row.
        let numbers = svg.split("class=\"taxel-numbers\"").nth(1).unwrap();
        let numbers = &numbers[..numbers.find("</g>").unwrap()];
        for i in 0..49 {
            assert!(numbers.contains(&format!(">{i}</text>")), "taxel {i}");
        }
        assert_eq!(count(&svg, "<image class=\"events\" "), 1);
        assert!(svg.contains("href=\"data:image/png;base64,"));
        assert!(svg.contains("t = 10.000 s"));
        assert!(svg.contains("1 234 567 pixel events → 456 789 after filters"));
        assert!(svg.contains("37 % of the 12 034 pixel events"));
        assert!(svg.contains("4.2× real time"));
    }

    #[test]
    fn spikes_outside_the_window_or_the_rows_are_still_drawn_once_each() {
        let mut frame = frame_with(0);
        frame.raster.spikes = vec![(0, f64::NAN), (300, 9.0), (3, 1e9), (4, -5.0)];
        let svg = draw_frame(&frame);
        assert_eq!(count(&svg, "class=\"spike\""), 4);
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        assert_balanced(&svg);
    }

    #[test]
    fn user_text_is_escaped() {
        let mut frame = with_decisions(frame_with(10));
        frame.source = "<script>alert(\"x\") & 'y'</script>\u{1}".into();
        frame.class_names[3] = "<b>&\"rough\"</b>".into();
        frame.decisions[0].coding = "<i>".into();
        frame.notice = Some("device <unplugged> & gone".into());
        let svg = draw_frame(&frame);
        assert!(!svg.contains("<script>") && !svg.contains("<b>") && !svg.contains("<i>"));
        assert!(svg.contains(
            "&lt;script&gt;alert(&quot;x&quot;) &amp; &apos;y&apos;&lt;/script&gt;\u{fffd}"
        ));
        assert!(svg.contains("&lt;b&gt;&amp;&quot;rough&quot;&lt;/b&gt;"));
        assert!(svg.contains("device &lt;unplugged&gt; &amp; gone"));
        assert_balanced(&svg);
    }

    #[test]
    fn a_notice_is_shown_in_red() {
        let mut frame = frame_with(10);
        frame.notice = Some("the camera was unplugged".into());
        let svg = draw_frame(&frame);
        let at = svg.find("the camera was unplugged").expect("notice drawn");
        let tspan = svg[..at].rfind("<tspan").expect("in a tspan");
        assert!(svg[tspan..at].contains("fill=\"#c62828\""));
    }

    #[test]
    fn a_wrong_sized_event_image_draws_an_empty_panel_with_a_note() {
        let mut frame = frame_with(10);
        frame.image.intensity.truncate(1000);
        let svg = draw_frame(&frame);
        assert_eq!(count(&svg, "<image"), 0);
        assert!(svg.contains("no event image: 1000 intensities for 240 × 180 px"));
        assert_eq!(count(&svg, "class=\"field\""), 49);
        assert_balanced(&svg);
        // A huge stated size with few intensities allocates nothing by the stated size.
        frame.image.width = u16::MAX;
        frame.image.height = u16::MAX;
        assert!(event_image_png(&frame.image).is_empty());
        assert!(draw_frame(&frame).contains("no event image"));
    }

    #[test]
    fn the_decisions_panel_appears_only_with_a_recogniser() {
        let svg = draw_frame(&frame_with(10));
        assert_eq!(count(&svg, "class=\"decisions\""), 0);
        assert_eq!(count(&svg, "class=\"decision-run\""), 0);

        let svg = draw_frame(&with_decisions(frame_with(10)));
        assert_balanced(&svg);
        assert_eq!(count(&svg, "class=\"decisions\""), 1);
        // One timeline rect per run of equal decisions (tie, 3 3 | 2 | 5), the final
        // decision marked once.
        assert_eq!(count(&svg, "class=\"decision-run\""), 4);
        assert_eq!(count(&svg, "class=\"final-decision\""), 1);
        // The latest decisions by name, with their vote share, the first one stable.
        assert!(svg.contains(">grid 1.5 mm</text>"));
        assert!(svg.contains(">grid 2.5 mm</text>"));
        assert_eq!(count(&svg, ">60 %</text>"), 2);
        assert_eq!(count(&svg, "class=\"stable\""), 1);
        // The legend names every class.
        for k in 0..11 {
            assert!(svg.contains(&format!(">grid {:.1} mm</text>", k as f64 * 0.5)));
        }
    }

    #[test]
    fn a_tie_is_named_tie_and_drawn_grey() {
        let mut frame = with_decisions(frame_with(10));
        assert!(!draw_frame(&frame).contains(">tie</text>"));
        frame.decisions[1].history.last_mut().unwrap().tie = true;
        let svg = draw_frame(&frame);
        let at = svg
            .find(">tie</text>")
            .expect("the latest decision reads tie");
        let swatch = svg[..at].rfind("<rect").expect("a swatch before the name");
        assert!(svg[swatch..at].contains(&format!("fill=\"{}\"", colour::NO_CLASS)));
    }

    #[test]
    fn counts_group_thousands_and_nice_steps_are_one_two_five() {
        assert_eq!(Count(0).to_string(), "0");
        assert_eq!(Count(999).to_string(), "999");
        assert_eq!(Count(12_034).to_string(), "12 034");
        assert_eq!(Count(1_000_000).to_string(), "1 000 000");
        assert_eq!(nice_step(2.0, 8), 0.5);
        assert_eq!(nice_step(10.0, 5), 2.0);
        assert_eq!(nice_ceil(10.0), 10.0);
        assert_eq!(nice_ceil(13.0), 20.0);
        assert_eq!(nice_ceil(0.3), 0.5);
        assert_eq!(decimals_for(0.5), 1);
        assert_eq!(decimals_for(0.05), 2);
        assert_eq!(decimals_for(2.0), 0);
        assert_eq!(clipped("abcdef", 4), "a…ef");
        assert_eq!(
            clipped("natural texture number 12", 17),
            "natural …umber 12"
        );
        assert_eq!(clipped("äöüäöü", 5), "äö…öü");
        for (x, text) in [
            (0.0, "0.0"),
            (-0.04, "0.0"),
            (12.34, "12.3"),
            (-7.25, "-7.3"),
            (480.0, "480.0"),
            (0.96, "1.0"),
        ] {
            assert_eq!(F1(x).to_string(), text);
        }
        assert_eq!(F1(f64::NAN).to_string(), "NaN");
        assert_eq!(clipped("abcd", 4), "abcd");
    }
}
