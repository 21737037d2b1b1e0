//! A figure's chart: two [`Axis`] with room for their labels, and its axes drawn with
//! their descriptions (shrunk to fit) and ticks.

use super::axis::Axis;
use super::colour::BLACK;
use super::style::{fitting_size, text_style, upx, AXIS_FONT, TICK_FONT};
use super::DrawResult;
use plotters::coord::Shift;
use plotters::prelude::*;

/// A chart on two [`Axis`], as every figure here draws.
pub(super) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// The chart of a figure on `area` (below its title), with room for the axis labels.
pub(super) fn chart<'a, DB: DrawingBackend>(
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
pub(super) fn axes<DB: DrawingBackend>(chart: &Chart<'_, DB>) -> (Axis, Axis) {
    let spec = chart.as_coord_spec();
    (*spec.x_spec(), *spec.y_spec())
}

/// Draws the axes with their labels (shrunk to fit the axis if long) and their ticks
/// ([`Axis::label`]); `grid` adds light grid lines (maps cover them).
pub(super) fn draw_axes<DB: DrawingBackend>(
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
