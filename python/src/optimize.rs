//! `hopsim.optimize`: the CMA-ES search of hopsim-studies (`hopsim optimize`) driven from
//! Python as ask and tell, so that any Python objective (local threads or a Dask cluster)
//! evaluates its points.

use crate::errors::guard;
use hopsim_studies::optimize::{
    Checkpoint, Direction, OptimizeReport, Outcome, Parameter, Problem, Search,
};
use hopsim_studies::{write_files, Report};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;

/// A CMA-ES search in progress (`hopsim_studies::optimize::Search`).
#[pyclass(name = "Search", module = "hopsim._hopsim")]
pub struct PySearch {
    search: Search,
}

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

#[pymethods]
impl PySearch {
    /// `params`: `[(key, lower, upper, integer)]`; the other arguments as `hopsim optimize`'s.
    #[new]
    #[pyo3(signature = (params, maximize, start, sigma, population, seed, generations, objective))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        params: Vec<(String, f64, f64, bool)>,
        maximize: bool,
        start: Option<Vec<f64>>,
        sigma: f64,
        population: Option<usize>,
        seed: u64,
        generations: usize,
        objective: String,
    ) -> PyResult<Self> {
        let parameters = params
            .into_iter()
            .map(|(key, lower, upper, integer)| Parameter {
                key,
                lower,
                upper,
                integer,
            })
            .collect();
        let direction = if maximize {
            Direction::Maximize
        } else {
            Direction::Minimize
        };
        let problem = Problem {
            parameters,
            direction,
            start,
            sigma,
            population,
            seed,
            max_generations: generations,
            objective,
        };
        let search = Search::new(problem).map_err(value_error)?;
        Ok(PySearch { search })
    }

    /// The search of a checkpoint's JSON text, at its last complete generation; refused
    /// (`ValueError`) unless its problem is that of `self`.
    fn resumed(&self, text: &str) -> PyResult<PySearch> {
        let checkpoint: Checkpoint = serde_json::from_str(text).map_err(value_error)?;
        let problem = self.search.problem();
        if !checkpoint.problem.same_search(problem) {
            return Err(PyValueError::new_err(
                "the checkpoint was written by another search (parameters, goal or settings \
                 differ; another number of generations extends or ends it)",
            ));
        }
        let search = Search::resume(checkpoint)
            .and_then(|s| s.with_max_generations(problem.max_generations))
            .map_err(value_error)?;
        Ok(PySearch { search })
    }

    /// The next generation's points (the parameters' values), or `None` once it has ended.
    fn ask(&mut self, py: Python<'_>) -> PyResult<Option<Vec<Vec<f64>>>> {
        guard(py, "optimize", || self.search.ask().map_err(value_error))
    }

    /// The outcomes of the last `ask`'s points: `(value, None)` or `(None, reason)`.
    fn tell(&mut self, outcomes: Vec<(Option<f64>, Option<String>)>) -> PyResult<()> {
        let outcomes: Vec<Outcome> = outcomes
            .into_iter()
            .map(|(value, error)| match (value, error) {
                (Some(v), None) => Ok(v),
                (_, Some(e)) => Err(e),
                (None, None) => Err("no value".to_string()),
            })
            .collect();
        self.search.tell(outcomes).map_err(value_error)
    }

    /// Generations told so far.
    #[getter]
    fn generations(&self) -> usize {
        self.search.generations().len()
    }

    /// The checkpoint as JSON text.
    fn checkpoint_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.search.checkpoint()).map_err(value_error)
    }

    /// Writes the checkpoint to `path` atomically.
    fn write_checkpoint(&self, path: PathBuf) -> PyResult<()> {
        hopsim_studies::optimize::write_checkpoint(&path, &self.search.checkpoint())
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    /// The report as JSON text (`hopsim optimize --json`); `interrupted` when the search
    /// stopped before its end.
    fn report_json(&self, interrupted: bool) -> PyResult<String> {
        let report = OptimizeReport::of(&self.search, interrupted);
        serde_json::to_string(&report).map_err(value_error)
    }

    /// `evaluations.csv` as text.
    fn table_csv(&self) -> String {
        OptimizeReport::of(&self.search, false)
            .table()
            .to_csv_string()
    }

    /// The report's text.
    fn text(&self) -> String {
        OptimizeReport::of(&self.search, false).text()
    }

    /// Writes `evaluations.csv` and `convergence.png`/`.svg` into `folder`; returns the
    /// files written.
    fn write_files(&self, folder: PathBuf) -> PyResult<Vec<PathBuf>> {
        let report = OptimizeReport::of(&self.search, false);
        let written = write_files(&folder, &report.files())
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok(written.files)
    }
}
