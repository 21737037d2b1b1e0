//! The one typeface of every figure: DejaVu Sans, embedded in the binary
//! (`crates/hopsim-studies/fonts/`, with its licence), and [`Typeset`], the backend wrapper
//! through which every figure is drawn: it measures all text with the embedded font and,
//! on a pixel backend, draws it with it (ab_glyph), so that figures look the same on every
//! machine and never ask the system for fonts (no fontconfig, no font files).
//!
//! Sizes follow plotters' convention, under which a text style's size is 1.24 em (its SVG
//! backend writes `font-size = size / 1.24`), and the baseline sits where an SVG viewer
//! puts it for plotters' anchors, so that the PNG and the SVG of a figure agree.

use ab_glyph::{point, Font, FontRef, GlyphId, PxScale, ScaleFont};
use plotters::prelude::DrawingBackend;
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use std::sync::OnceLock;

/// DejaVu Sans 2.37, unmodified (`fonts/LICENSE-DejaVu.txt`).
const DEJAVU_SANS: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// The family SVG files name: DejaVu Sans where the viewer has it (the PNG's face), else
/// the viewer's sans-serif face.
pub const FAMILY: &str = "DejaVu Sans, sans-serif";

/// A plotters text size per em.
const SIZE_PER_EM: f64 = 1.24;

/// The baseline below the anchor's top, in em (SVG `dy = 0.76em` of plotters' `Top`).
const TOP_BASELINE_EM: f32 = 0.76;

/// The embedded font could not be read.
#[derive(Debug, thiserror::Error)]
#[error("the embedded font (DejaVu Sans) is not a readable font")]
pub struct FontError;

/// The embedded font and the metrics text placement needs.
struct Face {
    font: FontRef<'static>,
    /// `PxScale` per pixel of em.
    scale_per_em: f32,
    /// x-height in em (the SVG `ex`).
    x_height_em: f32,
}

fn face() -> Result<&'static Face, FontError> {
    static FACE: OnceLock<Option<Face>> = OnceLock::new();
    FACE.get_or_init(|| {
        let font = FontRef::try_from_slice(DEJAVU_SANS).ok()?;
        let units = font.units_per_em()?;
        let x_height = font
            .outline(font.glyph_id('x'))
            .map_or(0.5 * units, |o| o.bounds.height().abs());
        Some(Face {
            scale_per_em: font.height_unscaled() / units,
            x_height_em: x_height / units,
            font,
        })
    })
    .as_ref()
    .ok_or(FontError)
}

/// A line of text laid out at `em` pixels per em: its glyphs with their pen positions
/// along the baseline, and its advance width.
struct Line {
    scale: PxScale,
    glyphs: Vec<(GlyphId, f32)>,
    width: f32,
    em: f32,
}

impl Face {
    fn line(&self, text: &str, size: f64) -> Line {
        let em = (size / SIZE_PER_EM) as f32;
        let scale = PxScale::from(em * self.scale_per_em);
        let scaled = self.font.as_scaled(scale);
        let mut glyphs = Vec::with_capacity(text.len());
        let (mut x, mut previous) = (0.0, None);
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                x += scaled.kern(p, id);
            }
            glyphs.push((id, x));
            x += scaled.h_advance(id);
            previous = Some(id);
        }
        Line {
            scale,
            glyphs,
            width: x,
            em,
        }
    }

    /// Where the line starts relative to the anchor: `(x, baseline y)`.
    fn origin(&self, line: &Line, h: HPos, v: VPos) -> (f32, f32) {
        let x = match h {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * line.width,
            HPos::Right => -line.width,
        };
        let ex = self.x_height_em * line.em;
        let y = match v {
            VPos::Top => TOP_BASELINE_EM * line.em,
            VPos::Center => 0.5 * ex,
            VPos::Bottom => -0.5 * ex,
        };
        (x, y)
    }
}

/// The size `(width, height)` in pixels of `text` at plotters size `size`: its advance
/// width and one em.
pub fn text_size(text: &str, size: f64) -> Result<(u32, u32), FontError> {
    let line = face()?.line(text, size);
    Ok((line.width.ceil() as u32, line.em.round() as u32))
}

/// A drawing backend whose text is set in the embedded font: measured here always, drawn
/// here on pixel backends ([`Typeset::raster`]) and left to backends that write text
/// themselves ([`Typeset::vector`], SVG). Every other call goes to the backend.
pub struct Typeset<DB> {
    inner: DB,
    raster: bool,
}

impl<DB: DrawingBackend> Typeset<DB> {
    /// A pixel backend (PNG): text is rasterised here.
    pub fn raster(inner: DB) -> Self {
        Typeset {
            inner,
            raster: true,
        }
    }

    /// A backend that writes text as text (SVG): only measured here.
    pub fn vector(inner: DB) -> Self {
        Typeset {
            inner,
            raster: false,
        }
    }

    /// Rasterises `text` with its anchor at `pos`, blending each pixel by its coverage.
    fn set_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let face = face().map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let line = face.line(text, style.size());
        let anchor = style.anchor();
        let (x0, y0) = face.origin(&line, anchor.h_pos, anchor.v_pos);
        let transform = style.transform();
        let (w, h) = self.inner.get_size();
        let scaled = face.font.as_scaled(line.scale);
        let mut result = Ok(());
        for &(id, x) in &line.glyphs {
            let glyph = id.with_scale_and_position(line.scale, point(x0 + x, y0));
            let Some(outline) = scaled.outline_glyph(glyph) else {
                continue;
            };
            let bounds = outline.px_bounds();
            let inner = &mut self.inner;
            outline.draw(|gx, gy, coverage| {
                let local = (
                    bounds.min.x as i32 + gx as i32,
                    bounds.min.y as i32 + gy as i32,
                );
                let (dx, dy) = transform.transform(local.0, local.1);
                let (x, y) = (pos.0 + dx, pos.1 + dy);
                let inside = x >= 0 && y >= 0 && x < w as i32 && y < h as i32;
                if coverage > 0.0 && inside && result.is_ok() {
                    let alpha = color.alpha * f64::from(coverage.min(1.0));
                    result = inner.draw_pixel((x, y), BackendColor { alpha, ..color });
                }
            });
        }
        result
    }
}

impl<DB: DrawingBackend> DrawingBackend for Typeset<DB> {
    type ErrorType = DB::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        match self.raster {
            true => self.set_text(text, style, pos),
            false => self.inner.draw_text(text, style, pos),
        }
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<DB::ErrorType>> {
        text_size(text, style.size()).map_err(|e| DrawingErrorKind::FontError(Box::new(e)))
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    /// Text is measured in the embedded font: an em of `size / 1.24` pixels, widths that
    /// grow with the text and match DejaVu Sans' advances (`0` is 0.636 em wide).
    #[test]
    fn text_is_measured_in_the_embedded_font() {
        let size = 124.0;
        assert_eq!(text_size("", size).unwrap(), (0, 100));
        let (zero, _) = text_size("0", size).unwrap();
        assert!((63..=64).contains(&zero), "{zero}");
        let (ten, _) = text_size("00000 00000", size).unwrap();
        assert!(ten > 10 * zero && ten < 12 * zero, "{ten}");
        assert!(text_size("ζ0* ≥ 1 N m s", size).unwrap().0 > 0);
    }

    /// A pixel backend gets the text drawn: dark pixels inside the text's measured box
    /// (right of a right-anchored point, centred on a centre anchor), none elsewhere.
    #[test]
    fn text_is_drawn_inside_its_box() {
        let (w, h) = (400u32, 100u32);
        let mut buffer = vec![255u8; (w * h * 3) as usize];
        {
            let root = Typeset::raster(BitMapBackend::with_buffer(&mut buffer, (w, h)))
                .into_drawing_area();
            let style = TextStyle::from((FAMILY, 62.0).into_font()).pos(
                plotters::style::text_anchor::Pos::new(HPos::Left, VPos::Center),
            );
            root.draw_text("hopsim", &style, (20, 50)).unwrap();
            root.present().unwrap();
        }
        let (tw, _) = text_size("hopsim", 62.0).unwrap();
        let dark: Vec<(u32, u32)> = (0..w * h)
            .filter(|i| buffer[3 * *i as usize] < 128)
            .map(|i| (i % w, i / w))
            .collect();
        assert!(dark.len() > 200, "{} dark pixels", dark.len());
        let (x_min, x_max) = dark
            .iter()
            .fold((w, 0), |(a, b), p| (a.min(p.0), b.max(p.0)));
        let (y_min, y_max) = dark
            .iter()
            .fold((h, 0), |(a, b), p| (a.min(p.1), b.max(p.1)));
        assert!(
            x_min >= 20 && x_max <= 20 + tw,
            "{x_min}…{x_max}, width {tw}"
        );
        // An em of 50 pixels, the baseline half an x-height (0.27 em) below the anchor:
        // 'h' rises 0.76 em above it (to y ≈ 26), 'p' falls 0.21 em below it (y ≈ 74).
        assert!(
            (20..=32).contains(&y_min) && (68..=80).contains(&y_max),
            "{y_min}…{y_max}"
        );
    }
}
