//! `hopsim sweep SCENE --grid KEY=START:STOP:N …`: a scene run over a parameter grid on all
//! cores, with a CSV of the run summaries and a plot (`docs/sweeps.md`).

use anyhow::Context;
use clap::Args;
use hopsim_control::ControllerConfig;
use hopsim_io::{create_dir, Cell, CsvTable};
use hopsim_scene::{Override, Scene};
use hopsim_sim::{grid_jobs, CubeBaseline, GridAxis, Summary, SweepJob, SweepPoint};
use hopsim_studies::plot::{write_png_and_svg, LinePlot, RGBColor, Series, SeriesStyle, BLACK};
use std::path::PathBuf;
use std::process::ExitCode;

use super::{exit, progress, scene::SceneArgs};

/// Run a scene over a grid of parameter values in parallel; write a CSV of the run
/// summaries and a plot.
#[derive(Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// A grid axis: KEY=START:STOP:COUNT (evenly spaced, inclusive) or KEY=V1,V2,…; any
    /// scalar scene key (repeat for a Cartesian grid; the last axis varies fastest).
    #[arg(long = "grid", value_name = "AXIS", required = true)]
    pub grid: Vec<GridAxis>,
    /// An extra run drawn as a horizontal reference line: NAME:KEY=VALUE[,KEY=VALUE…],
    /// e.g. --baseline retracted:controller.cane_mode=retracted (repeatable).
    #[arg(long = "baseline", value_name = "NAME:KEY=VALUE")]
    pub baselines: Vec<Baseline>,
    /// Simulated time of every run in seconds (overrides simulation.duration).
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Output directory for sweep.csv and the plot [default: out/<scene>-sweep].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Quantity plotted against the first grid axis (scenes without the Robbit
    /// controller; Robbit's plot is mean speed against impulse per distance).
    #[arg(long, value_name = "FIELD", default_value = "distance_per_hop_m", value_parser = metric_name)]
    pub y: String,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `--baseline NAME:KEY=VALUE[,KEY=VALUE…]`.
#[derive(Clone, Debug)]
pub struct Baseline {
    pub name: String,
    pub overrides: Vec<Override>,
}

impl std::str::FromStr for Baseline {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (name, rest) = s
            .split_once(':')
            .filter(|(n, _)| !n.trim().is_empty())
            .ok_or_else(|| format!("'{s}': expected NAME:KEY=VALUE[,KEY=VALUE…]"))?;
        let overrides = rest
            .split(',')
            .map(str::parse)
            .collect::<Result<Vec<Override>, _>>()?;
        Ok(Self {
            name: name.trim().to_string(),
            overrides,
        })
    }
}

/// A summary quantity: its CSV column name and how to read it.
type Metric = (&'static str, fn(&Summary) -> f64);

/// The summary quantities a sweep reports.
const METRICS: &[Metric] = &[
    ("distance_m", |s| s.distance_m),
    ("mean_speed_mps", |s| s.mean_speed_mps),
    ("hops", |s| s.hops as f64),
    ("distance_per_hop_m", |s| s.distance_per_hop_m),
    ("impulses_count", |s| s.impulses.count as f64),
    ("impulses_total_Nms", |s| s.impulses.total_ns),
    ("impulse_per_distance_Nms_per_m", |s| s.impulse_per_distance),
    ("brakes_per_s", |s| {
        s.robbit.as_ref().map_or(f64::NAN, |r| r.brakes_per_s)
    }),
    ("window_impulse_per_distance_Nms_per_m", |s| {
        s.robbit
            .as_ref()
            .map_or(f64::NAN, |r| r.impulse_per_distance)
    }),
    ("gait_period", |s| {
        s.gait
            .as_ref()
            .and_then(|g| g.period)
            .map_or(f64::NAN, |p| p as f64)
    }),
    ("gait_residual", |s| {
        s.gait.as_ref().map_or(f64::NAN, |g| g.residual())
    }),
    ("max_penetration_m", |s| s.max_penetration_m),
    ("energy_balance_error_J", |s| s.energy.max_abs_balance_error),
    ("lcp_failures", |s| s.lcp.failures as f64),
    ("wall_time_s", |s| s.wall_time_s),
];

fn metric_name(s: &str) -> Result<String, String> {
    METRICS
        .iter()
        .any(|(n, _)| *n == s)
        .then(|| s.to_string())
        .ok_or_else(|| {
            let names: Vec<&str> = METRICS.iter().map(|(n, _)| *n).collect();
            format!("unknown field '{s}'; one of: {}", names.join(", "))
        })
}

fn metric(name: &str, s: &Summary) -> f64 {
    METRICS
        .iter()
        .find(|(n, _)| *n == name)
        .map_or(f64::NAN, |(_, f)| f(s))
}

pub fn run(args: SweepArgs) -> anyhow::Result<ExitCode> {
    let extra: Vec<Override> = args
        .duration
        .map(|d| Override::from_flag("--duration", "simulation.duration", format!("{d:?}")))
        .into_iter()
        .collect();
    // Validate the base scene once, so a broken file fails before hundreds of runs do.
    let scene = match args.scene.load(&extra) {
        Ok(scene) => scene,
        Err(code) => return Ok(code),
    };
    if let Some(message) = repeated_names(&args) {
        eprintln!("error: {message}");
        return Ok(ExitCode::from(exit::INVALID_INPUT));
    }
    let mut jobs = grid_jobs(&args.grid);
    let baselines = args.baselines.iter().map(|b| SweepJob {
        label: b.name.clone(),
        values: Vec::new(),
        overrides: b.overrides.clone(),
    });
    let first_baseline = jobs.len();
    jobs.extend(baselines);
    // A misspelt key would fail every run: check the grid's first point and every
    // baseline once.
    for (i, job) in jobs.iter().enumerate() {
        if i > 0 && i < first_baseline {
            continue;
        }
        let mut overrides = extra.clone();
        overrides.extend(job.overrides.iter().cloned());
        if let Err(code) = args.scene.load(&overrides) {
            let what = if i == 0 {
                "the grid's first point".to_string()
            } else {
                format!("baseline '{}'", job.label)
            };
            eprintln!("error: {what} is invalid (see above); nothing was run");
            return Ok(code);
        }
    }
    let mut base = args.scene.overrides.clone();
    base.extend(extra);
    let bar = progress::count_bar(jobs.len() as u64, "runs", args.quiet);
    let points = hopsim_sim::sweep(&scene.path, &scene.text, &base, &jobs, Some(&bar));
    bar.finish_and_clear();

    let stem = scene
        .path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy());
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-sweep")));
    create_dir(&out)?;
    let csv = out.join("sweep.csv");
    table(&args.grid, &points)
        .write(&csv)
        .with_context(|| format!("writing {}", csv.display()))?;
    let figure = if matches!(scene.controller, ControllerConfig::MomentumImpulse(_)) {
        speed_against_impulse(&scene, &points)
    } else {
        quantity_against_axis(&args.grid, &args.y, &points)
    };
    let plots = write_png_and_svg(&figure, &out.join("sweep"))?;
    if !args.quiet {
        report(&args.grid, &points);
        println!("wrote {}", csv.display());
        for p in plots {
            println!("wrote {}", p.display());
        }
    }
    let failed = points.iter().filter(|p| p.result.is_err()).count();
    if failed == points.len() {
        eprintln!(
            "error: every run failed (their errors are in {})",
            csv.display()
        );
        return Ok(ExitCode::from(exit::SIMULATION_FAILED));
    }
    if failed > 0 {
        eprintln!(
            "warning: {failed} of {} runs failed (status = error in {})",
            points.len(),
            csv.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// A grid key given twice, or a baseline named like another or like the grid's rows.
fn repeated_names(args: &SweepArgs) -> Option<String> {
    let keys: Vec<&str> = args.grid.iter().map(|a| a.key.as_str()).collect();
    if let Some((_, key)) = keys
        .iter()
        .enumerate()
        .find(|(i, k)| keys[..*i].contains(k))
    {
        return Some(format!("--grid {key} is given twice; give each axis once"));
    }
    let mut names = vec!["grid"];
    for b in &args.baselines {
        if names.contains(&b.name.as_str()) {
            return Some(format!(
                "--baseline name '{}' is taken (by another baseline or the grid's rows); \
                 give each baseline its own name",
                b.name
            ));
        }
        names.push(&b.name);
    }
    None
}

/// One CSV row per run: label, grid values, status, error, then every metric.
fn table(axes: &[GridAxis], points: &[SweepPoint]) -> CsvTable {
    let mut header: Vec<String> = vec!["label".into()];
    header.extend(axes.iter().map(|a| a.key.clone()));
    header.extend(["status".into(), "error".into()]);
    header.extend(METRICS.iter().map(|(n, _)| n.to_string()));
    let mut t = CsvTable::new(&header);
    for p in points {
        let mut row: Vec<Cell> = vec![p.job.label.as_str().into()];
        row.extend((0..axes.len()).map(|i| Cell::from(p.job.values.get(i).copied())));
        match &p.result {
            Ok(s) => {
                row.extend([Cell::from("ok"), Cell::Empty]);
                row.extend(METRICS.iter().map(|(_, f)| Cell::from(f(s))));
            }
            Err(e) => {
                row.extend([Cell::from("error"), Cell::from(e.as_str())]);
                row.extend(METRICS.iter().map(|_| Cell::Empty));
            }
        }
        t.push(row);
    }
    t
}

/// Robbit: mean speed against transferred impulse per distance, with the cube baselines of
/// physics.md §5.3 as curves (the thesis' speed-versus-impulse figure).
fn speed_against_impulse(scene: &Scene, points: &[SweepPoint]) -> LinePlot {
    let runs: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| p.result.as_ref().ok())
        .filter_map(|s| Some((s.robbit.as_ref()?.impulse_per_distance, s.mean_speed_mps)))
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *y > 0.0)
        .collect();
    let mut plot = LinePlot::new(
        format!("{}: speed against transferred impulse", scene.title),
        "transferred angular impulse per distance [N m s/m]",
        "mean speed [m/s]",
    )
    .with_series(Series::points("simulated runs", runs.clone()));
    if !runs.is_empty() {
        let hi = runs.iter().map(|p| p.1).fold(0.0, f64::max);
        // Show the bulk of the runs: up to 1.5 times the 90th percentile of the impulse.
        let mut xs: Vec<f64> = runs.iter().map(|p| p.0).collect();
        xs.sort_by(f64::total_cmp);
        let x_max = 1.5 * xs[(xs.len() * 9 / 10).min(xs.len() - 1)];
        for eps in [0.0, scene.settings.cube_restitution] {
            let curve: Vec<(f64, f64)> = (1..=200)
                .map(|i| 1.3 * hi * i as f64 / 200.0)
                .filter_map(|u| {
                    let x = CubeBaseline::for_scene(scene, u, eps)?.impulse_per_distance;
                    (x <= x_max).then_some((x, u))
                })
                .collect();
            if !curve.is_empty() {
                plot = plot.with_series(Series::line(format!("cube, ε = {eps}"), curve));
            }
        }
        plot = plot.with_x_range(0.0, x_max).with_y_range(0.0, 1.3 * hi);
    }
    plot
}

/// Other scenes: `y` against the first grid axis, one series per value of the second axis,
/// baselines as horizontal lines.
fn quantity_against_axis(axes: &[GridAxis], y: &str, points: &[SweepPoint]) -> LinePlot {
    let x_axis = &axes[0];
    let mut plot = LinePlot::new(format!("{y} against {}", x_axis.key), &x_axis.key, y);
    let grid: Vec<&SweepPoint> = points.iter().filter(|p| !p.job.values.is_empty()).collect();
    let series_values: Vec<Option<f64>> = match axes.get(1) {
        Some(axis) => axis.values.iter().copied().map(Some).collect(),
        None => vec![None],
    };
    for sv in series_values {
        let pts: Vec<(f64, f64)> = grid
            .iter()
            .filter(|p| sv.is_none_or(|v| p.job.values[1] == v))
            .filter_map(|p| Some((p.job.values[0], metric(y, p.result.as_ref().ok()?))))
            .filter(|(_, v)| v.is_finite())
            .collect();
        let label = match sv {
            Some(v) => format!("{} = {v}", axes[1].key),
            None => y.to_string(),
        };
        plot = plot.with_series(Series::line(label, pts).style(SeriesStyle::LineAndPoints));
    }
    let (x0, x1) = x_axis
        .values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let baselines = points.iter().filter(|p| p.job.values.is_empty());
    for (p, color) in baselines.zip(BASELINE_COLORS.iter().cycle()) {
        let value = p.result.as_ref().ok().map(|s| metric(y, s));
        if let Some(v) = value.filter(|v| v.is_finite()) {
            let line = vec![(x0, v), (x1, v)];
            plot = plot.with_series(Series::line(p.job.label.clone(), line).color(*color));
        }
    }
    plot
}

/// Colours of the baseline lines: dark, apart from the palette of the grid's series.
const BASELINE_COLORS: [RGBColor; 3] = [BLACK, RGBColor(110, 110, 110), RGBColor(150, 60, 60)];

/// A short table on stdout: every run if there are few, else counts and the extremes.
fn report(axes: &[GridAxis], points: &[SweepPoint]) {
    let failed = points.iter().filter(|p| p.result.is_err()).count();
    println!("{} runs, {} failed", points.len(), failed);
    let keys: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
    let describe = |p: &SweepPoint| {
        let at = if p.job.values.is_empty() {
            p.job.label.clone()
        } else {
            keys.iter()
                .zip(&p.job.values)
                .map(|(k, v)| format!("{k}={v:.4}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        match &p.result {
            Ok(s) if s.hops == 0 => format!("  {at}: {:.4} m/s, no hop", s.mean_speed_mps),
            Ok(s) => format!(
                "  {at}: {:.4} m/s, {} hops, {:.4} m per hop",
                s.mean_speed_mps, s.hops, s.distance_per_hop_m
            ),
            Err(e) => format!("  {at}: error: {e}"),
        }
    };
    if points.len() <= 30 {
        points.iter().for_each(|p| println!("{}", describe(p)));
        return;
    }
    let fastest = points
        .iter()
        .filter(|p| p.result.is_ok())
        .max_by(|a, b| speed(a).total_cmp(&speed(b)));
    if let Some(p) = fastest {
        println!("fastest:\n{}", describe(p));
    }
    for p in points.iter().filter(|p| p.result.is_err()).take(5) {
        println!("{}", describe(p));
    }
}

fn speed(p: &SweepPoint) -> f64 {
    p.result.as_ref().map_or(f64::NAN, |s| s.mean_speed_mps)
}
