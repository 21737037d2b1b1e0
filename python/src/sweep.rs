//! `hopsim.sweep`: the sweep of hopsim-studies (`hopsim sweep`) over a grid given from
//! Python, whole or in chunks of runs.

use crate::errors::guard;
use crate::scene::{overrides_from, scene_error, PyScene};
use crate::signals::wait_for;
use hopsim_studies::progress::Silent;
use hopsim_studies::sweep::GridAxis;
use hopsim_studies::sweep::{Sweep, SweepBaseline, SweepInputError, SweepParams, DEFAULT_MAX_RUNS};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

/// The sweep's parameters: `grid` `[(key, values)]` in axis order (the last varies
/// fastest), `baselines` `{name: {key: value}}`.
fn params(
    grid: Vec<(String, Vec<f64>)>,
    baselines: Option<&Bound<'_, PyDict>>,
) -> PyResult<SweepParams> {
    if grid.is_empty() {
        return Err(PyValueError::new_err("the grid needs at least one axis"));
    }
    let mut axes = Vec::with_capacity(grid.len());
    for (key, values) in grid {
        if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "grid axis {key}: needs one or more finite values"
            )));
        }
        axes.push(GridAxis { key, values });
    }
    let mut runs = Vec::new();
    if let Some(baselines) = baselines {
        for (name, overrides) in baselines.iter() {
            let overrides = overrides.cast::<PyDict>().map_err(|_| {
                PyValueError::new_err("baselines must map names to {key: value} dicts")
            })?;
            runs.push(SweepBaseline {
                name: name.extract()?,
                overrides: overrides_from(Some(overrides))?,
            });
        }
    }
    Ok(SweepParams {
        axes,
        baselines: runs,
        y: Some("mean_speed_mps".into()),
        // The command line's default limit (`hopsim sweep --max-runs`).
        max_runs: DEFAULT_MAX_RUNS,
    })
}

/// The checked sweep of `scene` (its own overrides apply to every run).
fn checked<'a>(py: Python<'_>, scene: &'a PyScene, params: SweepParams) -> PyResult<Sweep<'a>> {
    let s = &scene.scene;
    Sweep::new(s, &s.overrides, params).map_err(|e| match e {
        SweepInputError::InvalidRun { what, error } => {
            let err = scene_error(py, &error);
            let _ = err.value(py).setattr("run", what);
            err
        }
        other => PyValueError::new_err(other.to_string()),
    })
}

/// The number of runs of a sweep (grid points, then baselines), after checking it as
/// `hopsim sweep` does (axes named once, baselines named apart, the grid's first point
/// and every baseline valid scenes).
#[pyfunction]
#[pyo3(signature = (scene, grid, baselines = None))]
pub fn sweep_runs(
    py: Python<'_>,
    scene: &PyScene,
    grid: Vec<(String, Vec<f64>)>,
    baselines: Option<&Bound<'_, PyDict>>,
) -> PyResult<usize> {
    guard(py, "sweep", || {
        Ok(checked(py, scene, params(grid, baselines)?)?.runs())
    })
}

/// Runs the runs `start..stop` of a sweep on `threads` threads (default: all cores), the
/// GIL released, and returns their rows of `hopsim sweep`'s `sweep.csv` (CSV text with
/// its header). Python's signal handlers run about every 50 ms: on Ctrl-C the runs stop at
/// their next step and `KeyboardInterrupt` carries the rows (those stopped are errors) as
/// `_partial_csv`.
#[pyfunction]
#[pyo3(signature = (scene, grid, baselines = None, start = 0, stop = None, threads = None))]
pub fn sweep_csv(
    py: Python<'_>,
    scene: &PyScene,
    grid: Vec<(String, Vec<f64>)>,
    baselines: Option<&Bound<'_, PyDict>>,
    start: usize,
    stop: Option<usize>,
    threads: Option<usize>,
) -> PyResult<String> {
    guard(py, "sweep", || {
        let interrupted = AtomicBool::new(false);
        let sweep = checked(py, scene, params(grid, baselines)?)?.stopped_by(&interrupted);
        let part = start..stop.unwrap_or(usize::MAX);
        let pool = threads
            .map(|n| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n.max(1))
                    .build()
            })
            .transpose()
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        let run = move || {
            let run = || sweep.run_part(part, &Silent).table().to_csv_string();
            match pool {
                Some(pool) => pool.install(run),
                None => run(),
            }
        };
        // The sweep on a thread of its own; this one runs Python's signal handlers.
        std::thread::scope(|scope| {
            let (send, mut receive) = mpsc::sync_channel(1);
            scope.spawn(move || send.send(run()));
            let raised = match wait_for(py, &mut receive) {
                Ok(Some(csv)) => return Ok(csv),
                // The sweep panicked: the scope raises it again when it ends.
                Ok(None) => return Ok(String::new()),
                Err(raised) => raised,
            };
            interrupted.store(true, Ordering::Relaxed);
            if let Ok(csv) = py.detach(move || receive.recv()) {
                raised.value(py).setattr("_partial_csv", csv)?;
            }
            Err(raised)
        })
    })
}

/// The figures a sweep reports of each run, in the order of its table's columns after
/// `error`.
#[pyfunction]
pub fn sweep_figure_names() -> Vec<&'static str> {
    hopsim_studies::sweep::figure_names()
}
