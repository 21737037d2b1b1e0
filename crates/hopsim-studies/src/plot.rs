//! Reusable figures: line plots, heatmaps (with blank cells and a colour bar) and category
//! maps, written as PNG and SVG (plotters), atomically.
//!
//! ```no_run
//! use hopsim_studies::plot::{Heatmap, LinePlot, Series, write_png_and_svg};
//! let plot = LinePlot::new("speed", "hop", "speed [m/s]")
//!     .with_series(Series::line("run 1", vec![(0.0, 0.1), (1.0, 0.2)]));
//! write_png_and_svg(&plot, std::path::Path::new("out/speed")).unwrap(); // out/speed.png + .svg
//! let map = Heatmap::new("cost", "x", "y", "CoT", vec![0.0, 1.0], vec![0.0, 1.0],
//!     vec![Some(1.0), None, Some(2.0), Some(3.0)]);
//! write_png_and_svg(&map, std::path::Path::new("out/cost")).unwrap();
//! ```
//!
//! A new kind of figure implements [`Figure`] (drawing on any plotters backend) and gets
//! PNG/SVG output from [`write_png`], [`write_svg`] and [`write_png_and_svg`].

use crate::error::{Result, StudyError};
use hopsim_io::{AtomicPath, IoError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Default figure size in pixels.
pub const DEFAULT_SIZE: (u32, u32) = (960, 640);

/// Font family of all text.
const FONT: &str = "sans-serif";

/// Error text of a drawing step.
pub type DrawResult = std::result::Result<(), String>;

/// Something that can draw itself on any plotters backend.
pub trait Figure {
    /// Figure size in pixels.
    fn size(&self) -> (u32, u32) {
        DEFAULT_SIZE
    }
    /// Draws the figure on `root` (already sized; not yet filled).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult;
}

/// Draws `figure` as a PNG file into a temporary file for `path`, committed by the caller.
fn stage_png<F: Figure>(figure: &F, path: &Path) -> Result<AtomicPath> {
    let output = AtomicPath::create(path)?;
    {
        let root = BitMapBackend::new(output.temporary(), figure.size()).into_drawing_area();
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
        let root = SVGBackend::with_string(&mut svg, figure.size()).into_drawing_area();
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

/// Draws `stem.png` and `stem.svg` into temporary files, committed by the caller (so that a
/// set of files appears together, [`crate::write_files`]).
pub fn stage_png_and_svg<F: Figure>(figure: &F, stem: &Path) -> Result<Vec<AtomicPath>> {
    Ok(vec![
        stage_png(figure, &stem.with_extension("png"))?,
        stage_svg(figure, &stem.with_extension("svg"))?,
    ])
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
    /// Dot size or line width in pixels.
    pub size: u32,
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

    /// Sets the dot size / line width.
    pub fn size(mut self, size: u32) -> Self {
        self.size = size;
        self
    }

    /// Removes the legend entry.
    pub fn unlabelled(mut self) -> Self {
        self.label = None;
        self
    }
}

pub use plotters::style::RGBColor;

/// Black, for reference lines.
pub const BLACK: RGBColor = RGBColor(0, 0, 0);

/// Qualitative palette (Tableau 10).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Viridis colour map at `t ∈ [0, 1]` (piecewise-linear through 9 samples).
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let pos = t * (STOPS.len() - 1) as f64;
    let i = (pos.floor() as usize).min(STOPS.len() - 2);
    let f = pos - i as f64;
    let lerp = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
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

/// A chart with linear `f64` axes, as every figure here draws.
type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The chart of a figure on `area`: the caption `title` above, room for the axis labels.
fn chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    x_range: (f64, f64),
    y_range: (f64, f64),
) -> std::result::Result<Chart<'a, DB>, String> {
    ChartBuilder::on(area)
        .caption(title, (FONT, 24))
        .margin(12)
        .margin_right(28)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(|e| e.to_string())
}

/// Draws the axes with their labels; `grid` adds light grid lines (maps cover them);
/// `log_x`: the chart's x coordinate is `log10 x`, labelled with `x`.
fn draw_axes<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    x_label: &str,
    y_label: &str,
    grid: bool,
    log_x: bool,
) -> DrawResult {
    let mut mesh = chart.configure_mesh();
    if grid {
        mesh.light_line_style(RGBColor(235, 235, 235));
    } else {
        mesh.disable_mesh();
    }
    let log_label = |v: &f64| three_significant_digits(10f64.powf(*v));
    if log_x {
        mesh.x_label_formatter(&log_label);
    }
    mesh.x_desc(x_label)
        .y_desc(y_label)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .draw()
        .map_err(|e| e.to_string())
}

/// `x` with three significant digits, without trailing zeros (axis labels).
fn three_significant_digits(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.decimals$}");
    match text.contains('.') {
        true => text.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => text,
    }
}

/// Draws the legend (one row per entry of `labels`) in the place of the plotting area that
/// covers the fewest points of `avoid`: the upper right corner unless another place covers
/// fewer.
fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    labels: &[&str],
    avoid: &[Series],
) -> DrawResult {
    // The legend's size as plotters lays it out: text rows of the 15 px font, a 30 px
    // symbol column and 10 px margins (estimated, with a little room to spare).
    let widest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as i32;
    let (w, h) = (widest * 8 + 60, labels.len() as i32 * 19 + 24);
    let (area_w, area_h) = chart.plotting_area().dim_in_pixel();
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let pixels: Vec<(i32, i32)> = avoid
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|p| chart.backend_coord(p))
        .map(|(x, y)| (x - xs.start, y - ys.start))
        .collect();
    let (right, bottom) = (area_w as i32 - w - 5, area_h as i32 - h - 5);
    let (middle_x, middle_y) = ((area_w as i32 - w) / 2, (area_h as i32 - h) / 2);
    let places = [
        (right, 5),
        (5, 5),
        (middle_x, 5),
        (right, bottom),
        (5, bottom),
        (middle_x, bottom),
        (right, middle_y),
        (5, middle_y),
    ];
    let covered = |&(x0, y0): &(i32, i32)| {
        pixels
            .iter()
            .filter(|(x, y)| (x0..=x0 + w).contains(x) && (y0..=y0 + h).contains(y))
            .count()
    };
    // The first place with the fewest covered points.
    let (x, y) = places
        .iter()
        .min_by_key(|p| covered(p))
        .copied()
        .unwrap_or((right, 5));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::Coordinate(x, y))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 15))
        .draw()
        .map_err(|e| e.to_string())
}

/// The labels of the labelled series.
fn labels(series: &[Series]) -> Vec<&str> {
    series.iter().filter_map(|s| s.label.as_deref()).collect()
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

fn draw_series<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    series: &Series,
    default_color: RGBColor,
) -> DrawResult {
    let color = series.color.unwrap_or(default_color);
    let size = series.size.max(1);
    let finite: Vec<(f64, f64)> = series
        .points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let mut legend_drawn = false;
    let label = |anno: &mut plotters::chart::SeriesAnno<'_, DB>, style: SeriesStyle| {
        if let Some(text) = &series.label {
            anno.label(text.clone());
            match style {
                SeriesStyle::Points | SeriesStyle::Crosses => {
                    anno.legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
                }
                _ => {
                    anno.legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                }
            }
        }
    };
    if matches!(series.style, SeriesStyle::Line | SeriesStyle::LineAndPoints) {
        // Break the polyline at non-finite points.
        let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for &(x, y) in &series.points {
            if x.is_finite() && y.is_finite() {
                if let Some(segment) = segments.last_mut() {
                    segment.push((x, y));
                }
            } else if !segments.last().is_some_and(Vec::is_empty) {
                segments.push(Vec::new());
            }
        }
        for segment in segments.into_iter().filter(|s| !s.is_empty()) {
            let anno = chart
                .draw_series(LineSeries::new(segment, color.stroke_width(size)))
                .map_err(|e| e.to_string())?;
            if !legend_drawn {
                label(anno, SeriesStyle::Line);
                legend_drawn = true;
            }
        }
    }
    if matches!(
        series.style,
        SeriesStyle::Points | SeriesStyle::LineAndPoints
    ) {
        let radius = if series.style == SeriesStyle::LineAndPoints {
            size + 1
        } else {
            size
        };
        let anno = chart
            .draw_series(
                finite
                    .iter()
                    .map(|&p| Circle::new(p, radius, color.filled())),
            )
            .map_err(|e| e.to_string())?;
        if !legend_drawn {
            label(anno, SeriesStyle::Points);
            legend_drawn = true;
        }
    }
    if series.style == SeriesStyle::Crosses {
        let anno = chart
            .draw_series(
                finite
                    .iter()
                    .map(|&p| Cross::new(p, size.max(3), color.stroke_width(2))),
            )
            .map_err(|e| e.to_string())?;
        if !legend_drawn {
            label(anno, SeriesStyle::Crosses);
        }
    }
    Ok(())
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
    /// x range (None: data range with 3 % padding).
    pub x_range: Option<(f64, f64)>,
    /// y range (None: data range with 5 % padding).
    pub y_range: Option<(f64, f64)>,
    /// Size in pixels.
    pub size: (u32, u32),
    /// Logarithmic x axis (points with `x ≤ 0` are left out; the x range is in `x`).
    pub log_x: bool,
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
            x_range: None,
            y_range: None,
            size: DEFAULT_SIZE,
            log_x: false,
        }
    }

    /// Makes the x axis logarithmic.
    pub fn with_log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    /// Adds a series.
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
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
}

impl Figure for LinePlot {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        // On a logarithmic axis the chart's coordinate is log10 x.
        let to_chart = |x: f64| if self.log_x { x.log10() } else { x };
        let series: Vec<Series> = self
            .series
            .iter()
            .map(|s| Series {
                points: (s.points.iter())
                    .filter(|p| !self.log_x || p.0 > 0.0)
                    .map(|&(x, y)| (to_chart(x), y))
                    .collect(),
                ..s.clone()
            })
            .collect();
        let all = || series.iter().flat_map(|s| s.points.iter());
        let x_range = match self.x_range {
            Some((lo, hi)) => (to_chart(lo), to_chart(hi)),
            None => padded(finite_range(all().map(|p| p.0)), 0.03),
        };
        let y_range = self
            .y_range
            .unwrap_or_else(|| padded(finite_range(all().map(|p| p.1)), 0.05));
        let mut chart = chart(root, &self.title, x_range, y_range)?;
        draw_axes(&mut chart, &self.x_label, &self.y_label, true, self.log_x)?;
        for (i, series) in series.iter().enumerate() {
            draw_series(&mut chart, series, PALETTE[i % PALETTE.len()])?;
        }
        if self.series.iter().any(|s| s.label.is_some()) {
            draw_legend(&mut chart, &labels(&series), &series)?;
        }
        Ok(())
    }
}

/// Line plots stacked vertically under one title (e.g. `x`, `y` and `φ` of a gait over one
/// cycle); each panel keeps its own axes, labels and legend.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotStack {
    /// Caption above all panels.
    pub title: String,
    /// The panels, top to bottom.
    pub panels: Vec<LinePlot>,
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
            size: (DEFAULT_SIZE.0, height),
        }
    }
}

impl Figure for PlotStack {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        if self.panels.is_empty() {
            return Err("a plot stack needs at least one panel".into());
        }
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let body = root
            .titled(&self.title, (FONT, 22))
            .map_err(|e| e.to_string())?;
        let areas = body.split_evenly((self.panels.len(), 1));
        for (panel, area) in self.panels.iter().zip(&areas) {
            panel.draw(area)?;
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
}

impl Figure for Heatmap {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let (nx, ny) = (self.x.len(), self.y.len());
        check_grid("heatmap", "values", nx, ny, self.values.len())?;
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (main, bar) = root.split_horizontally(self.size.0.saturating_sub(130));
        let grid = CellGrid::new(&self.x, &self.y);
        let value = |v: &Option<f64>| v.filter(|v| v.is_finite());
        let (lo, hi) = self
            .value_range
            .or_else(|| finite_range(self.values.iter().filter_map(value)))
            .unwrap_or((0.0, 1.0));
        let span = if hi > lo { hi - lo } else { 1.0 };
        let (x_range, y_range) = grid.ranges();
        let mut chart = chart(&main, &self.title, x_range, y_range)?;
        draw_axes(&mut chart, &self.x_label, &self.y_label, false, false)?;
        let cells = grid.cells().filter_map(|(k, rect)| {
            value(&self.values[k]).map(|v| Rectangle::new(rect, viridis((v - lo) / span).filled()))
        });
        chart.draw_series(cells).map_err(|e| e.to_string())?;
        for (i, series) in self.overlays.iter().enumerate() {
            draw_series(&mut chart, series, PALETTE[(i + 3) % PALETTE.len()])?;
        }
        if self.overlays.iter().any(|s| s.label.is_some()) {
            draw_legend(&mut chart, &labels(&self.overlays), &self.overlays)?;
        }
        // Colour bar.
        let mut bar_chart = ChartBuilder::on(&bar)
            .margin_top(52)
            .margin_bottom(60)
            .margin_right(8)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..1.0, lo..(lo + span))
            .map_err(|e| e.to_string())?;
        bar_chart
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(&self.value_label)
            .label_style((FONT, 13))
            .axis_desc_style((FONT, 15))
            .draw()
            .map_err(|e| e.to_string())?;
        let steps = 100;
        bar_chart
            .draw_series((0..steps).map(|i| {
                let a = lo + span * i as f64 / steps as f64;
                let b = lo + span * (i + 1) as f64 / steps as f64;
                Rectangle::new(
                    [(0.0, a), (1.0, b)],
                    viridis((i as f64 + 0.5) / steps as f64).filled(),
                )
            }))
            .map_err(|e| e.to_string())?;
        Ok(())
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

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let (nx, ny) = (self.x.len(), self.y.len());
        check_grid("category map", "cells", nx, ny, self.cells.len())?;
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let grid = CellGrid::new(&self.x, &self.y);
        let color = |k: usize| {
            self.colors
                .as_ref()
                .and_then(|c| c.get(k).copied())
                .unwrap_or(PALETTE[k % PALETTE.len()])
        };
        let (x_range, y_range) = grid.ranges();
        let mut chart = chart(root, &self.title, x_range, y_range)?;
        draw_axes(&mut chart, &self.x_label, &self.y_label, false, false)?;
        for (k, name) in self.categories.iter().enumerate() {
            let c = color(k);
            let rects = grid
                .cells()
                .filter(|&(i, _)| self.cells[i] == Some(k))
                .map(|(_, rect)| Rectangle::new(rect, c.filled()));
            chart
                .draw_series(rects)
                .map_err(|e| e.to_string())?
                .label(name.clone())
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], c.filled()));
        }
        for (i, series) in self.overlays.iter().enumerate() {
            draw_series(
                &mut chart,
                series,
                PALETTE[(i + self.categories.len()) % PALETTE.len()],
            )?;
        }
        let mut entries: Vec<&str> = self.categories.iter().map(String::as_str).collect();
        entries.extend(labels(&self.overlays));
        draw_legend(&mut chart, &entries, &self.overlays)?;
        Ok(())
    }
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

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), RGBColor(68, 1, 84));
    }
}
