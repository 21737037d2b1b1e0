//! Parameter sweeps (docs/sweeps.md): a scene run over a grid of overrides, plus baseline
//! runs, in parallel; one row of run-summary figures per run (`sweep.csv`) and a figure
//! (`sweep.png`, `sweep.svg`). For Robbit the figure is the thesis' speed against
//! transferred impulse with the cube baselines (docs/physics.md §5.3, Fig. 5.7); for other scenes
//! one figure against the first grid axis.

use crate::plot::{LinePlot, RGBColor, Scale, Series, SeriesStyle, BLACK};
use crate::progress::Progress;
use crate::report::{Report, ReportFile};
use crate::run_summary::{robbit_cube, run_scene, RunReport};
use hopsim_control::ControllerConfig;
use hopsim_io::{Cell, CsvTable};
use hopsim_model::Shape;
use hopsim_scene::{axis_label, key_words, value_label, Override, Scene, SceneError};
use hopsim_sim::StopFlag;

mod grid;
pub use grid::{
    grid_jobs, grid_points, sweep, GridAxis, RunDone, SweepJob, SweepPoint, MAX_AXIS_POINTS,
    NO_PROGRESS,
};
use hopsim_theory::cube::Cube;
use serde::Serialize;
use std::fmt::Write;
use std::ops::Range;
use std::sync::atomic::AtomicBool;

/// What a run-summary figure measures, for its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A length (m): round-off below [`ROUND_OFF`] of the scene's size.
    Length,
    /// A speed (m/s): round-off below [`ROUND_OFF`] of the scene's size per second.
    Speed,
    /// A whole number (hops, events, a period in cycles): ticked at whole numbers.
    Count,
    /// Anything else, drawn as it is.
    Other,
}

/// A run-summary figure: its CSV column name, its axis label (words and unit), its kind
/// and how to read it.
struct Metric {
    name: &'static str,
    label: &'static str,
    kind: Kind,
    value: fn(&RunReport) -> f64,
}

const fn metric(
    name: &'static str,
    label: &'static str,
    kind: Kind,
    value: fn(&RunReport) -> f64,
) -> Metric {
    Metric {
        name,
        label,
        kind,
        value,
    }
}

/// The run-summary figures a sweep reports, in CSV column order.
const METRICS: &[Metric] = &[
    metric("distance_m", "distance (m)", Kind::Length, |r| {
        r.summary.distance_m
    }),
    metric("mean_speed_mps", "mean speed (m/s)", Kind::Speed, |r| {
        r.summary.mean_speed_mps
    }),
    metric("hops", "hops", Kind::Count, |r| r.summary.hops as f64),
    metric(
        "distance_per_hop_m",
        "distance per hop (m)",
        Kind::Length,
        |r| r.summary.distance_per_hop_m,
    ),
    metric("impulses_count", "impulses", Kind::Count, |r| {
        r.summary.impulses.count as f64
    }),
    metric(
        "impulses_total_Nms",
        "total impulse (N m s)",
        Kind::Other,
        |r| r.summary.impulses.total,
    ),
    metric(
        "impulse_per_distance_Nms_per_m",
        "impulse per distance (N m s/m)",
        Kind::Other,
        |r| r.summary.impulse_per_distance,
    ),
    metric(
        "brakes_per_s",
        "brakes per second (1/s)",
        Kind::Other,
        |r| r.robbit.as_ref().map_or(f64::NAN, |b| b.brakes_per_s),
    ),
    metric(
        "window_impulse_per_distance_Nms_per_m",
        "impulse per distance in the speed window (N m s/m)",
        Kind::Other,
        |r| {
            r.robbit
                .as_ref()
                .map_or(f64::NAN, |b| b.impulse_per_distance)
        },
    ),
    metric("gait_period", "gait period (cycles)", Kind::Count, |r| {
        r.gait
            .as_ref()
            .and_then(|g| g.period)
            .map_or(f64::NAN, |p| p as f64)
    }),
    metric(
        "gait_residual",
        "gait residual (1 = tolerance)",
        Kind::Other,
        |r| r.gait.as_ref().map_or(f64::NAN, |g| g.residual()),
    ),
    metric(
        "max_penetration_m",
        "largest penetration (m)",
        Kind::Other,
        |r| r.summary.max_penetration_m,
    ),
    metric(
        "energy_balance_error_J",
        "energy balance error (J)",
        Kind::Other,
        |r| r.summary.energy.max_abs_balance_error,
    ),
    metric("lcp_failures", "contact LCP failures", Kind::Count, |r| {
        r.summary.lcp.failures as f64
    }),
    metric("wall_time_s", "wall time (s)", Kind::Other, |r| {
        r.summary.wall_time_s
    }),
];

/// The figures a sweep reports of `report`, with their CSV column names, in column order
/// (the columns of [`Sweep::table`] after `error`): for a front end that runs the sweep's
/// runs itself (a controller written in Python).
pub fn figures(report: &RunReport) -> Vec<(&'static str, f64)> {
    METRICS
        .iter()
        .map(|m| (m.name, (m.value)(report)))
        .collect()
}

/// The names of the figures a sweep reports, in column order ([`figures`]).
pub fn figure_names() -> Vec<&'static str> {
    METRICS.iter().map(|m| m.name).collect()
}

/// Lengths and speeds below this fraction of the scene's size (per second) are round-off,
/// drawn as zero: a robot hopping in place travels 1e-13 m, not a distance.
pub const ROUND_OFF: f64 = 1e-9;

/// The figures a sweep plots by default, in order of preference: the first that varies
/// over the grid (beyond round-off) is plotted.
pub const DEFAULT_Y: [&str; 5] = [
    "distance_per_hop_m",
    "mean_speed_mps",
    "hops",
    "gait_period",
    "gait_residual",
];

/// `name` if it is one of the figures a sweep reports (the CSV columns after `error`).
pub fn metric_name(name: &str) -> Result<String, String> {
    find_metric(name)
        .map(|m| m.name.to_string())
        .ok_or_else(|| {
            let names: Vec<&str> = METRICS.iter().map(|m| m.name).collect();
            format!("unknown field '{name}'; one of: {}", names.join(", "))
        })
}

fn find_metric(name: &str) -> Option<&'static Metric> {
    METRICS.iter().find(|m| m.name == name)
}

/// The size of a scene's mechanism: the largest distance of a shape's outline from its
/// body's centre of mass (1 m for a scene without shapes).
pub fn length_scale(scene: &Scene) -> f64 {
    let reach = |shape: &Shape| match shape {
        Shape::Circle { center, radius } | Shape::Arc { center, radius, .. } => {
            center.norm() + radius
        }
        Shape::Ellipse {
            center,
            semi_x,
            semi_y,
        } => center.norm() + semi_x.max(*semi_y),
        Shape::Point { position } => position.norm(),
        Shape::Capsule { from, to, radius } => from.norm().max(to.norm()) + radius,
        Shape::Polygon { vertices } => vertices.iter().map(|v| v.norm()).fold(0.0, f64::max),
    };
    let size = (scene.model.shapes().iter())
        .map(|s| reach(&s.shape))
        .fold(0.0, f64::max);
    if size > 0.0 && size.is_finite() {
        size
    } else {
        1.0
    }
}

/// An extra run drawn as a horizontal reference line: `NAME:KEY=VALUE[,KEY=VALUE…]`.
#[derive(Clone, Debug)]
pub struct SweepBaseline {
    pub name: String,
    pub overrides: Vec<Override>,
}

impl std::str::FromStr for SweepBaseline {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (name, rest) = s
            .split_once(':')
            .filter(|(n, _)| !n.trim().is_empty())
            .ok_or_else(|| format!("'{s}': expected NAME:KEY=VALUE[,KEY=VALUE…]"))?;
        // Errors in these overrides name the --baseline option, not --set.
        let overrides = rest
            .split(',')
            .map(|text| {
                let o: Override = text.parse()?;
                Ok(Override::from_flag("--baseline", o.key, o.value))
            })
            .collect::<Result<Vec<Override>, String>>()?;
        Ok(Self {
            name: name.trim().to_string(),
            overrides,
        })
    }
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepParams {
    /// The grid axes (the last one varies fastest).
    pub axes: Vec<GridAxis>,
    /// Extra runs, after the grid's.
    pub baselines: Vec<SweepBaseline>,
    /// The figure plotted against the first axis (scenes without the Robbit controller),
    /// one of the CSV columns ([`metric_name`]); `None`: the first of [`DEFAULT_Y`] that
    /// varies over the grid.
    pub y: Option<String>,
    /// The most grid points the sweep may run ([`DEFAULT_MAX_RUNS`] unless raised).
    pub max_runs: usize,
}

/// Default of [`SweepParams::max_runs`]: 100 000 runs (the thesis' 150 × 150 grid is 22 500).
pub const DEFAULT_MAX_RUNS: usize = 100_000;

/// Why a sweep cannot start.
#[derive(Debug, thiserror::Error)]
pub enum SweepInputError {
    #[error("--grid {0} is given twice; give each axis once")]
    RepeatedAxis(String),
    #[error(
        "--baseline name '{0}' is taken (by another baseline or the grid's rows); give each \
         baseline its own name"
    )]
    TakenName(String),
    #[error(
        "the grid has {runs} points, more than --max-runs {limit}; raise --max-runs to run it"
    )]
    TooManyRuns { runs: String, limit: usize },
    /// The scene of the grid's first point or of a baseline is invalid (`what` names it).
    #[error("{what} is invalid: {error}")]
    InvalidRun { what: String, error: SceneError },
}

/// A checked sweep, ready to run.
pub struct Sweep<'a> {
    scene: &'a Scene,
    base: Vec<Override>,
    params: SweepParams,
    jobs: Vec<SweepJob>,
    stop: Option<&'a AtomicBool>,
}

impl<'a> Sweep<'a> {
    /// The sweep of `scene` (already loaded with `base`, the overrides every run gets):
    /// refuses an axis given twice, a baseline named like another or like the grid's rows,
    /// and checks the grid's first point and every baseline, so that a misspelt key is one
    /// error rather than a failed run per point.
    pub fn new(
        scene: &'a Scene,
        base: &[Override],
        params: SweepParams,
    ) -> Result<Self, SweepInputError> {
        let keys: Vec<&str> = params.axes.iter().map(|a| a.key.as_str()).collect();
        if let Some((_, key)) = keys
            .iter()
            .enumerate()
            .find(|(i, k)| keys[..*i].contains(k))
        {
            return Err(SweepInputError::RepeatedAxis(key.to_string()));
        }
        let mut names = vec!["grid"];
        for b in &params.baselines {
            if names.contains(&b.name.as_str()) {
                return Err(SweepInputError::TakenName(b.name.clone()));
            }
            names.push(&b.name);
        }
        let runs = params
            .axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()));
        if runs.is_none_or(|n| n > params.max_runs) {
            let runs = runs.map_or_else(|| "too many".to_string(), |n| n.to_string());
            return Err(SweepInputError::TooManyRuns {
                runs,
                limit: params.max_runs,
            });
        }
        let mut jobs = grid_jobs(&params.axes);
        let first_baseline = jobs.len();
        jobs.extend(params.baselines.iter().map(|b| SweepJob {
            label: b.name.clone(),
            values: Vec::new(),
            overrides: b.overrides.clone(),
        }));
        for (i, job) in jobs.iter().enumerate() {
            if i > 0 && i < first_baseline {
                continue;
            }
            let mut overrides = base.to_vec();
            overrides.extend(job.overrides.iter().cloned());
            if let Err(error) = hopsim_scene::parse(&scene.text, &scene.path, &overrides) {
                let what = if i == 0 {
                    "the grid's first point".to_string()
                } else {
                    format!("baseline '{}'", job.label)
                };
                return Err(SweepInputError::InvalidRun { what, error });
            }
        }
        Ok(Sweep {
            scene,
            base: base.to_vec(),
            params,
            jobs,
            stop: None,
        })
    }

    /// Once `stop` is set (by another thread), every run stops at its next step, and the
    /// runs not yet started stop at their first: their rows are errors saying so.
    pub fn stopped_by(mut self, stop: &'a AtomicBool) -> Self {
        self.stop = Some(stop);
        self
    }

    /// The number of runs: the grid's points, then the baselines.
    pub fn runs(&self) -> usize {
        self.jobs.len()
    }

    /// Runs every point on all cores, ticking `progress` after each run.
    pub fn run(self, progress: &dyn Progress) -> SweepReport {
        let all = 0..self.jobs.len();
        self.run_part(all, progress)
    }

    /// Runs only the runs `part` of the sweep's [`Sweep::runs`] (grid points, then
    /// baselines), on all cores: a chunk of a sweep shared out over several processes or
    /// machines. Its rows are those of [`Sweep::run`] in `part`, in order. A `part` beyond
    /// the runs is cut to them.
    pub fn run_part(mut self, part: Range<usize>, progress: &dyn Progress) -> SweepReport {
        let end = part.end.min(self.jobs.len());
        self.jobs.truncate(end);
        self.jobs.drain(..part.start.min(end));
        let scene = self.scene;
        let tick = progress.task(self.jobs.len(), "sweep");
        let points = grid::sweep(
            &scene.path,
            &scene.text,
            &self.base,
            &self.jobs,
            |s| run_scene(s, &mut self.stop.map(StopFlag)),
            &*tick,
        );
        drop(tick);
        let robbit = matches!(scene.controller, ControllerConfig::MomentumImpulse(_));
        let mut report = SweepReport {
            scene: scene.title.clone(),
            axes: self.params.axes,
            y: String::new(),
            length_scale_m: length_scale(scene),
            runs: points.into_iter().map(SweepRun::from).collect(),
            cube: robbit.then(|| CubeCurves {
                cube: robbit_cube(scene),
                restitution: scene.settings.cube_restitution,
            }),
        };
        report.y = (self.params.y).unwrap_or_else(|| report.default_y().to_string());
        report
    }
}

/// One run of a sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepRun {
    /// `grid` for the grid's points, the baseline's name otherwise.
    pub label: String,
    /// The grid values, in axis order (empty for a baseline).
    pub values: Vec<f64>,
    /// The run summary; `None` when the run failed.
    pub summary: Option<RunReport>,
    /// Why the run failed (or its scene was invalid).
    pub error: Option<String>,
}

impl From<SweepPoint<RunReport>> for SweepRun {
    fn from(p: SweepPoint<RunReport>) -> Self {
        let (summary, error) = match p.result {
            Ok(s) => (Some(s), None),
            Err(e) => (None, Some(e)),
        };
        SweepRun {
            label: p.job.label,
            values: p.job.values,
            summary,
            error,
        }
    }
}

/// Robbit sweeps: the cube of docs/physics.md §5.3 drawn for `ε = 0` and `restitution`.
#[derive(Clone, Debug, Serialize)]
pub struct CubeCurves {
    /// `None` when the main body is not a disc.
    pub cube: Option<Cube>,
    /// The scene's `summary.cube_restitution`.
    pub restitution: f64,
}

/// A sweep's runs, in grid order (row-major, the last axis fastest), then the baselines.
#[derive(Clone, Debug, Serialize)]
pub struct SweepReport {
    /// The scene's title.
    pub scene: String,
    pub axes: Vec<GridAxis>,
    /// The figure plotted against the first axis (scenes without the Robbit controller).
    pub y: String,
    /// The scene's size ([`length_scale`]), against which lengths are round-off.
    pub length_scale_m: f64,
    pub runs: Vec<SweepRun>,
    /// Robbit scenes: the figure is speed against impulse per distance with these curves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cube: Option<CubeCurves>,
}

impl SweepReport {
    /// The value of the figure `m` in run `r`, round-off drawn as zero ([`ROUND_OFF`]).
    fn plotted(&self, m: &Metric, r: &RunReport) -> f64 {
        let v = (m.value)(r);
        let floor = match m.kind {
            Kind::Length | Kind::Speed => ROUND_OFF * self.length_scale_m,
            Kind::Count | Kind::Other => 0.0,
        };
        if v.abs() < floor {
            0.0
        } else {
            v
        }
    }

    /// The first of [`DEFAULT_Y`] whose plotted values vary over the grid's completed runs,
    /// else the first that is not zero everywhere, else the first.
    pub fn default_y(&self) -> &'static str {
        let values = |name: &str| -> Vec<f64> {
            let m = find_metric(name).expect("DEFAULT_Y names metrics");
            (self.runs.iter().filter(|r| !r.values.is_empty()))
                .filter_map(|r| r.summary.as_ref())
                .map(|s| self.plotted(m, s))
                .filter(|v| v.is_finite())
                .collect()
        };
        let varies = |v: &[f64]| v.iter().any(|x| *x != v[0]);
        (DEFAULT_Y.iter().find(|n| varies(&values(n))))
            .or_else(|| {
                DEFAULT_Y
                    .iter()
                    .find(|n| values(n).iter().any(|x| *x != 0.0))
            })
            .copied()
            .unwrap_or(DEFAULT_Y[0])
    }

    /// Runs that failed.
    pub fn failed(&self) -> usize {
        self.runs.iter().filter(|r| r.summary.is_none()).count()
    }

    /// One CSV row per run: label, grid values, status, error, then every figure.
    pub fn table(&self) -> CsvTable {
        let mut header: Vec<String> = vec!["label".into()];
        header.extend(self.axes.iter().map(|a| a.key.clone()));
        header.extend(["status".into(), "error".into()]);
        header.extend(METRICS.iter().map(|m| m.name.to_string()));
        let mut t = CsvTable::new(&header);
        for r in &self.runs {
            let mut row: Vec<Cell> = vec![r.label.as_str().into()];
            row.extend((0..self.axes.len()).map(|i| Cell::from(r.values.get(i).copied())));
            match (&r.summary, &r.error) {
                (Some(s), _) => {
                    row.extend([Cell::from("ok"), Cell::Empty]);
                    row.extend(METRICS.iter().map(|m| Cell::from((m.value)(s))));
                }
                (None, e) => {
                    row.extend([
                        Cell::from("error"),
                        Cell::from(e.as_deref().unwrap_or_default()),
                    ]);
                    row.extend(METRICS.iter().map(|_| Cell::Empty));
                }
            }
            t.push(row);
        }
        t
    }

    /// The figure: speed against impulse for Robbit, else `y` against the first axis.
    pub fn figure(&self) -> LinePlot {
        match &self.cube {
            Some(curves) => self.speed_against_impulse(curves),
            None => self.quantity_against_axis(),
        }
    }

    /// Robbit: mean speed against transferred impulse per distance, with the cube baselines
    /// of docs/physics.md §5.3 as curves (the thesis' speed-versus-impulse figure).
    fn speed_against_impulse(&self, curves: &CubeCurves) -> LinePlot {
        let runs: Vec<(f64, f64)> = self
            .runs
            .iter()
            .filter_map(|r| r.summary.as_ref())
            .filter_map(|s| {
                Some((
                    s.robbit.as_ref()?.impulse_per_distance,
                    s.summary.mean_speed_mps,
                ))
            })
            .collect();
        speed_against_impulse(
            format!("{}: speed against transferred impulse", self.scene),
            vec![Series::points("simulated runs", runs)],
            curves.cube.as_ref(),
            &[0.0, curves.restitution].map(|eps| (eps, format!("cube, ε = {eps}"))),
        )
    }

    /// Other scenes: `y` against the first grid axis, one series per value of the second
    /// axis, baselines as horizontal lines; round-off drawn as zero, counts on whole
    /// numbers, the axis in words with the unit of its scene key.
    fn quantity_against_axis(&self) -> LinePlot {
        let x_axis = &self.axes[0];
        let (y_label, kind) =
            find_metric(&self.y).map_or((self.y.as_str(), Kind::Other), |m| (m.label, m.kind));
        let value = |s: &RunReport| find_metric(&self.y).map_or(f64::NAN, |m| self.plotted(m, s));
        // The quantity in words: the label without its unit.
        let y_words = y_label.split(" (").next().unwrap_or(y_label);
        let mut plot = LinePlot::new(
            format!(
                "{}: {y_words} against {}",
                self.scene,
                key_words(&x_axis.key)
            ),
            axis_label(&x_axis.key),
            y_label,
        );
        if kind == Kind::Count {
            plot = plot.with_y_scale(Scale::Integer);
        }
        let grid: Vec<&SweepRun> = self.runs.iter().filter(|r| !r.values.is_empty()).collect();
        let series_values: Vec<Option<f64>> = match self.axes.get(1) {
            Some(axis) => axis.values.iter().copied().map(Some).collect(),
            None => vec![None],
        };
        for series_value in series_values {
            let pts: Vec<(f64, f64)> = grid
                .iter()
                .filter(|r| series_value.is_none_or(|v| r.values[1] == v))
                .filter_map(|r| Some((r.values[0], value(r.summary.as_ref()?))))
                .filter(|(_, v)| v.is_finite())
                .collect();
            let label = match series_value {
                Some(v) => value_label(&self.axes[1].key, v),
                None => y_words.to_string(),
            };
            plot = plot.with_series(Series::line(label, pts).style(SeriesStyle::LineAndPoints));
        }
        let (x0, x1) = x_axis
            .values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let baselines = self.runs.iter().filter(|r| r.values.is_empty());
        for (r, color) in baselines.zip(BASELINE_COLORS.iter().cycle()) {
            if let Some(v) = r.summary.as_ref().map(value).filter(|v| v.is_finite()) {
                let line = vec![(x0, v), (x1, v)];
                let label = format!("baseline: {}", r.label);
                plot = plot.with_series(Series::line(label, line).color(*color));
            }
        }
        plot
    }

    /// Where run `r` is: its grid values (`key=value …`) or the baseline's name.
    fn place(&self, r: &SweepRun) -> String {
        if r.values.is_empty() {
            return r.label.clone();
        }
        self.axes
            .iter()
            .zip(&r.values)
            .map(|(a, v)| format!("{}={v:.4}", a.key))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// One line about run `r`.
    fn describe(&self, r: &SweepRun) -> String {
        let at = self.place(r);
        match (&r.summary, &r.error) {
            (Some(s), _) if s.summary.hops == 0 => {
                format!("  {at}: {:.4} m/s, no hop", s.summary.mean_speed_mps)
            }
            (Some(s), _) => format!(
                "  {at}: {:.4} m/s, {} hops, {:.4} m per hop",
                s.summary.mean_speed_mps, s.summary.hops, s.summary.distance_per_hop_m
            ),
            (None, e) => format!("  {at}: error: {}", e.as_deref().unwrap_or_default()),
        }
    }

    /// The fastest run that completed.
    pub fn fastest(&self) -> Option<&SweepRun> {
        self.runs
            .iter()
            .filter_map(|r| Some((r, r.summary.as_ref()?.summary.mean_speed_mps)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(r, _)| r)
    }
}

/// Mean speed against transferred angular impulse per distance (the axes of the thesis'
/// Fig. 5.7, docs/physics.md §5.3) for the points of `series` (non-finite points and points not
/// moving forward are left out), with the cube baseline [5.21] as one curve per
/// `(ε, label)` of `cubes`. The impulse axis is logarithmic, so that the cubes, which may
/// need ten times the robot's impulse, show beside every point.
pub(crate) fn speed_against_impulse(
    title: String,
    mut series: Vec<Series>,
    cube: Option<&Cube>,
    cubes: &[(f64, String)],
) -> LinePlot {
    for s in &mut series {
        s.points
            .retain(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0);
    }
    let points = || series.iter().flat_map(|s| s.points.iter());
    let top_speed = points().map(|p| p.1).fold(0.0, f64::max);
    let (x_min, x_max) = points().fold((f64::INFINITY, 0.0_f64), |(lo, hi), p| {
        (lo.min(p.0), hi.max(p.0))
    });
    let mut plot = LinePlot::new(
        title,
        "transferred angular impulse per distance (N m s/m), log scale",
        "mean speed (m/s)",
    )
    .with_x_scale(Scale::Log);
    for s in series {
        plot = plot.with_series(s);
    }
    if top_speed == 0.0 {
        return plot;
    }
    // Every point, and each cube down to half the top speed.
    let cube_at = |u: f64, eps: f64| cube.map_or(0.0, |c| c.impulse_per_distance(u, eps));
    let (lo, hi) = cubes
        .iter()
        .filter(|(eps, _)| cube_at(top_speed, *eps) > 0.0)
        .fold((x_min, x_max), |(lo, hi), (eps, _)| {
            (
                lo.min(cube_at(1.3 * top_speed, *eps)),
                hi.max(cube_at(0.5 * top_speed, *eps)),
            )
        });
    let (lo, hi) = (lo / 1.2, hi * 1.2);
    for (eps, label) in cubes {
        let curve: Vec<(f64, f64)> = (1..=400)
            .map(|i| 1.3 * top_speed * i as f64 / 400.0)
            .filter_map(|u| {
                let x = cube?.impulse_per_distance(u, *eps);
                (x >= lo && x <= hi).then_some((x, u))
            })
            .collect();
        if !curve.is_empty() {
            plot = plot.with_series(Series::line(label.clone(), curve));
        }
    }
    plot.with_x_range(lo, hi).with_y_range(0.0, 1.3 * top_speed)
}

/// Colours of the baseline lines: dark, apart from the palette of the grid's series.
const BASELINE_COLORS: [RGBColor; 3] = [BLACK, RGBColor(110, 110, 110), RGBColor(150, 60, 60)];

/// Runs listed one by one up to this many; above, the fastest and the first failures.
const LISTED_RUNS: usize = 30;

/// Failed runs listed in a long sweep's text.
const LISTED_FAILURES: usize = 5;

impl Report for SweepReport {
    /// A short table: every run if there are few, else the fastest and the first failures.
    fn text(&self) -> String {
        let mut text = format!("{} runs, {} failed\n", self.runs.len(), self.failed());
        if self.runs.len() <= LISTED_RUNS {
            for r in &self.runs {
                let _ = writeln!(text, "{}", self.describe(r));
            }
            return text;
        }
        if let Some(r) = self.fastest() {
            let _ = writeln!(text, "fastest:\n{}", self.describe(r));
        }
        let failures = self.runs.iter().filter(|r| r.summary.is_none());
        for r in failures.take(LISTED_FAILURES) {
            let _ = writeln!(text, "{}", self.describe(r));
        }
        text
    }

    /// `sweep.csv` and the figure `sweep.png`, `sweep.svg`.
    fn files(&self) -> Vec<ReportFile> {
        vec![
            ReportFile::csv("sweep.csv", self.table()),
            ReportFile::figure("sweep", self.figure()),
        ]
    }
}
