//! PNG copies of the SVG figures, rasterised in pure Rust by resvg (no system library). Text
//! is drawn with the fonts found in the machine's usual font folders; on a machine with none,
//! the PNGs carry the plots without their labels (the SVGs always have them).

use resvg::{tiny_skia, usvg};

/// A figure that could not be rasterised.
#[derive(Debug, thiserror::Error)]
pub enum PngError {
    /// The SVG did not parse.
    #[error("the SVG figure does not parse: {0}")]
    Parse(String),
    /// The image would be empty or too large.
    #[error("a {width} × {height} px image cannot be drawn")]
    Size {
        /// Width (px).
        width: u32,
        /// Height (px).
        height: u32,
    },
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Encode(String),
}

/// Renders SVG documents to PNG, loading the system fonts once.
pub struct PngRenderer {
    options: usvg::Options<'static>,
}

impl Default for PngRenderer {
    fn default() -> Self {
        Self::new()
    }
}

impl PngRenderer {
    /// A renderer with the machine's fonts; the figures' `sans-serif` is the first of a few
    /// common sans-serif families that is installed, else any installed family.
    pub fn new() -> Self {
        let mut options = usvg::Options::default();
        let db = options.fontdb_mut();
        db.load_system_fonts();
        let installed = |name: &str| {
            db.faces()
                .any(|face| face.families.iter().any(|(family, _)| family == name))
        };
        let family = [
            "DejaVu Sans",
            "Liberation Sans",
            "Arial",
            "Helvetica",
            "Noto Sans",
        ]
        .into_iter()
        .find(|f| installed(f))
        .map(str::to_owned)
        .or_else(|| {
            db.faces()
                .find_map(|face| face.families.first().map(|(family, _)| family.clone()))
        });
        if let Some(family) = family {
            db.set_sans_serif_family(&family);
            options.font_family = family;
        }
        Self { options }
    }

    /// Whether any font was found (else text is left out of the PNGs).
    pub fn has_fonts(&self) -> bool {
        !self.options.fontdb.is_empty()
    }

    /// `svg` as PNG bytes, scaled by `scale` (1 = the SVG's own size in px).
    pub fn render(&self, svg: &str, scale: f32) -> Result<Vec<u8>, PngError> {
        let tree =
            usvg::Tree::from_str(svg, &self.options).map_err(|e| PngError::Parse(e.to_string()))?;
        let size = tree.size();
        let (width, height) = (
            (size.width() * scale).ceil() as u32,
            (size.height() * scale).ceil() as u32,
        );
        let too_large = (width as u64) * (height as u64) > 64 << 20;
        let mut pixmap = (!too_large)
            .then(|| tiny_skia::Pixmap::new(width, height))
            .flatten()
            .ok_or(PngError::Size { width, height })?;
        resvg::render(
            &tree,
            tiny_skia::Transform::from_scale(scale, scale),
            &mut pixmap.as_mut(),
        );
        pixmap
            .encode_png()
            .map_err(|e| PngError::Encode(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_a_chart_and_rejects_bad_svg() {
        let r = PngRenderer::new();
        let png = r
            .render(
                r#"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="20"><rect width="40" height="20" fill="red"/></svg>"#,
                2.0,
            )
            .unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        // IHDR width and height (big-endian) follow the signature and chunk header.
        assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 80);
        assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 40);
        assert!(matches!(r.render("<svg", 1.0), Err(PngError::Parse(_))));
    }
}
