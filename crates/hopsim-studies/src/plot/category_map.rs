//! Category maps: one category per cell of a rectilinear grid (e.g. the cheapest
//! strategy), with their legend beside the map.

use super::chart::{chart, draw_axes};
use super::colour::{RGBColor, PALETTE};
use super::grid::{check_grid, overlay_colors, CellGrid};
use super::legend::{draw_outside_legend, legend_layout, split_for_legend, LegendEntry};
use super::series::{draw_series, Series};
use super::style::draw_title;
use super::{DrawResult, Figure, Typeset, DEFAULT_SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;

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
        let (x_axis, y_axis) = grid.axes();
        let y_range = y_axis.bounds();
        let mut chart = chart(&chart_area, x_axis, y_axis)?;
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
