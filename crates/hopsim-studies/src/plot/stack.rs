//! Line plots stacked under one title, with their own legends or one for all.

use super::colour::{RGBColor, PALETTE};
use super::legend::{draw_legend_row, legend_row_height, LegendEntry};
use super::line::LinePlot;
use super::style::draw_title;
use super::{DrawResult, Figure, Typeset, DEFAULT_SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;

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
