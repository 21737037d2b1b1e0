//! `hopsim analyze …`: closed-form maps and reduced models of docs/physics.md §5
//! (`docs/analysis.md`), computed by the studies of `hopsim-studies` over the theory of
//! `hopsim-theory`, and the gait of a simulated or recorded run.
//!
//! Every subcommand prints a readable table by default, one JSON object with `--json`, and
//! writes CSV files and PNG/SVG plots into `--out DIR` (created if missing, files written
//! atomically); `-q/--quiet` hides the progress bar and the table. Invalid arguments exit
//! with code 2.
//!
//! Adding a subcommand: create `src/cmd/analyze/<name>.rs` with a clap `Args` struct (with
//! [`common::OutputArgs`] flattened in), the conversion of the arguments to the study's
//! parameters (checking them: [`common::invalid`] for exit code 2), and
//! `pub fn run(args) -> anyhow::Result<()>` that calls the study and
//! [`render`](crate::cmd::render::render)s its report; then add one variant to
//! [`AnalyzeCommand`] and one arm to [`run`].

pub mod common;
pub mod fixed_points;
pub mod gait;
pub mod impulsive_wheel;
pub mod obstacle;
pub mod template;

use clap::{Args, Subcommand};
use std::process::ExitCode;

/// Closed-form maps and reduced models of the thesis.
#[derive(Args)]
pub struct AnalyzeArgs {
    #[command(subcommand)]
    pub command: AnalyzeCommand,
}

#[derive(Subcommand)]
pub enum AnalyzeCommand {
    /// The four-map impulsive eccentric-wheel template (§5.1): named cases, the Cargo
    /// l/R × φ_TO grid, animal stride-versus-speed sweeps.
    Template(template::TemplateArgs),
    /// Energy to get a wheel over a wall: rolling, trivial hop, rotational hop (§5.2);
    /// region maps over α × Fr and over body mass × speed.
    Obstacle(obstacle::ObstacleArgs),
    /// The impulsive wheel's take-off-angle return map (§5.5): fixed point, eigenvalue,
    /// stable impulse interval, bifurcation diagram, iteration series.
    ImpulsiveWheel(impulsive_wheel::ImpulsiveWheelArgs),
    /// Robbit's fixed-point controls β* = (T*, ζ0*) and their stability over a grid of
    /// take-off angle × take-off energy (§5.3).
    FixedPoints(fixed_points::FixedPointsArgs),
    /// A run (scene or MCAP recording) cycle by cycle: periods, distances, flight, stance
    /// and spin-up fractions, apex heights, periodicity, and the last cycles overlaid
    /// against cycle progress (Fig. 5.11).
    Gait(gait::GaitArgs),
}

pub fn run(args: AnalyzeArgs) -> anyhow::Result<ExitCode> {
    match args.command {
        AnalyzeCommand::Template(args) => template::run(args),
        AnalyzeCommand::Obstacle(args) => obstacle::run(args),
        AnalyzeCommand::ImpulsiveWheel(args) => impulsive_wheel::run(args),
        AnalyzeCommand::FixedPoints(args) => fixed_points::run(args),
        AnalyzeCommand::Gait(args) => gait::run(args),
    }?;
    Ok(ExitCode::SUCCESS)
}
