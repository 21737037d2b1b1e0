//! The exceptions of the package and the panic boundary of every binding.
//!
//! `hopsim.HopsimError` (an `Exception`) is the base of them all: `SceneError` is also a
//! `ValueError`, `SimulationError` also a `RuntimeError`, and `InternalError` is a bug: a
//! panic in Rust, caught where Python called in ([`guard`]) instead of escaping as
//! `pyo3_runtime.PanicException`, which `except Exception` does not catch.

use hopsim_sim::panic_message;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

/// The exception classes of the package.
#[derive(Clone, Copy)]
pub enum Class {
    Hopsim,
    Scene,
    Simulation,
    Internal,
}

impl Class {
    pub const ALL: [Class; 4] = [
        Class::Hopsim,
        Class::Scene,
        Class::Simulation,
        Class::Internal,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Class::Hopsim => "HopsimError",
            Class::Scene => "SceneError",
            Class::Simulation => "SimulationError",
            Class::Internal => "InternalError",
        }
    }

    fn doc(self) -> &'static str {
        match self {
            Class::Hopsim => "The base of every exception hopsim raises.",
            Class::Scene => {
                "An invalid scene: unreadable file, TOML syntax error, or a key missing, of \
                 the wrong type or out of range. Attributes: `file`, `line`, `column` \
                 (1-based), `key` (dotted path), `override` (the override that set the value) \
                 and `message`; those that do not apply are None."
            }
            Class::Simulation => {
                "A simulation stopped: a non-finite or runaway state, or (in strict mode) a \
                 contact LCP without a certified solution. A stopped `Simulation.run` \
                 carries the frames up to the stop as `trajectory`."
            }
            Class::Internal => {
                "A bug in hopsim (a panic in its Rust code), caught where Python called in. \
                 Attributes: `step` and `t` (s) of the step that failed, or None; \
                 `message`. Please report it with the scene file and the code that raised it."
            }
        }
    }

    /// The class's Python bases: the package's base, and the built-in one it refines.
    fn bases<'py>(self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
        let base = || class(py, Class::Hopsim);
        match self {
            Class::Hopsim => PyTuple::new(py, [py.get_type::<PyException>()]),
            Class::Scene => PyTuple::new(py, [base()?, py.get_type::<PyValueError>()]),
            Class::Simulation => PyTuple::new(py, [base()?, py.get_type::<PyRuntimeError>()]),
            Class::Internal => PyTuple::new(py, [base()?]),
        }
    }
}

static CLASSES: [PyOnceLock<Py<PyType>>; 4] = [
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
];

/// The Python class of `which`, made on first use as `type(name, bases, namespace)` (the
/// classes with two bases cannot be declared with `create_exception!`).
pub fn class(py: Python<'_>, which: Class) -> PyResult<Bound<'_, PyType>> {
    CLASSES[which as usize]
        .get_or_try_init(py, || {
            let namespace = PyDict::new(py);
            namespace.set_item("__module__", "hopsim")?;
            namespace.set_item("__doc__", which.doc())?;
            let made =
                py.get_type::<PyType>()
                    .call1((which.name(), which.bases(py)?, namespace))?;
            Ok::<_, PyErr>(made.cast_into::<PyType>()?.unbind())
        })
        .map(|class| class.bind(py).clone())
}

/// An exception of class `which` with `message`.
pub fn error(py: Python<'_>, which: Class, message: String) -> PyErr {
    match class(py, which) {
        Ok(class) => PyErr::from_type(class, message),
        Err(e) => e,
    }
}

/// `hopsim.InternalError` for a panic in `what` (`Simulation.step`, `lcp.solve`, …) with
/// its `message`, and the step and time where known.
pub fn internal_error(py: Python<'_>, what: &str, at: Option<(u64, f64)>, message: &str) -> PyErr {
    let place = match at {
        Some((step, t)) => format!("step {step} (t = {t:.6} s) of {what}"),
        None => what.to_string(),
    };
    let err = error(
        py,
        Class::Internal,
        format!(
            "internal error in {place}: {message}. This is a bug in hopsim; please report \
             it with the scene file and the code that raised it"
        ),
    );
    let value = err.value(py);
    // Setting an attribute on a fresh exception instance does not fail.
    let _ = value.setattr("step", at.map(|a| a.0));
    let _ = value.setattr("t", at.map(|a| a.1));
    let _ = value.setattr("message", message);
    err
}

/// Runs the Rust code of binding `what` (its Python name): a panic inside it (a bug) is
/// raised as `hopsim.InternalError`, never as a `PanicException`.
pub fn guard<T>(py: Python<'_>, what: &str, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    let run = || {
        test_hook(what);
        f()
    };
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)) {
        Ok(result) => result,
        Err(payload) => Err(internal_error(
            py,
            what,
            None,
            &panic_message(payload.as_ref()),
        )),
    }
}

/// Environment variable of the test hook (cargo feature `test-hooks`): the binding it names
/// (`lcp.solve`, `read_mcap`, …) panics on purpose.
#[cfg(feature = "test-hooks")]
pub const PANIC_IN: &str = "HOPSIM_PANIC_IN";

/// With the cargo feature `test-hooks`, panics when [`PANIC_IN`] names `what`; without it,
/// nothing.
#[cfg(feature = "test-hooks")]
pub fn test_hook(what: &str) {
    if std::env::var(PANIC_IN).is_ok_and(|v| v == what) {
        panic!("forced by {PANIC_IN}={what} (a test hook)");
    }
}

#[cfg(not(feature = "test-hooks"))]
#[inline(always)]
pub fn test_hook(_what: &str) {}
