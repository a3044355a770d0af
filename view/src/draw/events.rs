//! The event image panel: the decaying event image as a PNG in a data URI, scaled to fit
//! (×2 for a DAVIS240's 240 × 180 px), with the receptive fields' outlines over it.

use std::fmt::{self, Write};

use base64::Engine;

use super::colour::{EVENT_BACKGROUND, EVENT_OFF, EVENT_ON};
use super::svg::{Area, TITLE_STYLE, finite_or};
use crate::frame::{EventImage, Frame};

/// The event image as an RGBA PNG (fast compression; it is made for every frame): a pixel at
/// intensity `a` is the dark background moved by `|a|` towards the ON colour (warm
/// white-yellow, `a > 0`) or the OFF colour (blue, `a < 0`); fully opaque.
///
/// Empty when the image is malformed — `intensity.len() != width × height`, or no pixels
/// (a PNG cannot be empty) — so nothing is allocated by a size the image only states.
pub fn event_image_png(image: &EventImage) -> Vec<u8> {
    let (width, height) = (image.width as usize, image.height as usize);
    if width == 0 || height == 0 || image.intensity.len() != width * height {
        return Vec::new();
    }
    let mut rgba = Vec::with_capacity(4 * image.intensity.len());
    for &a in &image.intensity {
        let colour = if a > 0.0 {
            EVENT_BACKGROUND.mix(EVENT_ON, a)
        } else if a < 0.0 {
            EVENT_BACKGROUND.mix(EVENT_OFF, -a)
        } else {
            EVENT_BACKGROUND
        };
        rgba.extend_from_slice(&[colour.0, colour.1, colour.2, 255]);
    }
    let mut png_bytes = Vec::with_capacity(rgba.len() / 8);
    let mut encoder = png::Encoder::new(&mut png_bytes, image.width.into(), image.height.into());
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    let written = encoder.write_header().and_then(|mut writer| {
        writer
            .write_image_data(&rgba)
            .and_then(|()| writer.finish())
    });
    // Encoding a well-formed image into memory does not fail; should it, no picture.
    if written.is_err() {
        return Vec::new();
    }
    png_bytes
}

/// The panel: title, image (or a note when the image is malformed), field outlines.
pub(super) fn panel(out: &mut String, frame: &Frame, area: Area) -> fmt::Result {
    let image = &frame.image;
    let (width, height) = (
        f64::from(image.width.max(1)),
        f64::from(image.height.max(1)),
    );
    let scale = (area.w / width).min(area.h / height);
    let (w, h) = (width * scale, height * scale);
    write!(
        out,
        r#"<text x="{:.1}" y="{:.1}" {TITLE_STYLE}>pixel events: ON <tspan fill="{EVENT_ON}" font-size="13">■</tspan> OFF <tspan fill="{EVENT_OFF}" font-size="13">■</tspan>, fading with τ = {:.0} ms; receptive fields (r = {:.1} px)</text>"#,
        area.x,
        area.y - 8.0,
        finite_or(image.decay_ms, 0.0),
        finite_or(frame.field_radius_px, 0.0),
    )?;
    let png_bytes = event_image_png(image);
    if png_bytes.is_empty() {
        write!(
            out,
            r##"<rect x="{:.1}" y="{:.1}" width="{w:.1}" height="{h:.1}" fill="{EVENT_BACKGROUND}"/><text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="11" fill="#bbbbbb">no event image: {} intensities for {} × {} px</text>"##,
            area.x,
            area.y,
            area.x + w / 2.0,
            area.y + 20.0,
            image.intensity.len(),
            image.width,
            image.height,
        )?;
    } else {
        write!(
            out,
            r#"<image class="events" x="{:.1}" y="{:.1}" width="{w:.1}" height="{h:.1}" preserveAspectRatio="none" style="image-rendering:pixelated" href="data:image/png;base64,"#,
            area.x, area.y,
        )?;
        base64::engine::general_purpose::STANDARD.encode_string(&png_bytes, out);
        out.push_str("\"/>");
    }
    // Field outlines, in the image's pixel coordinates (pixel centres at +0.5).
    write!(
        out,
        r##"<g stroke="#ffffff" stroke-opacity="0.55" stroke-width="0.8" fill="none">"##
    )?;
    let r = finite_or(frame.field_radius_px, 0.0).max(0.0) * scale;
    for &(x, y) in &frame.field_centres {
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        write!(
            out,
            r#"<circle class="field" cx="{:.1}" cy="{:.1}" r="{r:.1}"/>"#,
            area.x + (x + 0.5) * scale,
            area.y + (y + 0.5) * scale,
        )?;
    }
    out.push_str("</g>");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_png_holds_on_off_and_background_colours_at_their_pixels() {
        let (width, height) = (240u16, 180u16);
        let mut intensity = vec![0.0f32; 240 * 180];
        intensity[10 * 240 + 20] = 1.0;
        intensity[50 * 240 + 7] = -1.0;
        intensity[60 * 240 + 8] = 0.5;
        let image = EventImage {
            width,
            height,
            intensity,
            decay_ms: 30.0,
        };
        let bytes = event_image_png(&image);
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut buf).expect("decodes");
        assert_eq!((info.width, info.height), (240, 180));
        assert_eq!(info.color_type, png::ColorType::Rgba);
        let at = |x: usize, y: usize| {
            let i = 4 * (y * 240 + x);
            (buf[i], buf[i + 1], buf[i + 2], buf[i + 3])
        };
        let rgba = |c: super::super::colour::Rgb| (c.0, c.1, c.2, 255);
        assert_eq!(at(20, 10), rgba(EVENT_ON));
        assert_eq!(at(7, 50), rgba(EVENT_OFF));
        assert_eq!(at(0, 0), rgba(EVENT_BACKGROUND));
        assert_eq!(at(8, 60), rgba(EVENT_BACKGROUND.mix(EVENT_ON, 0.5)));
        let half = at(8, 60);
        assert!(half.0 > EVENT_BACKGROUND.0 && half.0 < EVENT_ON.0);
    }

    #[test]
    fn an_image_without_pixels_gives_no_png() {
        let image = EventImage {
            width: 0,
            height: 180,
            intensity: vec![],
            decay_ms: 30.0,
        };
        assert!(event_image_png(&image).is_empty());
    }
}
