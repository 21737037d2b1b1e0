//! Data series and how they are drawn: lines, dots, crosses, rings; points beyond the y
//! range as triangles at its edge.

use super::chart::Chart;
use super::colour::RGBColor;
use super::style::{px, upx};
use super::DrawResult;
use plotters::coord::Shift;
use plotters::prelude::*;

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

/// One data series of a [`LinePlot`](super::LinePlot) or an overlay of a map.
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
    /// scaled by [`SCALE`](super::SCALE)).
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

/// The marker a series or a legend entry is drawn with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Marker {
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
    pub(super) fn of(style: SeriesStyle) -> Self {
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
pub(super) fn dot_radius(style: SeriesStyle, size: u32) -> i32 {
    let size = size.max(1) as f64;
    match style {
        SeriesStyle::LineAndPoints => px(size + 1.0),
        SeriesStyle::Crosses => px(size.max(3.0)),
        SeriesStyle::Rings => px(size.max(3.0) + 2.0),
        _ => px(size),
    }
}

/// Draws one marker centred at pixel `(x, y)` of `area` (`up`: a triangle points up).
pub(super) fn draw_marker<DB: DrawingBackend>(
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

/// Pixels (relative to the plotting area) that the data of `series` cover: every point
/// (off-scale ones at the edge of `y_range`), and points along the lines every few pixels.
pub(super) fn data_pixels<DB: DrawingBackend>(
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

/// Draws `series` on `chart`; points whose y lies outside `y_range` are drawn as triangles
/// at the edge they lie beyond (lines break there).
pub(super) fn draw_series<DB: DrawingBackend>(
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
