//! Design optimisation (docs/optimize.md): CMA-ES over parameters within bounds (scene keys
//! or a function's arguments), minimising or maximising an objective (a run-summary field,
//! or any function); a generation's points evaluated in parallel on all cores; rejected
//! points (failed runs, broken constraints) penalised and recorded; a checkpoint after
//! every generation, from which a search resumes to the result of an uninterrupted one.
//!
//! CMA-ES is the `cmaes` crate's (0.2.2), driven as ask and tell by replaying its history
//! ([`Search`], `search.rs`).

mod objective;
mod problem;
mod search;

pub use objective::{json_number, Constraint, FunctionObjective, Objective, SceneObjective};
pub use problem::{Direction, Parameter, Problem, DEFAULT_SIGMA};
pub use search::{
    best_of, Checkpoint, Evaluation, Outcome, Search, SearchError, Stop, CHECKPOINT_FORMAT,
};

use crate::error::{Result, StudyError};
use crate::plot::{LinePlot, Series, SeriesStyle, BLACK};
use crate::progress::Progress;
use crate::report::{num, Report, ReportFile, TextTable};
use hopsim_io::{Cell, CsvTable, IoError};
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

impl From<SearchError> for StudyError {
    fn from(e: SearchError) -> Self {
        StudyError::Input(e.to_string())
    }
}

/// Writes `checkpoint` to `path` atomically (JSON; every number exact).
pub fn write_checkpoint(path: &Path, checkpoint: &Checkpoint) -> Result<()> {
    let text = serde_json::to_string(checkpoint).map_err(|e| StudyError::Input(e.to_string()))?;
    hopsim_io::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
    Ok(())
}

/// Reads a checkpoint written by [`write_checkpoint`].
pub fn read_checkpoint(path: &Path) -> Result<Checkpoint> {
    let text = std::fs::read_to_string(path).map_err(|e| IoError::new(path, e))?;
    serde_json::from_str(&text).map_err(|e| {
        StudyError::Input(format!(
            "{}: not a checkpoint of hopsim optimize: {e}",
            path.display()
        ))
    })
}

/// Runs `search` to its end: asks for each generation, evaluates it with `objective`
/// (ticking `progress` per point), tells the outcomes and writes the checkpoint to
/// `checkpoint` after every generation. Once `stop` is set the generation under way is
/// dropped (the checkpoint keeps the ones before) and the report says so.
pub fn run(
    search: &mut Search,
    objective: &dyn Objective,
    progress: &dyn Progress,
    checkpoint: Option<&Path>,
    stop: Option<&AtomicBool>,
) -> Result<OptimizeReport> {
    let problem = search.problem().clone();
    let remaining = problem
        .max_generations
        .saturating_sub(search.generations().len());
    let tick = progress.task(remaining * problem.population(), "optimize");
    let mut interrupted = false;
    while let Some(points) = search.ask()? {
        let outcomes = objective.evaluate(&points, &*tick);
        if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            interrupted = true;
            break;
        }
        search.tell(outcomes)?;
        if let Some(path) = checkpoint {
            write_checkpoint(path, &search.checkpoint())?;
        }
    }
    drop(tick);
    Ok(OptimizeReport::of(search, interrupted))
}

/// A search's record: every evaluation, the best point, why it stopped.
#[derive(Clone, Debug, Serialize)]
pub struct OptimizeReport {
    pub problem: Problem,
    /// Every generation's evaluations, in the order CMA-ES sampled them.
    pub generations: Vec<Vec<Evaluation>>,
    /// The best accepted evaluation.
    pub best: Option<Evaluation>,
    pub evaluations: usize,
    pub rejected: usize,
    /// Why the search ended (`None`: interrupted).
    pub stop: Option<Stop>,
}

impl OptimizeReport {
    /// The report of `search` as it stands.
    pub fn of(search: &Search, interrupted: bool) -> Self {
        let all = || search.generations().iter().flatten();
        OptimizeReport {
            problem: search.problem().clone(),
            generations: search.generations().to_vec(),
            best: search.best().cloned(),
            evaluations: all().count(),
            rejected: all().filter(|e| e.objective.is_none()).count(),
            stop: if interrupted {
                None
            } else {
                search.stopped().cloned()
            },
        }
    }

    /// Whether `a` is better than `b` in the search's direction.
    fn better(&self, a: f64, b: f64) -> bool {
        match self.problem.direction {
            Direction::Minimize => a < b,
            Direction::Maximize => a > b,
        }
    }

    /// One row per evaluation: generation, index, the parameters, status, objective, the
    /// best objective so far, the reason of a rejection.
    pub fn table(&self) -> CsvTable {
        let mut header: Vec<String> = vec!["generation".into(), "index".into()];
        header.extend(self.problem.parameters.iter().map(|p| p.key.clone()));
        header.extend(["status", "objective", "best_so_far", "error"].map(String::from));
        let mut t = CsvTable::new(&header);
        let mut best: Option<f64> = None;
        for (g, generation) in self.generations.iter().enumerate() {
            for (i, e) in generation.iter().enumerate() {
                if let Some(v) = e.objective {
                    if best.is_none_or(|b| self.better(v, b)) {
                        best = Some(v);
                    }
                }
                let mut row: Vec<Cell> = vec![Cell::from(g as f64), Cell::from(i as f64)];
                row.extend(e.values.iter().map(|v| Cell::from(*v)));
                let status = if e.objective.is_some() {
                    "ok"
                } else {
                    "rejected"
                };
                row.extend([
                    Cell::from(status),
                    Cell::from(e.objective),
                    Cell::from(best),
                    Cell::from(e.error.as_deref().unwrap_or_default()),
                ]);
                t.push(row);
            }
        }
        t
    }

    /// Convergence: every accepted evaluation's objective against the evaluation count,
    /// the best so far as a line, each generation's best as a line with dots.
    pub fn figure(&self) -> LinePlot {
        let mut all = Vec::new();
        let mut best_so_far = Vec::new();
        let mut generation_best = Vec::new();
        let mut best: Option<f64> = None;
        let mut n = 0usize;
        for generation in &self.generations {
            let mut g_best: Option<f64> = None;
            for e in generation {
                n += 1;
                if let Some(v) = e.objective {
                    all.push((n as f64, v));
                    if best.is_none_or(|b| self.better(v, b)) {
                        best = Some(v);
                    }
                    if g_best.is_none_or(|b| self.better(v, b)) {
                        g_best = Some(v);
                    }
                }
                if let Some(b) = best {
                    best_so_far.push((n as f64, b));
                }
            }
            if let Some(b) = g_best {
                generation_best.push((n as f64, b));
            }
        }
        let direction = match self.problem.direction {
            Direction::Minimize => "minimised",
            Direction::Maximize => "maximised",
        };
        let quantity = self.problem.quantity();
        LinePlot::new(
            format!(
                "CMA-ES: {quantity} {direction} over {}, {} evaluations, {} rejected",
                self.problem
                    .parameters
                    .iter()
                    .map(|p| p.key.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                self.evaluations,
                self.rejected
            ),
            "evaluations (runs of the objective)",
            quantity,
        )
        .with_series(Series::points("every accepted evaluation", all).size(2))
        .with_series(
            Series::line("best of each generation", generation_best)
                .style(SeriesStyle::LineAndPoints),
        )
        .with_series(
            Series::line("best so far", best_so_far)
                .color(BLACK)
                .size(3),
        )
    }
}

impl Report for OptimizeReport {
    fn text(&self) -> String {
        let mut t = TextTable::new(format!("CMA-ES: {}", self.problem.objective));
        t.row("generations", self.generations.len());
        t.row(
            "evaluations",
            format!("{} ({} rejected)", self.evaluations, self.rejected),
        );
        t.row(
            "stopped",
            self.stop
                .as_ref()
                .map_or("interrupted (resume with --resume)".to_string(), |s| {
                    s.to_string()
                }),
        );
        match &self.best {
            Some(b) => {
                t.row("best objective", num(b.objective.unwrap_or(f64::NAN), ""));
                for (p, v) in self.problem.parameters.iter().zip(&b.values) {
                    t.row(format!("  {}", p.key), hopsim_io::number(*v));
                }
            }
            None => {
                t.row("best objective", "none: every evaluation was rejected");
            }
        }
        t.to_string()
    }

    /// `evaluations.csv` and the figure `convergence.png`, `convergence.svg`.
    fn files(&self) -> Vec<ReportFile> {
        vec![
            ReportFile::csv("evaluations.csv", self.table()),
            ReportFile::figure("convergence", self.figure()),
        ]
    }
}
