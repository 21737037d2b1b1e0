//! Bodies, shapes, joints and actuators addressed from Python by name or by index.

use hopsim_model::{JointKind, Model};
use pyo3::exceptions::{PyIndexError, PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyString;

/// What a name or index addresses.
#[derive(Clone, Copy)]
pub(crate) enum Part {
    Body,
    Shape,
    /// A joint, named after the body it carries (docs/scene-format.md).
    Joint,
    Actuator,
}

impl Part {
    fn noun(self) -> &'static str {
        match self {
            Part::Body => "body",
            Part::Shape => "shape",
            Part::Joint => "joint",
            Part::Actuator => "actuator",
        }
    }

    fn plural(self) -> &'static str {
        match self {
            Part::Body => "bodies",
            Part::Shape => "shapes",
            Part::Joint => "joints",
            Part::Actuator => "actuators",
        }
    }

    /// The names of `model`'s parts of this kind, with the index each name stands for
    /// (a joint's index is its body's).
    pub(crate) fn names(self, model: &Model) -> Vec<(String, usize)> {
        match self {
            Part::Body => enumerated(model.bodies().iter().map(|b| &b.name)),
            Part::Shape => enumerated(model.shapes().iter().map(|s| &s.name)),
            Part::Actuator => enumerated(model.actuators().iter().map(|a| &a.name)),
            Part::Joint => model
                .bodies()
                .iter()
                .enumerate()
                .filter(|(_, b)| {
                    b.joint
                        .as_ref()
                        .is_some_and(|j| !matches!(j.kind, JointKind::Fixed { .. }))
                })
                .map(|(i, b)| (b.name.clone(), i))
                .collect(),
        }
    }
}

/// The names of `model`'s parts of kind `part`, in index order.
pub(crate) fn part_names(model: &Model, part: Part) -> Vec<String> {
    part.names(model).into_iter().map(|(n, _)| n).collect()
}

fn enumerated<'a>(names: impl Iterator<Item = &'a String>) -> Vec<(String, usize)> {
    names.enumerate().map(|(i, n)| (n.clone(), i)).collect()
}

/// The index `key` stands for among `model`'s parts of kind `part`: a name (`str`), or an
/// index (`int`) into the model's bodies (for a joint: its body), shapes or actuators. An
/// unknown name is a `KeyError` listing the valid names, an index out of range an
/// `IndexError`, anything else a `TypeError`.
pub(crate) fn index(model: &Model, part: Part, key: &Bound<'_, PyAny>) -> PyResult<usize> {
    let names = part.names(model);
    let listed = || {
        let names: Vec<&str> = names.iter().map(|(n, _)| n.as_str()).collect();
        format!("the {} are {names:?}", part.plural())
    };
    if key.is_instance_of::<PyString>() {
        let name: String = key.extract()?;
        return names
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, i)| i)
            .ok_or_else(|| {
                PyKeyError::new_err(format!("no {} named '{name}'; {}", part.noun(), listed()))
            });
    }
    let Ok(i) = key.extract::<i64>() else {
        return Err(PyTypeError::new_err(format!(
            "expected a {}'s name (str) or index (int), got {}",
            part.noun(),
            key.get_type().name()?
        )));
    };
    let valid = usize::try_from(i)
        .ok()
        .filter(|&i| names.iter().any(|&(_, j)| j == i));
    valid.ok_or_else(|| {
        PyIndexError::new_err(format!("{} {i} does not exist; {}", part.noun(), listed()))
    })
}
