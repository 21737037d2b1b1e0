//! Heatmaps: values on a rectilinear grid in a colour scale, with a colour bar that marks
//! values beyond its range and a diverging scale's centre, overlays and their legend in a
//! row under the map.

use super::axis::{three_significant_digits, Axis, Scale, MAX_TICKS};
use super::chart::{chart, draw_axes};
use super::colour::{ColourScale, BLACK};
use super::grid::{check_grid, overlay_colors, CellGrid};
use super::legend::{draw_legend_row, legend_row_height, LegendEntry};
use super::range::finite_range;
use super::series::{draw_series, Series};
use super::style::{draw_title, px, text_size, text_style, upx, AXIS_FONT, TICK_FONT};
use super::{DrawResult, Figure, Typeset, DEFAULT_SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;

/// A heatmap of values on a rectilinear grid; `None` (or non-finite) cells stay blank.
/// Its colour bar marks values beyond the colour range (`≥ hi` at the top, `≤ lo` at the
/// bottom, with a triangle in the end colour) and, on a diverging scale, its centre; the
/// overlays' legend is a row under the map.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    /// Caption.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Colour-bar label.
    pub value_label: String,
    /// Cell-centre x values (monotonic).
    pub x: Vec<f64>,
    /// Cell-centre y values (monotonic).
    pub y: Vec<f64>,
    /// Values, row-major: `values[iy * x.len() + ix]`.
    pub values: Vec<Option<f64>>,
    /// Colour range (None: range of the values).
    pub value_range: Option<(f64, f64)>,
    /// How values become colours.
    pub colour_scale: ColourScale,
    /// Series drawn on top (lines, markers for special cells).
    pub overlays: Vec<Series>,
    /// Size in pixels.
    pub size: (u32, u32),
}

impl Heatmap {
    /// A heatmap without overlays.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        value_label: impl Into<String>,
        x: Vec<f64>,
        y: Vec<f64>,
        values: Vec<Option<f64>>,
    ) -> Self {
        Heatmap {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            value_label: value_label.into(),
            x,
            y,
            values,
            value_range: None,
            colour_scale: ColourScale::Sequential,
            overlays: Vec::new(),
            size: DEFAULT_SIZE,
        }
    }

    /// Adds an overlay series.
    pub fn with_overlay(mut self, series: Series) -> Self {
        self.overlays.push(series);
        self
    }

    /// Fixes the colour range.
    pub fn with_value_range(mut self, lo: f64, hi: f64) -> Self {
        self.value_range = Some((lo, hi));
        self
    }

    /// Sets how values become colours.
    pub fn with_colour_scale(mut self, scale: ColourScale) -> Self {
        self.colour_scale = scale;
        self
    }

    fn finite_values(&self) -> impl Iterator<Item = f64> + Clone + '_ {
        self.values
            .iter()
            .flatten()
            .copied()
            .filter(|v| v.is_finite())
    }

    /// The colour range: the fixed one, else the values' (`0 … 1` without values), reaching
    /// the centre of a diverging scale.
    pub fn colour_range(&self) -> (f64, f64) {
        let range = (self.value_range)
            .or_else(|| finite_range(self.finite_values()))
            .unwrap_or((0.0, 1.0));
        let (lo, hi) = self.colour_scale.range(range);
        match hi > lo {
            true => (lo, hi),
            false => (lo - 0.5, hi + 0.5),
        }
    }

    /// The colour bar's ticks and labels, bottom to top: evenly stepped values, the centre
    /// of a diverging scale, and `≤ lo` / `≥ hi` at an end that some value lies beyond.
    pub fn colour_bar_labels(&self) -> Vec<(f64, String)> {
        let (lo, hi) = self.colour_range();
        let axis = Axis::new((lo, hi), Scale::Linear);
        let mut marks = Vec::new();
        if let ColourScale::Diverging { centre } = self.colour_scale {
            marks.push((centre, axis.label(centre)));
        }
        if self.finite_values().any(|v| v < lo) {
            marks.push((lo, format!("≤ {}", three_significant_digits(lo))));
        }
        if self.finite_values().any(|v| v > hi) {
            marks.push((hi, format!("≥ {}", three_significant_digits(hi))));
        }
        let clear = |t: f64| marks.iter().all(|(m, _)| (t - m).abs() > 0.06 * (hi - lo));
        let mut labels: Vec<(f64, String)> = (axis.ticks(MAX_TICKS).into_iter())
            .filter(|&t| clear(t))
            .map(|t| (t, axis.label(t)))
            .collect();
        labels.extend(marks);
        labels.sort_by(|a, b| a.0.total_cmp(&b.0));
        labels
    }
}

/// Strips of colour a colour bar is drawn with.
const COLOUR_BAR_STRIPS: i32 = 256;

/// The colour bar: its strip's width and the gaps around it, in design units.
const BAR_GAP: f64 = 10.0;
const BAR_WIDTH: f64 = 26.0;
const BAR_TICK: f64 = 5.0;

/// The width in pixels of a colour bar with tick `labels` and the `label` beside them.
fn colour_bar_width<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    labels: &[(f64, String)],
    label: &str,
) -> i32 {
    let widest = (labels.iter())
        .map(|(_, text)| text_size(area, text, &text_style(TICK_FONT)).0)
        .max()
        .unwrap_or(0);
    let label_height = text_size(area, label, &text_style(AXIS_FONT)).1;
    px(BAR_GAP + BAR_WIDTH + BAR_TICK + 4.0) + widest + px(14.0) + label_height + px(BAR_GAP)
}

/// Draws a colour bar on `area` between pixel rows `top` and `bottom` (relative to it):
/// the strip of `scale` over `range`, a triangle at an end labelled `≥`/`≤`, the ticks
/// `labels` and the rotated `label`.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (top, bottom): (i32, i32),
    (scale, range): (ColourScale, (f64, f64)),
    labels: &[(f64, String)],
    label: &str,
) -> DrawResult {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (x0, x1) = (px(BAR_GAP), px(BAR_GAP + BAR_WIDTH));
    let (lo, hi) = range;
    let row = |v: f64| bottom as f64 - (v - lo) / (hi - lo) * (bottom - top) as f64;
    // At most `COLOUR_BAR_STRIPS` strips (a few pixels each on a print-size figure).
    let strips = (bottom - top).clamp(1, COLOUR_BAR_STRIPS);
    let edge = |i: i32| bottom - ((bottom - top) as f64 * i as f64 / strips as f64).round() as i32;
    for i in 0..strips {
        let v = lo + (hi - lo) * (i as f64 + 0.5) / strips as f64;
        let fill = scale.colour(v, range).filled();
        area.draw(&Rectangle::new([(x0, edge(i + 1)), (x1, edge(i))], fill))
            .map_err(e)?;
    }
    area.draw(&Rectangle::new(
        [(x0, top), (x1, bottom)],
        BLACK.stroke_width(upx(1.0)),
    ))
    .map_err(e)?;
    // A triangle beyond each end that values pass, in the end's colour.
    let (half, tip) = ((x1 - x0) / 2, px(14.0));
    for (text, (edge, out, value)) in [("≥", (top, -1, hi)), ("≤", (bottom, 1, lo))] {
        if labels.iter().any(|(_, l)| l.starts_with(text)) {
            let points = vec![(x0, edge), (x1, edge), (x0 + half, edge + out * tip)];
            area.draw(&Polygon::new(
                points.clone(),
                scale.colour(value, range).filled(),
            ))
            .map_err(e)?;
            let outline: Vec<(i32, i32)> = points.iter().chain(&points[..1]).copied().collect();
            area.draw(&PathElement::new(outline, BLACK.stroke_width(upx(1.0))))
                .map_err(e)?;
        }
    }
    let style = text_style(TICK_FONT).pos(Pos::new(HPos::Left, VPos::Center));
    let mut widest = 0;
    for (value, text) in labels {
        let y = row(*value).round() as i32;
        let tick = vec![(x1, y), (x1 + px(BAR_TICK), y)];
        area.draw(&PathElement::new(tick, BLACK.stroke_width(upx(1.0))))
            .map_err(e)?;
        area.draw_text(text, &style, (x1 + px(BAR_TICK + 4.0), y))
            .map_err(e)?;
        widest = widest.max(text_size(area, text, &style).0);
    }
    let rotated = text_style(AXIS_FONT)
        .pos(Pos::new(HPos::Center, VPos::Top))
        .transform(FontTransform::Rotate270);
    let x = x1 + px(BAR_TICK + 4.0) + widest + px(14.0);
    area.draw_text(label, &rotated, (x, (top + bottom) / 2))
        .map_err(e)
}

impl Figure for Heatmap {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<Typeset<DB>, Shift>) -> DrawResult {
        let (nx, ny) = (self.x.len(), self.y.len());
        check_grid("heatmap", "values", nx, ny, self.values.len())?;
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let body = draw_title(root, &self.title)?;
        let colors = overlay_colors(&self.overlays, 3);
        let entries: Vec<LegendEntry> = (self.overlays.iter().zip(&colors))
            .filter_map(|(s, c)| LegendEntry::of(s, *c))
            .collect();
        // The overlays' legend in a row under the map (inside, it would hide cells).
        let (body, legend) = match entries.is_empty() {
            true => (body, None),
            false => {
                let (_, h) = body.dim_in_pixel();
                let height = legend_row_height(&body, &entries);
                let (map, row) = body.split_vertically(h as i32 - height);
                (map, Some(row))
            }
        };
        let labels = self.colour_bar_labels();
        let (w, _) = body.dim_in_pixel();
        let bar_width = colour_bar_width(&body, &labels, &self.value_label);
        let (main, bar) = body.split_horizontally(w as i32 - bar_width);
        let grid = CellGrid::new(&self.x, &self.y);
        let range = self.colour_range();
        let (x_axis, y_axis) = grid.axes();
        let y_range = y_axis.bounds();
        let mut chart = chart(&main, x_axis, y_axis)?;
        draw_axes(&mut chart, &self.x_label, &self.y_label, false)?;
        let value = |v: &Option<f64>| v.filter(|v| v.is_finite());
        let cells = grid.cells().filter_map(|(k, rect)| {
            let v = value(&self.values[k])?;
            Some(Rectangle::new(
                rect,
                self.colour_scale.colour(v, range).filled(),
            ))
        });
        chart.draw_series(cells).map_err(|e| e.to_string())?;
        for (series, color) in self.overlays.iter().zip(&colors) {
            draw_series(&mut chart, series, *color, y_range)?;
        }
        if let Some(row) = legend {
            draw_legend_row(&row, &entries)?;
        }
        // The colour bar, level with the map.
        let (_, rows) = chart.plotting_area().get_pixel_range();
        let base = bar.get_base_pixel().1;
        draw_colour_bar(
            &bar,
            (rows.start - base, rows.end - base),
            (self.colour_scale, range),
            &labels,
            &self.value_label,
        )
    }
}
