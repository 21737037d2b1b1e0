//! Reusable figures: line plots, heatmaps (with blank cells and a colour bar) and category
//! maps, written as PNG and SVG (plotters), atomically, in one style:
//!
//! - print resolution: 2400 × 1600 pixels by default (8 × 5⅓ in at 300 dpi), with fonts,
//!   line widths and markers scaled to match ([`SCALE`]);
//! - titles wrapped to the figure's width (never cut at the edge), axis labels in words
//!   with SI units in parentheses, e.g. `mean speed (m/s)`;
//! - tick labels without trailing zeros (`10`, not `10.0`) and never `-0`;
//! - y ranges robust to outliers: a few points far outside the rest are drawn as
//!   triangles at the edge of the plot, with a legend entry giving their values,
//!   instead of flattening every other point;
//! - legends whose markers are the ones drawn, placed inside the plot only where they
//!   cover no data, else beside the plot.
//!
//! ```no_run
//! use hopsim_studies::plot::{Heatmap, LinePlot, Series, write_png_and_svg};
//! let plot = LinePlot::new("speed", "hop", "speed (m/s)")
//!     .with_series(Series::line("run 1", vec![(0.0, 0.1), (1.0, 0.2)]));
//! write_png_and_svg(&plot, std::path::Path::new("out/speed")).unwrap(); // out/speed.png + .svg
//! let map = Heatmap::new("cost", "x (m)", "y (m)", "cost of transport", vec![0.0, 1.0],
//!     vec![0.0, 1.0], vec![Some(1.0), None, Some(2.0), Some(3.0)]);
//! write_png_and_svg(&map, std::path::Path::new("out/cost")).unwrap();
//! ```
//!
//! A new kind of figure implements [`Figure`] (drawing on any plotters backend) and gets
//! PNG/SVG output from [`write_png_and_svg`] and [`stage_png_and_svg`].

mod axis;
mod colour;
mod font;

pub use axis::{three_significant_digits, tick_label, Axis, Scale, MAX_TICKS};
pub use colour::{blue_white_red, on_white, viridis, ColourScale, RGBColor, BLACK, PALETTE};
pub use font::Typeset;

use crate::error::{Result, StudyError};
use hopsim_io::{AtomicPath, IoError};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;
use std::path::{Path, PathBuf};

/// Default figure size in pixels: 8 × 5⅓ inches at 300 dpi.
pub const DEFAULT_SIZE: (u32, u32) = (2400, 1600);

/// Pixels per design unit: font sizes, line widths, marker sizes and margins are given for
/// a 960-pixel-wide figure and multiplied by this factor.
pub const SCALE: f64 = DEFAULT_SIZE.0 as f64 / 960.0;

/// `v` design units in pixels.
fn px(v: f64) -> i32 {
    (v * SCALE).round() as i32
}

/// `v` design units in pixels, unsigned.
fn upx(v: f64) -> u32 {
    px(v).max(0) as u32
}

/// Font sizes in design units: title, axis descriptions, tick labels and legend.
const TITLE_FONT: f64 = 22.0;
const AXIS_FONT: f64 = 17.0;
const TICK_FONT: f64 = 15.0;
const LEGEND_FONT: f64 = 15.0;

/// Error text of a drawing step.
pub type DrawResult = std::result::Result<(), String>;

/// Something that can draw itself on any plotters backend.
pub trait Figure {
    /// Figure size in pixels.
    fn size(&self) -> (u32, u32) {
        DEFAULT_SIZE
    }
    /// Draws the figure on `root` (already sized; not yet filled), whose text is set in
    /// the embedded font ([`Typeset`]).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<Typeset<DB>, Shift>) -> DrawResult;
}
/// Draws `figure` as a PNG file into a temporary file for `path`, committed by the caller.
fn stage_png<F: Figure>(figure: &F, path: &Path) -> Result<AtomicPath> {
    let output = AtomicPath::create(path)?;
    {
        let backend = BitMapBackend::new(output.temporary(), figure.size());
        let root = Typeset::raster(backend).into_drawing_area();
        figure
            .draw(&root)
            .and_then(|()| root.present().map_err(|e| e.to_string()))
            .map_err(|message| plot_error(path, message))?;
    }
    Ok(output)
}

/// Draws `figure` as an SVG file into a temporary file for `path`, committed by the caller.
fn stage_svg<F: Figure>(figure: &F, path: &Path) -> Result<AtomicPath> {
    let mut svg = String::new();
    {
        let backend = SVGBackend::with_string(&mut svg, figure.size());
        let root = Typeset::vector(backend).into_drawing_area();
        figure
            .draw(&root)
            .and_then(|()| root.present().map_err(|e| e.to_string()))
            .map_err(|message| plot_error(path, message))?;
    }
    let output = AtomicPath::create(path)?;
    std::fs::write(output.temporary(), svg).map_err(|e| IoError::new(path, e))?;
    Ok(output)
}

fn plot_error(path: &Path, message: String) -> StudyError {
    StudyError::Plot {
        path: path.to_path_buf(),
        message,
    }
}

/// The files of the figure `stem`: `stem.png` and `stem.svg`.
pub fn figure_paths(stem: &Path) -> [PathBuf; 2] {
    ["png", "svg"].map(|extension| stem.with_extension(extension))
}

/// Draws `stem.png` and `stem.svg` into temporary files, committed by the caller (so that a
/// set of files appears together, [`crate::write_files`]).
pub fn stage_png_and_svg<F: Figure>(figure: &F, stem: &Path) -> Result<Vec<AtomicPath>> {
    let [png, svg] = figure_paths(stem);
    Ok(vec![stage_png(figure, &png)?, stage_svg(figure, &svg)?])
}

/// Writes `stem.png` and `stem.svg` (atomically, both or neither); returns both paths.
pub fn write_png_and_svg<F: Figure>(figure: &F, stem: &Path) -> Result<Vec<PathBuf>> {
    commit_all(stage_png_and_svg(figure, stem)?)
}

/// Commits every staged file, in order; returns their paths.
pub fn commit_all(staged: Vec<AtomicPath>) -> Result<Vec<PathBuf>> {
    staged
        .into_iter()
        .map(|output| {
            let path = output.path().to_path_buf();
            output.commit()?;
            Ok(path)
        })
        .collect()
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A polyline through the points (breaks at non-finite points).
    Line,
    /// Filled dots.
    Points,
    /// Crosses (e.g. to mark special cells on a heatmap).
    Crosses,
    /// Open circles (e.g. to mark other special cells, beside crosses).
    Rings,
    /// A polyline with dots.
    LineAndPoints,
}

/// One data series of a [`LinePlot`] or an overlay of a map.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry (None: not in the legend).
    pub label: Option<String>,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: SeriesStyle,
    /// Colour (None: next colour of the palette).
    pub color: Option<RGBColor>,
    /// Dot radius or line width in design units (pixels of a 960-pixel-wide figure,
    /// scaled by [`SCALE`]).
    pub size: u32,
    /// Whether the series' points set the automatic y range (false: points outside the
    /// range of the other series are drawn at the edge, e.g. results that did not
    /// converge).
    pub sets_range: bool,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: Some(label.into()),
            points,
            style: SeriesStyle::Line,
            color: None,
            size: 2,
            sets_range: true,
        }
    }

    /// A scatter series.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: Some(label.into()),
            points,
            style: SeriesStyle::Points,
            color: None,
            size: 3,
            sets_range: true,
        }
    }

    /// Sets the style.
    pub fn style(mut self, style: SeriesStyle) -> Self {
        self.style = style;
        self
    }

    /// Sets the colour.
    pub fn color(mut self, color: RGBColor) -> Self {
        self.color = Some(color);
        self
    }

    /// Sets the dot radius / line width (design units).
    pub fn size(mut self, size: u32) -> Self {
        self.size = size;
        self
    }

    /// Leaves the series out of the automatic y range ([`Series::sets_range`]).
    pub fn without_range(mut self) -> Self {
        self.sets_range = false;
        self
    }

    /// Removes the legend entry.
    pub fn unlabelled(mut self) -> Self {
        self.label = None;
        self
    }
}

fn finite_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    (lo <= hi).then_some((lo, hi))
}

fn padded(range: Option<(f64, f64)>, fraction: f64) -> (f64, f64) {
    match range {
        None => (0.0, 1.0),
        Some((lo, hi)) if hi - lo <= f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) => {
            let d = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
            (lo - d, hi + d)
        }
        Some((lo, hi)) => {
            let d = fraction * (hi - lo);
            (lo - d, hi + d)
        }
    }
}

/// Tukey's fences are this many interquartile ranges beyond the quartiles.
const FENCE_IQRS: f64 = 3.0;

/// At most this fraction of the points may lie outside the fences to be drawn as outliers
/// (more are data, and the range covers them).
const MAX_OUTLIER_FRACTION: f64 = 0.05;

/// Tukey's outer fences of the finite `values`: the quartiles ∓ [`FENCE_IQRS`]
/// interquartile ranges (None without finite values; the full range if the quartiles
/// coincide).
fn tukey_fences(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut v: Vec<f64> = values.filter(|v| v.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let full = (*v.first()?, *v.last()?);
    let quantile = |q: f64| {
        let pos = q * (v.len() - 1) as f64;
        let (i, f) = (pos.floor() as usize, pos.fract());
        v[i] + f * (v[(i + 1).min(v.len() - 1)] - v[i])
    };
    let (q1, q3) = (quantile(0.25), quantile(0.75));
    let iqr = q3 - q1;
    Some(match iqr > 0.0 {
        true => (q1 - FENCE_IQRS * iqr, q3 + FENCE_IQRS * iqr),
        false => full,
    })
}

/// The range of the finite `values` that a few far outliers do not stretch. Outliers lie
/// outside Tukey's outer fences ([`FENCE_IQRS`] interquartile ranges beyond the quartiles)
/// and farther from the values inside them than those values span; if more than
/// [`MAX_OUTLIER_FRACTION`] of the values lie outside the fences, none is an outlier.
/// `None` without finite values.
pub fn robust_range(values: impl Iterator<Item = f64> + Clone) -> Option<(f64, f64)> {
    let fence = tukey_fences(values.clone())?;
    let finite = || values.clone().filter(|v| v.is_finite());
    let inside = || finite().filter(|x| *x >= fence.0 && *x <= fence.1);
    let (n, outside) = (finite().count(), finite().count() - inside().count());
    if outside as f64 > MAX_OUTLIER_FRACTION * n as f64 {
        return finite_range(finite());
    }
    // Only values at least the inner values' span away from them are outliers: a peak
    // just above the rest is data.
    let (lo, hi) = finite_range(inside())?;
    let span = hi - lo;
    finite_range(finite().filter(|x| *x >= lo - span && *x <= hi + span))
}

/// The automatic y range of `series`: the [`robust_range`] of the series that set the
/// range, widened to the points of the others that lie within their Tukey fences (the
/// robust range of all points if no series sets it).
fn auto_y_range(series: &[Series]) -> Option<(f64, f64)> {
    let ys = |sets: bool| {
        (series.iter().filter(move |s| s.sets_range == sets))
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0.is_finite())
            .map(|p| p.1)
    };
    let Some(base) = robust_range(ys(true)) else {
        return robust_range(ys(false));
    };
    let fence = tukey_fences(ys(true)).unwrap_or(base);
    let extra = finite_range(ys(false).filter(|y| *y >= fence.0 && *y <= fence.1));
    Some(match extra {
        Some((lo, hi)) => (base.0.min(lo), base.1.max(hi)),
        None => base,
    })
}

/// The text style of `size` design units in the embedded font.
fn text_style(size: f64) -> TextStyle<'static> {
    TextStyle::from((font::FAMILY, px(size) as f64).into_font())
}

/// The pixel size of `text` in `style` on `area` (a generous estimate if the backend cannot
/// measure it).
fn text_size<DB: DrawingBackend>(
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
fn fitting_size<DB: DrawingBackend>(
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
fn draw_title<DB: DrawingBackend>(
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

/// A chart on two [`Axis`], as every figure here draws.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// The chart of a figure on `area` (below its title), with room for the axis labels.
fn chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x: Axis,
    y: Axis,
) -> std::result::Result<Chart<'a, DB>, String> {
    ChartBuilder::on(area)
        .margin(upx(12.0))
        .margin_right(upx(28.0))
        .x_label_area_size(upx(50.0))
        .y_label_area_size(upx(78.0))
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())
}

/// The axes of `chart`.
fn axes<DB: DrawingBackend>(chart: &Chart<'_, DB>) -> (Axis, Axis) {
    let spec = chart.as_coord_spec();
    (*spec.x_spec(), *spec.y_spec())
}

/// Draws the axes with their labels (shrunk to fit the axis if long) and their ticks
/// ([`Axis::label`]); `grid` adds light grid lines (maps cover them).
fn draw_axes<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    x_label: &str,
    y_label: &str,
    grid: bool,
) -> DrawResult {
    let (x_axis, y_axis) = axes(chart);
    let area = chart.plotting_area().strip_coord_spec();
    let (w, h) = area.dim_in_pixel();
    let axis_size =
        |label: &str, room: u32| fitting_size(&area, &[label.to_string()], AXIS_FONT, room as i32);
    let (x_size, y_size) = (axis_size(x_label, w), axis_size(y_label, h));
    let x_format = |v: &f64| x_axis.label(*v);
    let y_format = |v: &f64| y_axis.label(*v);
    let mut mesh = chart.configure_mesh();
    if grid {
        mesh.light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(215, 215, 215).stroke_width(upx(1.0)));
    } else {
        mesh.disable_mesh();
    }
    mesh.x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(text_style(TICK_FONT))
        .x_label_style(text_style(TICK_FONT))
        .axis_desc_style(text_style(x_size.min(y_size)))
        .axis_style(BLACK.stroke_width(upx(1.0)))
        .set_all_tick_mark_size(upx(5.0))
        .draw()
        .map_err(|e| e.to_string())
}

/// The marker a series or a legend entry is drawn with.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Marker {
    Line,
    Dot,
    LineAndDot,
    Cross,
    Ring,
    /// Off-scale points: a triangle at the plot's edge, pointing out of it.
    Triangle,
    /// A map's cell.
    Square,
}

impl Marker {
    fn of(style: SeriesStyle) -> Self {
        match style {
            SeriesStyle::Line => Marker::Line,
            SeriesStyle::Points => Marker::Dot,
            SeriesStyle::Crosses => Marker::Cross,
            SeriesStyle::Rings => Marker::Ring,
            SeriesStyle::LineAndPoints => Marker::LineAndDot,
        }
    }
}

/// The radius in pixels of a dot of a series of `style` and `size` (design units).
fn dot_radius(style: SeriesStyle, size: u32) -> i32 {
    let size = size.max(1) as f64;
    match style {
        SeriesStyle::LineAndPoints => px(size + 1.0),
        SeriesStyle::Crosses => px(size.max(3.0)),
        SeriesStyle::Rings => px(size.max(3.0) + 2.0),
        _ => px(size),
    }
}

/// Draws one marker centred at pixel `(x, y)` of `area` (`up`: a triangle points up).
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    marker: Marker,
    (x, y): (i32, i32),
    radius: i32,
    width: u32,
    color: RGBColor,
    up: bool,
) -> DrawResult {
    let stroke = color.stroke_width(width.max(1));
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    match marker {
        Marker::Dot => area
            .draw(&Circle::new((x, y), radius, color.filled()))
            .map_err(e),
        Marker::Ring => {
            // A thin line, so that a cross fits inside the ring.
            let thin = color.stroke_width(upx(1.2));
            area.draw(&Circle::new((x, y), radius, thin)).map_err(e)
        }
        Marker::Cross => {
            let r = radius;
            area.draw(&PathElement::new(
                vec![(x - r, y - r), (x + r, y + r)],
                stroke,
            ))
            .map_err(e)?;
            area.draw(&PathElement::new(
                vec![(x - r, y + r), (x + r, y - r)],
                stroke,
            ))
            .map_err(e)
        }
        Marker::Triangle => {
            let (r, s) = (radius, if up { -1 } else { 1 });
            let points = vec![(x, y + s * r), (x - r, y - s * r), (x + r, y - s * r)];
            area.draw(&Polygon::new(points, color.filled())).map_err(e)
        }
        Marker::Square => area
            .draw(&Rectangle::new(
                [(x - radius, y - radius), (x + radius, y + radius)],
                color.filled(),
            ))
            .map_err(e),
        Marker::Line | Marker::LineAndDot => {
            let half = px(12.0);
            area.draw(&PathElement::new(
                vec![(x - half, y), (x + half, y)],
                stroke,
            ))
            .map_err(e)?;
            if marker == Marker::LineAndDot {
                area.draw(&Circle::new((x, y), radius, color.filled()))
                    .map_err(e)?;
            }
            Ok(())
        }
    }
}

/// One row of a legend.
#[derive(Debug, Clone)]
struct LegendEntry {
    label: String,
    marker: Marker,
    color: RGBColor,
    /// Marker radius and line width in pixels.
    radius: i32,
    width: u32,
}

impl LegendEntry {
    fn of(series: &Series, color: RGBColor) -> Option<Self> {
        Some(LegendEntry {
            label: series.label.clone()?,
            marker: Marker::of(series.style),
            color,
            radius: dot_radius(series.style, series.size),
            width: px(series.size.max(1) as f64).max(1) as u32,
        })
    }

    fn square(label: &str, color: RGBColor) -> Self {
        LegendEntry {
            label: label.to_string(),
            marker: Marker::Square,
            color,
            radius: px(7.0),
            width: 1,
        }
    }
}

/// The legend's box: padding, symbol column and row height in pixels.
struct LegendLayout {
    pad: i32,
    symbol: i32,
    row: i32,
    size: (i32, i32),
}

fn legend_layout<DB: DrawingBackend>(
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
fn draw_legend_box<DB: DrawingBackend>(
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
            true,
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
enum LegendSpot {
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
fn split_for_legend<DB: DrawingBackend>(
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
fn draw_outside_legend<DB: DrawingBackend>(
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
    fn new<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[LegendEntry]) -> Self {
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
    fn height(&self) -> i32 {
        self.rows.len() as i32 * self.row_height + px(12.0)
    }
}

/// The height in pixels of the legend rows of `entries` in the width of `area`.
fn legend_row_height<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> i32 {
    LegendRows::new(area, entries).height()
}

/// Draws `entries` side by side in rows, each centred in `area` (a legend under a map or a
/// title).
fn draw_legend_row<DB: DrawingBackend>(
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
                true,
            )?;
            area.draw_text(&entry.label, &style, (x + symbol + px(4.0), y))
                .map_err(|e| e.to_string())?;
            x += layout.widths[i] + px(ROW_GAP);
        }
    }
    Ok(())
}

/// Pixels (relative to the plotting area) that the data of `series` cover: every point
/// (off-scale ones at the edge of `y_range`), and points along the lines every few pixels.
fn data_pixels<DB: DrawingBackend>(
    chart: &Chart<'_, DB>,
    series: &[Series],
    y_range: (f64, f64),
) -> Vec<(i32, i32)> {
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let to_pixel = |p: &(f64, f64)| {
        let (x, y) = chart.backend_coord(&(p.0, p.1.clamp(y_range.0, y_range.1)));
        (x - xs.start, y - ys.start)
    };
    let step = px(3.0).max(1) as f64;
    let mut pixels = Vec::new();
    for s in series {
        let finite: Vec<(i32, i32)> = s
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(to_pixel)
            .collect();
        pixels.extend(&finite);
        if matches!(s.style, SeriesStyle::Line | SeriesStyle::LineAndPoints) {
            for w in finite.windows(2) {
                let (a, b) = (w[0], w[1]);
                let d = ((b.0 - a.0) as f64).hypot((b.1 - a.1) as f64);
                let n = (d / step).ceil() as i32;
                for k in 1..n {
                    let t = k as f64 / n as f64;
                    pixels.push((
                        a.0 + (t * (b.0 - a.0) as f64) as i32,
                        a.1 + (t * (b.1 - a.1) as f64) as i32,
                    ));
                }
            }
        }
    }
    pixels
}

/// Checks that the `figure` has `len = nx × ny > 0` `cells`.
fn check_grid(figure: &str, cells: &str, nx: usize, ny: usize, len: usize) -> DrawResult {
    if nx == 0 || ny == 0 || len != nx * ny {
        return Err(format!(
            "{figure} needs {nx}×{ny} = {} {cells}, got {len}",
            nx * ny
        ));
    }
    Ok(())
}

/// Draws `series` on `chart`; points whose y lies outside `y_range` are drawn as triangles
/// at the edge they lie beyond (lines break there).
fn draw_series<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    series: &Series,
    color: RGBColor,
    y_range: (f64, f64),
) -> DrawResult {
    let size = series.size.max(1);
    let width = px(size as f64).max(1) as u32;
    let inside = |y: f64| y >= y_range.0 && y <= y_range.1;
    if matches!(series.style, SeriesStyle::Line | SeriesStyle::LineAndPoints) {
        // Break the polyline at non-finite and off-scale points.
        let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for &(x, y) in &series.points {
            if x.is_finite() && y.is_finite() && inside(y) {
                if let Some(segment) = segments.last_mut() {
                    segment.push((x, y));
                }
            } else if !segments.last().is_some_and(Vec::is_empty) {
                segments.push(Vec::new());
            }
        }
        for segment in segments.into_iter().filter(|s| !s.is_empty()) {
            chart
                .draw_series(LineSeries::new(segment, color.stroke_width(width)))
                .map_err(|e| e.to_string())?;
        }
    }
    let area = chart.plotting_area().strip_coord_spec();
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let radius = dot_radius(series.style, size);
    let marker = Marker::of(series.style);
    for &(x, y) in &series.points {
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        let (mut px_x, mut px_y) = chart.backend_coord(&(x, y.clamp(y_range.0, y_range.1)));
        px_x -= xs.start;
        px_y -= ys.start;
        if !inside(y) {
            draw_marker(
                &area,
                Marker::Triangle,
                (px_x, px_y),
                px(7.0),
                1,
                color,
                y > y_range.1,
            )?;
        } else if matches!(
            marker,
            Marker::Dot | Marker::LineAndDot | Marker::Cross | Marker::Ring
        ) {
            let marker = if marker == Marker::LineAndDot {
                Marker::Dot
            } else {
                marker
            };
            draw_marker(&area, marker, (px_x, px_y), radius, width, color, true)?;
        }
    }
    Ok(())
}

/// Grey of the off-scale note.
const OFF_SCALE_COLOR: RGBColor = RGBColor(90, 90, 90);

/// The legend entry for the finite points of `series` outside the range of `y` (None if
/// none is): how many and their values.
fn off_scale_entry(series: &[Series], y: &Axis) -> Option<LegendEntry> {
    let (lo, hi) = y.bounds();
    let off: Vec<f64> = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(px, py)| px.is_finite() && py.is_finite() && (*py < lo || *py > hi))
        .map(|p| y.scale().to_value(p.1))
        .collect();
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
    })
}

/// A shaded stretch of the x axis behind the data (e.g. the flight phase of a cycle).
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// Legend entry (None: not in the legend).
    pub label: Option<String>,
    /// Its ends, in x.
    pub from: f64,
    pub to: f64,
    /// Its colour, drawn translucent.
    pub color: RGBColor,
    /// Its opacity.
    pub opacity: f64,
}

/// Default opacity of a [`Band`], and of its legend entry.
const BAND_OPACITY: f64 = 0.15;

impl Band {
    /// A band from `from` to `to` in `color`, [`BAND_OPACITY`] opaque.
    pub fn new(label: impl Into<String>, from: f64, to: f64, color: RGBColor) -> Self {
        Band {
            label: Some(label.into()),
            from,
            to,
            color,
            opacity: BAND_OPACITY,
        }
    }

    /// Sets the opacity (e.g. lower for bands that overlap).
    pub fn opacity(mut self, opacity: f64) -> Self {
        self.opacity = opacity;
        self
    }
}

/// Draws `bands` (in chart coordinates) over the whole height of `chart`.
fn draw_bands<DB: DrawingBackend>(chart: &mut Chart<'_, DB>, bands: &[Band]) -> DrawResult {
    let (lo, hi) = axes(chart).1.bounds();
    let rects = (bands.iter())
        .map(|b| Rectangle::new([(b.from, lo), (b.to, hi)], b.color.mix(b.opacity).filled()));
    chart
        .draw_series(rects)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// Draws a chart of `series` (colours `colors`) over `bands`, with axes and the legend
/// `entries`, on `body`: the legend inside the plotting area where it covers no data, else
/// beside it.
#[allow(clippy::too_many_arguments)]
fn draw_line_chart<DB: DrawingBackend>(
    body: &DrawingArea<DB, Shift>,
    (x_label, y_label): (&str, &str),
    series: &[Series],
    colors: &[RGBColor],
    bands: &[Band],
    (x, y): (Axis, Axis),
    entries: &[LegendEntry],
) -> DrawResult {
    let layout = legend_layout(body, entries);
    let y_range = y.bounds();
    let place = match entries.is_empty() {
        true => None,
        false => {
            let trial = chart(body, x, y)?;
            let (w, h) = trial.plotting_area().dim_in_pixel();
            let pixels = data_pixels(&trial, series, y_range);
            free_legend_place((w as i32, h as i32), layout.size, &pixels)
        }
    };
    let (chart_area, outside) = match (entries.is_empty(), place) {
        (false, None) => {
            let (chart_area, legend_area, spot) = split_for_legend(body, &layout);
            (chart_area, Some((legend_area, spot)))
        }
        _ => (body.clone(), None),
    };
    let mut chart = chart(&chart_area, x, y)?;
    draw_bands(&mut chart, bands)?;
    draw_axes(&mut chart, x_label, y_label, true)?;
    for (s, color) in series.iter().zip(colors) {
        draw_series(&mut chart, s, *color, y_range)?;
    }
    match (place, outside) {
        (Some(place), _) if !entries.is_empty() => {
            let area = chart.plotting_area().strip_coord_spec();
            draw_legend_box(&area, entries, &layout, place)
        }
        (_, Some((area, spot))) => draw_outside_legend(&area, entries, &layout, spot),
        _ => Ok(()),
    }
}

/// A 2-D line / scatter plot with a legend.
#[derive(Debug, Clone, PartialEq)]
pub struct LinePlot {
    /// Caption.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Data.
    pub series: Vec<Series>,
    /// Shaded stretches of x behind the data.
    pub bands: Vec<Band>,
    /// x range, in values (None: data range with 3 % padding).
    pub x_range: Option<(f64, f64)>,
    /// y range, in values (None: data range with 5 % padding).
    pub y_range: Option<(f64, f64)>,
    /// Size in pixels.
    pub size: (u32, u32),
    /// How the x axis maps and ticks (on a logarithmic axis points with `x ≤ 0` are left out).
    pub x_scale: Scale,
    /// How the y axis maps and ticks (on a logarithmic axis points with `y ≤ 0` are left out).
    pub y_scale: Scale,
}

impl LinePlot {
    /// An empty plot.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        LinePlot {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            bands: Vec::new(),
            x_range: None,
            y_range: None,
            size: DEFAULT_SIZE,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
        }
    }

    /// Sets how the x axis maps and ticks.
    pub fn with_x_scale(mut self, scale: Scale) -> Self {
        self.x_scale = scale;
        self
    }

    /// Sets how the y axis maps and ticks.
    pub fn with_y_scale(mut self, scale: Scale) -> Self {
        self.y_scale = scale;
        self
    }

    /// Adds a series.
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a shaded band.
    pub fn with_band(mut self, band: Band) -> Self {
        self.bands.push(band);
        self
    }

    /// Fixes the x range.
    pub fn with_x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Fixes the y range.
    pub fn with_y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// The series in chart coordinates: points outside a logarithmic x axis left out,
    /// outside a logarithmic y axis non-finite (a break in a line).
    fn chart_series(&self) -> Vec<Series> {
        let (sx, sy) = (self.x_scale, self.y_scale);
        (self.series.iter())
            .map(|s| Series {
                points: (s.points.iter())
                    .filter(|p| sx != Scale::Log || p.0 > 0.0)
                    .map(|&(x, y)| (sx.to_chart(x), sy.to_chart(y)))
                    .collect(),
                ..s.clone()
            })
            .collect()
    }

    /// The axes of the chart of `series` (chart coordinates).
    fn axes(&self, series: &[Series]) -> (Axis, Axis) {
        let to_chart =
            |scale: Scale, (lo, hi): (f64, f64)| (scale.to_chart(lo), scale.to_chart(hi));
        let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
        let x_range = match self.x_range {
            Some(range) => to_chart(self.x_scale, range),
            None => padded(finite_range(xs), 0.03),
        };
        let y_range = match self.y_range {
            Some(range) => to_chart(self.y_scale, range),
            None => padded(auto_y_range(series), 0.05),
        };
        (
            Axis::new(x_range, self.x_scale),
            Axis::new(y_range, self.y_scale),
        )
    }
}

impl LinePlot {
    /// The legend entries of the bands and series (in chart coordinates, on the axis `y`)
    /// and of the points off its scale.
    fn legend_entries(&self, series: &[Series], colors: &[RGBColor], y: &Axis) -> Vec<LegendEntry> {
        let mut entries: Vec<LegendEntry> = (series.iter().zip(colors))
            .filter_map(|(s, c)| LegendEntry::of(s, *c))
            .collect();
        entries.extend(self.bands.iter().filter_map(|b| {
            let label = b.label.as_deref()?;
            Some(LegendEntry::square(label, on_white(b.color, BAND_OPACITY)))
        }));
        entries.extend(off_scale_entry(series, y));
        entries
    }

    /// Draws the plot on `root`, with its own legend or (`own_legend = false`, a panel of
    /// a stack with one legend) without.
    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        own_legend: bool,
    ) -> DrawResult {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let series = self.chart_series();
        let (x, y) = self.axes(&series);
        let bands: Vec<Band> = (self.bands.iter())
            .map(|b| Band {
                from: self.x_scale.to_chart(b.from),
                to: self.x_scale.to_chart(b.to),
                ..b.clone()
            })
            .collect();
        let colors: Vec<RGBColor> = (series.iter().enumerate())
            .map(|(i, s)| s.color.unwrap_or(PALETTE[i % PALETTE.len()]))
            .collect();
        let entries = match own_legend {
            true => self.legend_entries(&series, &colors, &y),
            false => Vec::new(),
        };
        let body = draw_title(root, &self.title)?;
        draw_line_chart(
            &body,
            (&self.x_label, &self.y_label),
            &series,
            &colors,
            &bands,
            (x, y),
            &entries,
        )
    }
}

impl Figure for LinePlot {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<Typeset<DB>, Shift>) -> DrawResult {
        self.draw_on(root, true)
    }
}

/// Line plots stacked vertically under one title (e.g. `x`, `y` and `φ` of a gait over one
/// cycle); each panel keeps its own axes and labels, and its own legend unless the stack
/// has one legend for all, a row under the title (panels sharing their series, whose
/// plotting areas then line up).
#[derive(Debug, Clone, PartialEq)]
pub struct PlotStack {
    /// Caption above all panels.
    pub title: String,
    /// The panels, top to bottom.
    pub panels: Vec<LinePlot>,
    /// One legend for all panels: every distinct entry of theirs, under the title.
    pub shared_legend: bool,
    /// Size in pixels.
    pub size: (u32, u32),
}

impl PlotStack {
    /// Panels of `DEFAULT_SIZE.1 / 2` pixels each (at least the default height).
    pub fn new(title: impl Into<String>, panels: Vec<LinePlot>) -> Self {
        let height = (panels.len() as u32 * DEFAULT_SIZE.1 / 2).max(DEFAULT_SIZE.1);
        PlotStack {
            title: title.into(),
            panels,
            shared_legend: false,
            size: (DEFAULT_SIZE.0, height),
        }
    }

    /// One legend for all panels.
    pub fn with_shared_legend(mut self) -> Self {
        self.shared_legend = true;
        self
    }

    /// The distinct legend entries of all panels, in order.
    fn shared_entries(&self) -> Vec<LegendEntry> {
        let mut entries: Vec<LegendEntry> = Vec::new();
        for panel in &self.panels {
            let series = panel.chart_series();
            let (_, y) = panel.axes(&series);
            let colors: Vec<RGBColor> = (series.iter().enumerate())
                .map(|(i, s)| s.color.unwrap_or(PALETTE[i % PALETTE.len()]))
                .collect();
            for entry in panel.legend_entries(&series, &colors, &y) {
                if !entries.iter().any(|e| e.label == entry.label) {
                    entries.push(entry);
                }
            }
        }
        entries
    }
}

impl Figure for PlotStack {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<Typeset<DB>, Shift>) -> DrawResult {
        if self.panels.is_empty() {
            return Err("a plot stack needs at least one panel".into());
        }
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut body = draw_title(root, &self.title)?;
        let entries = match self.shared_legend {
            true => self.shared_entries(),
            false => Vec::new(),
        };
        if !entries.is_empty() {
            let (row, rest) = body.split_vertically(legend_row_height(&body, &entries));
            draw_legend_row(&row, &entries)?;
            body = rest;
        }
        let areas = body.split_evenly((self.panels.len(), 1));
        for (panel, area) in self.panels.iter().zip(&areas) {
            panel.draw_on(area, !self.shared_legend)?;
        }
        Ok(())
    }
}

/// Cell edges for cell centres `centres` (ascending): midpoints, ends extended by half a gap.
fn cell_edges(centres: &[f64]) -> Vec<f64> {
    match centres.len() {
        0 => Vec::new(),
        1 => vec![centres[0] - 0.5, centres[0] + 0.5],
        n => {
            let mut edges = Vec::with_capacity(n + 1);
            edges.push(centres[0] - 0.5 * (centres[1] - centres[0]));
            for w in centres.windows(2) {
                edges.push(0.5 * (w[0] + w[1]));
            }
            edges.push(centres[n - 1] + 0.5 * (centres[n - 1] - centres[n - 2]));
            edges
        }
    }
}

fn sorted_edges(centres: &[f64]) -> (Vec<f64>, bool) {
    let ascending = centres.windows(2).all(|w| w[0] <= w[1]);
    if ascending {
        (cell_edges(centres), true)
    } else {
        let reversed: Vec<f64> = centres.iter().rev().copied().collect();
        (cell_edges(&reversed), false)
    }
}

fn cell_rect(edges: &[f64], ascending: bool, n: usize, i: usize) -> (f64, f64) {
    let k = if ascending { i } else { n - 1 - i };
    (edges[k], edges[k + 1])
}

/// The cells of a rectilinear grid with (monotonic, non-empty) cell centres `x` and `y`.
struct CellGrid {
    x: (Vec<f64>, bool),
    y: (Vec<f64>, bool),
}

impl CellGrid {
    fn new(x: &[f64], y: &[f64]) -> Self {
        CellGrid {
            x: sorted_edges(x),
            y: sorted_edges(y),
        }
    }

    /// The x and y ranges the cells cover.
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let range = |edges: &[f64]| (edges[0], edges[edges.len() - 1]);
        (range(&self.x.0), range(&self.y.0))
    }

    /// Every cell's row-major index `iy · nx + ix` and rectangle, in that order.
    fn cells(&self) -> impl Iterator<Item = (usize, [(f64, f64); 2])> + '_ {
        let (nx, ny) = (self.x.0.len() - 1, self.y.0.len() - 1);
        (0..ny).flat_map(move |iy| {
            (0..nx).map(move |ix| {
                let (x0, x1) = cell_rect(&self.x.0, self.x.1, nx, ix);
                let (y0, y1) = cell_rect(&self.y.0, self.y.1, ny, iy);
                (iy * nx + ix, [(x0, y0), (x1, y1)])
            })
        })
    }
}

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
        let (x_range, y_range) = grid.ranges();
        let axes = (
            Axis::new(x_range, Scale::Linear),
            Axis::new(y_range, Scale::Linear),
        );
        let mut chart = chart(&main, axes.0, axes.1)?;
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

/// A map of categories (e.g. the cheapest strategy) on a rectilinear grid, with a legend;
/// `None` cells stay blank.
#[derive(Debug, Clone, PartialEq)]
pub struct CategoryMap {
    /// Caption.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Category names (legend), indexed by the cell values.
    pub categories: Vec<String>,
    /// Category colours (None: the palette).
    pub colors: Option<Vec<RGBColor>>,
    /// Cell-centre x values (monotonic).
    pub x: Vec<f64>,
    /// Cell-centre y values (monotonic).
    pub y: Vec<f64>,
    /// Category index per cell, row-major: `cells[iy * x.len() + ix]`.
    pub cells: Vec<Option<usize>>,
    /// Series drawn on top.
    pub overlays: Vec<Series>,
    /// Size in pixels.
    pub size: (u32, u32),
}

impl CategoryMap {
    /// A category map without overlays.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        categories: Vec<String>,
        x: Vec<f64>,
        y: Vec<f64>,
        cells: Vec<Option<usize>>,
    ) -> Self {
        CategoryMap {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            categories,
            colors: None,
            x,
            y,
            cells,
            overlays: Vec::new(),
            size: DEFAULT_SIZE,
        }
    }

    /// Adds an overlay series.
    pub fn with_overlay(mut self, series: Series) -> Self {
        self.overlays.push(series);
        self
    }
}

impl Figure for CategoryMap {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<Typeset<DB>, Shift>) -> DrawResult {
        let (nx, ny) = (self.x.len(), self.y.len());
        check_grid("category map", "cells", nx, ny, self.cells.len())?;
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let body = draw_title(root, &self.title)?;
        let grid = CellGrid::new(&self.x, &self.y);
        let color = |k: usize| {
            self.colors
                .as_ref()
                .and_then(|c| c.get(k).copied())
                .unwrap_or(PALETTE[k % PALETTE.len()])
        };
        let colors = overlay_colors(&self.overlays, self.categories.len());
        let mut entries: Vec<LegendEntry> = (self.categories.iter().enumerate())
            .map(|(k, name)| LegendEntry::square(name, color(k)))
            .collect();
        entries.extend(
            (self.overlays.iter().zip(&colors)).filter_map(|(s, c)| LegendEntry::of(s, *c)),
        );
        // The legend beside the map (inside, it would hide cells).
        let layout = legend_layout(&body, &entries);
        let (chart_area, legend_area, spot) = split_for_legend(&body, &layout);
        let (x_range, y_range) = grid.ranges();
        let axes = (
            Axis::new(x_range, Scale::Linear),
            Axis::new(y_range, Scale::Linear),
        );
        let mut chart = chart(&chart_area, axes.0, axes.1)?;
        draw_axes(&mut chart, &self.x_label, &self.y_label, false)?;
        for k in 0..self.categories.len() {
            let c = color(k);
            let rects = grid
                .cells()
                .filter(|&(i, _)| self.cells[i] == Some(k))
                .map(|(_, rect)| Rectangle::new(rect, c.filled()));
            chart.draw_series(rects).map_err(|e| e.to_string())?;
        }
        for (series, color) in self.overlays.iter().zip(&colors) {
            draw_series(&mut chart, series, *color, y_range)?;
        }
        draw_outside_legend(&legend_area, &entries, &layout, spot)
    }
}

/// The colours of overlay series: their own, else the palette from entry `first`.
fn overlay_colors(overlays: &[Series], first: usize) -> Vec<RGBColor> {
    (overlays.iter().enumerate())
        .map(|(i, s)| s.color.unwrap_or(PALETTE[(i + first) % PALETTE.len()]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_edges_are_midpoints() {
        assert_eq!(cell_edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        let (edges, up) = sorted_edges(&[3.0, 1.0, 0.0]);
        assert!(!up);
        assert_eq!(cell_rect(&edges, up, 3, 0), (2.0, 4.0));
    }
}
