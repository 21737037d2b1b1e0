//! Reusable figures: line plots, stacks of them, heatmaps (with blank cells and a colour
//! bar) and category maps, written as PNG and SVG (plotters), atomically, in one style:
//!
//! - print resolution: 2400 × 1600 pixels by default (8 × 5⅓ in at 300 dpi), with fonts,
//!   line widths and markers scaled to match ([`SCALE`]);
//! - titles wrapped to the figure's width (never cut at the edge), axis labels in words
//!   with SI units in parentheses, e.g. `mean speed (m/s)`;
//! - text set in an embedded font, the same on every machine ([`Typeset`]);
//! - ticks at 1, 2 or 5 × 10^k, at whole numbers on counts, at decades (and 2 and 5 times
//!   them) on logarithmic axes; labels without trailing zeros (`10`, not `10.0`), never `-0`;
//! - y ranges robust to outliers: a few points far outside the rest are drawn as
//!   triangles at the edge of the plot, with a legend entry giving their values,
//!   instead of flattening every other point;
//! - legends whose markers are the ones drawn, placed inside the plot only where they
//!   cover no data, else beside the plot; under a map, in a row.
//!
//! One module per figure kind ([`LinePlot`], [`PlotStack`], [`Heatmap`], [`CategoryMap`])
//! over shared ones: `style` (sizes, text, titles), `axis` (scales and ticks), `chart`
//! (axes drawn), `range` (data ranges), `series` (markers and lines), `legend`, `grid`
//! (cells of maps), `colour` (palette and colour scales), `font` (the embedded font) and
//! `output` (PNG and SVG files).
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
//! A new kind of figure implements [`Figure`] (drawing on any plotters backend wrapped in
//! [`Typeset`]) and gets PNG/SVG output from [`write_png_and_svg`] and
//! [`stage_png_and_svg`].

mod axis;
mod category_map;
mod chart;
mod colour;
mod font;
mod grid;
mod heatmap;
mod legend;
mod line;
mod output;
mod range;
mod series;
mod stack;
mod style;

pub use axis::{three_significant_digits, tick_label, Axis, Scale, MAX_TICKS};
pub use category_map::CategoryMap;
pub use colour::{blue_white_red, on_white, viridis, ColourScale, RGBColor, BLACK, PALETTE};
pub use font::Typeset;
pub use heatmap::Heatmap;
pub use legend::free_legend_place;
pub use line::{Band, LinePlot};
pub use output::{commit_all, figure_paths, stage_png_and_svg, write_png_and_svg};
pub use range::robust_range;
pub use series::{Series, SeriesStyle};
pub use stack::PlotStack;
pub use style::SCALE;

use plotters::coord::Shift;
use plotters::prelude::*;

/// Default figure size in pixels: 8 × 5⅓ inches at 300 dpi.
pub const DEFAULT_SIZE: (u32, u32) = (2400, 1600);

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
