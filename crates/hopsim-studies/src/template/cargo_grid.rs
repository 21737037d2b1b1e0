//! The Cargo template over its Table-3.1 `l/R × φ_TO` grid (docs/physics.md §5.1): which cells
//! have a converged gait, the cheapest and the fastest, and heatmaps of both.

use super::ParamsWithEccentricity;
use crate::plot::Heatmap;
use crate::progress::Progress;
use crate::report::{num, num_range, Report, ReportFile, TextTable};
use crate::Result;
use hopsim_io::{Cell, CsvTable};
use hopsim_theory::template::{CargoGrid, GaitSummary, GridCell, TemplateParams};
use hopsim_theory::AnalysisError;
use serde::{Serialize, Serializer};
use std::time::Instant;

/// The grid to run.
#[derive(Clone, Copy, Debug)]
pub struct CargoGridParams {
    /// Parameters of every cell but `R` and `φ_TO` (the `l/R` axis follows its leg length).
    pub base: TemplateParams,
    /// Cells per axis.
    pub resolution: usize,
}

/// One cell as the report lists it.
#[derive(Serialize)]
struct CellRow<'a> {
    leg_over_radius: f64,
    radius_m: f64,
    takeoff_angle_rad: f64,
    converged: bool,
    mean_speed_mps: Option<f64>,
    stride_m: Option<f64>,
    hop_frequency_hz: Option<f64>,
    cost_of_transport: Option<f64>,
    no_gait_reason: Option<&'a str>,
}

impl<'a> From<&'a GridCell> for CellRow<'a> {
    fn from(c: &'a GridCell) -> Self {
        let s = c.summary.as_ref();
        CellRow {
            leg_over_radius: c.leg_over_radius,
            radius_m: c.radius,
            takeoff_angle_rad: c.takeoff_angle,
            converged: s.is_some_and(|s| s.converged),
            mean_speed_mps: s.map(|s| s.mean_speed_mps),
            stride_m: s.map(|s| s.stride_m),
            hop_frequency_hz: s.map(|s| s.hop_frequency_hz),
            cost_of_transport: s.map(|s| s.cost_of_transport),
            no_gait_reason: c.no_gait.as_deref(),
        }
    }
}

fn cell_rows<S: Serializer>(cells: &[GridCell], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(cells.iter().map(CellRow::from))
}

fn optional_cell_row<S: Serializer>(
    cell: &Option<GridCell>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    cell.as_ref().map(CellRow::from).serialize(s)
}

/// The grid's result.
#[derive(Serialize)]
pub struct CargoGridReport {
    analysis: &'static str,
    grid: &'static str,
    base_parameters: ParamsWithEccentricity,
    /// `l/R` axis.
    pub leg_over_radius: Vec<f64>,
    /// `φ_TO` axis [rad].
    #[serde(rename = "takeoff_angles_rad")]
    pub takeoff_angles: Vec<f64>,
    cells_total: usize,
    cells_with_gait: usize,
    cells_converged: usize,
    /// Wall-clock time of the grid [s].
    pub elapsed_s: f64,
    /// The converged cell of the lowest cost of transport.
    #[serde(serialize_with = "optional_cell_row")]
    pub min_cost_of_transport: Option<GridCell>,
    /// The converged cell of the highest mean speed.
    #[serde(serialize_with = "optional_cell_row")]
    pub max_speed: Option<GridCell>,
    /// Every cell, `φ_TO` outer, `l/R` inner.
    #[serde(serialize_with = "cell_rows")]
    pub cells: Vec<GridCell>,
}

/// The converged cells' gaits.
fn converged(cells: &[GridCell]) -> impl Iterator<Item = (&GridCell, &GaitSummary)> {
    cells.iter().filter_map(|c| c.converged().map(|s| (c, s)))
}

/// The converged cell of the lowest cost of transport (the first of equals).
pub fn lowest_cost_of_transport(cells: &[GridCell]) -> Option<&GridCell> {
    converged(cells)
        .min_by(|a, b| a.1.cost_of_transport.total_cmp(&b.1.cost_of_transport))
        .map(|(c, _)| c)
}

/// The converged cell of the highest mean speed (the last of equals).
pub fn fastest(cells: &[GridCell]) -> Option<&GridCell> {
    converged(cells)
        .max_by(|a, b| a.1.mean_speed_mps.total_cmp(&b.1.mean_speed_mps))
        .map(|(c, _)| c)
}

/// Runs the Table-3.1 Cargo grid around `p.base`, `p.resolution²` cells.
pub fn cargo_grid(p: &CargoGridParams, progress: &dyn Progress) -> Result<CargoGridReport> {
    let n = p.resolution;
    if n < 2 {
        let reason = "must be at least 2 (cells per axis)";
        return Err(AnalysisError::invalid("resolution", n as f64, reason).into());
    }
    let grid = CargoGrid::table_3_1_around(p.base, n, n);
    let started = Instant::now();
    let cells = {
        let tick = progress.task(n * n, "Cargo grid");
        grid.run(&*tick)?
    };
    let elapsed_s = started.elapsed().as_secs_f64();
    Ok(CargoGridReport {
        analysis: "template-grid",
        grid: "cargo",
        base_parameters: grid.base.into(),
        cells_total: cells.len(),
        cells_with_gait: cells.iter().filter(|c| c.summary.is_some()).count(),
        cells_converged: converged(&cells).count(),
        elapsed_s,
        min_cost_of_transport: lowest_cost_of_transport(&cells).cloned(),
        max_speed: fastest(&cells).cloned(),
        leg_over_radius: grid.leg_over_radius,
        takeoff_angles: grid.takeoff_angles,
        cells,
    })
}

impl CargoGridReport {
    fn csv(&self) -> CsvTable {
        let mut csv = CsvTable::new(&[
            "leg_over_radius",
            "radius_m",
            "takeoff_angle_rad",
            "gait",
            "converged",
            "mean_speed_mps",
            "stride_m",
            "hop_frequency_hz",
            "cost_of_transport",
            "dimensionless_speed",
            "speed_spread",
            "no_gait_reason",
        ]);
        for c in &self.cells {
            let s = c.summary.as_ref();
            csv.push(vec![
                c.leg_over_radius.into(),
                c.radius.into(),
                c.takeoff_angle.into(),
                s.is_some().into(),
                s.is_some_and(|s| s.converged).into(),
                s.map(|s| s.mean_speed_mps).into(),
                s.map(|s| s.stride_m).into(),
                s.map(|s| s.hop_frequency_hz).into(),
                s.map(|s| s.cost_of_transport).into(),
                s.map(|s| s.dimensionless_speed).into(),
                s.map(|s| s.speed_spread).into(),
                c.no_gait.clone().map_or(Cell::Empty, Cell::Text),
            ]);
        }
        csv
    }

    /// A heatmap of `f` over the converged cells (the others blank).
    fn heatmap(&self, title: &str, label: &str, f: fn(&GaitSummary) -> f64) -> Heatmap {
        Heatmap::new(
            format!("Cargo template: {title} (blank: no converged gait)"),
            "leg length over radius l / R",
            "take-off angle φ_TO (rad)",
            label,
            self.leg_over_radius.clone(),
            self.takeoff_angles.clone(),
            self.cells.iter().map(|c| c.converged().map(f)).collect(),
        )
    }
}

/// `CoT … at … m/s (l/R …, R …, φ_TO …)` of a converged cell.
fn describe(c: &GridCell) -> String {
    let (cot, speed) = c.converged().map_or((f64::NAN, f64::NAN), |s| {
        (s.cost_of_transport, s.mean_speed_mps)
    });
    format!(
        "CoT {} at {} m/s (l/R {}, R {}, φ_TO {})",
        num(cot, ""),
        num(speed, ""),
        num(c.leg_over_radius, ""),
        num(c.radius, "m"),
        num(c.takeoff_angle, "rad")
    )
}

impl Report for CargoGridReport {
    fn text(&self) -> String {
        let (ratios, angles) = (&self.leg_over_radius, &self.takeoff_angles);
        let mut t = TextTable::new(format!(
            "Cargo template grid, {} × {} cells (l/R × φ_TO)",
            ratios.len(),
            angles.len()
        ));
        t.row(
            "l/R range",
            num_range(ratios[0], ratios[ratios.len() - 1], ""),
        )
        .row(
            "φ_TO range",
            num_range(angles[0], angles[angles.len() - 1], "rad"),
        )
        .row("cells with a gait", self.cells_with_gait)
        .row("cells converged", self.cells_converged)
        .row("elapsed", num(self.elapsed_s, "s"));
        if let Some(c) = &self.min_cost_of_transport {
            t.row("lowest CoT", describe(c));
        }
        if let Some(c) = &self.max_speed {
            t.row("fastest", describe(c));
        }
        t.to_string()
    }

    fn files(&self) -> Vec<ReportFile> {
        vec![
            ReportFile::csv("cargo_grid.csv", self.csv()),
            ReportFile::figure(
                "cargo_grid_cost_of_transport",
                self.heatmap("cost of transport", "cost of transport", |s| {
                    s.cost_of_transport
                }),
            ),
            ReportFile::figure(
                "cargo_grid_speed",
                self.heatmap("mean speed", "mean speed (m/s)", |s| s.mean_speed_mps),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(ratio: f64, gait: Option<(f64, f64, bool)>) -> GridCell {
        GridCell {
            leg_over_radius: ratio,
            radius: 1.0,
            takeoff_angle: -0.1,
            summary: gait.map(|(cot, speed, converged)| GaitSummary {
                mean_speed_mps: speed,
                stride_m: 1.0,
                hop_frequency_hz: speed,
                cost_of_transport: cot,
                dimensionless_speed: 1.0,
                froude_number: 1.0,
                impulse_n_s: 1.0,
                flight_time_s: 0.1,
                touchdown_angle_rad: 0.0,
                touchdown_loss_j: 0.0,
                speed_spread: 0.0,
                converged,
            }),
            no_gait: gait.is_none().then(|| "no lift-off".to_string()),
        }
    }

    #[test]
    fn cheapest_and_fastest_are_chosen_among_converged_cells_only() {
        let cells = [
            cell(0.1, Some((0.1, 9.0, false))), // cheapest and fastest, but not converged
            cell(0.2, Some((0.5, 2.0, true))),
            cell(0.3, None),
            cell(0.4, Some((0.3, 1.0, true))),
            cell(0.5, Some((0.3, 2.0, true))),
        ];
        assert_eq!(
            lowest_cost_of_transport(&cells).unwrap().leg_over_radius,
            0.4
        );
        assert_eq!(fastest(&cells).unwrap().leg_over_radius, 0.5);
        assert_eq!(converged(&cells).count(), 3);
        let none = [cell(0.1, None), cell(0.2, Some((0.1, 1.0, false)))];
        assert!(lowest_cost_of_transport(&none).is_none() && fastest(&none).is_none());
    }

    #[test]
    fn a_grid_needs_two_cells_per_axis() {
        let p = CargoGridParams {
            base: CargoGrid::table_3_1_base(),
            resolution: 1,
        };
        let err = cargo_grid(&p, &crate::progress::Silent).err().unwrap();
        assert!(err.is_invalid_input(), "{err}");
    }

    #[test]
    fn cell_rows_show_null_gaits_and_the_reason() {
        let row = serde_json::to_value(CellRow::from(&cell(0.3, None))).unwrap();
        assert_eq!(row["converged"], false);
        assert!(row["mean_speed_mps"].is_null() && row["cost_of_transport"].is_null());
        assert_eq!(row["no_gait_reason"], "no lift-off");
        assert_eq!(row.as_object().unwrap().len(), 9);
    }
}
