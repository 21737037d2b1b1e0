//! `hopsim.Simulation` and `hopsim.Actuation`: a scene stepped from Python, by its own
//! controller or by a controller written in Python.

use crate::errors::{error, guard, internal_error, Class};
use crate::names::{self, Part};
use crate::recording::{Closed, Steps, Watch};
use crate::scene::PyScene;
use crate::signals::SignalPoll;
use hopsim_control::ControlEvent;
use hopsim_model::{Model, Vec2};
use hopsim_record::{
    frame_columns, frame_values, Event, Frame, RecordError, Recorder, RecorderSet,
};
use hopsim_scene::{check_steps, Scene, StateProblem};
use hopsim_sim::{recording_info, Observer, RecordingObserver, RunError, Simulation};
use hopsim_step::{
    Actuation, ActuationError, ContactRecord, ImpulseCommand, JointForceCommand, State,
    TorqueCommand,
};
use hopsim_studies::run_summary::run_simulation;
use nalgebra::DVector;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayMethods};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};

/// The Python exception of a run error of `what` (`Simulation.step`, `Simulation.run`):
/// `InternalError` for a panic in a step, else `SimulationError`. An interrupted run
/// raises what the signal handler raised (`poll`), e.g. `KeyboardInterrupt`.
fn run_error(py: Python<'_>, what: &str, e: RunError, poll: Option<&mut SignalPoll>) -> PyErr {
    if let Some(raised) = poll.and_then(SignalPoll::take_error) {
        return raised;
    }
    match e {
        RunError::Internal { step, t, message } => {
            internal_error(py, what, Some((step, t)), &message)
        }
        RunError::Actuation(e) => actuation_error(&e),
        e => error(py, Class::Simulation, e.to_string()),
    }
}

/// Refuses a call of `steps` steps when the scene's `simulation.max_steps` is smaller (the
/// bound of every run, as `hopsim run` has it).
pub(crate) fn check_step_count(scene: &Scene, steps: u64) -> PyResult<()> {
    let max = scene.settings.max_steps;
    if steps <= max {
        return Ok(());
    }
    Err(PyValueError::new_err(format!(
        "{steps} steps are more than simulation.max_steps = {max}; {}",
        raise_max_steps(steps as f64)
    )))
}

/// How to allow `steps` steps from Python.
fn raise_max_steps(steps: f64) -> String {
    if steps > hopsim_scene::MAX_MAGNITUDE {
        return format!(
            "simulation.max_steps is at most {:e}: take fewer or larger steps",
            hopsim_scene::MAX_MAGNITUDE
        );
    }
    format!(
        "raise it with scene.with_overrides({{'simulation.max_steps': {steps}}}) and a new \
         Simulation to run this long"
    )
}

/// What a controller written in Python commands for one step: torques held over the step,
/// impulses applied inside it, velocity locks (brakes) and contact-shape switches
/// (docs/physics.md §3, §5.3, §5.4). Bodies, joints and shapes are indices (`Scene.bodies`,
/// `Scene.shapes`) or, for an actuation made for a scene (`Actuation(scene)`,
/// `Simulation.actuation()`), names too. Build one, fill it before each step, pass it to
/// `Simulation.step`, and `clear()` it: the buffers are reused.
#[pyclass(name = "Actuation", module = "hopsim")]
#[derive(Default)]
pub struct PyActuation {
    actuation: Actuation,
    events: Vec<ControlEvent>,
    /// The model whose names the commands may use.
    model: Option<Arc<Model>>,
}

impl PyActuation {
    /// A model's actuation: names of its parts are accepted.
    pub(crate) fn of(model: Arc<Model>) -> Self {
        Self {
            model: Some(model),
            ..Self::default()
        }
    }

    /// The index `key` stands for: an index as given (checked at the step) without a
    /// model, else a name or index of the model's parts.
    fn index(&self, part: Part, key: &Bound<'_, PyAny>) -> PyResult<usize> {
        match &self.model {
            Some(model) => names::index(model, part, key),
            None => key.extract::<usize>().map_err(|_| {
                PyTypeError::new_err(format!(
                    "expected an index (int), got {key}: an Actuation() made without a scene \
                     takes indices only; Actuation(scene) or Simulation.actuation() takes names too"
                ))
            }),
        }
    }

    fn body(&self, key: &Bound<'_, PyAny>) -> PyResult<usize> {
        self.index(Part::Body, key)
    }

    fn reaction(&self, key: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
        key.map(|k| self.body(k)).transpose()
    }
}

#[pymethods]
impl PyActuation {
    /// An empty actuation; with `scene` (a `Scene`), its commands take the scene's names
    /// of bodies, joints and shapes as well as indices.
    #[new]
    #[pyo3(signature = (scene = None))]
    fn new(scene: Option<PyRef<'_, PyScene>>) -> Self {
        match scene {
            Some(scene) => Self::of(scene.scene.model.clone()),
            None => Self::default(),
        }
    }

    /// Removes every command.
    fn clear(&mut self) {
        self.actuation.clear();
        self.events.clear();
    }

    /// A torque `torque` (N m) on `body`, and `-torque` on `reaction` (a motor between two
    /// bodies) if given.
    #[pyo3(signature = (body, torque, reaction = None))]
    fn torque(
        &mut self,
        body: &Bound<'_, PyAny>,
        torque: f64,
        reaction: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let command = TorqueCommand {
            body: self.body(body)?,
            reaction: self.reaction(reaction)?,
            torque,
        };
        self.actuation.torques.push(command);
        Ok(())
    }

    /// A generalised force on the joint of `body` (the body, or the joint by its name)
    /// held over the step: a torque (N m) on a revolute joint, a force (N) along a
    /// prismatic one (docs/physics.md §7).
    fn joint_force(&mut self, body: &Bound<'_, PyAny>, force: f64) -> PyResult<()> {
        let body = self.index(Part::Joint, body)?;
        self.actuation
            .joint_forces
            .push(JointForceCommand { body, force });
        Ok(())
    }

    /// A translational impulse `(ζx, ζy)` (N s, world frame) at the point of `body` at
    /// world offset `offset` (m) from its centre of mass, applied inside the step.
    #[pyo3(signature = (body, impulse, offset = (0.0, 0.0)))]
    fn point_impulse(
        &mut self,
        body: &Bound<'_, PyAny>,
        impulse: (f64, f64),
        offset: (f64, f64),
    ) -> PyResult<()> {
        let body = self.body(body)?;
        self.actuation.impulses.push(ImpulseCommand::Point {
            body,
            offset: Vec2::new(offset.0, offset.1),
            impulse: Vec2::new(impulse.0, impulse.1),
        });
        Ok(())
    }

    /// A rotational impulse `impulse` (N m s) on `body`, and its opposite on `reaction`.
    #[pyo3(signature = (body, impulse, reaction = None))]
    fn rotational_impulse(
        &mut self,
        body: &Bound<'_, PyAny>,
        impulse: f64,
        reaction: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let command = ImpulseCommand::Rotational {
            body: self.body(body)?,
            reaction: self.reaction(reaction)?,
            impulse,
        };
        self.actuation.impulses.push(command);
        Ok(())
    }

    /// Locks the rotation of `body` to that of `other` in this step (an engaged brake:
    /// `θ̇_body = θ̇_other` at the end of the step), without a brake event.
    fn lock(&mut self, body: &Bound<'_, PyAny>, other: &Bound<'_, PyAny>) -> PyResult<()> {
        let pair = (self.body(body)?, self.body(other)?);
        self.actuation.locks.push(pair);
        Ok(())
    }

    /// A brake: the lock of `lock(body, other)` and a brake event (counted in the run
    /// summary with the angular impulse it transferred).
    fn brake(&mut self, body: &Bound<'_, PyAny>, other: &Bound<'_, PyAny>) -> PyResult<()> {
        let (body, other) = (self.body(body)?, self.body(other)?);
        self.actuation.locks.push((body, other));
        self.events.push(ControlEvent::Brake { body, other });
        Ok(())
    }

    /// Switches contact shape `shape` on or off (a cane extended or retracted) before the
    /// step.
    fn switch_shape(&mut self, shape: &Bound<'_, PyAny>, active: bool) -> PyResult<()> {
        let shape = self.index(Part::Shape, shape)?;
        self.events
            .push(ControlEvent::ShapeSwitch { shape, active });
        Ok(())
    }

    fn __repr__(&self) -> String {
        let a = &self.actuation;
        format!(
            "Actuation({} torques, {} joint forces, {} impulses, {} locks, {} events)",
            a.torques.len(),
            a.joint_forces.len(),
            a.impulses.len(),
            a.locks.len(),
            self.events.len()
        )
    }
}

/// The Python exception of a command the model cannot carry out (`Actuation::validate`,
/// `ControlEvent::validate`, checked by `Simulation::step_with` before the step): an index
/// out of range is an `IndexError`, anything else a `ValueError`.
fn actuation_error(e: &ActuationError) -> PyErr {
    match e {
        ActuationError::NoSuchBody { .. }
        | ActuationError::NoSuchShape { .. }
        | ActuationError::NoSuchActuator { .. } => PyIndexError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A scene being simulated, one step at a time or a span at a time. State arrays are
/// returned as new numpy arrays (copies: changing them changes nothing in the
/// simulation; use `set_state`).
#[pyclass(name = "Simulation", module = "hopsim", subclass)]
pub struct PySimulation {
    /// `Simulation` holds the scene's controller, which is `Send` but not `Sync`; the
    /// mutex makes the class shareable between threads (methods taking `&mut self` reach
    /// it without locking).
    sim: Mutex<Simulation>,
    scene: Arc<Scene>,
    py_scene: Py<PyScene>,
    /// The recording under way (`record`), shown every step (behind a mutex, as `sim`,
    /// for the class to be shareable between threads).
    recording: Mutex<Option<Watch>>,
}

/// The error of a call that would restart a simulation being recorded.
fn recording_under_way(what: &str) -> PyErr {
    PyRuntimeError::new_err(format!(
        "{what}: the simulation is being recorded; close the recording first"
    ))
}

impl PySimulation {
    /// Per shape: its contact flag and its two forces ([`Simulation::shape_contacts_to`]).
    fn shape_contacts(&self) -> (Vec<bool>, Vec<f64>) {
        let shapes = self.scene.model.shapes().len();
        let (mut loaded, mut forces) = (vec![false; shapes], vec![0.0; 2 * shapes]);
        self.shared().shape_contacts_to(&mut loaded, &mut forces);
        (loaded, forces)
    }

    fn sim(&mut self) -> &mut Simulation {
        self.sim.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    fn recording(&mut self) -> &mut Option<Watch> {
        self.recording.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    fn shared(&self) -> MutexGuard<'_, Simulation> {
        self.sim.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Frames of a run collected for Python: one row of the CSV recorder's columns each.
#[derive(Default)]
struct Frames {
    values: Vec<f64>,
    steps: Vec<u64>,
    events: Vec<Event>,
}

/// A recorder that keeps the frames in memory.
struct FrameCollector(Arc<Mutex<Frames>>);

impl FrameCollector {
    fn frames(&self) -> MutexGuard<'_, Frames> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Recorder for FrameCollector {
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        let mut frames = self.frames();
        frames.values.push(frame.t);
        frames.values.push(frame.step as f64);
        frames.values.extend(frame_values(frame));
        frames.steps.push(frame.step);
        Ok(())
    }

    fn event(&mut self, event: &Event) -> Result<(), RecordError> {
        self.frames().events.push(event.clone());
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), RecordError> {
        Ok(())
    }
}

fn positive(name: &str, value: Option<f64>, default: f64) -> PyResult<f64> {
    match value {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => Err(PyValueError::new_err(format!(
            "{name} must be positive and finite, got {v}"
        ))),
    }
}

/// The dict of a run (see `PySimulation::_run`); `summary` is the run summary's JSON, or
/// None for a run that stopped early.
fn run_dict<'py>(
    py: Python<'py>,
    scene: &Scene,
    frames: Frames,
    summary: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let columns = frame_columns(&recording_info(scene));
    let width = columns.len();
    let rows = frames.steps.len();
    let events = serde_json::to_string(&frames.events)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let d = PyDict::new(py);
    d.set_item("columns", columns)?;
    d.set_item(
        "frames",
        PyArray1::from_vec(py, frames.values).reshape([rows, width])?,
    )?;
    d.set_item("steps", PyArray1::from_vec(py, frames.steps))?;
    d.set_item("events", events)?;
    d.set_item("summary", summary)?;
    d.set_item("coordinates", scene.coordinates.clone())?;
    Ok(d)
}

/// The message of a state `set_state` refuses.
fn state_error(problem: &StateProblem) -> PyErr {
    let hint = match problem {
        StateProblem::Start(_) => {
            "; a state a simulation of this scene reached (contacts in load are slightly \
             penetrated) is restored with restore=True"
        }
        _ => "",
    };
    PyValueError::new_err(format!("{problem}{hint}"))
}

#[pymethods]
impl PySimulation {
    /// A simulation of `scene` at its initial state.
    #[new]
    fn new(py: Python<'_>, scene: Bound<'_, PyScene>) -> PyResult<Self> {
        let shared = scene.get().scene.clone();
        let sim = guard(py, "Simulation", || Ok(Simulation::new(&shared)))?;
        Ok(Self {
            sim: Mutex::new(sim),
            scene: shared,
            py_scene: scene.unbind(),
            recording: Mutex::new(None),
        })
    }

    /// The scene being simulated.
    #[getter]
    fn scene(&self, py: Python<'_>) -> Py<PyScene> {
        self.py_scene.clone_ref(py)
    }

    /// Takes `n` steps (at most the scene's `simulation.max_steps`). Without `actuation`
    /// the scene's controller acts; with one, its commands act in each of these steps
    /// instead (the scene's controller is not called, so it does not advance). The GIL is
    /// released while more than one step runs, and Python's signal handlers run about
    /// every 50 ms (Ctrl-C raises `KeyboardInterrupt` after the step under way). Raises
    /// `SimulationError` when a step fails (a non-finite or runaway state) and
    /// `InternalError` when it panics (a bug).
    #[pyo3(signature = (n = 1, actuation = None))]
    fn step(
        &mut self,
        py: Python<'_>,
        n: u64,
        actuation: Option<PyRef<'_, PyActuation>>,
    ) -> PyResult<()> {
        const WHAT: &str = "Simulation.step";
        let scene = self.scene.clone();
        check_step_count(&scene, n)?;
        let sim = self.sim.get_mut().unwrap_or_else(|e| e.into_inner());
        let recording = self.recording.get_mut().unwrap_or_else(|e| e.into_inner());
        let mut recording = recording.as_mut();
        guard(py, WHAT, || {
            // One step returns to Python at once: no need to poll for signals.
            let (mut poll, mut single) = (SignalPoll::new(), ());
            let watch = Steps(recording.as_deref_mut());
            let result = match actuation {
                Some(a) => {
                    let first: &mut dyn Observer = if n > 1 { &mut poll } else { &mut single };
                    let mut observer = (first, watch);
                    (0..n).try_for_each(|_| sim.step_with(&a.actuation, &a.events, &mut observer))
                }
                None if n == 1 => sim.step(&mut (single, watch)),
                None => py.detach(|| {
                    let mut observer = (&mut poll, watch);
                    (0..n).try_for_each(|_| sim.step(&mut observer))
                }),
            };
            result.map_err(|e| {
                // A command refused before the step stops nothing.
                if let (Some(w), false) = (recording, matches!(e, RunError::Actuation(_))) {
                    w.stop(&e);
                }
                run_error(py, WHAT, e, Some(&mut poll))
            })
        })
    }

    /// Continues the simulation for `duration` seconds (default: the scene's
    /// `simulation.duration`; at most `simulation.max_steps` steps) with the scene's
    /// controller, the GIL released, Python's signal handlers run about every 50 ms.
    /// With `frames`, records frames at `record_rate` Hz (default: the scene's) and at
    /// every step with an event; without, keeps neither frames nor events (memory stays
    /// bounded however long the run). Returns a dict: `columns` (the CSV recorder's column
    /// names), `frames` (one row per frame), `steps`, `events` (JSON), `summary` (JSON, the
    /// CLI's `--summary` document). A run that stops early raises with this dict (its
    /// summary None) as the exception's `_partial_run`. `hopsim.Simulation.run` wraps it as
    /// a `Trajectory`.
    #[pyo3(signature = (duration = None, record_rate = None, frames = true))]
    fn _run<'py>(
        &mut self,
        py: Python<'py>,
        duration: Option<f64>,
        record_rate: Option<f64>,
        frames: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        const WHAT: &str = "Simulation.run";
        let scene = self.scene.clone();
        let duration = positive("duration", duration, scene.settings.duration)?;
        let dt = scene.settings.dt;
        check_steps(duration, dt, scene.settings.max_steps).map_err(|e| {
            PyValueError::new_err(format!("duration: {e}; {}", raise_max_steps(e.steps)))
        })?;
        if (duration / dt).round() < 1.0 {
            return Err(PyValueError::new_err(format!(
                "duration {duration} s is less than half a step of {dt} s: the run would take \
                 no step"
            )));
        }
        let rate = positive("record_rate", record_rate, scene.settings.record_rate)?;
        let sim = self.sim.get_mut().unwrap_or_else(|e| e.into_inner());
        let recording = self.recording.get_mut().unwrap_or_else(|e| e.into_inner());
        let recording = recording.as_mut();
        guard(py, WHAT, || {
            let (report, kept, mut poll) = py.detach(|| {
                let kept = Arc::new(Mutex::new(Frames::default()));
                let mut recorder = frames.then(|| {
                    let mut recorders = RecorderSet::default();
                    recorders.push(Box::new(FrameCollector(kept.clone())));
                    RecordingObserver::with_rate(recorders, &scene, rate)
                });
                let mut poll = SignalPoll::new();
                let mut watch = Steps(recording);
                let report =
                    run_simulation(sim, duration, &mut (&mut recorder, (&mut poll, &mut watch)))
                        .and_then(|r| recorder.map_or(Ok(()), |o| o.finish()).map(|()| r));
                if let (Err(e), Some(w)) = (&report, watch.0) {
                    w.stop(e);
                }
                let kept = std::mem::take(&mut *kept.lock().unwrap_or_else(|e| e.into_inner()));
                (report, kept, poll)
            });
            match report {
                Ok(report) => {
                    let summary = serde_json::to_string(&report)
                        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                    run_dict(py, &scene, kept, Some(summary))
                }
                Err(e) => {
                    let err = run_error(py, WHAT, e, Some(&mut poll));
                    err.value(py)
                        .setattr("_partial_run", run_dict(py, &scene, kept, None)?)?;
                    Err(err)
                }
            }
        })
    }

    /// Starts recording at the current state (its first frame) to `outputs`: paths ending
    /// in `.mcap`, `.rrd` or `.csv` (the recorders of `hopsim run`, written atomically),
    /// or `"live"` (a Rerun viewer, paced by `speed`: a factor or `"max"`). Frames at
    /// `record_rate` Hz (default: the scene's) and at every step with an event, whoever
    /// steps (`step`, with or without an `Actuation`, and `run`). `hopsim.Simulation.record`
    /// wraps it as a `Recorder`.
    #[pyo3(signature = (outputs, record_rate = None, speed = "1".to_string()))]
    fn _record_open(
        &mut self,
        py: Python<'_>,
        outputs: Vec<String>,
        record_rate: Option<f64>,
        speed: String,
    ) -> PyResult<()> {
        if self.recording().is_some() {
            return Err(PyRuntimeError::new_err(
                "record: the simulation is already being recorded; close that recording first",
            ));
        }
        let scene = self.scene.clone();
        let sim = self.sim.get_mut().unwrap_or_else(|e| e.into_inner());
        let watch = guard(py, "Simulation.record", || {
            let mut watch = Watch::new(sim, &scene, &outputs, record_rate, &speed)?;
            sim.start(&mut watch)
                .map_err(|e| error(py, Class::Simulation, e.to_string()))?;
            Ok(watch)
        })?;
        *self.recording() = Some(watch);
        Ok(())
    }

    /// Completes the recording and returns the run summary of the span recorded (JSON)
    /// and the figures a sweep reports of it (`[(column, value)]`);
    /// a recorded run that stopped keeps its recordings under their partial names and
    /// raises `SimulationError` naming them.
    fn _record_close(&mut self, py: Python<'_>) -> PyResult<Closed> {
        let watch = self
            .recording()
            .take()
            .ok_or_else(|| PyRuntimeError::new_err("the simulation is not being recorded"))?;
        let sim = self.sim.get_mut().unwrap_or_else(|e| e.into_inner());
        guard(py, "Recorder.close", || watch.close(py, sim))
    }

    /// Ends the recording without completing it: what was recorded is kept under the
    /// outputs' partial names (`run.partial.mcap`) with `reason`; returns those paths.
    fn _record_abort(&mut self, py: Python<'_>, reason: &str) -> PyResult<Vec<PathBuf>> {
        let watch = self
            .recording()
            .take()
            .ok_or_else(|| PyRuntimeError::new_err("the simulation is not being recorded"))?;
        guard(py, "Recorder.abort", || watch.abort(reason))
    }

    /// Time, s.
    #[getter]
    fn t(&self) -> f64 {
        self.shared().state().t
    }

    /// Steps taken since the simulation (re)started.
    #[getter]
    fn step_count(&self) -> u64 {
        self.shared().stepper().record().step
    }

    /// Generalised coordinates `q` (a copy).
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.shared().state().q.as_slice())
    }

    /// Generalised velocities `u = q̇` (a copy).
    #[getter]
    fn u<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.shared().state().u.as_slice())
    }

    /// Restarts the run at `q`, `u` and time `t` (default: the current time): the step
    /// count, energy ledger, LCP statistics and flight phases restart; the controller and
    /// the shapes switched on stay as they are. The state is checked as a scene's
    /// `[initial]` is: one finite value per coordinate within the scene's bounds
    /// (`|q_i| ≤ 1e6`, `|u_i| ≤ simulation.max_speed`, `|t| ≤ 1e9` s), and no shape inside
    /// the terrain or another body, no joint past a stop (`ValueError` naming the contact or
    /// joint and the depth). `restore=True` skips the latter for a state a simulation of
    /// the scene reached, whose contacts in load are slightly penetrated.
    #[pyo3(signature = (q, u, t = None, restore = false))]
    fn set_state(
        &mut self,
        py: Python<'_>,
        q: PyArrayLike1<'_, f64, AllowTypeChange>,
        u: PyArrayLike1<'_, f64, AllowTypeChange>,
        t: Option<f64>,
        restore: bool,
    ) -> PyResult<()> {
        if self.recording().is_some() {
            return Err(recording_under_way("Simulation.set_state"));
        }
        let (q, u) = (q.as_array(), u.as_array());
        let state = State {
            t: t.unwrap_or_else(|| self.shared().state().t),
            q: DVector::from_iterator(q.len(), q.iter().copied()),
            u: DVector::from_iterator(u.len(), u.iter().copied()),
        };
        let sim = self.sim();
        guard(py, "Simulation.set_state", || {
            let set = if restore {
                sim.restore_state(state)
            } else {
                sim.set_state(state)
            };
            set.map_err(|p| state_error(&p))
        })
    }

    /// The names of the scene's actuators (`[[actuators]]`, docs/physics.md §7.4), in the
    /// order of `control`.
    #[getter]
    fn actuator_names(&self) -> Vec<String> {
        self.scene
            .model
            .actuators()
            .iter()
            .map(|a| a.name.clone())
            .collect()
    }

    /// The actuators' controls (a copy), held from step to step. Setting it sets every
    /// control (one finite number per actuator). An actuator with a control signal in the
    /// scene gets the signal's value before each step the scene's controller takes.
    #[getter(control)]
    fn get_control<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.shared().controls())
    }

    #[setter(control)]
    fn set_control_all(&mut self, control: PyArrayLike1<'_, f64, AllowTypeChange>) -> PyResult<()> {
        let control = control.as_array();
        let values: Vec<f64> = control.iter().copied().collect();
        self.sim()
            .set_controls(&values)
            .map_err(|e| actuation_error(&e))
    }

    /// Sets one actuator's control, by name or index (`actuator_names`).
    fn set_control(&mut self, actuator: &Bound<'_, PyAny>, value: f64) -> PyResult<()> {
        let index = names::index(&self.scene.model, Part::Actuator, actuator)?;
        self.sim()
            .set_control(index, value)
            .map_err(|e| actuation_error(&e))
    }

    /// An empty `Actuation` that takes this scene's names of bodies, joints and shapes.
    fn actuation(&self) -> PyActuation {
        PyActuation::of(self.scene.model.clone())
    }

    /// Per shape (`shape_names`): whether it carried a normal percussion in the last step,
    /// (n_shapes,) bool (a new array).
    fn shape_in_contact<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let (loaded, _) = self.shape_contacts();
        PyArray1::from_vec(py, loaded)
    }

    /// Per shape (`shape_names`): its contacts' normal and tangential forces over the last
    /// step, `Λ_N / Δt` and `Λ_T / Δt` (N; each contact along its own normal, into the
    /// shape's body, and tangent `t = (n_y, -n_x)`; a contact between two bodies counts
    /// for both shapes), (n_shapes, 2) (a new array).
    fn shape_contact_forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (loaded, forces) = self.shape_contacts();
        PyArray1::from_vec(py, forces).reshape([loaded.len(), 2])
    }

    /// The generalised forces of the actuators at the current state under the current
    /// controls, one per coordinate (MuJoCo's `qfrc_actuator`): `gear · force` on each
    /// actuator's joint, controls and forces clamped to their ranges.
    fn actuator_forces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let sim = self.shared();
        let mut out = vec![0.0; sim.state().q.len()];
        sim.actuator_forces_to(&mut out);
        PyArray1::from_vec(py, out)
    }

    /// Absolute angular velocity of each body, rad/s (a copy).
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let sim = self.shared();
        let k = sim.stepper().kinematics();
        PyArray1::from_iter(py, (0..k.bodies()).map(|b| k.angular_velocity(b)))
    }

    /// Centre-of-mass position of each body, m, shape `(bodies, 2)` (a copy).
    #[getter]
    fn body_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let sim = self.shared();
        let k = sim.stepper().kinematics();
        let flat: Vec<f64> = (0..k.bodies())
            .flat_map(|b| [k.position(b).x, k.position(b).y])
            .collect();
        PyArray1::from_vec(py, flat).reshape([k.bodies(), 2])
    }

    /// Absolute angle of each body, rad (a copy).
    #[getter]
    fn body_angles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let sim = self.shared();
        let k = sim.stepper().kinematics();
        PyArray1::from_iter(py, (0..k.bodies()).map(|b| k.angle(b)))
    }

    /// Whether any contact carried a normal percussion in the last step (what the scene's
    /// controllers see; true before the first step).
    #[getter]
    fn in_contact(&self) -> bool {
        self.shared().in_contact()
    }

    /// Flight phases (hops) so far.
    #[getter]
    fn hops(&self) -> u64 {
        self.shared().hops()
    }

    /// Energies after the last step, J: `kinetic`, `potential`, `spring`, `actuator_work`,
    /// `dissipated`, `balance_error` (docs/physics.md §6).
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let sim = self.shared();
        let e = hopsim_record::EnergySample::from_ledger(&sim.stepper().record().energy);
        let d = PyDict::new(py);
        for (name, v) in hopsim_record::EnergySample::NAMES.iter().zip(e.values()) {
            d.set_item(*name, v)?;
        }
        Ok(d)
    }

    /// The contacts of the last step's index set (closed or closing at the midpoint), one
    /// dict each: `contact` (name), `index`, `gap` (m, ≤ 0, at the midpoint), `point`,
    /// `normal`, `impulse_normal` and `impulse_tangent` (N s), `slip_velocity` (m/s) and
    /// `state` (`"open"`, `"stick"` or `"slip"`).
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let sim = self.shared();
        let model = &self.scene.model;
        contact_list(py, &sim.stepper().record().contacts, |i| {
            (model.contacts()[i].name.as_str(), None)
        })
    }

    /// The body–body contacts of the last step's index set (docs/physics.md §7), as
    /// `contacts()` gives the terrain's, plus `probe` and `target` (the two shapes' names):
    /// `index` counts the scene's contact pairs, `point` is the probe's point, `normal`
    /// points from the target to the probe, and the percussions act on the probe's body
    /// (their opposites on the target's).
    fn pair_contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let sim = self.shared();
        let model = &self.scene.model;
        contact_list(py, &sim.stepper().record().pair_contacts, |i| {
            let pair = &model.pairs()[i];
            let shape = |s: usize| model.shapes()[s].name.as_str();
            (
                pair.name.as_str(),
                Some((shape(pair.probe), shape(pair.target))),
            )
        })
    }

    /// The events of the last step (JSON text, as recorded: `t_s`, `step`, `kind`, ...).
    fn _events(&self) -> PyResult<String> {
        let sim = self.shared();
        serde_json::to_string(sim.view().events).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        let sim = self.shared();
        format!(
            "Simulation({:?}, t={}, step={})",
            self.scene.title,
            sim.state().t,
            sim.stepper().record().step
        )
    }
}

/// One dict per contact record; `names(index)` gives the contact's name and, for a
/// body–body contact, its probe and target shapes.
fn contact_list<'py, 'a>(
    py: Python<'py>,
    records: &[ContactRecord],
    names: impl Fn(usize) -> (&'a str, Option<(&'a str, &'a str)>),
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for c in records {
        let d = PyDict::new(py);
        let (name, shapes) = names(c.contact);
        d.set_item("contact", name)?;
        if let Some((probe, target)) = shapes {
            d.set_item("probe", probe)?;
            d.set_item("target", target)?;
        }
        d.set_item("index", c.contact)?;
        d.set_item("gap", c.gap)?;
        d.set_item("point", (c.point.x, c.point.y))?;
        d.set_item("normal", (c.normal.x, c.normal.y))?;
        d.set_item("impulse_normal", c.impulse_normal)?;
        d.set_item("impulse_tangent", c.impulse_tangent)?;
        d.set_item("slip_velocity", c.slip_velocity)?;
        d.set_item("state", c.state.as_str())?;
        list.append(d)?;
    }
    Ok(list)
}
