//! `hopsim.read_mcap`: a hopsim MCAP recording read back into arrays.

use crate::errors::guard;
use hopsim_record::McapRecording;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Reads the hopsim MCAP recording at `path` (bit for bit: the numbers are those the run
/// computed), the GIL released. Returns a dict: `metadata` (scene, dt, coordinates,
/// bodies, contacts, springs, hopsim version), `scene_text` (the scene file stored in the
/// recording, or None), `steps`, `t`, `q`, `u` (`/hopsim/state`, one row per recorded
/// frame), `impulses` (`step`, `t`, `channel`, `normal`, `tangent`: the contact
/// percussions and brake impulses), `events` (JSON text) and `stopped`: None for a
/// complete run; for a recording kept after the run stopped early (`FILE.partial.mcap`),
/// `reason`, `step` (the last step completed) and `t` (s, at its end). Raises `ValueError`
/// when the file cannot be read or is not a hopsim recording.
#[pyfunction]
pub fn read_mcap<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    guard(py, "read_mcap", || recording_dict(py, &path))
}

fn recording_dict<'py>(py: Python<'py>, path: &std::path::Path) -> PyResult<Bound<'py, PyDict>> {
    let recording = py
        .detach(|| McapRecording::read(path))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let m = &recording.metadata;
    let metadata = PyDict::new(py);
    metadata.set_item("scene", &m.scene)?;
    metadata.set_item("scene_path", &m.scene_path)?;
    metadata.set_item("scene_file", &m.scene_file)?;
    metadata.set_item("dt", m.dt)?;
    metadata.set_item("coordinates", m.coordinates.clone())?;
    metadata.set_item("bodies", m.bodies.clone())?;
    metadata.set_item("contacts", m.contacts.clone())?;
    metadata.set_item("springs", m.springs.clone())?;
    metadata.set_item("hopsim_version", &m.hopsim_version)?;
    let states = &recording.states;
    let (rows, n) = (states.len(), m.coordinates.len());
    let matrix = |values: Vec<f64>| PyArray1::from_vec(py, values).reshape([rows, n]);
    let q = states.iter().flat_map(|s| s.q.iter().copied()).collect();
    let u = states.iter().flat_map(|s| s.u.iter().copied()).collect();
    let samples = &recording.impulses.samples;
    let impulses = PyDict::new(py);
    let column = |f: fn(&hopsim_record::ImpulseSample) -> f64| {
        PyArray1::from_vec(py, samples.iter().map(f).collect())
    };
    impulses.set_item(
        "step",
        PyArray1::from_vec(py, samples.iter().map(|s| s.step).collect()),
    )?;
    impulses.set_item("t", column(|s| s.t))?;
    let channels: Vec<&str> = samples.iter().map(|s| s.channel.as_str()).collect();
    impulses.set_item("channel", channels)?;
    impulses.set_item("normal", column(|s| s.normal))?;
    impulses.set_item("tangent", column(|s| s.tangent))?;
    let d = PyDict::new(py);
    d.set_item("metadata", metadata)?;
    d.set_item(
        "scene_text",
        recording.scene.as_ref().map(|s| s.text.clone()),
    )?;
    d.set_item(
        "steps",
        PyArray1::from_vec(py, states.iter().map(|s| s.step).collect()),
    )?;
    d.set_item(
        "t",
        PyArray1::from_vec(py, states.iter().map(|s| s.t).collect()),
    )?;
    d.set_item("q", matrix(q)?)?;
    d.set_item("u", matrix(u)?)?;
    d.set_item("impulses", impulses)?;
    let events = serde_json::to_string(&recording.events)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("events", events)?;
    let stopped = match &recording.stop {
        None => None,
        Some(stop) => {
            let s = PyDict::new(py);
            s.set_item("reason", &stop.reason)?;
            s.set_item("step", stop.step)?;
            s.set_item("t", stop.t)?;
            Some(s)
        }
    };
    d.set_item("stopped", stopped)?;
    Ok(d)
}
