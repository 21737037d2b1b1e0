//! CMA-ES as ask and tell over the `cmaes` crate, whose loop calls the objective itself:
//! the search keeps every evaluation (its history, which is also its checkpoint) and
//! rebuilds the crate's state by replaying it (the same seed, the recorded values fed back
//! in order), then samples the next generation with a placeholder objective. The crate is
//! deterministic for a seed, so a replay is bit for bit the state of an uninterrupted
//! search; a replay costs CMA-ES' own updates only (microseconds per generation), no run.

use super::problem::{Direction, Problem};
use cmaes::{CMAESOptions, DVector, Mode};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

/// Penalties of rejected points. CMA-ES only ranks its points: a rejected point ranks
/// below every accepted one, and rejected points among themselves by their distance (in
/// normalised coordinates) from the best accepted point so far (the start before there is
/// one), so that a generation of rejected points still tells the search where to go back:
/// the value is `w + (1 + |w|)(1 + d)` with `w` the worst accepted minimised value so far
/// (0 before there is one) and `d` that distance.
#[derive(Clone, Debug)]
struct Penalty {
    worst: Option<f64>,
    best: Option<(f64, Vec<f64>)>,
}

impl Penalty {
    fn new() -> Self {
        Penalty {
            worst: None,
            best: None,
        }
    }

    /// The minimised values of a generation, then the generation taken into account.
    fn values(
        &mut self,
        generation: &[Evaluation],
        direction: Direction,
        start: &[f64],
    ) -> Vec<f64> {
        for e in generation {
            if let Some(v) = e.minimised(direction) {
                self.worst = Some(self.worst.map_or(v, |w| w.max(v)));
                if self.best.as_ref().is_none_or(|(b, _)| v < *b) {
                    self.best = Some((v, e.raw.clone()));
                }
            }
        }
        let w = self.worst.unwrap_or(0.0);
        let centre = self.best.as_ref().map_or(start, |(_, raw)| raw.as_slice());
        generation
            .iter()
            .map(|e| {
                e.minimised(direction).unwrap_or_else(|| {
                    let d = (e.raw.iter().zip(centre))
                        .map(|(a, b)| (a - b) * (a - b))
                        .sum::<f64>()
                        .sqrt();
                    w + (1.0 + w.abs()) * (1.0 + d)
                })
            })
            .collect()
    }
}

/// One evaluated point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The point CMA-ES sampled (normalised coordinates, before folding into the bounds).
    pub raw: Vec<f64>,
    /// The parameters' values evaluated.
    pub values: Vec<f64>,
    /// The objective, or `None` for a rejected point.
    pub objective: Option<f64>,
    /// Why the point was rejected (a failed run, a constraint).
    pub error: Option<String>,
}

impl Evaluation {
    /// The value CMA-ES minimises: the objective, negated when maximising; `None` for a
    /// rejected point.
    fn minimised(&self, direction: Direction) -> Option<f64> {
        match (self.objective, direction) {
            (Some(v), Direction::Minimize) if v.is_finite() => Some(v),
            (Some(v), Direction::Maximize) if v.is_finite() => Some(-v),
            _ => None,
        }
    }
}

/// What evaluating one point gave: the objective, or why the point is rejected.
pub type Outcome = Result<f64, String>;

/// Why a search ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Stop {
    /// It ran its `max_generations`.
    MaxGenerations,
    /// CMA-ES' own termination criteria (e.g. `TolFun`, `TolX`), by name.
    Converged(Vec<String>),
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::MaxGenerations => write!(f, "the most generations were run"),
            Stop::Converged(r) => write!(f, "CMA-ES converged ({})", r.join(", ")),
        }
    }
}

/// A checkpoint: the problem and every generation evaluated (JSON, written atomically).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// `hopsim-optimize-1`.
    pub format: String,
    pub problem: Problem,
    pub generations: Vec<Vec<Evaluation>>,
}

/// The format tag of [`Checkpoint`].
pub const CHECKPOINT_FORMAT: &str = "hopsim-optimize-1";

/// A search in progress: ask for a generation's points, evaluate them, tell the outcomes.
#[derive(Clone, Debug)]
pub struct Search {
    problem: Problem,
    generations: Vec<Vec<Evaluation>>,
    /// The points asked for and not yet told (normalised).
    pending: Option<Vec<Vec<f64>>>,
    stop: Option<Stop>,
}

/// A checkpoint that does not replay (another search, another build of the crate).
#[derive(Debug, thiserror::Error)]
pub enum SearchError {
    #[error("invalid search: {0}")]
    Invalid(String),
    #[error(
        "the checkpoint does not replay: CMA-ES did not sample its point {point} of generation \
         {generation} (written by another search or another version of hopsim)"
    )]
    Replay { generation: usize, point: usize },
    #[error("{told} outcomes told for {asked} points asked")]
    Count { told: usize, asked: usize },
    #[error("nothing was asked: call ask before tell")]
    NothingAsked,
}

/// The crate's state after the recorded generations: why it stopped, if it did, and the
/// points of the next generation.
struct Replayed {
    stop: Option<Stop>,
    next: Vec<Vec<f64>>,
}

impl Search {
    /// A new search.
    pub fn new(problem: Problem) -> Result<Self, SearchError> {
        problem.check().map_err(SearchError::Invalid)?;
        Ok(Search {
            problem,
            generations: Vec::new(),
            pending: None,
            stop: None,
        })
    }

    /// The search a checkpoint was written by, at its last complete generation (replayed
    /// here, so that a checkpoint that does not belong to its problem is refused now).
    pub fn resume(checkpoint: Checkpoint) -> Result<Self, SearchError> {
        if checkpoint.format != CHECKPOINT_FORMAT {
            return Err(SearchError::Invalid(format!(
                "checkpoint format '{}', expected '{CHECKPOINT_FORMAT}'",
                checkpoint.format
            )));
        }
        let mut search = Search::new(checkpoint.problem)?;
        search.generations = checkpoint.generations;
        let replayed = search.replay()?;
        search.stop = replayed.stop;
        search.pending = Some(replayed.next);
        search.stop_at_most_generations();
        Ok(search)
    }

    /// The same search run to `generations` in all: more than its checkpoint's to extend
    /// it (CMA-ES' state does not depend on the planned number, so the extension gives the
    /// evaluations of a search planned that long from the start), fewer to end it there.
    pub fn with_max_generations(mut self, generations: usize) -> Result<Self, SearchError> {
        if generations == 0 {
            return Err(SearchError::Invalid(
                "generations must be at least 1".into(),
            ));
        }
        self.problem.max_generations = generations;
        if self.stop == Some(Stop::MaxGenerations) {
            // Ended by the old plan only: the next generation is sampled when asked for.
            self.stop = None;
            self.pending = None;
        }
        self.stop_at_most_generations();
        Ok(self)
    }

    /// Ends a search that has run its `max_generations` (and has not ended otherwise).
    fn stop_at_most_generations(&mut self) {
        if self.stop.is_none() && self.generations.len() >= self.problem.max_generations {
            self.stop = Some(Stop::MaxGenerations);
        }
    }

    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// Every generation told so far.
    pub fn generations(&self) -> &[Vec<Evaluation>] {
        &self.generations
    }

    /// Why the search ended, once it has.
    pub fn stopped(&self) -> Option<&Stop> {
        self.stop.as_ref()
    }

    /// The checkpoint of the generations told so far.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            format: CHECKPOINT_FORMAT.into(),
            problem: self.problem.clone(),
            generations: self.generations.clone(),
        }
    }

    /// The next generation's points, as the parameters' values (in parameter order), or
    /// `None` once the search has ended. Asking twice without telling gives the same points.
    pub fn ask(&mut self) -> Result<Option<Vec<Vec<f64>>>, SearchError> {
        if self.stop.is_none() && self.pending.is_none() {
            let replayed = self.replay()?;
            self.stop = replayed.stop;
            self.pending = Some(replayed.next);
        }
        Ok(match (&self.stop, &self.pending) {
            (None, Some(pending)) => Some(pending.iter().map(|y| self.problem.values(y)).collect()),
            _ => None,
        })
    }

    /// The outcomes of the points of the last [`Search::ask`], in its order.
    pub fn tell(&mut self, outcomes: Vec<Outcome>) -> Result<(), SearchError> {
        let pending = self.pending.take().ok_or(SearchError::NothingAsked)?;
        if outcomes.len() != pending.len() {
            let asked = pending.len();
            self.pending = Some(pending);
            return Err(SearchError::Count {
                told: outcomes.len(),
                asked,
            });
        }
        let generation = (pending.into_iter().zip(outcomes))
            .map(|(raw, outcome)| {
                let values = self.problem.values(&raw);
                let (objective, error) = match outcome {
                    Ok(v) if v.is_finite() => (Some(v), None),
                    Ok(v) => (None, Some(format!("the objective is {v}"))),
                    Err(e) => (None, Some(e)),
                };
                Evaluation {
                    raw,
                    values,
                    objective,
                    error,
                }
            })
            .collect();
        self.generations.push(generation);
        self.stop_at_most_generations();
        Ok(())
    }

    /// The best accepted evaluation so far (the first of equals).
    pub fn best(&self) -> Option<&Evaluation> {
        best_of(self.generations.iter().flatten(), self.problem.direction)
    }

    /// Replays the recorded generations through the crate and samples the next one.
    fn replay(&self) -> Result<Replayed, SearchError> {
        let p = &self.problem;
        let lookup = Rc::new(RefCell::new(Lookup::default()));
        let objective = {
            let lookup = Rc::clone(&lookup);
            move |x: &DVector<f64>| lookup.borrow_mut().value(x)
        };
        let mut cmaes = CMAESOptions::new(p.normalised_start(), p.sigma)
            .population_size(p.population())
            .mode(Mode::Minimize)
            .seed(p.seed)
            // Rejected points share one value: a generation of them only would meet the
            // function-value tolerances without having converged, so those are off; the
            // search ends at `max_generations` or by CMA-ES' step-size criteria.
            .tol_fun(0.0)
            .tol_fun_hist(0.0)
            .build(objective)
            .map_err(|e| SearchError::Invalid(format!("{e:?}")))?;
        let mut stop = None;
        let mut penalty = Penalty::new();
        let start = p.normalised_start();
        for (g, generation) in self.generations.iter().enumerate() {
            let values = penalty.values(generation, p.direction, &start);
            lookup.borrow_mut().reset(generation, &values);
            let ended = cmaes.next();
            let l = lookup.borrow();
            let unmatched = l
                .missing
                .or_else(|| (l.sampled.len() != generation.len()).then_some(l.sampled.len()));
            if let Some(point) = unmatched {
                return Err(SearchError::Replay {
                    generation: g,
                    point,
                });
            }
            if let Some(data) = ended {
                let reasons = data.reasons.iter().map(|r| format!("{r:?}")).collect();
                stop = Some(Stop::Converged(reasons));
                break;
            }
        }
        if stop.is_none() && self.generations.len() >= p.max_generations {
            stop = Some(Stop::MaxGenerations);
        }
        let next = if stop.is_none() {
            lookup.borrow_mut().reset(&[], &[]);
            let _ = cmaes.next();
            std::mem::take(&mut lookup.borrow_mut().sampled)
        } else {
            Vec::new()
        };
        Ok(Replayed { stop, next })
    }
}

/// The objective the crate calls during a replay: the recorded value of each point of the
/// generation being replayed, looked up by its bits; a point not recorded gets a
/// placeholder and is noted (the first of them).
#[derive(Default)]
struct Lookup {
    table: HashMap<Vec<u64>, f64>,
    sampled: Vec<Vec<f64>>,
    missing: Option<usize>,
}

fn bits(x: impl Iterator<Item = f64>) -> Vec<u64> {
    x.map(f64::to_bits).collect()
}

impl Lookup {
    fn reset(&mut self, generation: &[Evaluation], values: &[f64]) {
        self.table = (generation.iter().zip(values))
            .map(|(e, v)| (bits(e.raw.iter().copied()), *v))
            .collect();
        self.sampled.clear();
        self.missing = None;
    }

    fn value(&mut self, x: &DVector<f64>) -> f64 {
        let index = self.sampled.len();
        self.sampled.push(x.iter().copied().collect());
        match self.table.get(&bits(x.iter().copied())) {
            Some(v) => *v,
            None => {
                self.missing.get_or_insert(index);
                0.0
            }
        }
    }
}

/// The best accepted evaluation of `evaluations` in `direction` (the first of equals).
pub fn best_of<'a>(
    evaluations: impl Iterator<Item = &'a Evaluation>,
    direction: Direction,
) -> Option<&'a Evaluation> {
    evaluations
        .filter_map(|e| Some((e, e.minimised(direction)?)))
        .fold(
            None,
            |best: Option<(&Evaluation, f64)>, (e, v)| match best {
                Some((b, bv)) if bv <= v => Some((b, bv)),
                _ => Some((e, v)),
            },
        )
        .map(|(e, _)| e)
}
