//! `hopsim sweep SCENE --grid KEY=START:STOP:N …`: a scene run over a parameter grid on all
//! cores, with a CSV of the run summaries and a plot (`docs/sweeps.md`); the study is
//! `hopsim_studies::sweep`.

use clap::Args;
use hopsim_studies::sweep::GridAxis;
use hopsim_studies::sweep::{
    metric_name, Sweep, SweepBaseline, SweepInputError, SweepParams, DEFAULT_MAX_RUNS,
};
use std::path::PathBuf;
use std::process::ExitCode;

use super::analyze::common::OutputArgs;
use super::exit;
use super::progress::CountBars;
use super::render::render;
use super::scene::{load_for_runs, output_folder, SceneArgs};

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
    pub baselines: Vec<SweepBaseline>,
    /// Simulated time of every run in seconds (overrides simulation.duration).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = super::finite)]
    pub duration: Option<f64>,
    /// The most grid points to run; a larger grid is refused before any run.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_RUNS)]
    pub max_runs: usize,
    /// Output directory for sweep.csv and the plot [default: out/<scene>-sweep].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Quantity plotted against the first grid axis (scenes without the Robbit
    /// controller; Robbit's plot is mean speed against impulse per distance) [default: the
    /// first of distance_per_hop_m, mean_speed_mps, hops, gait_period, gait_residual that
    /// varies over the grid]
    #[arg(long, value_name = "FIELD", value_parser = metric_name)]
    pub y: Option<String>,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

impl From<&SweepArgs> for SweepParams {
    fn from(args: &SweepArgs) -> Self {
        SweepParams {
            axes: args.grid.clone(),
            baselines: args.baselines.clone(),
            y: args.y.clone(),
            max_runs: args.max_runs,
        }
    }
}

pub fn run(args: SweepArgs) -> anyhow::Result<ExitCode> {
    // Validate the base scene once, so a broken file fails before hundreds of runs do.
    let (scene, base) = load_for_runs(&args.scene, args.duration)?;
    let sweep = match Sweep::new(&scene, &base, SweepParams::from(&args)) {
        Ok(sweep) => sweep,
        Err(err) => {
            match &err {
                SweepInputError::InvalidRun { what, error } => {
                    eprintln!("error: {error}");
                    eprintln!("error: {what} is invalid (see above); nothing was run");
                }
                _ => eprintln!("error: {err}"),
            }
            return Ok(ExitCode::from(exit::INVALID_INPUT));
        }
    };
    let report = sweep.run(&CountBars {
        unit: "runs",
        quiet: args.quiet,
    });
    let out = output_folder(args.out.as_deref(), &scene, "sweep");
    let csv = out.join("sweep.csv");
    let output = OutputArgs {
        json: false,
        out: Some(out),
        quiet: args.quiet,
    };
    render(&report, &output)?;
    let failed = report.failed();
    if failed == report.runs.len() {
        eprintln!(
            "error: every run failed (their errors are in {})",
            csv.display()
        );
        return Ok(ExitCode::from(exit::SIMULATION_FAILED));
    }
    if failed > 0 {
        eprintln!(
            "warning: {failed} of {} runs failed (status = error in {})",
            report.runs.len(),
            csv.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}
