//! `hopsim.Scene` and `hopsim.SceneError`: a validated scene file, shared by the
//! simulations and sweeps made from it.

use crate::errors::{self, guard, Class};
use crate::names::{part_names, Part};
use hopsim_control::{ControllerConfig, Release};
use hopsim_scene::{Location, Override};
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The option named in errors about an override given from Python.
pub const OVERRIDE_FLAG: &str = "overrides";

/// The Python exception of a scene error (`hopsim.SceneError`), with its place as
/// attributes.
pub fn scene_error(py: Python<'_>, error: &hopsim_scene::SceneError) -> PyErr {
    let err = errors::error(py, Class::Scene, error.to_string());
    let (mut file, mut line, mut column, mut over) = (None, None, None, None);
    match (error, error.location()) {
        (
            _,
            Some(Location::File {
                path,
                line: l,
                column: c,
            }),
        ) => {
            file = Some(path.display().to_string());
            (line, column) = (Some(*l), Some(*c));
        }
        (_, Some(Location::Override(text))) => over = Some(text.clone()),
        (hopsim_scene::SceneError::Io { path, .. }, None) => {
            file = Some(path.display().to_string())
        }
        (hopsim_scene::SceneError::Override { text, .. }, None) => over = Some(text.clone()),
        _ => {}
    }
    let message = match error {
        hopsim_scene::SceneError::Io { source, .. } => source.to_string(),
        hopsim_scene::SceneError::Syntax { message, .. }
        | hopsim_scene::SceneError::Invalid { message, .. }
        | hopsim_scene::SceneError::Override { message, .. } => message.clone(),
        hopsim_scene::SceneError::Import(message) => message.clone(),
    };
    let value = err.value(py);
    // Setting an attribute on a fresh exception instance does not fail.
    let _ = value.setattr("file", file);
    let _ = value.setattr("line", line);
    let _ = value.setattr("column", column);
    let _ = value.setattr("key", error.key());
    let _ = value.setattr("override", over);
    let _ = value.setattr("message", message);
    err
}

/// A Python value as the TOML text of an override: numbers, booleans, strings (TOML as
/// typed on the command line: a bare word is a string) and lists of these.
fn toml_value(key: &str, value: &Bound<'_, PyAny>, nested: bool) -> PyResult<String> {
    if value.is_instance_of::<PyBool>() {
        return Ok(value.extract::<bool>()?.to_string());
    }
    if value.is_instance_of::<PyString>() {
        let s: String = value.extract()?;
        return Ok(if nested { format!("{s:?}") } else { s });
    }
    if !value.is_instance_of::<PyFloat>() {
        if let Ok(i) = value.extract::<i64>() {
            return Ok(i.to_string());
        }
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(match x {
            x if x.is_nan() => "nan".into(),
            x if x.is_infinite() => (if x > 0.0 { "inf" } else { "-inf" }).into(),
            x => format!("{x:?}"),
        });
    }
    if let Ok(items) = value.try_iter() {
        let items = items
            .map(|item| toml_value(key, &item?, true))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(format!("[{}]", items.join(", ")));
    }
    Err(PyTypeError::new_err(format!(
        "override {key}: expected a number, bool, string or list, got {}",
        value.get_type().name()?
    )))
}

/// A TOML value as Python's: tables as dicts, arrays as lists, date-times as their text.
fn python_value<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(python_value(py, item)?)?;
            }
            list.into_any()
        }
        toml::Value::Table(table) => {
            let dict = PyDict::new(py);
            for (key, item) in table {
                dict.set_item(key, python_value(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// `{key: value}` as scene overrides (`key` a dotted path such as `controller.torque`).
pub fn overrides_from(dict: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<Override>> {
    let Some(dict) = dict else {
        return Ok(Vec::new());
    };
    dict.iter()
        .map(|(k, v)| {
            let key: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err("override keys must be strings"))?;
            let value = toml_value(&key, &v, false)?;
            Ok(Override::from_flag(OVERRIDE_FLAG, key, value))
        })
        .collect()
}

/// A validated scene: robot, world, controller and run settings, read from a TOML scene
/// file (docs/scene-format.md) with overrides applied. Immutable; `with_overrides` makes
/// a new one. Picklable (as its text, path and overrides), so it can be sent to Dask
/// workers.
#[pyclass(name = "Scene", module = "hopsim", frozen)]
pub struct PyScene {
    pub scene: Arc<hopsim_scene::Scene>,
}

impl PyScene {
    fn parse(py: Python<'_>, text: &str, path: &Path, overrides: &[Override]) -> PyResult<Self> {
        let scene = guard(py, "Scene", || {
            py.detach(|| hopsim_scene::parse(text, path, overrides))
                .map_err(|e| scene_error(py, &e))
        })?;
        Ok(Self {
            scene: Arc::new(scene),
        })
    }
}

#[pymethods]
impl PyScene {
    /// Reads the scene file at `path` with `overrides` (`{"controller.torque": 0.2}`)
    /// applied; a MuJoCo model (`.xml`) is imported as its scene, its coordinates MuJoCo's
    /// `qpos` (docs/mjcf.md). Raises `SceneError` (with file, line, column and key) when it
    /// is invalid.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = None))]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        overrides: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let overrides = overrides_from(overrides)?;
        let scene = guard(py, "Scene.load", || {
            py.detach(|| hopsim_scene::load(&path, &overrides))
                .map_err(|e| scene_error(py, &e))
        })?;
        Ok(Self {
            scene: Arc::new(scene),
        })
    }

    /// A scene from TOML `text`; `path` names it in errors (and relative paths in it are
    /// not used: scenes are self-contained).
    #[staticmethod]
    #[pyo3(signature = (text, overrides = None, path = "<string>"))]
    fn from_toml(
        py: Python<'_>,
        text: &str,
        overrides: Option<&Bound<'_, PyDict>>,
        path: &str,
    ) -> PyResult<Self> {
        let overrides = overrides_from(overrides)?;
        Self::parse(py, text, Path::new(path), &overrides)
    }

    /// This scene with more `overrides` applied on top of its own.
    fn with_overrides(&self, py: Python<'_>, overrides: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut all = self.scene.overrides.clone();
        all.extend(overrides_from(Some(overrides))?);
        Self::parse(py, &self.scene.text, &self.scene.path, &all)
    }

    /// Rebuilds a pickled scene.
    #[staticmethod]
    fn _restore(
        py: Python<'_>,
        text: &str,
        path: PathBuf,
        overrides: Vec<(String, String)>,
    ) -> PyResult<Self> {
        let overrides: Vec<Override> = overrides
            .into_iter()
            .map(|(k, v)| Override::from_flag(OVERRIDE_FLAG, k, v))
            .collect();
        Self::parse(py, text, &path, &overrides)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let restore = py.get_type::<PyScene>().getattr("_restore")?;
        let s = &self.scene;
        let overrides: Vec<(String, String)> = s
            .overrides
            .iter()
            .map(|o| (o.key.clone(), o.value.clone()))
            .collect();
        let args = (s.text.clone(), s.path.clone(), overrides).into_pyobject(py)?;
        PyTuple::new(py, [restore, args.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, path={:?}, {} coordinates)",
            self.scene.title,
            self.scene.path.display().to_string(),
            self.scene.coordinates.len()
        )
    }

    /// The scene file's path.
    #[getter]
    fn path(&self) -> String {
        self.scene.path.display().to_string()
    }

    /// `meta.title` (or the file's stem).
    #[getter]
    fn title(&self) -> &str {
        &self.scene.title
    }

    /// The scene file's text as read (overrides not applied).
    #[getter]
    fn text(&self) -> &str {
        &self.scene.text
    }

    /// The overrides applied, `{key: value as TOML text}`.
    #[getter]
    fn overrides<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for o in &self.scene.overrides {
            d.set_item(&o.key, &o.value)?;
        }
        Ok(d)
    }

    /// What the scene's source leaves out or expresses otherwise (an imported MuJoCo
    /// model's unmodelled parts), one sentence each.
    #[getter]
    fn notices(&self) -> Vec<String> {
        self.scene.notices.clone()
    }

    /// Names of the generalised coordinates, e.g. `["x", "y", "phi", "psi"]`.
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.scene.coordinates.clone()
    }

    /// The bodies: `index`, `name`, `mass` (kg), `inertia` (kg m², about the centre of
    /// mass) and `parent` (the parent body's index, None for the floating base).
    #[getter]
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (i, b) in self.scene.model.bodies().iter().enumerate() {
            let d = PyDict::new(py);
            d.set_item("index", i)?;
            d.set_item("name", &b.name)?;
            d.set_item("mass", b.mass)?;
            d.set_item("inertia", b.inertia)?;
            d.set_item("parent", b.joint.as_ref().map(|j| j.parent))?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The index of the body called `name`.
    fn body_index(&self, name: &str) -> PyResult<usize> {
        let bodies = &self.scene.model.bodies();
        bodies.iter().position(|b| b.name == name).ok_or_else(|| {
            let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
            PyValueError::new_err(format!(
                "no body '{name}'; the bodies are {}",
                names.join(", ")
            ))
        })
    }

    /// Names of the contact shapes, in model order (the indices of `switch_shape`).
    #[getter]
    fn shapes(&self) -> Vec<String> {
        let shapes = &self.scene.model.shapes();
        shapes.iter().map(|s| s.name.clone()).collect()
    }

    /// The names of the scene's bodies, shapes, joints (named after the bodies they carry)
    /// or actuators (`part`: `"body"`, `"shape"`, `"joint"` or `"actuator"`), in index
    /// order: `Simulation.body_names` and its siblings.
    fn _part_names(&self, part: &str) -> PyResult<Vec<String>> {
        let part = match part {
            "body" => Part::Body,
            "shape" => Part::Shape,
            "joint" => Part::Joint,
            "actuator" => Part::Actuator,
            other => {
                return Err(PyValueError::new_err(format!(
                    "no part '{other}': body, shape, joint or actuator"
                )))
            }
        };
        Ok(part_names(&self.scene.model, part))
    }

    /// Names of the potential contacts (shape feature against terrain feature).
    #[getter]
    fn contacts(&self) -> Vec<String> {
        let contacts = &self.scene.model.contacts();
        contacts.iter().map(|c| c.name.clone()).collect()
    }

    /// `[simulation]` and `[summary]` settings: `duration` (s), `dt` (s), `gravity`
    /// (m/s²), `record_rate` (Hz), `speed_window` (s), `cube_restitution`, `strict`,
    /// `warm_start`, `max_speed` (m/s or rad/s), `max_steps` (the most steps of one run or
    /// call).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.scene.settings;
        let d = PyDict::new(py);
        d.set_item("duration", s.duration)?;
        d.set_item("dt", s.dt)?;
        d.set_item("gravity", s.gravity)?;
        d.set_item("record_rate", s.record_rate)?;
        d.set_item("speed_window", s.speed_window)?;
        d.set_item("cube_restitution", s.cube_restitution)?;
        d.set_item("strict", s.strict)?;
        d.set_item("warm_start", s.warm_start)?;
        d.set_item("max_speed", s.max_speed)?;
        d.set_item("max_steps", s.max_steps)?;
        Ok(d)
    }

    /// Step size `Δt`, s.
    #[getter]
    fn dt(&self) -> f64 {
        self.scene.settings.dt
    }

    /// Simulated time of a run, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.scene.settings.duration
    }

    /// The controller's settings: `type` (`"passive"`, `"momentum_impulse"` or
    /// `"pulse"`) and its parameters in SI units (body and shape indices).
    #[getter]
    fn controller<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match &self.scene.controller {
            ControllerConfig::Passive => d.set_item("type", "passive")?,
            ControllerConfig::MomentumImpulse(c) => {
                d.set_item("type", "momentum_impulse")?;
                d.set_item("flywheel", c.flywheel)?;
                d.set_item("torque", c.torque)?;
                d.set_item("impulse_limit", c.impulse_limit)?;
                match c.release {
                    Release::Touchdown { rearm_timeout } => {
                        d.set_item("release", "touchdown")?;
                        d.set_item("rearm_timeout", rearm_timeout)?;
                    }
                    Release::OffTime { off_time } => {
                        d.set_item("release", "off_time")?;
                        d.set_item("off_time", off_time)?;
                    }
                }
                d.set_item("hold_brake", c.hold_brake)?;
            }
            ControllerConfig::Pulse(c) => {
                d.set_item("type", "pulse")?;
                d.set_item("joint_body", c.joint_body)?;
                let key = if c.drives_force(&self.scene.model) {
                    "force"
                } else {
                    "torque"
                };
                d.set_item(key, c.torque)?;
                d.set_item("pulse_duration", c.pulse_duration)?;
                d.set_item("period", c.period)?;
                d.set_item("cane_shape", c.cane_shape)?;
                d.set_item("cane", c.cane.to_string())?;
            }
        }
        Ok(d)
    }

    /// This scene as a `hopsim.Model` (a new one at each access): its document with its
    /// overrides applied, and its title; change it in code and build it with
    /// `Model.scene()`.
    #[getter]
    fn model<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let s = &self.scene;
        let document = guard(py, "Scene.model", || {
            hopsim_scene::document(&s.text, &s.path, &s.overrides).map_err(|e| scene_error(py, &e))
        })?;
        let document = python_value(py, &toml::Value::Table(document))?;
        py.import("hopsim._model")?
            .getattr("Model")?
            .call_method1("_from_document", (document, &s.title))
    }

    /// Initial generalised coordinates `q` (a new array).
    #[getter]
    fn initial_q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.scene.initial.q.as_slice())
    }

    /// Initial generalised velocities `u` (a new array).
    #[getter]
    fn initial_u<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.scene.initial.u.as_slice())
    }
}
