//! Robbit's periodic gaits and their stability (docs/physics.md §5.3, docs/analysis.md §9): the
//! fixed-point controls `β* = (T*, ζ0*)` of the return map at one section state or over a
//! grid of take-off angle `φ_TO` × take-off energy `E_TO`, with the eigenvalues of the
//! return-map Jacobian, and optionally the time-stepper run from rest with a stable `β*`
//! against the predicted gait ([`crate::robbit_gait`]).
//!
//! * [`summary`]: what is reported of the robot, of each point and of the cross-check;
//! * [`selection`]: the most stable and fastest stable points, counts, colour ranges;
//! * `files` and `text`: the CSV files, maps and plots, and the text tables.

mod files;
pub mod gaits;
pub mod selection;
pub mod summary;
mod text;

use crate::progress::Progress;
use crate::report::{Report, ReportFile};
use crate::robbit_gait::{
    convergence_to_prediction, simulate_from_rest, GaitTolerance, StepperSettings,
};
use crate::Result;
use hopsim_theory::error::{require_finite, require_positive};
use hopsim_theory::fixed_points::{
    find_fixed_point, FixedPoint, FixedPointGrid, GridPoint, SolverSettings,
};
use hopsim_theory::robbit::{RobbitParams, SectionState};
use hopsim_theory::AnalysisError;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;
use summary::{GaitCheck, PointSummary, RobotParameters};

/// Brakes at the end of a cross-check run that are compared with the prediction.
pub const SIMULATION_WINDOW: usize = 10;

/// How the take-off energy `E_TO` is defined (reported with every result).
pub const ENERGY_DEFINITION: &str = "E_TO = ½ (m R² + m a² + I_S − 2 m R a cos φ_TO) φ̇_TO²: kinetic energy of the rolling robot just before the brake without the flywheel's spin; φ̇_TO = −sqrt(2 E_TO / (…)) < 0 (forward rolling)";

/// What to compute.
#[derive(Clone, Debug)]
pub struct FixedPointsParams {
    /// The robot.
    pub robot: RobbitParams,
    /// One section state or a grid of them.
    pub sections: Sections,
    /// Run the time-stepper from rest with a stable `β*` (the point's, or the grid's
    /// [`selection::most_stable`]) and these settings; `None`: no run.
    pub simulation: Option<StepperSettings>,
    /// Grids only: run every fixed point from rest with these settings (the thesis'
    /// Figure 5.7, [`gaits`]); `None`: no runs.
    pub gaits: Option<StepperSettings>,
}

/// The section states to solve.
#[derive(Clone, Copy, Debug)]
pub enum Sections {
    /// One section state: take-off angle `φ_TO` [rad] and energy `E_TO` [J].
    Point { angle_rad: f64, energy_j: f64 },
    /// `angle_points × energy_points` states evenly spaced over the ranges (rad, J).
    Grid {
        angle_range_rad: (f64, f64),
        energy_range_j: (f64, f64),
        angle_points: usize,
        energy_points: usize,
    },
}

impl FixedPointsParams {
    /// Checks every number: the robot, the section states and the cross-check's step and
    /// duration (invalid-parameter errors name the offending value).
    pub fn validate(&self) -> Result<()> {
        self.robot.validate()?;
        match self.sections {
            Sections::Point {
                angle_rad,
                energy_j,
            } => {
                require_finite("takeoff-angle", angle_rad)?;
                require_finite("takeoff-energy", energy_j)?;
            }
            Sections::Grid {
                angle_range_rad: (a0, a1),
                energy_range_j: (e0, e1),
                angle_points,
                energy_points,
            } => {
                require_range("angle", a0, a1, angle_points)?;
                require_range("energy", e0, e1, energy_points)?;
                if e0 < 0.0 {
                    Err(AnalysisError::invalid("energy-min", e0, "must be ≥ 0"))?;
                }
            }
        }
        for s in self.simulation.iter().chain(&self.gaits) {
            require_positive("dt", s.dt)?;
            if !(s.duration.is_finite() && s.duration > s.dt) {
                Err(AnalysisError::invalid(
                    "duration",
                    s.duration,
                    &format!("must be finite and exceed dt = {}", s.dt),
                ))?;
            }
        }
        Ok(())
    }
}

/// A grid axis `min … max` with `points` values: finite, at least one point, and
/// `min < max` unless there is a single point.
fn require_range(axis: &str, min: f64, max: f64, points: usize) -> Result<()> {
    require_finite(&format!("{axis}-min"), min)?;
    require_finite(&format!("{axis}-max"), max)?;
    if points == 0 {
        Err(AnalysisError::invalid(
            &format!("{axis}-points"),
            0.0,
            "must be at least 1",
        ))?;
    }
    if !(min < max || points == 1) {
        Err(AnalysisError::invalid(
            &format!("{axis}-min"),
            min,
            &format!("must be below {axis}-max = {max}"),
        ))?;
    }
    Ok(())
}

/// The study's name, mode and robot (the first keys of either report).
#[derive(Clone, Debug, Serialize)]
pub struct About {
    analysis: &'static str,
    /// `point` or `grid`.
    mode: &'static str,
    case: &'static str,
    pub parameters: RobotParameters,
    energy_definition: &'static str,
}

impl About {
    fn new(mode: &'static str, p: &RobbitParams) -> Self {
        About {
            analysis: "fixed-points",
            mode,
            case: "robbit",
            parameters: p.into(),
            energy_definition: ENERGY_DEFINITION,
        }
    }
}

/// One section state's fixed point.
#[derive(Clone, Debug, Serialize)]
pub struct PointReport {
    #[serde(flatten)]
    pub about: About,
    #[serde(flatten)]
    pub point: PointSummary,
    pub elapsed_s: f64,
    /// The time-stepper cross-check, if asked for and there is a fixed point.
    pub simulation: Option<GaitCheck>,
    /// Whether the cross-check was asked for.
    #[serde(skip)]
    pub simulate_requested: bool,
}

/// A grid of section states and their fixed points.
#[derive(Clone, Debug, Serialize)]
pub struct GridReport {
    #[serde(flatten)]
    pub about: About,
    pub angles_rad: Vec<f64>,
    /// [J].
    #[serde(rename = "energies_J")]
    pub energies: Vec<f64>,
    pub points_total: usize,
    pub fixed_points: usize,
    pub stable_points: usize,
    pub unstable_points: usize,
    pub no_fixed_point: usize,
    /// Points without a fixed point per kind of reason ([`selection::reason_counts`]).
    pub no_fixed_point_reasons: BTreeMap<&'static str, usize>,
    pub fixed_points_with_warnings: usize,
    pub elapsed_s: f64,
    /// [`selection::most_stable`].
    pub most_stable: Option<PointSummary>,
    /// [`selection::fastest_stable`].
    pub fastest_stable: Option<PointSummary>,
    /// Row-major: `E_TO` outer, `φ_TO` inner.
    pub points: Vec<PointSummary>,
    /// The time-stepper cross-check of the most stable point, if asked for.
    pub simulation: Option<GaitCheck>,
    /// Whether the cross-check was asked for.
    #[serde(skip)]
    pub simulate_requested: bool,
    /// Every fixed point run from rest, if asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gaits: Option<gaits::FixedPointGaits>,
}

/// The study's result: one point or a grid.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum FixedPointsReport {
    Point(Box<PointReport>),
    Grid(Box<GridReport>),
}

/// Solves the section states of `params`, reporting the grid's progress to `progress`,
/// and runs the cross-check if asked for.
pub fn fixed_points(
    params: &FixedPointsParams,
    progress: &dyn Progress,
) -> Result<FixedPointsReport> {
    params.validate()?;
    Ok(match params.sections {
        Sections::Point {
            angle_rad,
            energy_j,
        } => FixedPointsReport::Point(Box::new(solve_point(params, angle_rad, energy_j)?)),
        Sections::Grid {
            angle_range_rad,
            energy_range_j,
            angle_points,
            energy_points,
        } => {
            let grid = FixedPointGrid::new(
                params.robot,
                angle_range_rad,
                energy_range_j,
                angle_points,
                energy_points,
            );
            FixedPointsReport::Grid(Box::new(solve_grid(params, &grid, progress)?))
        }
    })
}

/// One section state `(φ_TO, E_TO)`.
fn solve_point(params: &FixedPointsParams, angle: f64, energy: f64) -> Result<PointReport> {
    let p = &params.robot;
    let z = SectionState::from_energy(p, angle, energy)?;
    let started = Instant::now();
    let outcome = find_fixed_point(p, &z, &SolverSettings::default())?;
    let elapsed_s = started.elapsed().as_secs_f64();
    let solved = GridPoint {
        angle,
        energy,
        angular_velocity: z.angular_velocity,
        fixed_point: outcome.as_ref().ok().cloned(),
        no_fixed_point: outcome.err(),
    };
    let simulation = match (&solved.fixed_point, &params.simulation) {
        (Some(fp), Some(settings)) => Some(gait_check(p, fp, settings)?),
        _ => None,
    };
    Ok(PointReport {
        about: About::new("point", p),
        point: PointSummary::new(p, &solved),
        elapsed_s,
        simulation,
        simulate_requested: params.simulation.is_some(),
    })
}

/// Every state of `grid`, one progress tick per state.
fn solve_grid(
    params: &FixedPointsParams,
    grid: &FixedPointGrid,
    progress: &dyn Progress,
) -> Result<GridReport> {
    let p = &params.robot;
    let started = Instant::now();
    let solved = {
        let tick = progress.task(
            grid.angles.len() * grid.energies.len(),
            "Robbit fixed points",
        );
        grid.run(&*tick)?
    };
    let elapsed_s = started.elapsed().as_secs_f64();
    let points: Vec<PointSummary> = solved.iter().map(|q| PointSummary::new(p, q)).collect();
    let most_stable = selection::most_stable(&points);
    let simulation = match (most_stable, &params.simulation) {
        (Some(i), Some(settings)) => {
            let fp = solved[i].fixed_point.as_ref().expect("a stable point");
            Some(gait_check(p, fp, settings)?)
        }
        _ => None,
    };
    let gaits = match &params.gaits {
        Some(settings) => Some(gaits::simulate_fixed_points(
            p, &solved, settings, progress,
        )?),
        None => None,
    };
    let fixed_points = points.iter().filter(|q| q.fixed_point).count();
    let stable_points = points.iter().filter(|q| q.stable).count();
    Ok(GridReport {
        about: About::new("grid", p),
        angles_rad: grid.angles.clone(),
        energies: grid.energies.clone(),
        points_total: points.len(),
        fixed_points,
        stable_points,
        unstable_points: fixed_points - stable_points,
        no_fixed_point: points.len() - fixed_points,
        no_fixed_point_reasons: selection::reason_counts(&points),
        fixed_points_with_warnings: selection::with_warnings(&points),
        elapsed_s,
        most_stable: most_stable.map(|i| points[i].clone()),
        fastest_stable: selection::fastest_stable(&points).map(|i| points[i].clone()),
        points,
        simulation,
        simulate_requested: params.simulation.is_some(),
        gaits,
    })
}

/// Runs the time-stepper from rest with `fp`'s control and measures how its take-offs
/// approach `fp` over the last [`SIMULATION_WINDOW`] brakes.
fn gait_check(p: &RobbitParams, fp: &FixedPoint, settings: &StepperSettings) -> Result<GaitCheck> {
    let started = Instant::now();
    let run = simulate_from_rest(p, &fp.control, settings)?;
    let convergence =
        convergence_to_prediction(fp, &run, SIMULATION_WINDOW, &GaitTolerance::default());
    let elapsed_s = started.elapsed().as_secs_f64();
    Ok(GaitCheck::new(p, fp, run, convergence.as_ref(), elapsed_s))
}

impl Report for FixedPointsReport {
    fn text(&self) -> String {
        match self {
            FixedPointsReport::Point(r) => text::point_text(r),
            FixedPointsReport::Grid(r) => text::grid_text(r),
        }
    }

    /// `fixed_point.csv` (point) or `fixed_points.csv` and the three maps (grid), then the
    /// cross-check's take-offs.
    fn files(&self) -> Vec<ReportFile> {
        let (mut out, simulation) = match self {
            FixedPointsReport::Point(r) => (
                vec![ReportFile::csv(
                    "fixed_point.csv",
                    files::points_csv([&r.point]),
                )],
                &r.simulation,
            ),
            FixedPointsReport::Grid(r) => {
                let mut out = vec![ReportFile::csv(
                    "fixed_points.csv",
                    files::points_csv(&r.points),
                )];
                let friction = r.about.parameters.friction;
                let maps = files::grid_maps(&r.angles_rad, &r.energies, &r.points, friction);
                out.extend(maps);
                out.extend(r.gaits.iter().flat_map(gaits::FixedPointGaits::files));
                (out, &r.simulation)
            }
        };
        if let Some(check) = simulation {
            out.extend(files::gait_check_files(check));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::Silent;

    fn point_params(angle_rad: f64, energy_j: f64, simulate: bool) -> FixedPointsParams {
        FixedPointsParams {
            robot: RobbitParams::default(),
            sections: Sections::Point {
                angle_rad,
                energy_j,
            },
            simulation: simulate.then(StepperSettings::default),
            gaits: None,
        }
    }

    fn file_names(report: &FixedPointsReport) -> Vec<String> {
        report
            .files()
            .iter()
            .map(|f| match f {
                ReportFile::Csv { name, .. } => name.clone(),
                ReportFile::Figure { stem, .. } => stem.clone(),
            })
            .collect()
    }

    /// A fixed point's fields join the point's object; without one they are absent and
    /// the reason says why, in the JSON, the CSV and the text alike.
    #[test]
    fn a_point_reports_its_fixed_point_or_its_reason() {
        let found = fixed_points(&point_params(-0.8, 0.08, false), &Silent).unwrap();
        let v = serde_json::to_value(&found).unwrap();
        assert_eq!(
            (v["mode"].as_str(), v["fixed_point"].as_bool()),
            (Some("point"), Some(true))
        );
        assert!(v["torque_Nm"].as_f64().unwrap() > 0.0);
        assert_eq!(v["eigenvalues"].as_array().unwrap().len(), 2);
        assert!(v["simulation"].is_null() && v["reason"].is_null());
        assert!(found.text().contains("β* = (T*, ζ0*)"));
        assert_eq!(file_names(&found), ["fixed_point.csv"]);

        let none = fixed_points(&point_params(-0.15, 0.005, true), &Silent).unwrap();
        let v = serde_json::to_value(&none).unwrap();
        assert_eq!(v["fixed_point"], false);
        assert_eq!(v["reason_kind"], "solver-failed");
        assert!(v.get("torque_Nm").is_none() && v["simulation"].is_null());
        let text = none.text();
        assert!(text.contains("none: solver failed"), "{text}");
        assert!(
            text.ends_with("--simulate: no fixed point to simulate\n"),
            "{text}"
        );
    }

    /// Each bad number is refused as the user's input and named: NaN, a reversed or empty
    /// axis, a negative energy, a zero time step.
    #[test]
    fn bad_numbers_are_named_invalid_parameters() {
        let grid = |angles: (f64, f64), energies: (f64, f64), n: usize| FixedPointsParams {
            sections: Sections::Grid {
                angle_range_rad: angles,
                energy_range_j: energies,
                angle_points: n,
                energy_points: n,
            },
            ..point_params(-0.8, 0.08, false)
        };
        let mut zero_dt = point_params(-0.8, 0.08, true);
        zero_dt.simulation.as_mut().unwrap().dt = 0.0;
        for (params, name) in [
            (point_params(f64::NAN, 0.08, false), "takeoff-angle"),
            (grid((0.2, -0.2), (0.02, 0.1), 3), "angle-min"),
            (grid((-1.0, -0.2), (-0.1, 0.1), 3), "energy-min"),
            (grid((-1.0, -0.2), (0.02, 0.1), 0), "angle-points"),
            (zero_dt, "dt"),
        ] {
            let err = fixed_points(&params, &Silent).unwrap_err();
            assert!(err.is_invalid_input(), "{err}");
            assert!(err.to_string().contains(&format!("`{name}`")), "{err}");
        }
        // One point per axis needs no span.
        assert!(grid((-0.5, -0.5), (0.05, 0.05), 1).validate().is_ok());
    }

    /// A grid reports every point, counts that add up, its selections among the points
    /// and one CSV with three maps.
    #[test]
    fn a_grid_counts_selects_and_maps_its_points() {
        let params = FixedPointsParams {
            robot: RobbitParams::default(),
            sections: Sections::Grid {
                angle_range_rad: (-1.2, -0.3),
                energy_range_j: (0.02, 0.1),
                angle_points: 3,
                energy_points: 2,
            },
            simulation: None,
            gaits: None,
        };
        let FixedPointsReport::Grid(r) = fixed_points(&params, &Silent).unwrap() else {
            panic!("a grid report")
        };
        assert_eq!((r.points.len(), r.points_total), (6, 6));
        assert_eq!(r.fixed_points + r.no_fixed_point, 6);
        assert_eq!(r.stable_points + r.unstable_points, r.fixed_points);
        assert_eq!(
            r.no_fixed_point_reasons.values().sum::<usize>(),
            r.no_fixed_point
        );
        let best = r.most_stable.as_ref().expect("a stable point");
        assert_eq!(
            best.takeoff_angle_rad,
            r.points[selection::most_stable(&r.points).unwrap()].takeoff_angle_rad
        );
        let report = FixedPointsReport::Grid(r);
        assert_eq!(
            file_names(&report),
            [
                "fixed_points.csv",
                "fixed_points_torque",
                "fixed_points_impulse_limit",
                "fixed_points_max_eigenvalue"
            ]
        );
        assert!(report.text().contains("3 × 2 grid"));
    }
}
