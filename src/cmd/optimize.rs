//! `hopsim optimize SCENE --param KEY=LO:HI … --maximize FIELD`: CMA-ES over scene keys,
//! each generation's runs in parallel, a checkpoint after every generation, `--resume`
//! (`docs/optimize.md`); the study is `hopsim_studies::optimize`.

use clap::Args;
use hopsim_studies::optimize::{
    read_checkpoint, run, Constraint, Direction, Parameter, Problem, SceneObjective, Search,
    DEFAULT_SIGMA,
};
use std::path::PathBuf;
use std::process::ExitCode;

use super::analyze::common::OutputArgs;
use super::exit;
use super::progress::CountBars;
use super::render::render;
use super::scene::{load_for_runs, output_folder, SceneArgs};

/// Search scene keys within bounds for the run that minimises or maximises a run-summary
/// field (CMA-ES); write a CSV of every evaluation, a convergence plot and a checkpoint.
#[derive(Args)]
#[command(group = clap::ArgGroup::new("goal").required(true).args(["minimize", "maximize"]))]
pub struct OptimizeArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// A searched scene key within bounds: KEY=LO:HI, or KEY=LO:HI:int for whole numbers
    /// (repeatable).
    #[arg(long = "param", value_name = "KEY=LO:HI", required = true)]
    pub params: Vec<Parameter>,
    /// Minimise this run-summary field (a dotted path into the JSON of `hopsim run
    /// --summary`, e.g. mean_speed_mps or gait.period).
    #[arg(long, value_name = "FIELD")]
    pub minimize: Option<String>,
    /// Maximise this run-summary field.
    #[arg(long, value_name = "FIELD")]
    pub maximize: Option<String>,
    /// Reject runs whose summary field lies outside bounds: FIELD=LO:HI, either bound may
    /// be empty (repeatable).
    #[arg(long = "constraint", value_name = "FIELD=LO:HI")]
    pub constraints: Vec<Constraint>,
    /// Simulated time of every run in seconds (overrides simulation.duration).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = super::finite)]
    pub duration: Option<f64>,
    /// Where the search starts, one value per --param [default: the centre of the bounds].
    #[arg(
        long,
        value_name = "V,V,…",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub start: Option<Vec<f64>>,
    /// Initial step size as a fraction of each parameter's span.
    #[arg(long, value_name = "FRACTION", default_value_t = DEFAULT_SIGMA, value_parser = super::finite)]
    pub sigma: f64,
    /// Points per generation [default: 4 + ⌊3 ln n⌋ for n parameters].
    #[arg(long, value_name = "N")]
    pub population: Option<usize>,
    /// The most generations.
    #[arg(long, value_name = "N", default_value_t = 30)]
    pub generations: usize,
    /// Seed of CMA-ES' random numbers (the same seed, the same search).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Continue the search whose checkpoint is in the output folder (the same command
    /// otherwise); starts afresh if there is none.
    #[arg(long)]
    pub resume: bool,
    /// Output folder for evaluations.csv, convergence.png/.svg and checkpoint.json
    /// [default: out/<scene>-optimize].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// FNV-1a of the scene's text: a checkpoint resumes only a search of the same file.
fn fingerprint(text: &str) -> u64 {
    text.bytes().fold(0xcbf29ce484222325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100000001b3)
    })
}

pub fn run_command(args: OptimizeArgs) -> anyhow::Result<ExitCode> {
    let (scene, base) = load_for_runs(&args.scene, args.duration)?;
    let (direction, field) = match (&args.minimize, &args.maximize) {
        (Some(f), _) => (Direction::Minimize, f.clone()),
        (None, Some(f)) => (Direction::Maximize, f.clone()),
        (None, None) => {
            eprintln!("error: give --minimize FIELD or --maximize FIELD");
            return Ok(ExitCode::from(exit::INVALID_INPUT));
        }
    };
    let mut objective = format!(
        "{field} of {} ({:016x})",
        scene.path.display(),
        fingerprint(&scene.text)
    );
    for o in &base {
        objective.push_str(&format!(" --set {}={}", o.key, o.value));
    }
    for c in &args.constraints {
        objective.push_str(&format!(" --constraint {c}"));
    }
    let problem = Problem {
        parameters: args.params.clone(),
        direction,
        start: args.start.clone(),
        sigma: args.sigma,
        population: args.population,
        seed: args.seed,
        max_generations: args.generations,
        objective,
    };
    if let Err(e) = problem.check() {
        eprintln!("error: {e}");
        return Ok(ExitCode::from(exit::INVALID_INPUT));
    }
    let out = output_folder(args.out.as_deref(), &scene, "optimize");
    let checkpoint = out.join("checkpoint.json");
    let mut search = if checkpoint.exists() {
        if !args.resume {
            eprintln!(
                "error: {} holds the checkpoint of a search: pass --resume to continue it, or \
                 choose another --out",
                checkpoint.display()
            );
            return Ok(ExitCode::from(exit::INVALID_INPUT));
        }
        let saved = read_checkpoint(&checkpoint)?;
        if !saved.problem.same_search(&problem) {
            eprintln!(
                "error: {} was written by another search (parameters, goal, settings, scene \
                 or overrides differ); give the same command (another --generations extends \
                 or ends it), or choose another --out",
                checkpoint.display()
            );
            return Ok(ExitCode::from(exit::INVALID_INPUT));
        }
        let search = Search::resume(saved)?.with_max_generations(problem.max_generations)?;
        if !args.quiet && !args.json {
            eprintln!(
                "resuming after generation {} of {}",
                search.generations().len(),
                problem.max_generations
            );
        }
        search
    } else {
        Search::new(problem)?
    };
    // The first point is checked before the search, so a misspelt key is one error.
    let objective = SceneObjective {
        scene: &scene,
        base: base.clone(),
        keys: args.params.iter().map(|p| p.key.clone()).collect(),
        field,
        constraints: args.constraints.clone(),
        stop: None,
    };
    let first: Vec<f64> = args.params.iter().map(|p| p.value(0.5)).collect();
    let mut overrides = base;
    overrides.extend(objective.job(&first).overrides);
    if let Err(error) = hopsim_scene::parse(&scene.text, &scene.path, &overrides) {
        eprintln!("error: {error}");
        eprintln!("error: the search's first point is invalid (see above); nothing was run");
        return Ok(ExitCode::from(exit::INVALID_INPUT));
    }
    hopsim_io::create_dir(&out)?;
    let progress = CountBars {
        unit: "runs",
        quiet: args.quiet || args.json,
    };
    let report = run(&mut search, &objective, &progress, Some(&checkpoint), None)?;
    let output = OutputArgs {
        json: args.json,
        out: Some(out.clone()),
        quiet: args.quiet,
    };
    render(&report, &output)?;
    if report.best.is_none() {
        eprintln!(
            "error: every evaluation was rejected (the reasons are in {})",
            out.join("evaluations.csv").display()
        );
        return Ok(ExitCode::from(exit::SIMULATION_FAILED));
    }
    Ok(ExitCode::SUCCESS)
}
