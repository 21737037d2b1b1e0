//! The thesis' Figure 5.7 (docs/physics.md §5.3): every fixed-point control `β* = (T*, ζ0*)` of
//! a grid run in the time-stepper from rest, its mean speed and transferred angular impulse
//! per distance over the run's last `speed_window` seconds (the run summary's window),
//! against the cube baseline [5.21] for `ε = 0` and for the restitution `ε_eq` whose cube
//! passes through the most stable decile of the runs.

use super::summary::SectionControl;
use crate::plot::{viridis, LinePlot, RGBColor, Series, SeriesStyle};
use crate::progress::Progress;
use crate::report::{num, ReportFile, TextTable};
use crate::robbit_gait::{rest_state, robbit_scene, StepperSettings};
use crate::run_summary::run_scene;
use crate::sweep::speed_against_impulse;
use hopsim_io::{Cell, CsvTable};
use hopsim_theory::cube::Cube;
use hopsim_theory::fixed_points::GridPoint;
use hopsim_theory::grid::par_map;
use hopsim_theory::robbit::RobbitParams;
use serde::Serialize;
use std::time::Instant;

/// What the thesis reports of Figure 5.7: the disc needs about ten times less impulse per
/// distance than the inelastic cube, and the cube with `ε = 0.87` passes through the most
/// stable disc points (docs/physics.md §5.3). Shown next to hopsim's figures, never used in them.
pub const THESIS_IMPULSE_RATIO: f64 = 10.0;
/// See [`THESIS_IMPULSE_RATIO`].
pub const THESIS_EQUIVALENT_RESTITUTION: f64 = 0.87;

/// The share of the completed stable runs, lowest max |λ| first, the cube is fitted to.
pub const FITTED_SHARE: f64 = 0.1;

/// One fixed point run from rest.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GaitRun {
    #[serde(flatten)]
    pub point: SectionControl,
    /// Spectral radius of the return-map Jacobian at `β*`.
    pub max_abs_eigenvalue: f64,
    pub stable: bool,
    /// Mean forward speed over the window [m/s] (None: the run failed).
    pub mean_speed_mps: Option<f64>,
    /// `Σζ / distance` over the window [N m s/m] (None: the run failed or did not move).
    #[serde(rename = "impulse_per_distance_Nms_per_m")]
    pub impulse_per_distance: Option<f64>,
    /// Flight phases of the whole run.
    pub hops: Option<u64>,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
}

impl GaitRun {
    /// `(Σζ/distance, speed)` when both are finite and the robot moved forward.
    pub fn point(&self) -> Option<(f64, f64)> {
        let (x, u) = (self.impulse_per_distance?, self.mean_speed_mps?);
        (x.is_finite() && u.is_finite() && x > 0.0 && u > 0.0).then_some((x, u))
    }
}

/// The cube that passes through the chosen runs: `1 − ε_eq` is the geometric mean of each
/// run's `Σζ/distance` over the inelastic cube's at the run's speed ([5.21] is linear in
/// `1 − ε`), so `ε_eq`'s curve passes through them in the mean of the logarithms.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EquivalentCube {
    /// `ε_eq`.
    pub restitution: f64,
    /// `1 / (1 − ε_eq)`: how many times less impulse per distance the runs need than the
    /// inelastic cube at the same speed.
    pub impulse_ratio: f64,
    /// Runs fitted.
    pub runs: usize,
    /// The largest max |λ| among them.
    pub max_abs_eigenvalue: f64,
}

/// Fits [`EquivalentCube`] to `points` = `(Σζ/distance, speed, max |λ|)`; `None` without
/// points.
pub fn fit_equivalent_cube(cube: &Cube, points: &[(f64, f64, f64)]) -> Option<EquivalentCube> {
    if points.is_empty() {
        return None;
    }
    let mean_log = points
        .iter()
        .map(|&(x, u, _)| (x / cube.impulse_per_distance(u, 0.0)).ln())
        .sum::<f64>()
        / points.len() as f64;
    let remaining = mean_log.exp();
    Some(EquivalentCube {
        restitution: 1.0 - remaining,
        impulse_ratio: 1.0 / remaining,
        runs: points.len(),
        max_abs_eigenvalue: points.iter().map(|p| p.2).fold(0.0, f64::max),
    })
}

/// The completed stable runs with the lowest max |λ|: [`FITTED_SHARE`] of them, at least one.
pub fn most_stable_share(runs: &[GaitRun]) -> Vec<(f64, f64, f64)> {
    let mut stable: Vec<(f64, f64, f64)> = runs
        .iter()
        .filter(|r| r.stable)
        .filter_map(|r| r.point().map(|(x, u)| (x, u, r.max_abs_eigenvalue)))
        .collect();
    stable.sort_by(|a, b| a.2.total_cmp(&b.2));
    let keep = ((stable.len() as f64 * FITTED_SHARE).ceil() as usize).max(1);
    stable.truncate(keep);
    stable
}

/// Every fixed point of a grid run from rest, and the cubes.
#[derive(Clone, Debug, Serialize)]
pub struct FixedPointGaits {
    /// Time step, duration and rearm timeout of every run.
    pub settings: StepperSettings,
    /// The window the speed and impulse are measured over: the run's last seconds [s].
    pub speed_window_s: f64,
    /// One row per fixed point, in grid order.
    pub runs: Vec<GaitRun>,
    pub failed_runs: usize,
    /// The cube equivalent to Robbit's disc, [5.21].
    pub cube: Cube,
    /// The cube through the most stable runs ([`most_stable_share`]).
    pub equivalent_cube: Option<EquivalentCube>,
    pub thesis_impulse_ratio: f64,
    pub thesis_equivalent_restitution: f64,
    pub elapsed_s: f64,
}

/// Runs every fixed point of `solved` from rest with `settings` on all cores, ticking
/// `progress` once per run.
pub fn simulate_fixed_points(
    p: &RobbitParams,
    solved: &[GridPoint],
    settings: &StepperSettings,
    progress: &dyn Progress,
) -> crate::Result<FixedPointGaits> {
    let started = Instant::now();
    let points: Vec<&GridPoint> = solved.iter().filter(|g| g.fixed_point.is_some()).collect();
    // The window comes from the scene (its summary settings); the first point's scene is
    // built here so that an invalid setting stops the study before any run.
    let window = match points.first() {
        Some(g) => {
            let fp = g.fixed_point.as_ref().expect("filtered");
            robbit_scene(p, &fp.control, settings, &rest_state(p))?
                .settings
                .speed_window
        }
        None => 0.0,
    };
    let tick = progress.task(points.len(), "fixed points from rest");
    let runs = par_map(&points, &*tick, |g| run_from_rest(p, g, settings));
    drop(tick);
    let cube = Cube::of_disc(
        p.total_mass(),
        p.body_inertia,
        p.radius,
        p.eccentricity,
        p.gravity,
    );
    Ok(FixedPointGaits {
        settings: *settings,
        speed_window_s: window,
        failed_runs: runs.iter().filter(|r| r.error.is_some()).count(),
        equivalent_cube: fit_equivalent_cube(&cube, &most_stable_share(&runs)),
        runs,
        cube,
        thesis_impulse_ratio: THESIS_IMPULSE_RATIO,
        thesis_equivalent_restitution: THESIS_EQUIVALENT_RESTITUTION,
        elapsed_s: started.elapsed().as_secs_f64(),
    })
}

/// One fixed point's run: Robbit's scene from rest with `β*`, summarised like `hopsim run`.
fn run_from_rest(p: &RobbitParams, g: &GridPoint, settings: &StepperSettings) -> GaitRun {
    let fp = g.fixed_point.as_ref().expect("a fixed point");
    let mut row = GaitRun {
        point: SectionControl::of(p, fp),
        max_abs_eigenvalue: fp.spectral_radius,
        stable: fp.stable,
        mean_speed_mps: None,
        impulse_per_distance: None,
        hops: None,
        error: None,
    };
    let report = robbit_scene(p, &fp.control, settings, &rest_state(p))
        .map_err(|e| e.to_string())
        .and_then(|scene| run_scene(&scene, &mut ()).map_err(|e| e.to_string()));
    match report {
        Ok(r) => {
            row.mean_speed_mps = Some(r.summary.mean_speed_mps);
            row.impulse_per_distance = r.robbit.map(|b| b.impulse_per_distance);
            row.hops = Some(r.summary.hops);
        }
        Err(e) => row.error = Some(e),
    }
    row
}

/// Bins of max |λ| for the stable runs' colours.
const STABILITY_BINS: usize = 5;

impl FixedPointGaits {
    /// One CSV row per run.
    pub fn table(&self) -> CsvTable {
        let mut t = CsvTable::new(&[
            "takeoff_angle_rad",
            "takeoff_energy_J",
            "torque_Nm",
            "impulse_limit_Nms",
            "max_abs_eigenvalue",
            "stable",
            "mean_speed_mps",
            "impulse_per_distance_Nms_per_m",
            "hops",
            "error",
        ]);
        for r in &self.runs {
            t.push(vec![
                r.point.takeoff_angle_rad.into(),
                r.point.takeoff_energy.into(),
                r.point.torque.into(),
                r.point.impulse_limit.into(),
                r.max_abs_eigenvalue.into(),
                r.stable.into(),
                r.mean_speed_mps.into(),
                r.impulse_per_distance.into(),
                r.hops.map_or(Cell::Empty, Cell::from),
                r.error.as_deref().unwrap_or_default().into(),
            ]);
        }
        t
    }

    /// Figure 5.7: speed against impulse per distance, stable runs coloured by max |λ|,
    /// unstable runs as grey crosses, the inelastic and the equivalent cube.
    pub fn figure(&self) -> LinePlot {
        let mut series = Vec::new();
        for bin in 0..STABILITY_BINS {
            let (lo, hi) = (
                bin as f64 / STABILITY_BINS as f64,
                (bin + 1) as f64 / STABILITY_BINS as f64,
            );
            let points: Vec<(f64, f64)> = self
                .runs
                .iter()
                .filter(|r| r.stable && r.max_abs_eigenvalue >= lo && r.max_abs_eigenvalue < hi)
                .filter_map(GaitRun::point)
                .collect();
            if !points.is_empty() {
                let label = format!("stable, max |λ| {lo:.1}–{hi:.1}");
                let colour = viridis((bin as f64 + 0.5) / STABILITY_BINS as f64);
                series.push(Series::points(label, points).color(colour));
            }
        }
        let unstable: Vec<(f64, f64)> = self
            .runs
            .iter()
            .filter(|r| !r.stable)
            .filter_map(GaitRun::point)
            .collect();
        if !unstable.is_empty() {
            series.push(
                Series::points("unstable (max |λ| ≥ 1)", unstable)
                    .style(SeriesStyle::Crosses)
                    .color(RGBColor(150, 150, 150)),
            );
        }
        let mut cubes = vec![(0.0, "inelastic cube, ε = 0".to_string())];
        if let Some(eq) = &self.equivalent_cube {
            let label = format!(
                "cube through the most stable runs, ε_eq = {:.2}",
                eq.restitution
            );
            cubes.push((eq.restitution, label));
        }
        speed_against_impulse(
            "Robbit's fixed points run from rest: speed against impulse".into(),
            series,
            Some(&self.cube),
            &cubes,
        )
    }

    /// The runs in numbers and the summary line against the thesis.
    pub fn text(&self) -> String {
        let mut table = TextTable::new("Fixed points run from rest (the thesis' Figure 5.7)");
        let completed = self.runs.iter().filter(|r| r.point().is_some()).count();
        table.row(
            "fixed points run from rest",
            format!(
                "{} ({} moved forward, {} failed), {} each, window {}, {:.1} s",
                self.runs.len(),
                completed,
                self.failed_runs,
                num(self.settings.duration, "s"),
                num(self.speed_window_s, "s"),
                self.elapsed_s
            ),
        );
        let line = match &self.equivalent_cube {
            Some(eq) => format!(
                "the disc needs {:.1}× less impulse per metre than the inelastic cube at the same speed (ε_eq = {:.3}, {} most stable runs, max |λ| ≤ {:.3}); thesis: ≈ {}×, ε_eq ≈ {}",
                eq.impulse_ratio,
                eq.restitution,
                eq.runs,
                eq.max_abs_eigenvalue,
                self.thesis_impulse_ratio,
                self.thesis_equivalent_restitution
            ),
            None => "no stable run moved forward: no equivalent cube".into(),
        };
        table.row("against the cube", line);
        table.to_string()
    }

    /// `fixed_point_gaits.csv` and the figure.
    pub fn files(&self) -> Vec<ReportFile> {
        vec![
            ReportFile::csv("fixed_point_gaits.csv", self.table()),
            ReportFile::figure("fixed_point_gaits", self.figure()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Cube {
        Cube::of_disc(1.405, 3.004e-3, 0.2, 0.1, 9.81)
    }

    /// Points lying on the cube of `ε = 0.8` give back `ε_eq = 0.8` and a ratio of 5,
    /// whatever their speeds; scattered points give the cube through their geometric mean.
    #[test]
    fn the_equivalent_cube_passes_through_the_points() {
        let c = cube();
        let on_curve: Vec<(f64, f64, f64)> = [0.2, 0.5, 1.3]
            .iter()
            .map(|&u| (c.impulse_per_distance(u, 0.8), u, 0.3))
            .collect();
        let fit = fit_equivalent_cube(&c, &on_curve).unwrap();
        assert!((fit.restitution - 0.8).abs() < 1e-12, "{fit:?}");
        assert!((fit.impulse_ratio - 5.0).abs() < 1e-10, "{fit:?}");
        // Two points at 1/2 and 1/8 of the inelastic cube: geometric mean 1/4, ε_eq = 0.75.
        let scattered = [
            (0.5 * c.impulse_per_distance(0.4, 0.0), 0.4, 0.1),
            (0.125 * c.impulse_per_distance(0.9, 0.0), 0.9, 0.2),
        ];
        let fit = fit_equivalent_cube(&c, &scattered).unwrap();
        assert!((fit.restitution - 0.75).abs() < 1e-12, "{fit:?}");
        assert_eq!((fit.runs, fit.max_abs_eigenvalue), (2, 0.2));
        assert!(fit_equivalent_cube(&c, &[]).is_none());
    }

    fn run(max_abs_eigenvalue: f64, speed: Option<f64>) -> GaitRun {
        GaitRun {
            point: SectionControl {
                takeoff_angle_rad: -0.5,
                takeoff_energy: 0.05,
                torque: 0.3,
                impulse_limit: 0.05,
            },
            max_abs_eigenvalue,
            stable: max_abs_eigenvalue < 1.0,
            mean_speed_mps: speed,
            impulse_per_distance: speed.map(|u| 1.0 / u),
            hops: Some(3),
            error: None,
        }
    }

    /// The fitted share is the lowest max |λ| tenth of the stable runs that moved forward
    /// (at least one); unstable, failed and backward runs are left out.
    #[test]
    fn the_most_stable_tenth_is_fitted() {
        let mut runs: Vec<GaitRun> = (0..25)
            .map(|i| run(0.9 - 0.03 * i as f64, Some(0.5)))
            .collect();
        runs.push(run(1.5, Some(0.5)));
        runs.push(run(0.01, None));
        runs.push(run(0.02, Some(-0.1)));
        let chosen = most_stable_share(&runs);
        assert_eq!(chosen.len(), 3, "ceil(25 / 10)");
        let lambdas: Vec<f64> = chosen.iter().map(|c| c.2).collect();
        assert!(
            lambdas.iter().all(|&l| l <= 0.9 - 0.03 * 22.0 + 1e-12),
            "{lambdas:?}"
        );
        assert_eq!(most_stable_share(&runs[..1]).len(), 1);
        assert!(most_stable_share(&runs[25..]).is_empty());
    }
}
