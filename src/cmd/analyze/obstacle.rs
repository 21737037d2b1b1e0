//! `hopsim analyze obstacle`: energy to get a wheel over a wall (docs/physics.md §5.2),
//! computed by [`hopsim_studies::obstacle`].

use clap::Args;
use hopsim_studies::obstacle::{obstacle, MapParams, ObstacleParams};
use hopsim_theory::obstacle::Wheel;

use super::common::{invalid, OutputArgs};
use crate::cmd::render::render;

/// Costs of rolling, trivial hopping and rotational hopping over a wall of height h, for a
/// wheel at one speed; with --out also cost curves and the region maps (cheapest strategy)
/// over α × Fr and over body mass × speed (allometric wheel).
#[derive(Args)]
pub struct ObstacleArgs {
    /// Wheel mass m [kg].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub mass: f64,
    /// Wheel radius R [m].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub radius: f64,
    /// Inertia about the centre of mass I [kg m²] (default: α m R²).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "inertia_factor")]
    pub inertia: Option<f64>,
    /// Inertia factor α = I / (m R²) (default 0.5, a solid disc).
    #[arg(long, allow_negative_numbers = true)]
    pub inertia_factor: Option<f64>,
    /// Wall height h [m] (default: 0.2 R).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "height_ratio")]
    pub height: Option<f64>,
    /// Wall height as a fraction of the radius, h / R (default 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub height_ratio: Option<f64>,
    /// Approach speed u_x [m/s] (default: Fr = 1).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "froude")]
    pub speed: Option<f64>,
    /// Froude number Fr = u_x² / (g R) (default 1).
    #[arg(long, allow_negative_numbers = true)]
    pub froude: Option<f64>,
    /// Gravitational acceleration [m/s²].
    #[arg(long, allow_negative_numbers = true, default_value_t = hopsim_theory::STANDARD_GRAVITY)]
    pub gravity: f64,
    /// h/R values of the region maps (with --out).
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        default_value = "0.1,0.2,0.3,0.4,0.5"
    )]
    pub map_height_ratios: Vec<f64>,
    /// Region-map cells per axis (with --out).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(2..=400))]
    pub resolution: u32,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// The study's parameters (checked by the study; the ratios given instead of a value are
/// checked here so that the error names them).
fn params(args: &ObstacleArgs) -> anyhow::Result<ObstacleParams> {
    for (name, value) in [
        ("inertia-factor", args.inertia_factor),
        ("height-ratio", args.height_ratio),
        ("froude", args.froude),
    ] {
        match value {
            Some(v) if !(v.is_finite() && v > 0.0) => {
                return invalid(format!("--{name} must be a finite number > 0, got {v}"))
            }
            _ => {}
        }
    }
    let inertia = args
        .inertia
        .unwrap_or(args.inertia_factor.unwrap_or(0.5) * args.mass * args.radius * args.radius);
    let wheel = Wheel {
        mass: args.mass,
        radius: args.radius,
        inertia,
        gravity: args.gravity,
    };
    Ok(ObstacleParams {
        speed_mps: args
            .speed
            .unwrap_or_else(|| wheel.speed_from_froude(args.froude.unwrap_or(1.0))),
        height_m: args
            .height
            .unwrap_or(args.height_ratio.unwrap_or(0.2) * args.radius),
        wheel,
        maps: args.output.out.is_some().then(|| MapParams {
            height_ratios: args.map_height_ratios.clone(),
            resolution: args.resolution as usize,
        }),
    })
}

pub fn run(args: ObstacleArgs) -> anyhow::Result<()> {
    let report = obstacle(&params(&args)?, &args.output.cell_bars())?;
    render(&report, &args.output)
}
