//! `hopsim analyze impulsive-wheel`: the impulsive wheel's return map (docs/physics.md §5.5),
//! computed by [`hopsim_studies::impulsive_wheel`].

use clap::Args;
use hopsim_studies::impulsive_wheel::{impulsive_wheel, BifurcationParams, ImpulsiveWheelParams};
use hopsim_theory::impulsive_wheel::ImpulsiveWheel;

use super::common::OutputArgs;
use crate::cmd::render::render;

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
    #[arg(long, allow_negative_numbers = true, default_value_t = hopsim_theory::STANDARD_GRAVITY)]
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

pub fn run(args: ImpulsiveWheelArgs) -> anyhow::Result<()> {
    render(&impulsive_wheel(&params(&args))?, &args.output)
}

/// The study's parameters (checked by the study).
fn params(args: &ImpulsiveWheelArgs) -> ImpulsiveWheelParams {
    ImpulsiveWheelParams {
        wheel: ImpulsiveWheel {
            mass: args.mass,
            radius: args.radius,
            inertia: args.inertia,
            cycle_time: args.cycle_time,
            rolling_energy: args.rolling_energy,
            gravity: args.gravity,
        },
        impulse_n_s: args.impulse,
        series_impulses_n_s: args.series.clone(),
        iterations: args.iterations,
        initial_angle_rad: args.initial_angle,
        bifurcation: args.output.out.is_some().then_some(BifurcationParams {
            impulse_min_n_s: args.impulse_min,
            impulse_max_n_s: args.impulse_max,
            points: args.bifurcation_points,
        }),
    }
}
