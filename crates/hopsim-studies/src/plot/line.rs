//! Line and scatter plots: series over shaded bands, on linear, integer or logarithmic
//! axes, with a legend that avoids the data.

use super::axis::{Axis, Scale};
use super::chart::{axes, chart, draw_axes, Chart};
use super::colour::{on_white, RGBColor, PALETTE};
use super::legend::{
    draw_legend_box, draw_outside_legend, free_legend_place, legend_layout, off_scale_entry,
    split_for_legend, LegendEntry,
};
use super::range::{auto_y_range, finite_range, padded};
use super::series::{data_pixels, draw_series, Series};
use super::style::draw_title;
use super::{DrawResult, Figure, Typeset, DEFAULT_SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;

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
    pub(super) fn chart_series(&self) -> Vec<Series> {
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
    pub(super) fn axes(&self, series: &[Series]) -> (Axis, Axis) {
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
    pub(super) fn legend_entries(
        &self,
        series: &[Series],
        colors: &[RGBColor],
        y: &Axis,
    ) -> Vec<LegendEntry> {
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
    pub(super) fn draw_on<DB: DrawingBackend>(
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
