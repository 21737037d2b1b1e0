//! `hopsim analyze fixed-points`: Robbit's periodic gaits and their stability (docs/physics.md §5.3,
//! docs/analysis.md §9).

use clap::{Args, ValueEnum};
use hopsim_studies::fixed_points::{fixed_points, FixedPointsParams, Sections};
use hopsim_studies::robbit_gait::StepperSettings;
use hopsim_theory::fixed_points::{DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE};
use hopsim_theory::robbit::{FlywheelAtTouchdown, RobbitParams};

use super::common::{InvalidInput, OutputArgs};
use crate::cmd::render::render;

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
    /// Run every fixed point of the grid from rest for --duration and plot mean speed
    /// against impulse per distance over the last 10 s with the cube baselines (the
    /// thesis' Figure 5.7); with --out, fixed_point_gaits.csv/.png/.svg.
    #[arg(long, conflicts_with_all = ["takeoff_angle", "takeoff_energy"])]
    pub simulate_all: bool,
    /// Time step of --simulate and --simulate-all [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 2e-4)]
    pub dt: f64,
    /// Simulated time of --simulate and --simulate-all [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 20.0)]
    pub duration: f64,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Default grid: 30 × 30 points (seconds); the thesis used 150 × 150.
const DEFAULT_GRID: u32 = 30;

/// The study's parameters (checked by the study), or the invalid `--grid` (exit code 2).
fn params(args: &FixedPointsArgs) -> anyhow::Result<FixedPointsParams> {
    let CaseName::Robbit = args.case;
    let base = RobbitParams::default();
    let robot = RobbitParams {
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
    let sections = match (args.takeoff_angle, args.takeoff_energy) {
        (Some(angle_rad), Some(energy_j)) => Sections::Point {
            angle_rad,
            energy_j,
        },
        _ => {
            let (n, m) = match &args.grid {
                None => (DEFAULT_GRID, DEFAULT_GRID),
                Some(spec) => grid_size(spec).ok_or_else(|| InvalidInput(format!(
                    "--grid must be ANGLESxENERGIES with 1 … 1000 points each (e.g. 150x150), got `{spec}`"
                )))?,
            };
            Sections::Grid {
                angle_range_rad: (args.angle_min, args.angle_max),
                energy_range_j: (args.energy_min, args.energy_max),
                angle_points: args.angle_points.unwrap_or(n) as usize,
                energy_points: args.energy_points.unwrap_or(m) as usize,
            }
        }
    };
    let settings = StepperSettings {
        dt: args.dt,
        duration: args.duration,
        ..StepperSettings::default()
    };
    Ok(FixedPointsParams {
        robot,
        sections,
        simulation: args.simulate.then_some(settings),
        gaits: args.simulate_all.then_some(settings),
    })
}

/// `ANGLESxENERGIES` with 1 … 1000 of each.
fn grid_size(spec: &str) -> Option<(u32, u32)> {
    let (a, b) = spec.split_once(['x', 'X', '×'])?;
    let (a, b) = (a.trim().parse().ok()?, b.trim().parse().ok()?);
    ((1..=1000).contains(&a) && (1..=1000).contains(&b)).then_some((a, b))
}

pub fn run(args: FixedPointsArgs) -> anyhow::Result<()> {
    let report = fixed_points(&params(&args)?, &args.output.cell_bars())?;
    render(&report, &args.output)
}
