//! The thesis' Figure 5.7 pipeline (docs/physics.md §5.3) on a small grid: every fixed point of
//! the grid run from rest in the time-stepper, its speed and impulse per distance over the
//! run's last seconds, and the cube through the most stable runs.

use hopsim_studies::fixed_points::gaits::{most_stable_share, FixedPointGaits};
use hopsim_studies::fixed_points::{fixed_points, FixedPointsParams, FixedPointsReport, Sections};
use hopsim_studies::progress::Silent;
use hopsim_studies::robbit_gait::StepperSettings;
use hopsim_studies::{Report, ReportFile};
use hopsim_theory::fixed_points::{DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE};
use hopsim_theory::robbit::RobbitParams;

fn gaits(angle_points: usize, energy_points: usize) -> (FixedPointsReport, FixedPointGaits) {
    let params = FixedPointsParams {
        robot: RobbitParams::default(),
        sections: Sections::Grid {
            angle_range_rad: DEFAULT_ANGLE_RANGE,
            energy_range_j: DEFAULT_ENERGY_RANGE,
            angle_points,
            energy_points,
        },
        simulation: None,
        gaits: Some(StepperSettings::default()),
    };
    let report = fixed_points(&params, &Silent).expect("the study runs");
    let FixedPointsReport::Grid(grid) = &report else {
        panic!("a grid report")
    };
    let gaits = grid.gaits.clone().expect("gaits were asked for");
    (report, gaits)
}

/// One row per fixed point of the grid, each run finite (or failed with its reason), the
/// same rows on a second run (the runs are spread over threads); the fitted cube passes
/// through the chosen runs (mean log ratio 0) and needs less impulse than the inelastic
/// one; the CSV has a row per run and the figure is drawn.
#[test]
fn every_fixed_point_runs_and_the_cube_is_fitted_through_the_most_stable() {
    let (report, g) = gaits(4, 3);
    let FixedPointsReport::Grid(grid) = &report else {
        unreachable!()
    };
    assert_eq!(g.runs.len(), grid.fixed_points);
    assert!(g.runs.len() >= 3, "{} fixed points", g.runs.len());
    for r in &g.runs {
        match &r.error {
            None => {
                let (u, x) = (r.mean_speed_mps.unwrap(), r.impulse_per_distance.unwrap());
                assert!(u.is_finite() && x.is_finite(), "{r:?}");
            }
            Some(e) => assert!(!e.is_empty() && r.mean_speed_mps.is_none(), "{r:?}"),
        }
        assert_eq!(r.stable, r.max_abs_eigenvalue < 1.0, "{r:?}");
    }
    println!(
        "{} runs, {} failed, ε_eq {:?}",
        g.runs.len(),
        g.failed_runs,
        g.equivalent_cube
    );

    let (_, again) = gaits(4, 3);
    assert_eq!(again.runs, g.runs, "reproducible rows in grid order");

    let chosen = most_stable_share(&g.runs);
    let eq = g
        .equivalent_cube
        .as_ref()
        .expect("a stable run moved forward");
    assert_eq!(eq.runs, chosen.len());
    let mean_log_ratio = chosen
        .iter()
        .map(|&(x, u, _)| (x / g.cube.impulse_per_distance(u, eq.restitution)).ln())
        .sum::<f64>()
        / chosen.len() as f64;
    assert!(mean_log_ratio.abs() < 1e-12, "{mean_log_ratio}");
    assert!(eq.restitution < 1.0 && eq.impulse_ratio > 0.0);

    let files = report.files();
    let csv = files
        .iter()
        .find_map(|f| match f {
            ReportFile::Csv { name, table } if name == "fixed_point_gaits.csv" => Some(table),
            _ => None,
        })
        .expect("fixed_point_gaits.csv");
    assert_eq!(csv.len(), g.runs.len());
    assert!(files
        .iter()
        .any(|f| matches!(f, ReportFile::Figure { stem, .. } if stem == "fixed_point_gaits")));
    assert!(report
        .text()
        .contains("less impulse per metre than the inelastic cube"));
}
