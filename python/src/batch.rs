//! `hopsim.Batch`: copies of a scene stepped together on Rust threads (`hopsim_sim::Batch`),
//! their states, controls, contact flags and done mask in numpy arrays filled in place.

use crate::errors::guard;
use crate::recording::{Closed, SharedWatch, Watch};
use crate::scene::PyScene;
use crate::signals::SignalPoll;
use crate::simulation::check_step_count;
use hopsim_scene::Scene;
use hopsim_sim::{Batch, BatchError};
use hopsim_step::State;
use nalgebra::DVector;
use numpy::{
    AllowTypeChange, PyArray1, PyArray2, PyArray3, PyArrayLike1, PyArrayLike2, PyArrayMethods,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// Copy steps (copies × steps) a batch takes between two polls for signals: a few
/// milliseconds at most, and few enough polls that they cost nothing measurable.
const POLL_COPY_STEPS: usize = 4096;

/// The Python exception of a batch refused or a copy's state refused.
fn batch_error(e: BatchError) -> PyErr {
    match e {
        BatchError::NoSuchCopy { .. } => PyIndexError::new_err(e.to_string()),
        BatchError::Observed { .. } => {
            PyRuntimeError::new_err(format!("{e}: close the copy's recording first"))
        }
        e => PyValueError::new_err(e.to_string()),
    }
}

/// `n` copies of a scene stepped together on `threads` Rust threads (default: the machine's
/// cores, at most `n`), the GIL released. Copy `i` equals a `Simulation` of the scene with
/// the same start and controls bit for bit, whatever the thread count. `t` (n,), `q`, `u`
/// (n, nq), `in_contact` and `done` (n,) are numpy arrays owned by the batch, filled in
/// place by every step and reset (read-only: use `set_state`); `controls` (n, nu) is
/// written by the caller (in place, or by assignment) and read before each step, as is
/// `brakes` (n, len(brake_pairs)), which brakes are engaged in each copy, and `switches`
/// (n, len(switch_shapes)), which switchable shapes are to be active.
#[pyclass(name = "Batch", module = "hopsim", subclass)]
pub struct PyBatch {
    /// `Batch` holds the copies' controllers (`Send`, not `Sync`); methods taking `&mut
    /// self` reach it without locking.
    batch: Mutex<Batch>,
    scene: Arc<Scene>,
    /// Each copy's scene (the batch's scene with the copy's overrides, if any).
    copies: Vec<Arc<Scene>>,
    py_scene: Py<PyScene>,
    t: Py<PyArray1<f64>>,
    q: Py<PyArray2<f64>>,
    u: Py<PyArray2<f64>>,
    controls: Py<PyArray2<f64>>,
    in_contact: Py<PyArray1<bool>>,
    done: Py<PyArray1<bool>>,
    brakes: Py<PyArray2<bool>>,
    switches: Py<PyArray2<bool>>,
    /// Per copy: its recording under way (`record`), if any.
    recordings: Vec<Option<SharedWatch>>,
    shape_in_contact: Py<PyArray2<bool>>,
    shape_contact_forces: Py<PyArray3<f64>>,
}

/// `n × width` zeros, writeable by Python or not.
fn matrix(py: Python<'_>, n: usize, width: usize, writeable: bool) -> PyResult<Py<PyArray2<f64>>> {
    let a = PyArray2::<f64>::zeros(py, [n, width], false);
    read_only(a.as_any(), writeable)?;
    Ok(a.unbind())
}

fn read_only(array: &Bound<'_, PyAny>, writeable: bool) -> PyResult<()> {
    if !writeable {
        array.call_method1("setflags", (false,))?;
    }
    Ok(())
}

/// Writes `values` into `array` (the batch's own array, of the same length).
fn fill<T: numpy::Element + Copy, D: numpy::ndarray::Dimension>(
    array: &Bound<'_, numpy::PyArray<T, D>>,
    values: &[T],
) {
    // SAFETY: the array is the batch's own, of `values.len()` elements, and is written
    // with the GIL held while no Rust borrow of it exists (Python code, which may
    // hold views of it, cannot run meanwhile).
    match unsafe { array.as_slice_mut() } {
        Ok(slice) => slice.copy_from_slice(values),
        Err(_) => {
            let mut view = unsafe { array.as_array_mut() };
            view.iter_mut()
                .zip(values)
                .for_each(|(to, from)| *to = *from);
        }
    }
}

/// The error of a copy without a recording.
fn not_recorded(i: usize) -> PyErr {
    PyRuntimeError::new_err(format!("copy {i} is not being recorded"))
}

impl PyBatch {
    /// Copy `i`'s recording, detached from it, with the error that stopped the copy.
    fn take_recording(&mut self, i: usize) -> PyResult<Watch> {
        let shared = self
            .recordings
            .get_mut(i)
            .and_then(Option::take)
            .ok_or_else(|| not_recorded(i))?;
        let batch = self.batch.get_mut().unwrap_or_else(|e| e.into_inner());
        drop(batch.detach(i));
        let mut watch = shared
            .into_inner()
            .ok_or_else(|| PyRuntimeError::new_err("the recording is still shared"))?;
        if let Some(e) = batch.error(i) {
            watch.stop(e);
        }
        Ok(watch)
    }

    fn batch(&mut self) -> &mut Batch {
        self.batch.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    /// The batch's arrays from its copies.
    fn publish(&mut self, py: Python<'_>) {
        let batch = self.batch.get_mut().unwrap_or_else(|e| e.into_inner());
        fill(self.t.bind(py), batch.t());
        fill(self.q.bind(py), batch.q());
        fill(self.u.bind(py), batch.u());
        fill(self.controls.bind(py), batch.controls());
        fill(self.in_contact.bind(py), batch.in_contact());
        fill(self.done.bind(py), batch.done());
        fill(self.shape_in_contact.bind(py), batch.shape_in_contact());
        fill(
            self.shape_contact_forces.bind(py),
            batch.shape_contact_forces(),
        );
    }

    /// The engaged brakes and the shapes' flags as Python left them, into the batch.
    fn take_commands(&mut self, py: Python<'_>) {
        let (brakes, switches) = (self.brakes.bind(py).clone(), self.switches.bind(py).clone());
        let (brakes, switches) = (brakes.readonly(), switches.readonly());
        let batch = self.batch();
        let copy = |to: &mut [bool], from: numpy::ndarray::ArrayView2<'_, bool>| {
            to.iter_mut()
                .zip(from.iter())
                .for_each(|(to, from)| *to = *from)
        };
        copy(batch.engaged_mut(), brakes.as_array());
        copy(batch.active_mut(), switches.as_array());
    }
}

#[pymethods]
impl PyBatch {
    #[new]
    #[pyo3(signature = (scene, n, threads = None, brakes = None, switches = None, copies = None))]
    fn new(
        py: Python<'_>,
        scene: Bound<'_, PyScene>,
        n: usize,
        threads: Option<usize>,
        brakes: Option<Vec<(usize, usize)>>,
        switches: Option<Vec<usize>>,
        copies: Option<Vec<Bound<'_, PyScene>>>,
    ) -> PyResult<Self> {
        let shared = scene.get().scene.clone();
        // One scene per copy (domain randomisation), or the one scene shared.
        let own = copies.is_some();
        let copies: Vec<Arc<Scene>> = match copies {
            Some(c) if c.len() != n => {
                return Err(PyValueError::new_err(format!(
                    "overrides: {} sets of overrides for {n} copies (one per copy)",
                    c.len()
                )))
            }
            Some(c) => c.iter().map(|s| s.get().scene.clone()).collect(),
            None => vec![shared.clone(); n],
        };
        let threads = threads.unwrap_or_else(|| {
            let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
            cores.min(n.max(1))
        });
        let (brakes, switches) = (brakes.unwrap_or_default(), switches.unwrap_or_default());
        let batch = guard(py, "Batch", || {
            let mut batch = py
                .detach(|| match own {
                    true => Batch::of_setups(
                        copies.iter().map(|s| Arc::new(s.setup.clone())).collect(),
                        threads,
                    ),
                    false => Batch::new(&shared.setup, n, threads),
                })
                .map_err(batch_error)?;
            batch
                .set_commands(&brakes, &switches)
                .map_err(batch_error)?;
            Ok(batch)
        })?;
        let (nq, nu) = (batch.nq(), batch.nu());
        let engaged = PyArray2::<bool>::zeros(py, [n, brakes.len()], false).unbind();
        let active = PyArray2::<bool>::zeros(py, [n, switches.len()], false).unbind();
        let flags = |writeable| -> PyResult<Py<PyArray1<bool>>> {
            let a = PyArray1::<bool>::zeros(py, n, false);
            read_only(a.as_any(), writeable)?;
            Ok(a.unbind())
        };
        let t = PyArray1::<f64>::zeros(py, n, false);
        read_only(t.as_any(), false)?;
        let shapes = batch.shapes();
        let shape_in_contact = PyArray2::<bool>::zeros(py, [n, shapes], false);
        read_only(shape_in_contact.as_any(), false)?;
        let shape_contact_forces = PyArray3::<f64>::zeros(py, [n, shapes, 2], false);
        read_only(shape_contact_forces.as_any(), false)?;
        let mut this = Self {
            batch: Mutex::new(batch),
            scene: shared,
            copies,
            py_scene: scene.unbind(),
            t: t.unbind(),
            q: matrix(py, n, nq, false)?,
            u: matrix(py, n, nq, false)?,
            controls: matrix(py, n, nu, true)?,
            in_contact: flags(false)?,
            done: flags(false)?,
            brakes: engaged,
            switches: active,
            recordings: (0..n).map(|_| None).collect(),
            shape_in_contact: shape_in_contact.unbind(),
            shape_contact_forces: shape_contact_forces.unbind(),
        };
        this.publish(py);
        Ok(this)
    }

    /// The scene of every copy.
    #[getter]
    fn scene(&self, py: Python<'_>) -> Py<PyScene> {
        self.py_scene.clone_ref(py)
    }

    /// The number of copies.
    fn __len__(&self) -> usize {
        self.batch.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    /// The threads the copies are stepped on.
    #[getter]
    fn threads(&self) -> usize {
        self.batch
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .threads()
    }

    /// Takes `n` steps of every copy that is not done (at most the scene's
    /// `simulation.max_steps`), under `controls` (n_copies, nu) if given, else under the
    /// array `controls`, held over the `n` steps; the scene's controller acts in every
    /// copy. The GIL is released while the copies step, and Python's signal handlers run
    /// about every 50 ms (Ctrl-C raises `KeyboardInterrupt`, the arrays holding the last
    /// steps taken). A copy whose step fails is marked `done` (its message in
    /// `error(i)`); the others go on.
    #[pyo3(signature = (n = 1, controls = None))]
    fn step(
        &mut self,
        py: Python<'_>,
        n: u64,
        controls: Option<PyArrayLike2<'_, f64, AllowTypeChange>>,
    ) -> PyResult<()> {
        check_step_count(&self.scene, n)?;
        let steps = usize::try_from(n).map_err(|e| PyValueError::new_err(e.to_string()))?;
        if let Some(c) = controls {
            self.set_controls(py, c)?;
        }
        self.take_commands(py);
        let own = self.controls.bind(py).clone();
        let batch = self.batch();
        // The controls as Python left them (row-major, as the batch's).
        let given = own.readonly();
        match given.as_slice() {
            Ok(slice) => batch.controls_mut().copy_from_slice(slice),
            Err(_) => batch
                .controls_mut()
                .iter_mut()
                .zip(given.as_array().iter())
                .for_each(|(to, from)| *to = *from),
        }
        drop(given);
        let mut poll = SignalPoll::new();
        guard(py, "Batch.step", || {
            py.detach(|| {
                // Blocks of about POLL_COPY_STEPS copy steps between polls for signals.
                let block = (POLL_COPY_STEPS / batch.len()).max(1);
                let mut left = steps;
                while left > 0 {
                    let k = left.min(block);
                    batch.step(k);
                    left -= k;
                    if !poll.poll() {
                        break;
                    }
                }
            });
            Ok(())
        })?;
        self.publish(py);
        poll.take_error().map_or(Ok(()), Err)
    }

    /// Time of each copy, s: (n,).
    #[getter]
    fn t(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.t.clone_ref(py)
    }

    /// Generalised coordinates of each copy: (n, nq).
    #[getter]
    fn q(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.q.clone_ref(py)
    }

    /// Generalised velocities of each copy: (n, nq).
    #[getter]
    fn u(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.u.clone_ref(py)
    }

    /// The actuators' controls of each copy, (n, nu), in the order of the scene's
    /// `[[actuators]]`: read before each step; after one, the controls that acted (a
    /// control signal of the scene replaces the given value).
    #[getter]
    fn get_controls(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.controls.clone_ref(py)
    }

    #[setter(controls)]
    fn set_controls(
        &mut self,
        py: Python<'_>,
        controls: PyArrayLike2<'_, f64, AllowTypeChange>,
    ) -> PyResult<()> {
        let own = self.controls.bind(py);
        let (shape, given) = (own.shape().to_vec(), controls.as_array());
        if given.shape() != shape.as_slice() {
            return Err(PyValueError::new_err(format!(
                "controls: expected shape {shape:?} (copies, actuators), got {:?}",
                given.shape()
            )));
        }
        own.readwrite().as_array_mut().assign(&given);
        Ok(())
    }

    /// The brakes `(body, other)` given at construction: each locks `θ̇_body = θ̇_other`
    /// at the end of every step of a copy in which it is engaged (docs/physics.md §4.4).
    #[getter]
    fn brake_pairs(&self) -> Vec<(usize, usize)> {
        self.batch
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .brakes()
            .to_vec()
    }

    /// Which brakes are engaged in each copy, (n, len(brake_pairs)) bool, written by the
    /// caller and read before each step (held over its steps). A copy's step with an
    /// engaged brake takes the brake's lock in place of the scene's controller, which
    /// does not act in it (as `Simulation.step(actuation=…)` with `lock`).
    #[getter]
    fn brakes(&self, py: Python<'_>) -> Py<PyArray2<bool>> {
        self.brakes.clone_ref(py)
    }

    /// The switchable shapes given at construction (shape indices, `scene.shapes`).
    #[getter]
    fn switch_shapes(&self) -> Vec<usize> {
        self.batch
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .switches()
            .to_vec()
    }

    /// Whether each copy's switchable shapes are to be active, (n, len(switch_shapes))
    /// bool, written by the caller and read before each step: a shape whose flag differs
    /// from its state is switched at the start of the copy's next step, which then takes
    /// the switch in place of the scene's controller (as `Simulation.step(actuation=…)`).
    #[getter]
    fn switches(&self, py: Python<'_>) -> Py<PyArray2<bool>> {
        self.switches.clone_ref(py)
    }

    /// Whether the world carried a normal percussion in each copy's last step: (n,).
    #[getter]
    fn in_contact(&self, py: Python<'_>) -> Py<PyArray1<bool>> {
        self.in_contact.clone_ref(py)
    }

    /// Whether each copy is done (a step failed: `error(i)`); a done copy does not step
    /// until `reset(i)` or `set_state(i, …)`: (n,).
    #[getter]
    fn done(&self, py: Python<'_>) -> Py<PyArray1<bool>> {
        self.done.clone_ref(py)
    }

    /// Per copy and shape (`shape_names`): whether the shape carried a normal percussion in
    /// the copy's last step, (n, n_shapes), filled in place.
    #[getter]
    fn shape_in_contact(&self, py: Python<'_>) -> Py<PyArray2<bool>> {
        self.shape_in_contact.clone_ref(py)
    }

    /// Per copy and shape: the shape's normal and tangential contact forces over the copy's
    /// last step, N (as `Simulation.shape_contact_forces`), (n, n_shapes, 2), filled in
    /// place.
    #[getter]
    fn shape_contact_forces(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.shape_contact_forces.clone_ref(py)
    }

    /// The message of the error that stopped copy `i`, or None.
    fn error(&self, i: usize) -> PyResult<Option<String>> {
        let batch = self.batch.lock().unwrap_or_else(|e| e.into_inner());
        if i >= batch.len() {
            return Err(batch_error(BatchError::NoSuchCopy {
                copy: i,
                copies: batch.len(),
            }));
        }
        Ok(batch.error(i).map(|e| e.to_string()))
    }

    /// Copy `i` anew at the scene's initial state (its controller, shapes and controls
    /// too), not done; every copy without `i`.
    #[pyo3(signature = (i = None))]
    fn reset(&mut self, py: Python<'_>, i: Option<usize>) -> PyResult<()> {
        let batch = self.batch();
        guard(py, "Batch.reset", || match i {
            Some(i) => batch.reset(i).map_err(batch_error),
            None => batch.reset_all().map_err(batch_error),
        })?;
        self.publish(py);
        Ok(())
    }

    /// Restarts copy `i` at `q`, `u` and time `t` (default: the copy's time), checked as
    /// `Simulation.set_state` checks (`ValueError`); with `restore=True` only the values
    /// are checked (a state a run reached, contacts and stops slightly penetrated). A done
    /// copy is reset first.
    #[pyo3(signature = (i, q, u, t = None, restore = false))]
    fn set_state(
        &mut self,
        py: Python<'_>,
        i: usize,
        q: PyArrayLike1<'_, f64, AllowTypeChange>,
        u: PyArrayLike1<'_, f64, AllowTypeChange>,
        t: Option<f64>,
        restore: bool,
    ) -> PyResult<()> {
        let (q, u) = (q.as_array(), u.as_array());
        let batch = self.batch();
        let t = match t {
            Some(t) => t,
            None => *batch.t().get(i).ok_or_else(|| {
                batch_error(BatchError::NoSuchCopy {
                    copy: i,
                    copies: batch.len(),
                })
            })?,
        };
        let state = State {
            t,
            q: DVector::from_iterator(q.len(), q.iter().copied()),
            u: DVector::from_iterator(u.len(), u.iter().copied()),
        };
        guard(py, "Batch.set_state", || {
            match restore {
                true => batch.restore_state(i, state),
                false => batch.set_state(i, state),
            }
            .map_err(batch_error)
        })?;
        self.publish(py);
        Ok(())
    }

    /// Starts recording copy `i` at its current state, as `Simulation._record_open`
    /// records a simulation; its energy account is switched on while it is recorded (the
    /// states do not depend on it). `hopsim.Batch.record` wraps it as a `Recorder`.
    #[pyo3(signature = (i, outputs, record_rate = None, speed = "1".to_string()))]
    fn _record_open(
        &mut self,
        py: Python<'_>,
        i: usize,
        outputs: Vec<String>,
        record_rate: Option<f64>,
        speed: String,
    ) -> PyResult<()> {
        let batch = self.batch.get_mut().unwrap_or_else(|e| e.into_inner());
        let sim = batch.simulation(i).ok_or_else(|| {
            batch_error(BatchError::NoSuchCopy {
                copy: i,
                copies: batch.len(),
            })
        })?;
        if self.recordings[i].is_some() {
            return Err(PyRuntimeError::new_err(format!(
                "record: copy {i} is already being recorded; close that recording first"
            )));
        }
        let scene = self.copies[i].clone();
        let watch = guard(py, "Batch.record", || {
            Watch::new(sim, &scene, &outputs, record_rate, &speed)
        })?;
        let shared = SharedWatch(Arc::new(Mutex::new(watch)));
        guard(py, "Batch.record", || {
            batch
                .observe(i, Box::new(shared.clone()))
                .map_err(batch_error)
        })?;
        self.recordings[i] = Some(shared);
        Ok(())
    }

    /// Completes copy `i`'s recording and returns the run summary of the span recorded
    /// (JSON), as `Simulation._record_close`.
    fn _record_close(&mut self, py: Python<'_>, i: usize) -> PyResult<Closed> {
        let watch = self.take_recording(i)?;
        let batch = self.batch.get_mut().unwrap_or_else(|e| e.into_inner());
        let sim = batch.simulation(i).ok_or_else(|| not_recorded(i))?;
        guard(py, "Recorder.close", || watch.close(py, sim))
    }

    /// Ends copy `i`'s recording without completing it, as `Simulation._record_abort`.
    fn _record_abort(&mut self, py: Python<'_>, i: usize, reason: &str) -> PyResult<Vec<PathBuf>> {
        let watch = self.take_recording(i)?;
        guard(py, "Recorder.abort", || watch.abort(reason))
    }

    fn __repr__(&self) -> String {
        let batch = self.batch.lock().unwrap_or_else(|e| e.into_inner());
        format!(
            "Batch({} copies of '{}', {} threads)",
            batch.len(),
            self.scene.title,
            batch.threads()
        )
    }
}
