//! `hopsim analyze impulsive-wheel`: the impulsive wheel's return map (physics.md §5.5).

use clap::Args;
use hopsim_analysis::impulsive_wheel::{wrap_half_turn, ImpulsiveWheel};
use hopsim_analysis::numerics::linspace;
use hopsim_io::CsvTable;
use hopsim_studies::plot::{LinePlot, Series, SeriesStyle, BLACK, PALETTE};
use serde_json::json;

use super::common::{self, invalid, num, nums, opt_num, OutDir, OutputArgs, Table};

/// Fixed point, eigenvalue and stable impulse interval of φ_{i+1} = φ_i − c sin 2φ_i + φ̇_S T_C,
/// c = R ‖ζ‖² / (m I g); with --out also the bifurcation diagram over ‖ζ‖ and iteration series.
#[derive(Args)]
pub struct ImpulsiveWheelArgs {
    /// Impulse magnitude ‖ζ‖ [N s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 3.5)]
    pub impulse: f64,
    /// Mass m [kg].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub mass: f64,
    /// Radius R [m].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub radius: f64,
    /// Inertia I [kg m²].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub inertia: f64,
    /// Time between impulses T_C [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub cycle_time: f64,
    /// Rolling energy E₀ = ½ (I + m R²) φ̇_S² [J].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub rolling_energy: f64,
    /// Gravitational acceleration [m/s²].
    #[arg(long, allow_negative_numbers = true, default_value_t = hopsim_analysis::STANDARD_GRAVITY)]
    pub gravity: f64,
    /// Impulses of the iteration series (default: --impulse), e.g. --series 3,3.5,3.8.
    #[arg(long, allow_negative_numbers = true, value_delimiter = ',')]
    pub series: Vec<f64>,
    /// Iterations of each series.
    #[arg(long, default_value_t = 40)]
    pub iterations: usize,
    /// Initial take-off angle of the series and the bifurcation diagram [rad].
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub initial_angle: f64,
    /// Smallest impulse of the bifurcation diagram [N s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 2.0)]
    pub impulse_min: f64,
    /// Largest impulse of the bifurcation diagram [N s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 5.0)]
    pub impulse_max: f64,
    /// Impulse values of the bifurcation diagram.
    #[arg(long, default_value_t = 600)]
    pub bifurcation_points: usize,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Iterations of the bifurcation diagram dropped as transient, and iterations kept.
const TRANSIENT: usize = 500;
const KEEP: usize = 64;

pub fn run(args: ImpulsiveWheelArgs) -> anyhow::Result<()> {
    common::check_all_finite(&[
        ("impulse", Some(args.impulse)),
        ("mass", Some(args.mass)),
        ("radius", Some(args.radius)),
        ("inertia", Some(args.inertia)),
        ("cycle-time", Some(args.cycle_time)),
        ("rolling-energy", Some(args.rolling_energy)),
        ("gravity", Some(args.gravity)),
        ("impulse-min", Some(args.impulse_min)),
        ("impulse-max", Some(args.impulse_max)),
        ("initial-angle", Some(args.initial_angle)),
    ])?;
    if args.impulse < 0.0 || args.impulse_min < 0.0 {
        return invalid("impulses must be ≥ 0");
    }
    if args.impulse_max <= args.impulse_min {
        return invalid(format!(
            "--impulse-max ({}) must exceed --impulse-min ({})",
            args.impulse_max, args.impulse_min
        ));
    }
    if args.bifurcation_points < 2 {
        return invalid("--bifurcation-points must be at least 2");
    }
    if let Some(bad) = args.series.iter().find(|z| !(z.is_finite() && **z >= 0.0)) {
        return invalid(format!(
            "--series impulses must be finite and ≥ 0, got {bad}"
        ));
    }
    let wheel = ImpulsiveWheel {
        mass: args.mass,
        radius: args.radius,
        inertia: args.inertia,
        cycle_time: args.cycle_time,
        rolling_energy: args.rolling_energy,
        gravity: args.gravity,
    };
    wheel.validate()?;
    let fp = wheel.fixed_point(args.impulse)?;
    let (lo, hi) = wheel.stable_impulse_interval();
    let series_impulses = if args.series.is_empty() {
        vec![args.impulse]
    } else {
        args.series.clone()
    };
    let series: Vec<(f64, Vec<f64>)> = series_impulses
        .iter()
        .map(|&z| (z, wheel.iterate(z, args.initial_angle, args.iterations)))
        .collect();
    let files = args
        .output
        .write_files(|out| write_outputs(&args, &wheel, &series, out))?;
    if args.output.json {
        return common::print_json(&json!({
            "analysis": "impulsive-wheel",
            "parameters": wheel,
            "rolling_speed_rad_s": wheel.rolling_speed(),
            "drift_rad": wheel.drift(),
            "impulse_Ns": fp.impulse_ns,
            "coupling": fp.coupling,
            "fixed_point_rad": fp.fixed_point_rad,
            "eigenvalue": fp.eigenvalue,
            "stable": fp.stable,
            "stable_impulse_interval_Ns": [lo, hi],
            "series": series.iter().map(|(z, phis)| json!({
                "impulse_Ns": z,
                "takeoff_angles_rad": phis,
            })).collect::<Vec<_>>(),
            "files": files,
        }));
    }
    if args.output.quiet {
        return Ok(());
    }
    let mut t = Table::new("impulsive wheel return map (physics.md §5.5)");
    t.row(
        "m, R, I",
        nums(&[
            (wheel.mass, "kg"),
            (wheel.radius, "m"),
            (wheel.inertia, "kg m²"),
        ]),
    )
    .row(
        "T_C, E₀, g",
        nums(&[
            (wheel.cycle_time, "s"),
            (wheel.rolling_energy, "J"),
            (wheel.gravity, "m/s²"),
        ]),
    )
    .row(
        "rolling speed (per cycle)",
        format!(
            "{} ({})",
            num(wheel.rolling_speed(), "rad/s"),
            num(wheel.drift(), "rad")
        ),
    )
    .row("impulse ‖ζ‖", num(fp.impulse_ns, "N s"))
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
    print!("{t}");
    for (z, phis) in &series {
        let last = phis.last().copied().unwrap_or(f64::NAN);
        println!(
            "series ‖ζ‖ = {}: φ_{} = {} (wrapped to [−π/2, π/2): {})",
            num(*z, "N s"),
            phis.len() - 1,
            num(last, "rad"),
            num(wrap_half_turn(last), "rad")
        );
    }
    common::print_written(&files);
    Ok(())
}

fn write_outputs(
    args: &ImpulsiveWheelArgs,
    wheel: &ImpulsiveWheel,
    series: &[(f64, Vec<f64>)],
    out: &mut OutDir,
) -> anyhow::Result<()> {
    let impulses = linspace(args.impulse_min, args.impulse_max, args.bifurcation_points);
    let diagram = wheel.bifurcation(&impulses, args.initial_angle, TRANSIENT, KEEP);
    let mut csv = CsvTable::new(&["impulse_Ns", "takeoff_angle_rad"]);
    let mut points = Vec::new();
    for (z, phis) in &diagram {
        for &phi in phis {
            csv.push(vec![(*z).into(), phi.into()]);
            points.push((*z, phi));
        }
    }
    out.csv("bifurcation.csv", &csv)?;
    let fixed: Vec<(f64, f64)> = impulses
        .iter()
        .map(|&z| {
            let fp = wheel.fixed_point(z).ok();
            (z, fp.and_then(|f| f.fixed_point_rad).unwrap_or(f64::NAN))
        })
        .collect();
    let (lo, hi) = wheel.stable_impulse_interval();
    let half_pi = 0.5 * std::f64::consts::PI;
    let mut plot = LinePlot::new(
        format!("impulsive wheel: take-off angle after {TRANSIENT} iterations (mod π)"),
        "impulse ‖ζ‖ [N s]",
        "φ [rad]",
    )
    .with_y_range(-half_pi, half_pi)
    .with_series(
        Series::line(
            "fixed point φ* (closed form; stable between the lines)",
            fixed,
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
    for (label, z) in [("stable interval", lo), ("", hi)] {
        let line = Series::line(label, vec![(z, -half_pi), (z, half_pi)])
            .color(BLACK)
            .size(1);
        plot = plot.with_series(if label.is_empty() {
            line.unlabelled()
        } else {
            line
        });
    }
    out.figure("bifurcation", &plot)?;
    let mut csv = CsvTable::new(&["impulse_Ns", "iteration", "takeoff_angle_rad"]);
    let mut plot = LinePlot::new(
        "impulsive wheel: iteration series",
        "iteration i",
        "φ_i [rad]",
    );
    for (k, (z, phis)) in series.iter().enumerate() {
        for (i, &phi) in phis.iter().enumerate() {
            csv.push(vec![(*z).into(), i.into(), phi.into()]);
        }
        plot = plot.with_series(
            Series::line(
                format!("‖ζ‖ = {z}"),
                phis.iter()
                    .enumerate()
                    .map(|(i, &p)| (i as f64, p))
                    .collect(),
            )
            .style(SeriesStyle::LineAndPoints)
            .color(PALETTE[k % PALETTE.len()]),
        );
    }
    out.csv("series.csv", &csv)?;
    out.figure("series", &plot)?;
    Ok(())
}
