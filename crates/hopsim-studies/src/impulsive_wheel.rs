//! The impulsive wheel's take-off-angle return map (docs/physics.md §5.5): the fixed point and
//! its eigenvalue for one impulse, the stable impulse interval, iteration series, and
//! (as files) the bifurcation diagram over the impulse.

use crate::plot::{LinePlot, Series, SeriesStyle, BLACK, PALETTE};
use crate::report::{num, nums, opt_num, Report, ReportFile, TextTable};
use crate::Result;
use hopsim_io::CsvTable;
use hopsim_theory::error::require_finite;
use hopsim_theory::impulsive_wheel::{wrap_half_turn, ImpulsiveWheel, TakeoffAngleFixedPoint};
use hopsim_theory::numerics::linspace;
use hopsim_theory::AnalysisError;
use serde::Serialize;
use std::f64::consts::FRAC_PI_2;

/// The most iterations of a series.
pub const MAX_ITERATIONS: usize = 1_000_000;
/// The most impulse values of the bifurcation diagram.
pub const MAX_BIFURCATION_POINTS: usize = 100_000;

/// Iterations of the bifurcation diagram dropped as transient, and iterations kept.
const TRANSIENT: usize = 500;
const KEEP: usize = 64;

/// What to compute.
#[derive(Clone, Debug)]
pub struct ImpulsiveWheelParams {
    /// The wheel.
    pub wheel: ImpulsiveWheel,
    /// Impulse `‖ζ‖` of the fixed point [N s].
    pub impulse_n_s: f64,
    /// Impulses of the iteration series [N s] (empty: `impulse_n_s` alone).
    pub series_impulses_n_s: Vec<f64>,
    /// Iterations of each series.
    pub iterations: usize,
    /// Initial take-off angle of the series and the bifurcation diagram [rad].
    pub initial_angle_rad: f64,
    /// The bifurcation diagram's impulses (None: no diagram).
    pub bifurcation: Option<BifurcationParams>,
}

impl ImpulsiveWheelParams {
    /// Checks every number (invalid-parameter errors name the offending value).
    pub fn validate(&self) -> Result<()> {
        self.wheel.validate()?;
        require_non_negative("impulse", self.impulse_n_s)?;
        for &z in &self.series_impulses_n_s {
            require_non_negative("series", z)?;
        }
        require_finite("initial-angle", self.initial_angle_rad)?;
        if self.iterations > MAX_ITERATIONS {
            Err(AnalysisError::invalid(
                "iterations",
                self.iterations as f64,
                &format!("must be at most {MAX_ITERATIONS}"),
            ))?;
        }
        if let Some(b) = &self.bifurcation {
            require_non_negative("impulse-min", b.impulse_min_n_s)?;
            if !(b.impulse_max_n_s.is_finite() && b.impulse_max_n_s > b.impulse_min_n_s) {
                Err(AnalysisError::invalid(
                    "impulse-max",
                    b.impulse_max_n_s,
                    &format!(
                        "must be finite and exceed impulse-min = {}",
                        b.impulse_min_n_s
                    ),
                ))?;
            }
            if !(2..=MAX_BIFURCATION_POINTS).contains(&b.points) {
                Err(AnalysisError::invalid(
                    "bifurcation-points",
                    b.points as f64,
                    &format!("must be from 2 to {MAX_BIFURCATION_POINTS}"),
                ))?;
            }
        }
        Ok(())
    }
}

/// Checks that an impulse is finite, ≥ 0 and at most `MAX_MAGNITUDE`.
fn require_non_negative(name: &str, value: f64) -> Result<()> {
    require_finite(name, value)?;
    if value >= 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::invalid(name, value, "must be ≥ 0").into())
    }
}

/// Impulses of the bifurcation diagram: `points` values evenly spaced from `min` to `max`.
#[derive(Clone, Copy, Debug)]
pub struct BifurcationParams {
    pub impulse_min_n_s: f64,
    pub impulse_max_n_s: f64,
    pub points: usize,
}

/// The take-off angles `φ_0 … φ_n` from the initial angle for one impulse.
#[derive(Clone, Debug, Serialize)]
pub struct IterationSeries {
    #[serde(rename = "impulse_Ns")]
    pub impulse_n_s: f64,
    #[serde(rename = "takeoff_angles_rad")]
    pub takeoff_angles: Vec<f64>,
}

/// The bifurcation diagram: per impulse, the iterates after the transient (wrapped to
/// `[−π/2, π/2)`) and the closed-form fixed point (NaN where there is none).
#[derive(Clone, Debug)]
pub struct Bifurcation {
    pub iterates: Vec<(f64, Vec<f64>)>,
    pub fixed_points: Vec<(f64, f64)>,
}

/// The study's result.
#[derive(Debug, Serialize)]
pub struct ImpulsiveWheelReport {
    analysis: &'static str,
    /// The wheel.
    #[serde(rename = "parameters")]
    pub wheel: ImpulsiveWheel,
    /// `φ̇_S` [rad/s].
    pub rolling_speed_rad_s: f64,
    /// `φ̇_S T_C` [rad].
    pub drift_rad: f64,
    /// Fixed point and eigenvalue at the impulse asked for.
    #[serde(flatten)]
    pub fixed_point: TakeoffAngleFixedPoint,
    /// Impulses with a stable fixed point (open interval) [N s].
    #[serde(rename = "stable_impulse_interval_Ns")]
    pub stable_impulse_interval: (f64, f64),
    /// One series per impulse.
    pub series: Vec<IterationSeries>,
    /// The diagram, when asked for.
    #[serde(skip)]
    pub bifurcation: Option<Bifurcation>,
}

/// Computes the fixed point, the series and the diagram asked for.
pub fn impulsive_wheel(p: &ImpulsiveWheelParams) -> Result<ImpulsiveWheelReport> {
    p.validate()?;
    let wheel = &p.wheel;
    let fixed_point = wheel.fixed_point(p.impulse_n_s)?;
    let impulses = if p.series_impulses_n_s.is_empty() {
        std::slice::from_ref(&p.impulse_n_s)
    } else {
        &p.series_impulses_n_s[..]
    };
    let series = impulses
        .iter()
        .map(|&z| IterationSeries {
            impulse_n_s: z,
            takeoff_angles: wheel.iterate(z, p.initial_angle_rad, p.iterations),
        })
        .collect();
    let bifurcation = p.bifurcation.map(|b| {
        let impulses = linspace(b.impulse_min_n_s, b.impulse_max_n_s, b.points);
        Bifurcation {
            fixed_points: impulses
                .iter()
                .map(|&z| {
                    let phi = wheel.fixed_point(z).ok().and_then(|f| f.fixed_point_rad);
                    (z, phi.unwrap_or(f64::NAN))
                })
                .collect(),
            iterates: wheel.bifurcation(&impulses, p.initial_angle_rad, TRANSIENT, KEEP),
        }
    });
    Ok(ImpulsiveWheelReport {
        analysis: "impulsive-wheel",
        wheel: *wheel,
        rolling_speed_rad_s: wheel.rolling_speed(),
        drift_rad: wheel.drift(),
        fixed_point,
        stable_impulse_interval: wheel.stable_impulse_interval(),
        series,
        bifurcation,
    })
}

impl ImpulsiveWheelReport {
    fn bifurcation_files(&self, b: &Bifurcation) -> [ReportFile; 2] {
        let mut csv = CsvTable::new(&["impulse_Ns", "takeoff_angle_rad"]);
        let mut points = Vec::new();
        for (z, phis) in &b.iterates {
            for &phi in phis {
                csv.push(vec![(*z).into(), phi.into()]);
                points.push((*z, phi));
            }
        }
        let mut plot = LinePlot::new(
            format!("impulsive wheel: take-off angle after {TRANSIENT} iterations (mod π)"),
            "impulse ‖ζ‖ (N s)",
            "take-off angle φ (rad)",
        )
        .with_y_range(-FRAC_PI_2, FRAC_PI_2)
        .with_series(
            Series::line(
                "fixed point φ* (closed form; stable between the lines)",
                b.fixed_points.clone(),
            )
            .color(PALETTE[3])
            .size(1),
        )
        .with_series(
            Series::points(
                format!("iterates {}–{}", TRANSIENT + 1, TRANSIENT + KEEP),
                points,
            )
            .color(PALETTE[0])
            .size(1),
        );
        let (lo, hi) = self.stable_impulse_interval;
        for (label, z) in [("stable interval", lo), ("", hi)] {
            let line = Series::line(label, vec![(z, -FRAC_PI_2), (z, FRAC_PI_2)])
                .color(BLACK)
                .size(1);
            plot = plot.with_series(if label.is_empty() {
                line.unlabelled()
            } else {
                line
            });
        }
        [
            ReportFile::csv("bifurcation.csv", csv),
            ReportFile::figure("bifurcation", plot),
        ]
    }

    fn series_files(&self) -> [ReportFile; 2] {
        let mut csv = CsvTable::new(&["impulse_Ns", "iteration", "takeoff_angle_rad"]);
        let mut plot = LinePlot::new(
            "impulsive wheel: iteration series",
            "iteration i",
            "take-off angle φ_i (rad)",
        );
        for (k, s) in self.series.iter().enumerate() {
            for (i, &phi) in s.takeoff_angles.iter().enumerate() {
                csv.push(vec![s.impulse_n_s.into(), i.into(), phi.into()]);
            }
            let points = s
                .takeoff_angles
                .iter()
                .enumerate()
                .map(|(i, &p)| (i as f64, p))
                .collect();
            plot = plot.with_series(
                Series::line(format!("‖ζ‖ = {} N s", s.impulse_n_s), points)
                    .style(SeriesStyle::LineAndPoints)
                    .color(PALETTE[k % PALETTE.len()]),
            );
        }
        [
            ReportFile::csv("series.csv", csv),
            ReportFile::figure("series", plot),
        ]
    }
}

impl Report for ImpulsiveWheelReport {
    fn text(&self) -> String {
        let (w, fp) = (&self.wheel, &self.fixed_point);
        let (lo, hi) = self.stable_impulse_interval;
        let mut t = TextTable::new("impulsive wheel return map (docs/physics.md §5.5)");
        t.row(
            "m, R, I",
            nums(&[(w.mass, "kg"), (w.radius, "m"), (w.inertia, "kg m²")]),
        )
        .row(
            "T_C, E₀, g",
            nums(&[
                (w.cycle_time, "s"),
                (w.rolling_energy, "J"),
                (w.gravity, "m/s²"),
            ]),
        )
        .row(
            "rolling speed (per cycle)",
            format!(
                "{} ({})",
                num(self.rolling_speed_rad_s, "rad/s"),
                num(self.drift_rad, "rad")
            ),
        )
        .row("impulse ‖ζ‖", num(fp.impulse_n_s, "N s"))
        .row("c = R‖ζ‖²/(m I g)", num(fp.coupling, ""))
        .row(
            "fixed point φ*",
            opt_num(fp.fixed_point_rad, "rad", "none (c < φ̇_S T_C)"),
        )
        .row("eigenvalue λ", opt_num(fp.eigenvalue, "", "—"))
        .row("stable", fp.stable)
        .row(
            "stable impulse interval",
            format!("({}, {}) N s", num(lo, ""), num(hi, "")),
        );
        let mut text = t.to_string();
        for s in &self.series {
            let last = s.takeoff_angles.last().copied().unwrap_or(f64::NAN);
            text += &format!(
                "series ‖ζ‖ = {}: φ_{} = {} (wrapped to [−π/2, π/2): {})\n",
                num(s.impulse_n_s, "N s"),
                s.takeoff_angles.len() - 1,
                num(last, "rad"),
                num(wrap_half_turn(last), "rad")
            );
        }
        text
    }

    fn files(&self) -> Vec<ReportFile> {
        let mut files = Vec::new();
        if let Some(b) = &self.bifurcation {
            files.extend(self.bifurcation_files(b));
        }
        files.extend(self.series_files());
        files
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> ImpulsiveWheelParams {
        ImpulsiveWheelParams {
            wheel: ImpulsiveWheel::default(),
            impulse_n_s: 3.5,
            series_impulses_n_s: Vec::new(),
            iterations: 3,
            initial_angle_rad: 0.1,
            bifurcation: None,
        }
    }

    /// Negative or non-finite impulses and an empty bifurcation range are the user's
    /// input, named.
    #[test]
    fn bad_impulses_are_named_invalid_parameters() {
        let mut series = params();
        series.series_impulses_n_s = vec![1.0, f64::NAN];
        let mut range = params();
        range.bifurcation = Some(BifurcationParams {
            impulse_min_n_s: 3.0,
            impulse_max_n_s: 2.0,
            points: 10,
        });
        for (p, name) in [(series, "series"), (range, "impulse-max")] {
            let err = impulsive_wheel(&p).unwrap_err();
            assert!(err.is_invalid_input(), "{err}");
            assert!(err.to_string().contains(&format!("`{name}`")), "{err}");
        }
    }

    #[test]
    fn the_series_default_to_the_fixed_point_impulse() {
        let report = impulsive_wheel(&params()).unwrap();
        assert_eq!(report.series.len(), 1);
        assert_eq!(report.series[0].impulse_n_s, 3.5);
        assert_eq!(report.series[0].takeoff_angles.len(), 4);
        assert!(report.bifurcation.is_none());
        let names = |r: &ImpulsiveWheelReport| -> Vec<String> {
            r.files()
                .iter()
                .map(|f| match f {
                    ReportFile::Csv { name, .. } => name.clone(),
                    ReportFile::Figure { stem, .. } => stem.clone(),
                })
                .collect()
        };
        assert_eq!(names(&report), ["series.csv", "series"]);
        let p = ImpulsiveWheelParams {
            series_impulses_n_s: vec![3.0, 3.9],
            bifurcation: Some(BifurcationParams {
                impulse_min_n_s: 0.1,
                impulse_max_n_s: 4.1,
                points: 2,
            }),
            ..params()
        };
        let report = impulsive_wheel(&p).unwrap();
        let z: Vec<f64> = report.series.iter().map(|s| s.impulse_n_s).collect();
        assert_eq!(z, [3.0, 3.9]);
        assert_eq!(
            names(&report),
            ["bifurcation.csv", "bifurcation", "series.csv", "series"]
        );
        // ‖ζ‖ = 0.1 has no fixed point (c < φ̇_S T_C = 1): its curve point is NaN.
        let b = report.bifurcation.unwrap();
        assert!(b.fixed_points[0].1.is_nan());
        assert!(b.fixed_points[1].1.is_finite());
        assert!(b.iterates.iter().all(|(_, phis)| phis.len() == KEEP));
    }
}
