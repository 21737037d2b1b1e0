//! The animals of Table 3.1 (docs/physics.md §5.1): stride against dimensionless speed
//! `u / sqrt(g l)` over each animal's ranges of take-off angle and energy input.

use super::{span, ParamsWithEccentricity};
use crate::plot::{three_significant_digits, LinePlot, RGBColor, Series, SeriesStyle, PALETTE};
use crate::progress::Progress;
use crate::report::{num, num_range, Report, ReportFile, TextTable};
use crate::Result;
use hopsim_io::{Cell, CsvTable};
use hopsim_theory::template::{sweep_case, AnimalPoint, GaitSummary, TemplateCase, TemplateParams};
use serde::{Serialize, Serializer};
use std::time::Instant;

/// Take-off angles of every sweep.
pub const TAKEOFF_ANGLES: usize = 5;

/// The sweeps to run.
#[derive(Clone, Debug)]
pub struct AnimalSweepsParams {
    /// Each animal with its parameters (`φ_TO` and `ΔE` are swept over the animal's ranges).
    pub animals: Vec<(TemplateCase, TemplateParams)>,
    /// Energy inputs per take-off angle.
    pub energies: usize,
}

/// One point as the report lists it.
#[derive(Serialize)]
struct PointRow<'a> {
    takeoff_angle_rad: f64,
    #[serde(rename = "energy_input_J")]
    energy_input_j: f64,
    converged: bool,
    mean_speed_mps: Option<f64>,
    dimensionless_speed: Option<f64>,
    stride_m: Option<f64>,
    no_gait_reason: Option<&'a str>,
}

impl<'a> From<&'a AnimalPoint> for PointRow<'a> {
    fn from(p: &'a AnimalPoint) -> Self {
        let s = p.summary.as_ref();
        PointRow {
            takeoff_angle_rad: p.takeoff_angle,
            energy_input_j: p.energy_input,
            converged: s.is_some_and(|s| s.converged),
            mean_speed_mps: s.map(|s| s.mean_speed_mps),
            dimensionless_speed: s.map(|s| s.dimensionless_speed),
            stride_m: s.map(|s| s.stride_m),
            no_gait_reason: p.no_gait.as_deref(),
        }
    }
}

fn point_rows<S: Serializer>(points: &[AnimalPoint], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(points.iter().map(PointRow::from))
}

fn case_name<S: Serializer>(case: &TemplateCase, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(case.name())
}

/// One animal's sweep.
#[derive(Serialize)]
pub struct AnimalSweep {
    /// The animal.
    #[serde(serialize_with = "case_name")]
    pub case: TemplateCase,
    base_parameters: ParamsWithEccentricity,
    /// The points, `φ_TO` outer, `ΔE` inner.
    #[serde(serialize_with = "point_rows")]
    pub points: Vec<AnimalPoint>,
}

/// The sweeps' result.
#[derive(Serialize)]
pub struct AnimalSweepsReport {
    analysis: &'static str,
    /// Wall-clock time of all sweeps [s].
    pub elapsed_s: f64,
    /// One sweep per animal.
    pub sweeps: Vec<AnimalSweep>,
    #[serde(skip)]
    energies: usize,
}

/// Runs the sweeps, one after the other (each on all cores).
pub fn animal_sweeps(
    p: &AnimalSweepsParams,
    progress: &dyn Progress,
) -> Result<AnimalSweepsReport> {
    let started = Instant::now();
    let mut sweeps = Vec::with_capacity(p.animals.len());
    for &(case, base) in &p.animals {
        let tick = progress.task(TAKEOFF_ANGLES * p.energies, case.name());
        let points = sweep_case(case, &base, TAKEOFF_ANGLES, p.energies, &*tick)?;
        sweeps.push(AnimalSweep {
            case,
            base_parameters: base.into(),
            points,
        });
    }
    Ok(AnimalSweepsReport {
        analysis: "template-animals",
        elapsed_s: started.elapsed().as_secs_f64(),
        sweeps,
        energies: p.energies,
    })
}

/// The take-off angles of `points` in order (each once; points are `φ_TO` outer).
fn takeoff_angles(points: &[AnimalPoint]) -> Vec<f64> {
    let mut angles: Vec<f64> = points.iter().map(|p| p.takeoff_angle).collect();
    angles.dedup();
    angles
}

/// `(u / sqrt(g l), stride)` of the points at take-off angle `phi` whose gait has
/// `converged` as given.
fn stride_against_speed(points: &[AnimalPoint], phi: f64, converged: bool) -> Vec<(f64, f64)> {
    points
        .iter()
        .filter(|p| p.takeoff_angle == phi)
        .filter_map(|p| p.summary.as_ref())
        .filter(|s| s.converged == converged)
        .map(|s| (s.dimensionless_speed, s.stride_m))
        .collect()
}

impl AnimalSweep {
    fn gaits(&self) -> impl Iterator<Item = &GaitSummary> + Clone {
        self.points.iter().filter_map(|p| p.summary.as_ref())
    }

    fn csv(&self) -> CsvTable {
        let mut csv = CsvTable::new(&[
            "takeoff_angle_rad",
            "energy_input_J",
            "gait",
            "converged",
            "mean_speed_mps",
            "dimensionless_speed",
            "stride_m",
            "hop_frequency_hz",
            "cost_of_transport",
            "no_gait_reason",
        ]);
        for pt in &self.points {
            let s = pt.summary.as_ref();
            csv.push(vec![
                pt.takeoff_angle.into(),
                pt.energy_input.into(),
                s.is_some().into(),
                s.is_some_and(|s| s.converged).into(),
                s.map(|s| s.mean_speed_mps).into(),
                s.map(|s| s.dimensionless_speed).into(),
                s.map(|s| s.stride_m).into(),
                s.map(|s| s.hop_frequency_hz).into(),
                s.map(|s| s.cost_of_transport).into(),
                pt.no_gait.clone().map_or(Cell::Empty, Cell::Text),
            ]);
        }
        csv
    }

    /// Stride against speed, one colour per take-off angle; crosses: not converged.
    fn plot(&self) -> LinePlot {
        let energy = self.case.ranges().energy_input;
        let mut plot = LinePlot::new(
            format!(
                "{}: stride against dimensionless speed (ΔE {}…{} J; ×: not converged)",
                self.case.name(),
                three_significant_digits(energy.0),
                three_significant_digits(energy.1)
            ),
            "dimensionless speed u / sqrt(g l)",
            "stride (m)",
        );
        for (i, phi) in takeoff_angles(&self.points).into_iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            plot = plot.with_series(
                Series::line(
                    format!("φ_TO = {} rad", three_significant_digits(phi)),
                    stride_against_speed(&self.points, phi, true),
                )
                .style(SeriesStyle::LineAndPoints)
                .color(color),
            );
            let open = stride_against_speed(&self.points, phi, false);
            if !open.is_empty() {
                plot = plot.with_series(
                    Series::points("", open)
                        .style(SeriesStyle::Crosses)
                        .color(color)
                        .unlabelled()
                        .without_range(),
                );
            }
        }
        // The crosses' legend entry (their colour is their take-off angle's).
        let open = |s: &Series| s.style == SeriesStyle::Crosses && !s.points.is_empty();
        if plot.series.iter().any(open) {
            let grey = RGBColor(110, 110, 110);
            plot = plot.with_series(
                Series::points("not converged (colour: its φ_TO)", Vec::new())
                    .style(SeriesStyle::Crosses)
                    .color(grey),
            );
        }
        plot
    }
}

impl Report for AnimalSweepsReport {
    fn text(&self) -> String {
        let mut text = String::new();
        for sweep in &self.sweeps {
            let mut t = TextTable::new(format!(
                "{} sweep: {} take-off angles × {} energies",
                sweep.case.name(),
                TAKEOFF_ANGLES,
                self.energies
            ));
            t.row("points with a gait", sweep.gaits().count())
                .row("converged", sweep.gaits().filter(|s| s.converged).count());
            if let Some((lo, hi)) = span(sweep.gaits().map(|s| s.dimensionless_speed)) {
                t.row("u / sqrt(g l)", num_range(lo, hi, ""));
            }
            if let Some((lo, hi)) = span(sweep.gaits().map(|s| s.stride_m)) {
                t.row("stride", num_range(lo, hi, "m"));
            }
            t.row("elapsed (all sweeps)", num(self.elapsed_s, "s"));
            text += &t.to_string();
        }
        text
    }

    fn files(&self) -> Vec<ReportFile> {
        self.sweeps
            .iter()
            .flat_map(|sweep| {
                let name = sweep.case.name();
                [
                    ReportFile::csv(format!("{name}_sweep.csv"), sweep.csv()),
                    ReportFile::figure(format!("{name}_stride_vs_speed"), sweep.plot()),
                ]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(phi: f64, gait: Option<(f64, bool)>) -> AnimalPoint {
        AnimalPoint {
            takeoff_angle: phi,
            energy_input: 1.0,
            summary: gait.map(|(speed, converged)| GaitSummary {
                mean_speed_mps: speed,
                stride_m: 2.0 * speed,
                hop_frequency_hz: 0.5,
                cost_of_transport: 0.1,
                dimensionless_speed: speed,
                froude_number: speed * speed,
                impulse_n_s: 1.0,
                flight_time_s: 0.1,
                touchdown_angle_rad: 0.0,
                touchdown_loss_j: 0.0,
                speed_spread: 0.0,
                converged,
            }),
            no_gait: None,
        }
    }

    #[test]
    fn points_are_grouped_by_angle_and_convergence() {
        let points = [
            point(-0.2, Some((1.0, true))),
            point(-0.2, Some((2.0, false))),
            point(-0.2, None),
            point(-0.1, Some((3.0, true))),
            point(-0.1, Some((4.0, true))),
        ];
        assert_eq!(takeoff_angles(&points), [-0.2, -0.1]);
        assert_eq!(stride_against_speed(&points, -0.2, true), [(1.0, 2.0)]);
        assert_eq!(stride_against_speed(&points, -0.2, false), [(2.0, 4.0)]);
        assert_eq!(
            stride_against_speed(&points, -0.1, true),
            [(3.0, 6.0), (4.0, 8.0)]
        );
        assert!(stride_against_speed(&points, -0.1, false).is_empty());
    }

    #[test]
    fn the_text_counts_gaits_and_spans_their_speeds() {
        let report = AnimalSweepsReport {
            analysis: "template-animals",
            elapsed_s: 0.5,
            sweeps: vec![AnimalSweep {
                case: TemplateCase::Wallaby,
                base_parameters: TemplateCase::Wallaby.params().into(),
                points: vec![
                    point(-0.2, Some((1.0, true))),
                    point(-0.2, None),
                    point(-0.1, Some((3.0, false))),
                ],
            }],
            energies: 2,
        };
        let text = report.text();
        assert!(
            text.starts_with("wallaby sweep: 5 take-off angles × 2 energies\n"),
            "{text}"
        );
        assert!(text.contains("points with a gait    2\n"), "{text}");
        assert!(text.contains("converged             1\n"), "{text}");
        assert!(text.contains("1.0000 … 3.0000\n"), "{text}");
        assert!(text.contains("2.0000 m … 6.0000 m\n"), "{text}");
    }
}
