//! The figures' one style: print resolution ([`SCALE`]), font sizes, text measured and
//! wrapped in the embedded font, and titles wrapped (and if need be shrunk) to the width.

use super::{font, DEFAULT_SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Pixels per design unit: font sizes, line widths, marker sizes and margins are given for
/// a 960-pixel-wide figure and multiplied by this factor.
pub const SCALE: f64 = DEFAULT_SIZE.0 as f64 / 960.0;

/// `v` design units in pixels.
pub(super) fn px(v: f64) -> i32 {
    (v * SCALE).round() as i32
}

/// `v` design units in pixels, unsigned.
pub(super) fn upx(v: f64) -> u32 {
    px(v).max(0) as u32
}

/// Font sizes in design units: title, axis descriptions, tick labels and legend.
const TITLE_FONT: f64 = 22.0;
pub(super) const AXIS_FONT: f64 = 17.0;
pub(super) const TICK_FONT: f64 = 15.0;
pub(super) const LEGEND_FONT: f64 = 15.0;

/// The text style of `size` design units in the embedded font.
pub(super) fn text_style(size: f64) -> TextStyle<'static> {
    TextStyle::from((font::FAMILY, px(size) as f64).into_font())
}

/// The pixel size of `text` in `style` on `area` (a generous estimate if the backend cannot
/// measure it).
pub(super) fn text_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
) -> (i32, i32) {
    area.estimate_text_size(text, style)
        .map(|(w, h)| (w as i32, h as i32))
        .unwrap_or_else(|_| {
            let size = style.font.get_size();
            (
                (0.6 * size * text.chars().count() as f64) as i32,
                size as i32,
            )
        })
}

/// `text` broken into lines at spaces so that each fits `width` pixels in `style` (a word
/// longer than the width stays whole on its own line).
fn wrap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    width: i32,
) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        match lines.last_mut() {
            Some(line) if text_size(area, &format!("{line} {word}"), style).0 <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// A font size (design units) at most `size` at which each of `lines` fits `width` pixels.
pub(super) fn fitting_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    lines: &[String],
    size: f64,
    width: i32,
) -> f64 {
    let widest = lines
        .iter()
        .map(|l| text_size(area, l, &text_style(size)).0)
        .max()
        .unwrap_or(0);
    if widest <= width || widest == 0 {
        size
    } else {
        size * width as f64 / widest as f64 * 0.98
    }
}

/// Draws `title` at the top of `area`, wrapped (and if need be shrunk) to its width, and
/// returns the area below it.
pub(super) fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> std::result::Result<DrawingArea<DB, Shift>, String> {
    let (w, _) = area.dim_in_pixel();
    let width = w as i32 - 2 * px(12.0);
    let lines = wrap(area, title, &text_style(TITLE_FONT), width);
    if lines.is_empty() {
        return Ok(area.clone().margin(upx(4.0), 0, 0, 0));
    }
    let size = fitting_size(area, &lines, TITLE_FONT, width);
    let style = text_style(size).pos(Pos::new(HPos::Center, VPos::Top));
    let line_height = (text_size(area, "Ag", &style).1 as f64 * 1.2).ceil() as i32;
    let top = px(8.0);
    for (i, line) in lines.iter().enumerate() {
        area.draw_text(line, &style, (w as i32 / 2, top + i as i32 * line_height))
            .map_err(|e| e.to_string())?;
    }
    let height = top + lines.len() as i32 * line_height + px(4.0);
    Ok(area.split_vertically(height).1)
}
