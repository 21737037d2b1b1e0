//! Legends: entries whose markers are the ones drawn; a box inside the plot where it covers
//! no data, else a column beside or a band below it; rows under a map or a title; the note
//! of off-scale points.

use super::axis::{three_significant_digits, Axis};
use super::colour::RGBColor;
use super::range::finite_range;
use super::series::{dot_radius, draw_marker, Marker, Series};
use super::style::{px, text_size, text_style, upx, LEGEND_FONT};
use super::DrawResult;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One row of a legend.
#[derive(Debug, Clone)]
pub(super) struct LegendEntry {
    pub(super) label: String,
    pub(super) marker: Marker,
    pub(super) color: RGBColor,
    /// Marker radius and line width in pixels.
    pub(super) radius: i32,
    pub(super) width: u32,
    /// A triangle marker points up (off-scale points above the plot) or down.
    pub(super) up: bool,
}

impl LegendEntry {
    pub(super) fn of(series: &Series, color: RGBColor) -> Option<Self> {
        Some(LegendEntry {
            label: series.label.clone()?,
            marker: Marker::of(series.style),
            color,
            radius: dot_radius(series.style, series.size),
            width: px(series.size.max(1) as f64).max(1) as u32,
            up: true,
        })
    }

    pub(super) fn square(label: &str, color: RGBColor) -> Self {
        LegendEntry {
            label: label.to_string(),
            marker: Marker::Square,
            color,
            radius: px(7.0),
            width: 1,
            up: true,
        }
    }
}

/// The legend's box: padding, symbol column and row height in pixels.
pub(super) struct LegendLayout {
    pub(super) pad: i32,
    pub(super) symbol: i32,
    pub(super) row: i32,
    pub(super) size: (i32, i32),
}

pub(super) fn legend_layout<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> LegendLayout {
    let style = text_style(LEGEND_FONT);
    let (pad, symbol) = (px(8.0), px(34.0));
    let row = (text_size(area, "Ag", &style).1 as f64 * 1.35).ceil() as i32;
    let widest = entries
        .iter()
        .map(|e| text_size(area, &e.label, &style).0)
        .max()
        .unwrap_or(0);
    LegendLayout {
        pad,
        symbol,
        row,
        size: (
            2 * pad + symbol + widest + px(4.0),
            2 * pad + row * entries.len() as i32,
        ),
    }
}

/// Draws the legend box with its top left corner at pixel `origin` of `area`.
pub(super) fn draw_legend_box<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
    layout: &LegendLayout,
    (x0, y0): (i32, i32),
) -> DrawResult {
    let (w, h) = layout.size;
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    area.draw(&Rectangle::new(
        [(x0, y0), (x0 + w, y0 + h)],
        WHITE.mix(0.9).filled(),
    ))
    .map_err(e)?;
    area.draw(&Rectangle::new(
        [(x0, y0), (x0 + w, y0 + h)],
        RGBColor(90, 90, 90).stroke_width(upx(1.0)),
    ))
    .map_err(e)?;
    let style = text_style(LEGEND_FONT).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, entry) in entries.iter().enumerate() {
        let y = y0 + layout.pad + layout.row * i as i32 + layout.row / 2;
        let x = x0 + layout.pad + layout.symbol / 2;
        draw_marker(
            area,
            entry.marker,
            (x, y),
            entry.radius,
            entry.width,
            entry.color,
            entry.up,
        )?;
        area.draw_text(
            &entry.label,
            &style,
            (x0 + layout.pad + layout.symbol + px(4.0), y),
        )
        .map_err(e)?;
    }
    Ok(())
}

/// Where in a plotting area of `dim` pixels a legend box of `size` pixels covers none of
/// the data `pixels` (relative to the area): the first free place of the upper right,
/// upper left, upper middle, lower right, lower left, lower middle, middle right and middle
/// left corners; `None` if every place covers data.
pub fn free_legend_place(
    dim: (i32, i32),
    size: (i32, i32),
    pixels: &[(i32, i32)],
) -> Option<(i32, i32)> {
    let (w, h) = size;
    let gap = px(6.0);
    if w + 2 * gap > dim.0 || h + 2 * gap > dim.1 {
        return None;
    }
    let (right, bottom) = (dim.0 - w - gap, dim.1 - h - gap);
    let (middle_x, middle_y) = ((dim.0 - w) / 2, (dim.1 - h) / 2);
    let places = [
        (right, gap),
        (gap, gap),
        (middle_x, gap),
        (right, bottom),
        (gap, bottom),
        (middle_x, bottom),
        (right, middle_y),
        (gap, middle_y),
    ];
    // A margin around the box, so that no marker (up to 7 design units across, the
    // off-scale triangles at the plot's edge) touches its border.
    let m = px(10.0);
    places.into_iter().find(|&(x0, y0)| {
        !pixels
            .iter()
            .any(|&(x, y)| (x0 - m..=x0 + w + m).contains(&x) && (y0 - m..=y0 + h + m).contains(&y))
    })
}

/// Where a legend outside the chart goes.
pub(super) enum LegendSpot {
    /// In a column right of the chart.
    Right,
    /// In a band under the chart.
    Below,
}

/// A legend that does not fit inside the plot goes into a column at the right if it is at
/// most this fraction of the figure's width, else into a band below.
const RIGHT_LEGEND_FRACTION: f64 = 0.3;

/// Splits `body` into the chart's area and the area of a legend of `layout` beside it.
#[allow(clippy::type_complexity)]
pub(super) fn split_for_legend<DB: DrawingBackend>(
    body: &DrawingArea<DB, Shift>,
    layout: &LegendLayout,
) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>, LegendSpot) {
    let (w, h) = body.dim_in_pixel();
    let (lw, lh) = layout.size;
    if (lw as f64) <= RIGHT_LEGEND_FRACTION * w as f64 {
        let (chart, legend) = body.split_horizontally(w as i32 - lw - px(16.0));
        (chart, legend, LegendSpot::Right)
    } else {
        let (chart, legend) = body.split_vertically(h as i32 - lh - px(10.0));
        (chart, legend, LegendSpot::Below)
    }
}

/// Draws a legend in the area `split_for_legend` set aside for it.
pub(super) fn draw_outside_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
    layout: &LegendLayout,
    spot: LegendSpot,
) -> DrawResult {
    let (w, h) = area.dim_in_pixel();
    let origin = match spot {
        // Level with the top of the plotting area.
        LegendSpot::Right => (px(4.0), (px(12.0)).min(h as i32 - layout.size.1).max(0)),
        _ => ((w as i32 - layout.size.0).max(0) / 2, px(2.0)),
    };
    draw_legend_box(area, entries, layout, origin)
}

/// A legend in rows under a map or a title: the entries of each row, left to right, as
/// many per row as fit `width` pixels, and the pixel widths of the entries.
struct LegendRows {
    rows: Vec<Vec<usize>>,
    widths: Vec<i32>,
    row_height: i32,
}

/// Gap between the entries of a legend row, and the width of an entry's symbol, in design
/// units.
const ROW_GAP: f64 = 28.0;
const ROW_SYMBOL: f64 = 34.0;

impl LegendRows {
    pub(super) fn new<DB: DrawingBackend>(
        area: &DrawingArea<DB, Shift>,
        entries: &[LegendEntry],
    ) -> Self {
        let style = text_style(LEGEND_FONT);
        let widths: Vec<i32> = (entries.iter())
            .map(|e| px(ROW_SYMBOL + 4.0) + text_size(area, &e.label, &style).0)
            .collect();
        let (w, _) = area.dim_in_pixel();
        let mut rows: Vec<Vec<usize>> = Vec::new();
        let mut used = 0;
        for (i, &width) in widths.iter().enumerate() {
            match rows.last_mut() {
                Some(row) if used + px(ROW_GAP) + width <= w as i32 => {
                    row.push(i);
                    used += px(ROW_GAP) + width;
                }
                _ => {
                    rows.push(vec![i]);
                    used = width;
                }
            }
        }
        let row_height = (text_size(area, "Ag", &style).1 as f64 * 1.35).ceil() as i32;
        LegendRows {
            rows,
            widths,
            row_height,
        }
    }

    /// The height of the legend in pixels, with a margin above and below.
    pub(super) fn height(&self) -> i32 {
        self.rows.len() as i32 * self.row_height + px(12.0)
    }
}

/// The height in pixels of the legend rows of `entries` in the width of `area`.
pub(super) fn legend_row_height<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> i32 {
    LegendRows::new(area, entries).height()
}

/// Draws `entries` side by side in rows, each centred in `area` (a legend under a map or a
/// title).
pub(super) fn draw_legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> DrawResult {
    let layout = LegendRows::new(area, entries);
    let style = text_style(LEGEND_FONT).pos(Pos::new(HPos::Left, VPos::Center));
    let (w, _) = area.dim_in_pixel();
    let symbol = px(ROW_SYMBOL);
    for (r, row) in layout.rows.iter().enumerate() {
        let total: i32 = row.iter().map(|&i| layout.widths[i]).sum::<i32>()
            + px(ROW_GAP) * (row.len() as i32 - 1);
        let mut x = ((w as i32 - total) / 2).max(0);
        let y = px(6.0) + layout.row_height * r as i32 + layout.row_height / 2;
        for &i in row {
            let entry = &entries[i];
            let (radius, line) = (entry.radius, entry.width);
            draw_marker(
                area,
                entry.marker,
                (x + symbol / 2, y),
                radius,
                line,
                entry.color,
                entry.up,
            )?;
            area.draw_text(&entry.label, &style, (x + symbol + px(4.0), y))
                .map_err(|e| e.to_string())?;
            x += layout.widths[i] + px(ROW_GAP);
        }
    }
    Ok(())
}

/// Grey of the off-scale note.
const OFF_SCALE_COLOR: RGBColor = RGBColor(90, 90, 90);

/// The legend entry for the finite points of `series` outside the range of `y` (None if
/// none is): how many and their values.
pub(super) fn off_scale_entry(series: &[Series], y: &Axis) -> Option<LegendEntry> {
    let (lo, hi) = y.bounds();
    let off: Vec<f64> = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(px, py)| px.is_finite() && py.is_finite() && (*py < lo || *py > hi))
        .map(|p| y.scale().to_value(p.1))
        .collect();
    // As the plot draws them: pointing out of its edge (all below: down).
    let above = series
        .iter()
        .flat_map(|s| s.points.iter())
        .any(|(px, py)| px.is_finite() && py.is_finite() && *py > hi);
    let (lo, hi) = finite_range(off.iter().copied())?;
    let values = match lo == hi {
        true => three_significant_digits(lo),
        false => format!(
            "{} to {}",
            three_significant_digits(lo),
            three_significant_digits(hi)
        ),
    };
    let points = if off.len() == 1 { "point" } else { "points" };
    Some(LegendEntry {
        label: format!("{} {points} off scale, y = {values}", off.len()),
        marker: Marker::Triangle,
        color: OFF_SCALE_COLOR,
        radius: px(7.0),
        width: 1,
        up: above,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::axis::Scale;

    fn entry(ys: &[f64]) -> Option<LegendEntry> {
        let points = ys.iter().enumerate().map(|(i, &y)| (i as f64, y)).collect();
        let series = [Series::points("runs", points)];
        off_scale_entry(&series, &Axis::new((0.0, 1.0), Scale::Linear))
    }

    #[test]
    fn the_off_scale_triangle_points_the_way_the_plot_draws_it() {
        assert!(entry(&[0.5, 0.2]).is_none());
        let below = entry(&[0.5, -12.0]).unwrap();
        assert!(!below.up);
        assert_eq!(below.label, "1 point off scale, y = -12");
        assert!(entry(&[0.5, 3.0]).unwrap().up);
        assert!(entry(&[-2.0, 3.0]).unwrap().up);
    }
}
