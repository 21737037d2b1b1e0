//! Recordings of runs stepped from Python (`Simulation.record`, `Batch.record`): the
//! recorders of `hopsim-record` (MCAP, Rerun `.rrd` and live viewer, CSV) fed by the run
//! loop's `RecordingObserver`, as `hopsim run` feeds them, with the run summary of the span
//! recorded (`RunWatch`).

use crate::errors::{error, Class};
use hopsim_record::{CsvRecorder, McapRecorder, RecorderSet};
use hopsim_scene::Scene;
use hopsim_sim::{recording_info, Observer, RecordingObserver, RunError, Simulation, StepView};
use hopsim_studies::run_summary::RunWatch;
use hopsim_studies::sweep::figures;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The output formats, by extension, and what `live` streams to.
const FORMATS: &str = "a .mcap, .rrd or .csv path, or \"live\" (a Rerun viewer)";

/// The recorders of `outputs` (paths by extension, or `live`; none: the summary only) for
/// `scene`; `speed` paces
/// the live stream (`"max"` or a factor, as `hopsim run --speed`).
fn recorders(scene: &Scene, outputs: &[String], speed: &str) -> PyResult<RecorderSet> {
    let info = recording_info(scene);
    let mut set = RecorderSet::default();
    let mut paths: Vec<PathBuf> = Vec::new();
    for output in outputs {
        if output == "live" {
            set.push(live(&info, speed)?);
            continue;
        }
        let path = Path::new(output);
        let same = |p: &PathBuf| std::path::absolute(p).ok() == std::path::absolute(path).ok();
        if paths.iter().any(same) {
            return Err(PyValueError::new_err(format!(
                "record: {output} is named twice; each output needs its own path"
            )));
        }
        paths.push(path.to_path_buf());
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let recorder = match extension.to_ascii_lowercase().as_str() {
            "mcap" => McapRecorder::create(path, &info).map(boxed),
            "rrd" => rrd(path, &info)?,
            "csv" => CsvRecorder::create(path, &info).map(boxed),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "record: {output}: expected {FORMATS}"
                )))
            }
        };
        set.push(recorder.map_err(|e| PyValueError::new_err(e.to_string()))?);
    }
    Ok(set)
}

fn boxed<R: hopsim_record::Recorder + 'static>(r: R) -> Box<dyn hopsim_record::Recorder> {
    Box::new(r)
}

type Made = Result<Box<dyn hopsim_record::Recorder>, hopsim_record::RecordError>;

#[cfg(feature = "rerun")]
fn rrd(path: &Path, info: &hopsim_record::RecordingInfo) -> PyResult<Made> {
    Ok(hopsim_record::RerunRecorder::save(path, info).map(boxed))
}

#[cfg(feature = "rerun")]
fn live(
    info: &hopsim_record::RecordingInfo,
    speed: &str,
) -> PyResult<Box<dyn hopsim_record::Recorder>> {
    let pace: hopsim_record::Pace = speed
        .parse()
        .map_err(|e| PyValueError::new_err(format!("record: speed: {e}")))?;
    hopsim_record::RerunRecorder::spawn(info, pace)
        .map(boxed)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

#[cfg(not(feature = "rerun"))]
const NO_RERUN: &str = "this build of hopsim has no Rerun recorder (the Python package was \
                        built without its default feature `rerun`)";

#[cfg(not(feature = "rerun"))]
fn rrd(_: &Path, _: &hopsim_record::RecordingInfo) -> PyResult<Made> {
    Err(PyValueError::new_err(NO_RERUN))
}

#[cfg(not(feature = "rerun"))]
fn live(_: &hopsim_record::RecordingInfo, _: &str) -> PyResult<Box<dyn hopsim_record::Recorder>> {
    Err(PyValueError::new_err(NO_RERUN))
}

/// A closed recording's run summary (JSON) and the figures a sweep reports of it.
pub(crate) type Closed = (String, Vec<(&'static str, f64)>);

/// A recording under way: the recorders and the summary watching the run, and the error
/// that stopped it, if one did.
pub(crate) struct Watch {
    summary: RunWatch,
    recording: RecordingObserver,
    stopped: Option<Stopped>,
}

/// Why a recorded run stopped: the error's message, and whether the recording itself
/// failed (then nothing is kept, as `hopsim run` keeps nothing).
struct Stopped {
    reason: String,
    record: bool,
}

impl Stopped {
    fn of(e: &RunError) -> Self {
        Self {
            reason: e.to_string(),
            record: matches!(e, RunError::Record(_)),
        }
    }
}

impl Watch {
    /// A recording of `sim` from its current state to `outputs`, frames at `rate` Hz
    /// (default: the scene's) and at every step with an event; it records its first frame
    /// when shown the start (`Simulation::start`).
    pub(crate) fn new(
        sim: &Simulation,
        scene: &Scene,
        outputs: &[String],
        rate: Option<f64>,
        speed: &str,
    ) -> PyResult<Self> {
        let rate = match rate {
            None => scene.settings.record_rate,
            Some(r) if r.is_finite() && r > 0.0 => r,
            Some(r) => {
                return Err(PyValueError::new_err(format!(
                    "record_rate must be positive and finite, got {r}"
                )))
            }
        };
        Ok(Self {
            summary: RunWatch::new(sim),
            recording: RecordingObserver::with_rate(recorders(scene, outputs, speed)?, scene, rate),
            stopped: None,
        })
    }

    /// Notes the error that stopped the run (the first one).
    pub(crate) fn stop(&mut self, e: &RunError) {
        if self.stopped.is_none() {
            self.stopped = Some(Stopped::of(e));
        }
    }

    /// Completes the recordings of `sim`'s run and returns its summary (JSON, as
    /// `hopsim run --summary`) and the figures a sweep reports of it. A run that stopped, or whose summary has a figure that is
    /// not finite, keeps its recordings under their partial names instead and raises
    /// `SimulationError` naming them.
    pub(crate) fn close(self, py: Python<'_>, sim: &Simulation) -> PyResult<Closed> {
        let Self {
            summary,
            recording,
            stopped,
        } = self;
        let stopped = match stopped {
            Some(stopped) => stopped,
            None => match summary.finish(sim) {
                Ok(report) => {
                    recording
                        .finish()
                        .map_err(|e| error(py, Class::Simulation, e.to_string()))?;
                    let json = hopsim_io::to_json_value(&report)
                        .and_then(|v| serde_json::to_string(&v))
                        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                    return Ok((json, figures(&report)));
                }
                Err(e) => Stopped::of(&e),
            },
        };
        let kept = match stopped.record {
            true => Vec::new(),
            false => keep(recording, &stopped.reason)?,
        };
        let kept = match kept.is_empty() {
            true => "nothing was kept".to_string(),
            false => format!("the recording up to the stop is kept: {}", names(&kept)),
        };
        Err(error(
            py,
            Class::Simulation,
            format!("the recorded run stopped: {}; {kept}", stopped.reason),
        ))
    }

    /// Keeps what was recorded under the outputs' partial names (`run.partial.mcap`) with
    /// `reason` as the stop's reason (or the error that stopped the run); returns those
    /// files.
    pub(crate) fn abort(self, reason: &str) -> PyResult<Vec<PathBuf>> {
        match self.stopped {
            Some(s) if s.record => Ok(Vec::new()),
            Some(s) => keep(self.recording, &s.reason),
            None => keep(self.recording, reason),
        }
    }
}

/// Keeps what `recording` recorded under its partial names, with `reason`.
fn keep(recording: RecordingObserver, reason: &str) -> PyResult<Vec<PathBuf>> {
    recording
        .finish_partial(&reason)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

fn names(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    names.join(", ")
}

impl Observer for Watch {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.summary.on_step(view)?;
        self.recording.on_step(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.summary.on_start(view)?;
        self.recording.on_start(view)
    }
}

/// A recording's steps only: a span run (`Simulation.run`) shows its start again, which
/// the recording has already seen.
pub(crate) struct Steps<'a>(pub Option<&'a mut Watch>);

impl Observer for Steps<'_> {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.0.on_step(view)
    }
}

/// The recording of a copy of a batch, shared between the batch's copy (which shows it its
/// steps on the thread that steps it) and `Batch.record`'s caller (which closes it).
#[derive(Clone)]
pub(crate) struct SharedWatch(pub Arc<Mutex<Watch>>);

impl SharedWatch {
    pub(crate) fn lock(&self) -> std::sync::MutexGuard<'_, Watch> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The watch, once the copy no longer holds it.
    pub(crate) fn into_inner(self) -> Option<Watch> {
        Arc::try_unwrap(self.0)
            .ok()
            .map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
    }
}

impl Observer for SharedWatch {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.lock().on_step(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.lock().on_start(view)
    }
}
