//! The fixed-point study's files: the points as CSV, the maps of `T*`, `ζ0*` and `max |λ|`
//! over the grid, and the take-off errors of the time-stepper cross-check.

use super::selection::{colour_range, grid_markers, unstable};
use super::summary::{FixedPointSummary, GaitCheck, PointSummary};
use crate::plot::{
    three_significant_digits, ColourScale, Heatmap, LinePlot, Series, SeriesStyle, BLACK, PALETTE,
};
use crate::report::ReportFile;
use hopsim_io::{Cell, CsvTable};

/// The CSV of section states and their fixed points, one row per point.
pub fn points_csv<'a>(points: impl IntoIterator<Item = &'a PointSummary>) -> CsvTable {
    let mut csv = CsvTable::new(&[
        "takeoff_angle_rad",
        "takeoff_energy_J",
        "takeoff_rate_rad_s",
        "fixed_point",
        "torque_Nm",
        "impulse_limit_Nms",
        "lambda1_re",
        "lambda1_im",
        "lambda1_modulus",
        "lambda1_argument_rad",
        "lambda2_re",
        "lambda2_im",
        "lambda2_modulus",
        "lambda2_argument_rad",
        "max_abs_lambda",
        "stable",
        "speed_mps",
        "stride_m",
        "period_s",
        "impulse_per_distance_Nms_per_m",
        "stance_reversals",
        "warnings",
        "reason",
    ]);
    for q in points {
        let f = q.details.as_ref();
        let value = |get: fn(&FixedPointSummary) -> f64| Cell::from(f.map(get));
        csv.push(vec![
            q.takeoff_angle_rad.into(),
            q.takeoff_energy.into(),
            q.takeoff_rate_rad_s.into(),
            q.fixed_point.into(),
            value(|f| f.torque),
            value(|f| f.impulse_limit),
            value(|f| f.eigenvalues[0].re),
            value(|f| f.eigenvalues[0].im),
            value(|f| f.eigenvalues[0].modulus),
            value(|f| f.eigenvalues[0].argument),
            value(|f| f.eigenvalues[1].re),
            value(|f| f.eigenvalues[1].im),
            value(|f| f.eigenvalues[1].modulus),
            value(|f| f.eigenvalues[1].argument),
            value(|f| f.max_abs_eigenvalue),
            f.map_or(Cell::Empty, |_| q.stable.into()),
            value(|f| f.speed_mps),
            value(|f| f.stride_m),
            value(|f| f.period_s),
            value(|f| f.impulse_per_distance),
            f.map_or(Cell::Empty, |f| f.stance_reversals.into()),
            f.map_or(Cell::Empty, |f| Cell::Text(f.warnings.join("; "))),
            q.reason.clone().map_or(Cell::Empty, Cell::Text),
        ]);
    }
    csv
}

/// One map of the grid: a quantity of the fixed points over `φ_TO × E_TO`.
struct GridMap {
    stem: &'static str,
    title: &'static str,
    label: &'static str,
    /// Cut a long upper tail of the colour scale (the torques next to `φ_TO = 0`).
    cap: bool,
    colours: ColourScale,
    value: fn(&FixedPointSummary) -> f64,
}

/// `T*` and `ζ0*` with capped colours; `max |λ|` keeps its full range on a scale that
/// diverges at 1, blue where the gait is stable and red where it is not.
const GRID_MAPS: [GridMap; 3] = [
    GridMap {
        stem: "fixed_points_torque",
        title: "fixed-point torque T*",
        label: "T* (N m)",
        cap: true,
        colours: ColourScale::Sequential,
        value: |f| f.torque,
    },
    GridMap {
        stem: "fixed_points_impulse_limit",
        title: "fixed-point impulse limit ζ0*",
        label: "ζ0* (N m s)",
        cap: true,
        colours: ColourScale::Sequential,
        value: |f| f.impulse_limit,
    },
    GridMap {
        stem: "fixed_points_max_eigenvalue",
        title: "max |λ| of ∂P/∂z",
        label: "max |λ|",
        cap: false,
        colours: ColourScale::Diverging { centre: 1.0 },
        value: |f| f.max_abs_eigenvalue,
    },
];

/// The heatmaps of [`GRID_MAPS`] over the grid `angles × energies` (points row-major,
/// angles inner); blank where there is no fixed point, a cross on unstable ones and a ring
/// on those that leave the friction cone of `μ = friction`.
pub fn grid_maps(
    angles: &[f64],
    energies: &[f64],
    points: &[PointSummary],
    friction: f64,
) -> Vec<ReportFile> {
    let slipping =
        |q: &PointSummary| (q.details.as_ref()).is_some_and(|f| f.leaves_friction_cone(friction));
    let markers = [
        (
            "unstable (max |λ| ≥ 1)".to_string(),
            SeriesStyle::Crosses,
            grid_markers(points, angles.len(), unstable),
        ),
        (
            format!(
                "leaves the friction cone (μ = {})",
                three_significant_digits(friction)
            ),
            SeriesStyle::Rings,
            grid_markers(points, angles.len(), slipping),
        ),
    ];
    GRID_MAPS
        .iter()
        .map(|map| {
            let values: Vec<Option<f64>> = points
                .iter()
                .map(|q| q.details.as_ref().map(map.value))
                .collect();
            let range = colour_range(&values, map.cap);
            let mut h = Heatmap::new(
                format!("Robbit {} (blank: no fixed point)", map.title),
                "take-off angle φ_TO (rad)",
                "take-off energy E_TO (J)",
                map.label,
                angles.to_vec(),
                energies.to_vec(),
                values,
            )
            .with_value_range(range.min, range.max)
            .with_colour_scale(map.colours);
            for (label, style, at) in markers.iter().filter(|m| !m.2.is_empty()) {
                let series = Series::points(label.clone(), at.clone()).style(*style);
                h = h.with_overlay(series.color(BLACK));
            }
            ReportFile::figure(map.stem, h)
        })
        .collect()
}

/// The cross-check's take-offs as CSV and their errors as a plot (none without two
/// brakes).
pub fn gait_check_files(check: &GaitCheck) -> Vec<ReportFile> {
    let Some(errors) = &check.takeoff_errors else {
        return Vec::new();
    };
    let mut csv = CsvTable::new(&[
        "brake",
        "t_s",
        "x_m",
        "takeoff_angle_rad",
        "takeoff_rate_rad_s",
        "stored_impulse_Nms",
        "angle_error_rad",
        "rate_error_rad_s",
    ]);
    for (b, d) in check.brake_states.iter().zip(errors) {
        csv.push(vec![
            d.brake.into(),
            b.t.into(),
            b.x.into(),
            b.state.angle.into(),
            b.state.angular_velocity.into(),
            b.stored_impulse.into(),
            d.angle_error_rad.into(),
            d.rate_error_rad_s.into(),
        ]);
    }
    let series = |error: fn(&super::summary::TakeoffError) -> f64| {
        errors
            .iter()
            .map(|d| (d.brake as f64, error(d)))
            .collect::<Vec<_>>()
    };
    let plot = LinePlot::new(
        "time-stepper take-off states minus the predicted fixed point",
        "brake number",
        "take-off state error (rad, rad/s)",
    )
    .with_series(
        Series::line("angle φ − φ* (rad)", series(|d| d.angle_error_rad))
            .style(SeriesStyle::LineAndPoints)
            .color(PALETTE[0]),
    )
    .with_series(
        Series::line(
            "rate dφ/dt − (dφ/dt)* (rad/s)",
            series(|d| d.rate_error_rad_s),
        )
        .style(SeriesStyle::LineAndPoints)
        .color(PALETTE[1]),
    )
    .with_series(
        Series::line("", vec![(0.0, 0.0), (errors.len() as f64, 0.0)])
            .color(BLACK)
            .size(1)
            .unlabelled(),
    );
    vec![
        ReportFile::csv("simulation_takeoffs.csv", csv),
        ReportFile::figure("simulation_takeoffs", plot),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::AnyFigure;

    /// A fixed point with `max |λ|`, touchdown percussions `(Λ_N, Λ_T)` and the stance's
    /// largest `|F_T|/F_N`.
    fn point(at: (f64, f64), radius: f64, percussion: (f64, f64), stance: f64) -> PointSummary {
        PointSummary {
            takeoff_angle_rad: at.0,
            takeoff_energy: at.1,
            fixed_point: true,
            stable: radius < 1.0,
            details: Some(FixedPointSummary {
                torque: 0.2,
                impulse_limit: 0.05,
                max_abs_eigenvalue: radius,
                touchdown_normal_percussion: percussion.0,
                touchdown_tangential_percussion: percussion.1,
                max_stance_friction_ratio: stance,
                ..FixedPointSummary::default()
            }),
            ..PointSummary::default()
        }
    }

    /// Every map marks the unstable fixed points with crosses and those that leave the
    /// friction cone (`|Λ_T| > μ Λ_N` at touchdown, or `|F_T|/F_N > μ` in stance) with
    /// rings; a pulling touchdown is another warning, not a ring. The `max |λ|` map diverges
    /// at 1, the others are sequential.
    #[test]
    fn maps_mark_unstable_and_slipping_fixed_points() {
        let points = [
            point((-1.0, 0.02), 0.5, (1.0, 0.5), 0.3),
            point((-0.5, 0.02), 1.5, (1.0, 0.5), 0.3),
            point((0.0, 0.02), 0.5, (-1.0, 5.0), 0.3),
            point((-1.0, 0.04), 0.5, (1.0, 1.2), 0.3),
            point((-0.5, 0.04), 0.5, (1.0, -0.2), 1.1),
            PointSummary {
                takeoff_angle_rad: 0.0,
                takeoff_energy: 0.04,
                ..PointSummary::default()
            },
        ];
        let maps = grid_maps(&[-1.0, -0.5, 0.0], &[0.02, 0.04], &points, 1.0);
        let heatmaps: Vec<&Heatmap> = (maps.iter())
            .map(|f| match f {
                ReportFile::Figure {
                    figure: AnyFigure::Heatmap(h),
                    ..
                } => h,
                _ => panic!("the grid's maps are heatmaps"),
            })
            .collect();
        assert_eq!(heatmaps.len(), 3);
        for h in &heatmaps {
            let marked = |style| {
                (h.overlays.iter())
                    .find(|s| s.style == style)
                    .map(|s| s.points.clone())
            };
            assert_eq!(marked(SeriesStyle::Crosses), Some(vec![(-0.5, 0.02)]));
            assert_eq!(
                marked(SeriesStyle::Rings),
                Some(vec![(-1.0, 0.04), (-0.5, 0.04)])
            );
        }
        let scales: Vec<ColourScale> = heatmaps.iter().map(|h| h.colour_scale).collect();
        assert_eq!(
            scales,
            [
                ColourScale::Sequential,
                ColourScale::Sequential,
                ColourScale::Diverging { centre: 1.0 }
            ]
        );
    }
}
