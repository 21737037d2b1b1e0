//! `hopsim analyze fixed-points`: Robbit's periodic gaits and their stability (physics.md §5.3,
//! docs/analysis.md §9).

use clap::{Args, ValueEnum};
use hopsim_analysis::fixed_points::{
    find_fixed_point, FixedPoint, FixedPointGrid, GridPoint, NoFixedPoint, SolverSettings,
    DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE,
};
use hopsim_analysis::numerics::Complex;
use hopsim_analysis::robbit::{FlywheelAtTouchdown, RobbitParams, SectionState};
use hopsim_io::{Cell, CsvTable};
use hopsim_studies::plot::{Heatmap, LinePlot, Series, SeriesStyle, BLACK, PALETTE};
use hopsim_studies::robbit_gait::{
    compare, simulate_from_rest, GaitComparison, GaitTolerance, StepperRun, StepperSettings,
};
use serde_json::{json, Value};
use std::time::Instant;

use super::common::{self, invalid, num, num_range, nums, opt_num, OutDir, OutputArgs, Table};

/// Named parameter sets.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum CaseName {
    /// Table 5.1: R 0.2, a 0.1, m_S 0.974, m_R 0.431, I_S 3.004e-3, I_R 1.543e-3, μ 1.
    #[value(name = "robbit")]
    Robbit,
}

/// The flywheel at touchdown.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum TouchdownName {
    /// Still braked: the impact acts on body and flywheel together.
    #[value(name = "locked")]
    Locked,
    /// Released after the brake (hopsim-control's one-step brake).
    #[value(name = "free")]
    Free,
}

/// Fixed-point controls β* = (T*, ζ0*) of Robbit's return map over a grid of take-off angle
/// φ_TO × take-off energy E_TO = ½ (m R² + m a² + I_S − 2 m R a cos φ) φ̇² (forward rolling,
/// φ̇ < 0, just before the brake), with the eigenvalues of the return-map Jacobian; or one
/// point with --takeoff-angle and --takeoff-energy. --simulate runs the time-stepper from rest
/// with a stable β* and compares its take-off states with the prediction.
#[derive(Args)]
pub struct FixedPointsArgs {
    /// Parameter set (Table 5.1).
    #[arg(long, value_enum, default_value = "robbit")]
    pub case: CaseName,
    /// One section state instead of a grid: take-off angle φ_TO [rad] (needs --takeoff-energy).
    #[arg(long, allow_negative_numbers = true, requires = "takeoff_energy")]
    pub takeoff_angle: Option<f64>,
    /// One section state: take-off energy E_TO [J] (needs --takeoff-angle).
    #[arg(long, allow_negative_numbers = true, requires = "takeoff_angle")]
    pub takeoff_energy: Option<f64>,
    /// Grid size as ANGLESxENERGIES, e.g. 150x150 (default 30x30).
    #[arg(long, value_name = "NxM", conflicts_with_all = ["takeoff_angle", "takeoff_energy"])]
    pub grid: Option<String>,
    /// Take-off angles of the grid (overrides --grid).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub angle_points: Option<u32>,
    /// Take-off energies of the grid (overrides --grid).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub energy_points: Option<u32>,
    /// Smallest take-off angle of the grid [rad].
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_ANGLE_RANGE.0)]
    pub angle_min: f64,
    /// Largest take-off angle of the grid [rad].
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_ANGLE_RANGE.1)]
    pub angle_max: f64,
    /// Smallest take-off energy of the grid [J].
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_ENERGY_RANGE.0)]
    pub energy_min: f64,
    /// Largest take-off energy of the grid [J].
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_ENERGY_RANGE.1)]
    pub energy_max: f64,
    /// Disc radius R [m].
    #[arg(long, allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Eccentricity a (CoM to disc centre) [m].
    #[arg(long, allow_negative_numbers = true)]
    pub eccentricity: Option<f64>,
    /// Main body mass m_S [kg].
    #[arg(long, allow_negative_numbers = true)]
    pub body_mass: Option<f64>,
    /// Flywheel mass m_R [kg].
    #[arg(long, allow_negative_numbers = true)]
    pub flywheel_mass: Option<f64>,
    /// Main body inertia about the CoM I_S [kg m²].
    #[arg(long, allow_negative_numbers = true)]
    pub body_inertia: Option<f64>,
    /// Flywheel inertia I_R [kg m²].
    #[arg(long, allow_negative_numbers = true)]
    pub flywheel_inertia: Option<f64>,
    /// Friction coefficient μ (checked against; the model assumes no slip).
    #[arg(long, allow_negative_numbers = true)]
    pub friction: Option<f64>,
    /// Gravitational acceleration [m/s²].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f64>,
    /// The flywheel at touchdown: still braked (locked) or released (free).
    #[arg(long, value_enum, default_value = "locked")]
    pub touchdown: TouchdownName,
    /// Also run the time-stepper from rest with a stable β* (the given point's, or the grid's
    /// stable point with the smallest max |λ| and no model warnings) and compare its take-off
    /// states with the prediction.
    #[arg(long)]
    pub simulate: bool,
    /// Time step of --simulate [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 2e-4)]
    pub dt: f64,
    /// Simulated time of --simulate [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 20.0)]
    pub duration: f64,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Default grid: 30 × 30 points (seconds); the thesis used 150 × 150.
const DEFAULT_GRID: u32 = 30;
/// Brakes at the end of a simulation that are compared with the prediction.
const SIMULATION_WINDOW: usize = 10;

fn params(args: &FixedPointsArgs) -> anyhow::Result<RobbitParams> {
    common::check_all_finite(&[
        ("radius", args.radius),
        ("eccentricity", args.eccentricity),
        ("body-mass", args.body_mass),
        ("flywheel-mass", args.flywheel_mass),
        ("body-inertia", args.body_inertia),
        ("flywheel-inertia", args.flywheel_inertia),
        ("friction", args.friction),
        ("gravity", args.gravity),
        ("takeoff-angle", args.takeoff_angle),
        ("takeoff-energy", args.takeoff_energy),
        ("angle-min", Some(args.angle_min)),
        ("angle-max", Some(args.angle_max)),
        ("energy-min", Some(args.energy_min)),
        ("energy-max", Some(args.energy_max)),
        ("dt", Some(args.dt)),
        ("duration", Some(args.duration)),
    ])?;
    let CaseName::Robbit = args.case;
    let base = RobbitParams::default();
    let p = RobbitParams {
        radius: args.radius.unwrap_or(base.radius),
        eccentricity: args.eccentricity.unwrap_or(base.eccentricity),
        body_mass: args.body_mass.unwrap_or(base.body_mass),
        flywheel_mass: args.flywheel_mass.unwrap_or(base.flywheel_mass),
        body_inertia: args.body_inertia.unwrap_or(base.body_inertia),
        flywheel_inertia: args.flywheel_inertia.unwrap_or(base.flywheel_inertia),
        friction: args.friction.unwrap_or(base.friction),
        gravity: args.gravity.unwrap_or(base.gravity),
        touchdown: match args.touchdown {
            TouchdownName::Locked => FlywheelAtTouchdown::Locked,
            TouchdownName::Free => FlywheelAtTouchdown::Free,
        },
    };
    p.validate()?;
    if args.simulate && !(args.dt > 0.0 && args.duration > args.dt) {
        return invalid(format!(
            "--dt ({}) must be > 0 and below --duration ({})",
            args.dt, args.duration
        ));
    }
    Ok(p)
}

fn params_json(p: &RobbitParams) -> Value {
    json!({
        "radius_m": p.radius,
        "eccentricity_m": p.eccentricity,
        "body_mass_kg": p.body_mass,
        "flywheel_mass_kg": p.flywheel_mass,
        "body_inertia_kg_m2": p.body_inertia,
        "flywheel_inertia_kg_m2": p.flywheel_inertia,
        "friction": p.friction,
        "gravity_mps2": p.gravity,
        "flywheel_at_touchdown": p.touchdown.name(),
        "reduced_inertia_kg_m2": p.reduced_inertia(),
    })
}

const ENERGY_DEFINITION: &str = "E_TO = ½ (m R² + m a² + I_S − 2 m R a cos φ_TO) φ̇_TO²: kinetic energy of the rolling robot just before the brake without the flywheel's spin; φ̇_TO = −sqrt(2 E_TO / (…)) < 0 (forward rolling)";

fn eigen_json(l: &Complex) -> Value {
    json!({ "re": l.re, "im": l.im, "modulus": l.modulus(), "argument": l.argument() })
}

fn fixed_point_json(p: &RobbitParams, fp: &FixedPoint) -> Value {
    let c = &fp.cycle;
    json!({
        "torque_Nm": fp.control.torque,
        "impulse_limit_Nms": fp.control.impulse_limit,
        "residual_rad": fp.residual,
        "iterations": fp.iterations,
        "jacobian": fp.jacobian,
        "eigenvalues": fp.eigenvalues.iter().map(eigen_json).collect::<Vec<_>>(),
        "max_abs_eigenvalue": fp.spectral_radius,
        "stable": fp.stable,
        "speed_mps": fp.speed(),
        "stride_m": c.stride,
        "period_s": c.period,
        "flight_time_s": c.flight_time,
        "touchdown_angle_rad": c.touchdown_angle,
        "stance_time_s": c.stance.duration,
        "stance_reversals": c.stance.reversals,
        "brake_loss_J": c.brake.energy_loss,
        "touchdown_loss_J": c.touchdown.energy_loss,
        "motor_work_J": c.stance.motor_work,
        "impulse_per_distance_Nms_per_m": fp.impulse_per_distance(),
        "touchdown_normal_percussion_Ns": c.touchdown.normal_percussion,
        "touchdown_tangential_percussion_Ns": c.touchdown.tangential_percussion,
        "min_stance_normal_force_N": c.stance.min_normal_force,
        "max_stance_friction_ratio": c.stance.max_friction_ratio,
        "warnings": fp.warnings(p),
    })
}

fn point_json(p: &RobbitParams, pt: &GridPoint) -> Value {
    let mut v = json!({
        "takeoff_angle_rad": pt.angle,
        "takeoff_energy_J": pt.energy,
        "takeoff_rate_rad_s": pt.angular_velocity,
        "fixed_point": pt.fixed_point.is_some(),
        "stable": pt.fixed_point.as_ref().is_some_and(|f| f.stable),
        "reason": pt.no_fixed_point.as_ref().map(|r| r.to_string()),
        "reason_kind": pt.no_fixed_point.as_ref().map(reason_kind),
    });
    if let (Some(fp), Some(map)) = (&pt.fixed_point, v.as_object_mut()) {
        if let Some(extra) = fixed_point_json(p, fp).as_object() {
            map.extend(extra.clone());
        }
    }
    v
}

fn reason_kind(r: &NoFixedPoint) -> String {
    match r {
        NoFixedPoint::NoCycle { reason } => serde_json::to_value(reason)
            .ok()
            .and_then(|v| v["kind"].as_str().map(str::to_string))
            .unwrap_or_else(|| "no-cycle".into()),
        NoFixedPoint::NotConverged { .. } => "solver-failed".into(),
        NoFixedPoint::MovesBackward { .. } => "moves-backward".into(),
    }
}

fn grid_size(args: &FixedPointsArgs) -> anyhow::Result<(usize, usize)> {
    let (mut n, mut m) = (DEFAULT_GRID, DEFAULT_GRID);
    if let Some(spec) = &args.grid {
        let parsed = spec
            .split_once(['x', 'X', '×'])
            .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)))
            .filter(|&(a, b)| (1..=1000).contains(&a) && (1..=1000).contains(&b));
        match parsed {
            Some((a, b)) => (n, m) = (a, b),
            None => {
                return invalid(format!(
                    "--grid must be ANGLESxENERGIES with 1 … 1000 points each (e.g. 150x150), got `{spec}`"
                ))
            }
        }
    }
    n = args.angle_points.unwrap_or(n);
    m = args.energy_points.unwrap_or(m);
    if !(args.angle_min < args.angle_max || n == 1) {
        return invalid(format!(
            "--angle-min ({}) must be below --angle-max ({})",
            args.angle_min, args.angle_max
        ));
    }
    if !(args.energy_min < args.energy_max || m == 1) || args.energy_min < 0.0 {
        return invalid(format!(
            "the energy range must satisfy 0 ≤ --energy-min ({}) < --energy-max ({})",
            args.energy_min, args.energy_max
        ));
    }
    Ok((n as usize, m as usize))
}

pub fn run(args: FixedPointsArgs) -> anyhow::Result<()> {
    let p = params(&args)?;
    match (args.takeoff_angle, args.takeoff_energy) {
        (Some(angle), Some(energy)) => run_point(&args, &p, angle, energy),
        _ => run_grid(&args, &p),
    }
}

/// The stepper cross-check of a fixed point.
struct Simulation {
    fixed_point: FixedPoint,
    run: StepperRun,
    comparison: Option<GaitComparison>,
    elapsed_s: f64,
}

fn simulate(
    args: &FixedPointsArgs,
    p: &RobbitParams,
    fp: &FixedPoint,
) -> anyhow::Result<Simulation> {
    let started = Instant::now();
    let settings = StepperSettings {
        dt: args.dt,
        duration: args.duration,
        ..StepperSettings::default()
    };
    let run = simulate_from_rest(p, &fp.control, &settings)?;
    let comparison = compare(fp, &run, SIMULATION_WINDOW, &GaitTolerance::default());
    Ok(Simulation {
        fixed_point: fp.clone(),
        run,
        comparison,
        elapsed_s: started.elapsed().as_secs_f64(),
    })
}

fn simulation_json(p: &RobbitParams, sim: &Simulation) -> Value {
    let fp = &sim.fixed_point;
    let c = sim.comparison.as_ref();
    let last = sim.run.brakes.last();
    json!({
        "takeoff_angle_rad": fp.state.angle,
        "takeoff_energy_J": fp.state.energy(p),
        "torque_Nm": fp.control.torque,
        "impulse_limit_Nms": fp.control.impulse_limit,
        "dt_s": sim.run.settings.dt,
        "duration_s": sim.run.settings.duration,
        "brakes": sim.run.brakes.len(),
        "predicted": {
            "takeoff_angle_rad": fp.state.angle,
            "takeoff_rate_rad_s": fp.state.angular_velocity,
            "speed_mps": fp.speed(),
            "period_s": fp.cycle.period,
            "max_abs_eigenvalue": fp.spectral_radius,
        },
        "simulated": {
            "last_takeoff_angle_rad": last.map(|b| b.state.angle),
            "last_takeoff_rate_rad_s": last.map(|b| b.state.angular_velocity),
            "speed_mps": c.map(|c| c.simulated_speed),
            "period_s": c.map(|c| c.simulated_period),
        },
        "window": c.map(|c| c.window),
        "max_angle_error_rad": c.map(|c| c.max_angle_error),
        "max_rate_error_rad_s": c.map(|c| c.max_rate_error),
        "converged": c.is_some_and(|c| c.converged),
        "angle_tolerance_rad": c.map(|c| c.angle_tolerance),
        "rate_tolerance_rad_s": c.map(|c| c.rate_tolerance),
        "max_penetration_m": sim.run.max_penetration,
        "energy_balance_error_J": sim.run.energy_balance_error,
        "elapsed_s": sim.elapsed_s,
        "takeoff_errors": c.map(|c| c.takeoffs.iter().map(|d| json!({
            "brake": d.index, "t_s": d.t, "angle_error_rad": d.angle_error, "rate_error_rad_s": d.rate_error,
        })).collect::<Vec<_>>()),
    })
}

/// `β* = (T*, ζ0*)` of a fixed point, for the tables.
fn control(fp: &FixedPoint) -> String {
    nums(&[
        (fp.control.torque, "N m"),
        (fp.control.impulse_limit, "N m s"),
    ])
}

/// `predicted P, <label> S` in `unit` (`—` for a missing `S`).
fn versus(predicted: f64, label: &str, simulated: Option<f64>, unit: &str) -> String {
    format!(
        "predicted {}, {label} {}",
        num(predicted, unit),
        opt_num(simulated, unit, "—")
    )
}

fn print_simulation(sim: &Simulation) {
    let fp = &sim.fixed_point;
    let mut t = Table::new(format!(
        "time-stepper from rest (Δt = {} s, {} s, {} brakes) vs predicted gait",
        sim.run.settings.dt,
        sim.run.settings.duration,
        sim.run.brakes.len()
    ));
    t.row("β* = (T*, ζ0*)", control(fp));
    match &sim.comparison {
        Some(c) => {
            let last = sim.run.brakes.last().map(|b| b.state);
            t.row(
                "take-off angle φ_TO",
                versus(
                    fp.state.angle,
                    "last simulated",
                    last.map(|s| s.angle),
                    "rad",
                ),
            )
            .row(
                "take-off rate φ̇_TO",
                versus(
                    fp.state.angular_velocity,
                    "last simulated",
                    last.map(|s| s.angular_velocity),
                    "rad/s",
                ),
            )
            .row(
                format!("max error, last {} brakes", c.window),
                format!(
                    "{} (tolerance {}), {} (tolerance {})",
                    num(c.max_angle_error, "rad"),
                    num(c.angle_tolerance, "rad"),
                    num(c.max_rate_error, "rad/s"),
                    num(c.rate_tolerance, "rad/s")
                ),
            )
            .row(
                "speed",
                versus(
                    c.predicted_speed,
                    "simulated",
                    Some(c.simulated_speed),
                    "m/s",
                ),
            )
            .row(
                "period",
                versus(
                    c.predicted_period,
                    "simulated",
                    Some(c.simulated_period),
                    "s",
                ),
            )
            .row(
                "converges to the predicted gait",
                if c.converged { "yes" } else { "no" },
            );
        }
        None => {
            t.row(
                "converges to the predicted gait",
                "no: fewer than two brakes in the run",
            );
        }
    }
    t.row("elapsed", num(sim.elapsed_s, "s"));
    print!("{t}");
}

fn write_simulation(out: &mut OutDir, sim: &Simulation) -> anyhow::Result<()> {
    let Some(c) = &sim.comparison else {
        return Ok(());
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
    for (b, d) in sim.run.brakes.iter().zip(&c.takeoffs) {
        csv.push(vec![
            d.index.into(),
            b.t.into(),
            b.x.into(),
            b.state.angle.into(),
            b.state.angular_velocity.into(),
            b.stored_impulse.into(),
            d.angle_error.into(),
            d.rate_error.into(),
        ]);
    }
    out.csv("simulation_takeoffs.csv", &csv)?;
    let series = |f: fn(&hopsim_studies::robbit_gait::TakeoffDifference) -> f64| {
        c.takeoffs
            .iter()
            .map(|d| (d.index as f64, f(d)))
            .collect::<Vec<_>>()
    };
    let plot = LinePlot::new(
        "time-stepper take-off states minus the predicted fixed point",
        "brake",
        "error",
    )
    .with_series(
        Series::line("angle: φ − φ* [rad]", series(|d| d.angle_error))
            .style(SeriesStyle::LineAndPoints)
            .color(PALETTE[0]),
    )
    .with_series(
        Series::line("rate: dφ/dt − (dφ/dt)* [rad/s]", series(|d| d.rate_error))
            .style(SeriesStyle::LineAndPoints)
            .color(PALETTE[1]),
    )
    .with_series(
        Series::line("", vec![(0.0, 0.0), (c.takeoffs.len() as f64, 0.0)])
            .color(BLACK)
            .size(1)
            .unlabelled(),
    );
    out.figure("simulation_takeoffs", &plot)
}

fn run_point(
    args: &FixedPointsArgs,
    p: &RobbitParams,
    angle: f64,
    energy: f64,
) -> anyhow::Result<()> {
    let z = SectionState::from_energy(p, angle, energy)?;
    let started = Instant::now();
    let outcome = find_fixed_point(p, &z, &SolverSettings::default())?;
    let elapsed = started.elapsed().as_secs_f64();
    let point = GridPoint {
        angle,
        energy,
        angular_velocity: z.angular_velocity,
        fixed_point: outcome.as_ref().ok().cloned(),
        no_fixed_point: outcome.as_ref().err().cloned(),
    };
    let sim = match (&point.fixed_point, args.simulate) {
        (Some(fp), true) => Some(simulate(args, p, fp)?),
        _ => None,
    };
    let files = args.output.write_files(|out| {
        let mut csv = grid_csv_table();
        csv.push(grid_csv_row(p, &point));
        out.csv("fixed_point.csv", &csv)?;
        match &sim {
            Some(sim) => write_simulation(out, sim),
            None => Ok(()),
        }
    })?;
    if args.output.json {
        let mut v = point_json(p, &point);
        if let Some(map) = v.as_object_mut() {
            map.insert("analysis".into(), json!("fixed-points"));
            map.insert("mode".into(), json!("point"));
            map.insert("case".into(), json!("robbit"));
            map.insert("parameters".into(), params_json(p));
            map.insert("energy_definition".into(), json!(ENERGY_DEFINITION));
            map.insert("elapsed_s".into(), json!(elapsed));
            map.insert(
                "simulation".into(),
                sim.as_ref().map_or(Value::Null, |s| simulation_json(p, s)),
            );
            map.insert("files".into(), json!(files));
        }
        return common::print_json(&v);
    }
    if args.output.quiet {
        return Ok(());
    }
    let mut t =
        Table::new("Robbit fixed point (physics.md §5.3; forward = +x, φ counter-clockwise)");
    t.row("flywheel at touchdown", p.touchdown.name()).row(
        "section state z = (φ_TO, φ̇_TO)",
        format!(
            "{} (E_TO {})",
            nums(&[(angle, "rad"), (z.angular_velocity, "rad/s")]),
            num(energy, "J")
        ),
    );
    match (&point.fixed_point, &point.no_fixed_point) {
        (Some(fp), _) => {
            let c = &fp.cycle;
            t.row("β* = (T*, ζ0*)", control(fp))
                .row(
                    "eigenvalues of ∂P/∂z",
                    format!(
                        "{}, {}",
                        complex(&fp.eigenvalues[0]),
                        complex(&fp.eigenvalues[1])
                    ),
                )
                .row(
                    "max |λ|",
                    format!(
                        "{} ({})",
                        num(fp.spectral_radius, ""),
                        if fp.stable { "stable" } else { "unstable" }
                    ),
                )
                .row(
                    "speed, stride, period",
                    nums(&[(fp.speed(), "m/s"), (c.stride, "m"), (c.period, "s")]),
                )
                .row(
                    "flight, stance",
                    format!(
                        "{} ({} reversals of φ̇)",
                        nums(&[(c.flight_time, "s"), (c.stance.duration, "s")]),
                        c.stance.reversals
                    ),
                )
                .row("touchdown angle", num(c.touchdown_angle, "rad"))
                .row(
                    "energy per cycle",
                    format!(
                        "motor {} = brake loss {} + touchdown loss {}",
                        num(c.stance.motor_work, "J"),
                        num(c.brake.energy_loss, "J"),
                        num(c.touchdown.energy_loss, "J")
                    ),
                )
                .row(
                    "impulse per distance ζ0/stride",
                    num(fp.impulse_per_distance(), "N m s/m"),
                )
                .row("residual", num(fp.residual, "rad"));
            print!("{t}");
            for w in fp.warnings(p) {
                println!("warning: {w}");
            }
        }
        (None, Some(reason)) => {
            t.row("fixed point", format!("none: {reason}"));
            print!("{t}");
        }
        (None, None) => print!("{t}"),
    }
    if let Some(sim) = &sim {
        print_simulation(sim);
    } else if args.simulate {
        println!("--simulate: no fixed point to simulate");
    }
    common::print_written(&files);
    Ok(())
}

fn complex(l: &Complex) -> String {
    if l.im == 0.0 {
        num(l.re, "")
    } else {
        format!(
            "{} {} {}i",
            num(l.re, ""),
            if l.im < 0.0 { "−" } else { "+" },
            num(l.im.abs(), "")
        )
    }
}

fn grid_csv_table() -> CsvTable {
    CsvTable::new(&[
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
    ])
}

fn grid_csv_row(p: &RobbitParams, pt: &GridPoint) -> Vec<Cell> {
    let fp = pt.fixed_point.as_ref();
    let eig = |i: usize, f: fn(&Complex) -> f64| fp.map(|f0| f(&f0.eigenvalues[i]));
    vec![
        pt.angle.into(),
        pt.energy.into(),
        pt.angular_velocity.into(),
        fp.is_some().into(),
        fp.map(|f| f.control.torque).into(),
        fp.map(|f| f.control.impulse_limit).into(),
        eig(0, |l| l.re).into(),
        eig(0, |l| l.im).into(),
        eig(0, Complex::modulus).into(),
        eig(0, Complex::argument).into(),
        eig(1, |l| l.re).into(),
        eig(1, |l| l.im).into(),
        eig(1, Complex::modulus).into(),
        eig(1, Complex::argument).into(),
        fp.map(|f| f.spectral_radius).into(),
        fp.map_or(Cell::Empty, |f| f.stable.into()),
        fp.map(FixedPoint::speed).into(),
        fp.map(|f| f.cycle.stride).into(),
        fp.map(|f| f.cycle.period).into(),
        fp.map(FixedPoint::impulse_per_distance).into(),
        fp.map_or(Cell::Empty, |f| f.cycle.stance.reversals.into()),
        fp.map_or(Cell::Empty, |f| Cell::Text(f.warnings(p).join("; "))),
        pt.no_fixed_point
            .as_ref()
            .map_or(Cell::Empty, |r| Cell::Text(r.to_string())),
    ]
}

/// Colour range of a heatmap: minimum to maximum, except that with `cap` a long upper tail
/// (the range more than twice the range up to the 95th percentile, e.g. the large torques
/// next to `φ_TO = 0`) is cut at the 95th percentile so that the rest of the map keeps its
/// contrast; the flag says whether it was cut.
fn colour_range(values: &[Option<f64>], cap: bool) -> ((f64, f64), bool) {
    let mut finite: Vec<f64> = values
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    if finite.is_empty() {
        return ((0.0, 1.0), false);
    }
    finite.sort_by(f64::total_cmp);
    let (lo, hi) = (finite[0], finite[finite.len() - 1]);
    let p95 = finite[(0.95 * (finite.len() - 1) as f64).round() as usize];
    if cap && hi - lo > 2.0 * (p95 - lo) && p95 > lo {
        ((lo, p95), true)
    } else if hi > lo {
        ((lo, hi), false)
    } else {
        ((lo - 0.5, hi + 0.5), false)
    }
}

/// The fixed point of a grid point known to have one.
fn found_fixed_point(q: &GridPoint) -> &FixedPoint {
    q.fixed_point.as_ref().expect("fixed point")
}

fn run_grid(args: &FixedPointsArgs, p: &RobbitParams) -> anyhow::Result<()> {
    let (n, m) = grid_size(args)?;
    let grid = FixedPointGrid::new(
        *p,
        (args.angle_min, args.angle_max),
        (args.energy_min, args.energy_max),
        n,
        m,
    );
    let started = Instant::now();
    let bar = common::bar(n * m, "Robbit fixed points", args.output.hide_progress());
    let points = grid.run(&|| bar.inc(1))?;
    bar.finish_and_clear();
    let elapsed = started.elapsed().as_secs_f64();
    let found: Vec<&GridPoint> = points.iter().filter(|q| q.fixed_point.is_some()).collect();
    let stable: Vec<&GridPoint> = found
        .iter()
        .copied()
        .filter(|q| q.fixed_point.as_ref().is_some_and(|f| f.stable))
        .collect();
    let with_warnings = found
        .iter()
        .filter(|q| {
            q.fixed_point
                .as_ref()
                .is_some_and(|f| !f.warnings(p).is_empty())
        })
        .count();
    // The stable point with the smallest max |λ| among those the no-slip, closed-contact
    // model describes consistently (no warnings), else among all stable points.
    let consistent = |q: &&GridPoint| {
        q.fixed_point
            .as_ref()
            .is_some_and(|f| f.warnings(p).is_empty())
    };
    let by_radius = |a: &&GridPoint, b: &&GridPoint| {
        found_fixed_point(a)
            .spectral_radius
            .total_cmp(&found_fixed_point(b).spectral_radius)
    };
    let most_stable = stable
        .iter()
        .copied()
        .filter(consistent)
        .min_by(by_radius)
        .or_else(|| stable.iter().copied().min_by(by_radius));
    let fastest = stable.iter().copied().max_by(|a, b| {
        found_fixed_point(a)
            .speed()
            .total_cmp(&found_fixed_point(b).speed())
    });
    let mut reasons: std::collections::BTreeMap<String, usize> = Default::default();
    for q in &points {
        if let Some(r) = &q.no_fixed_point {
            *reasons.entry(reason_kind(r)).or_default() += 1;
        }
    }
    let sim = match (args.simulate, most_stable) {
        (true, Some(q)) => Some(simulate(args, p, found_fixed_point(q))?),
        _ => None,
    };
    let files = args.output.write_files(|out| {
        let mut csv = grid_csv_table();
        for q in &points {
            csv.push(grid_csv_row(p, q));
        }
        out.csv("fixed_points.csv", &csv)?;
        // Unstable points get a cross; on dense grids only every k-th row and column
        // (k = ⌈max(n, m) / 40⌉), so that the crosses hatch the region without hiding it.
        let k = n.max(m).div_ceil(40);
        let unstable: Vec<(f64, f64)> = points
            .iter()
            .enumerate()
            .filter(|(i, _)| (i % n) % k == 0 && (i / n) % k == 0)
            .filter(|(_, q)| q.fixed_point.as_ref().is_some_and(|f| !f.stable))
            .map(|(_, q)| (q.angle, q.energy))
            .collect();
        // `cap`: cut a long upper tail of the colour scale (the torques next to φ_TO = 0);
        // max |λ| keeps its full range, so that the unstable region shows its gradient.
        let map = |title: &str, label: &str, cap: bool, f: fn(&FixedPoint) -> f64| {
            let values: Vec<Option<f64>> = points
                .iter()
                .map(|q| q.fixed_point.as_ref().map(f))
                .collect();
            let (range, capped) = colour_range(&values, cap);
            let note = if capped {
                format!(", colours capped at {}", num(range.1, ""))
            } else {
                String::new()
            };
            let mut h = Heatmap::new(
                format!("Robbit {title} (blank: none, ×: unstable{note})"),
                "take-off angle φ_TO [rad]",
                "take-off energy E_TO [J]",
                label,
                grid.angles.clone(),
                grid.energies.clone(),
                values,
            )
            .with_value_range(range.0, range.1);
            if !unstable.is_empty() {
                h = h.with_overlay(
                    Series::points("unstable (max |λ| ≥ 1)", unstable.clone())
                        .style(SeriesStyle::Crosses)
                        .color(BLACK),
                );
            }
            h
        };
        out.figure(
            "fixed_points_torque",
            &map("fixed-point torque T*", "T* [N m]", true, |f| {
                f.control.torque
            }),
        )?;
        out.figure(
            "fixed_points_impulse_limit",
            &map(
                "fixed-point impulse limit ζ0*",
                "ζ0* [N m s]",
                true,
                |f| f.control.impulse_limit,
            ),
        )?;
        out.figure(
            "fixed_points_max_eigenvalue",
            &map("max |λ| of ∂P/∂z", "max |λ|", false, |f| {
                f.spectral_radius
            }),
        )?;
        match &sim {
            Some(sim) => write_simulation(out, sim),
            None => Ok(()),
        }
    })?;
    if args.output.json {
        return common::print_json(&json!({
            "analysis": "fixed-points",
            "mode": "grid",
            "case": "robbit",
            "parameters": params_json(p),
            "energy_definition": ENERGY_DEFINITION,
            "angles_rad": grid.angles,
            "energies_J": grid.energies,
            "points_total": points.len(),
            "fixed_points": found.len(),
            "stable_points": stable.len(),
            "unstable_points": found.len() - stable.len(),
            "no_fixed_point": points.len() - found.len(),
            "no_fixed_point_reasons": reasons,
            "fixed_points_with_warnings": with_warnings,
            "elapsed_s": elapsed,
            "most_stable": most_stable.map(|q| point_json(p, q)),
            "fastest_stable": fastest.map(|q| point_json(p, q)),
            "points": points.iter().map(|q| point_json(p, q)).collect::<Vec<_>>(),
            "simulation": sim.as_ref().map_or(Value::Null, |s| simulation_json(p, s)),
            "files": files,
        }));
    }
    if args.output.quiet {
        return Ok(());
    }
    let mut t = Table::new(format!(
        "Robbit fixed points (physics.md §5.3), {n} × {m} grid (φ_TO × E_TO)"
    ));
    t.row(
        "φ_TO range",
        num_range(grid.angles[0], grid.angles[n - 1], "rad"),
    )
    .row(
        "E_TO range",
        format!(
            "{} (rolling kinetic energy before the brake)",
            num_range(grid.energies[0], grid.energies[m - 1], "J")
        ),
    )
    .row("flywheel at touchdown", p.touchdown.name())
    .row(
        "fixed points",
        format!(
            "{} of {} (stable {}, unstable {})",
            found.len(),
            points.len(),
            stable.len(),
            found.len() - stable.len()
        ),
    )
    .row(
        "no fixed point",
        if reasons.is_empty() {
            "0".to_string()
        } else {
            reasons
                .iter()
                // The kinds of `no_fixed_point_reasons` in words, e.g. "2 solver failed", the
                // words that start the CSV's and the JSON's reason text for that kind.
                .map(|(k, v)| format!("{v} {}", k.replace('-', " ")))
                .collect::<Vec<_>>()
                .join(", ")
        },
    )
    .row(
        "model warnings",
        format!("{with_warnings} fixed points leave the friction cone or need a pulling ground"),
    )
    .row("elapsed", num(elapsed, "s"));
    print!("{t}");
    let sample: Vec<&GridPoint> = if found.len() <= 8 {
        found.clone()
    } else {
        (0..8).map(|i| found[i * (found.len() - 1) / 7]).collect()
    };
    let labelled: Vec<(&str, &GridPoint)> = most_stable
        .map(|q| ("most stable¹", q))
        .into_iter()
        .chain(fastest.map(|q| ("fastest stable", q)))
        .chain(sample.into_iter().map(|q| ("", q)))
        .collect();
    if !labelled.is_empty() {
        println!(
            "  {:<15} {:>8} {:>8} {:>9} {:>10} {:>8} {:>8} {:>8}",
            "", "φ_TO", "E_TO", "T*", "ζ0*", "max|λ|", "stable", "speed"
        );
        for (label, q) in labelled {
            let f = found_fixed_point(q);
            println!(
                "  {:<15} {:>8.4} {:>8.4} {:>9.4} {:>10.5} {:>8.4} {:>8} {:>8.4}",
                label,
                q.angle,
                q.energy,
                f.control.torque,
                f.control.impulse_limit,
                f.spectral_radius,
                if f.stable { "yes" } else { "no" },
                f.speed()
            );
        }
        println!(
            "  (angles rad, energies J, T* N m, ζ0* N m s, speed m/s; ¹ without model warnings)"
        );
    }
    if let Some(sim) = &sim {
        print_simulation(sim);
    } else if args.simulate {
        println!("--simulate: no stable fixed point in the grid to simulate");
    }
    common::print_written(&files);
    Ok(())
}
