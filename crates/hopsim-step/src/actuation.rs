//! What a controller asks of one step: torques, impulses and velocity locks; and the
//! controls of the model's actuators, which hold from step to step.

use hopsim_model::{Model, Vec2};

/// A torque on a body, with the opposite torque on a reaction body (a motor between two
/// bodies) or on nothing (an external torque).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueCommand {
    /// Body that receives `+torque`.
    pub body: usize,
    /// Body that receives `-torque`, if any.
    pub reaction: Option<usize>,
    /// Torque, N m.
    pub torque: f64,
}

/// A generalised force in the joint of `body` (a joint motor, docs/physics.md §7): a torque on
/// `body` with its reaction on the parent (revolute, N m), or a force along the axis with
/// its reaction on the parent (prismatic, N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointForceCommand {
    /// The body on the joint.
    pub body: usize,
    /// Torque (N m) or force (N) along the joint's coordinate.
    pub force: f64,
}

/// An impulse applied within the step (docs/physics.md §3, [2.22]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ImpulseCommand {
    /// A translational impulse `ζ` (world frame, N s) at the material point of `body` at
    /// world offset `offset` from its centre of mass.
    Point {
        body: usize,
        offset: Vec2,
        impulse: Vec2,
    },
    /// A rotational impulse on `body` (and its opposite on `reaction`), N m s.
    Rotational {
        body: usize,
        reaction: Option<usize>,
        impulse: f64,
    },
}

/// The actuation of one step; cleared and refilled by the controller every step
/// (its buffers keep their capacity, so refilling does not allocate).
#[derive(Clone, Debug, Default)]
pub struct Actuation {
    /// Torques held over the step.
    pub torques: Vec<TorqueCommand>,
    /// Joint forces and torques held over the step.
    pub joint_forces: Vec<JointForceCommand>,
    /// Impulses applied inside the step.
    pub impulses: Vec<ImpulseCommand>,
    /// Bodies whose relative rotation is locked inelastically in this step (a brake):
    /// `(body, other)` enforces `θ̇_body = θ̇_other` at the end of the step.
    pub locks: Vec<(usize, usize)>,
    /// The control of each of the model's actuators (`Model::actuators`, docs/physics.md
    /// §7.4), held over the step; an actuator past the end gets control 0 (an empty vector:
    /// every control 0). Not a command: [`Actuation::clear`] keeps it.
    pub controls: Vec<f64>,
}

impl Actuation {
    /// Removes every command, keeping the buffers and the controls.
    pub fn clear(&mut self) {
        self.torques.clear();
        self.joint_forces.clear();
        self.impulses.clear();
        self.locks.clear();
    }
}

/// A command the model cannot carry out: it names a body or shape that does not exist, a joint
/// where there is none, or a lock of a body with itself; or its value is not finite.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ActuationError {
    #[error("{command} names body {body}; the model has {bodies} bodies")]
    NoSuchBody {
        command: &'static str,
        body: usize,
        bodies: usize,
    },
    #[error("{command} names shape {shape}; the model has {shapes} shapes")]
    NoSuchShape {
        command: &'static str,
        shape: usize,
        shapes: usize,
    },
    #[error("joint_force names body {0}, which has no joint")]
    NoJoint(usize),
    #[error("actuator {actuator} does not exist; the model has {actuators} actuators")]
    NoSuchActuator { actuator: usize, actuators: usize },
    #[error("{given} controls given; the model has {actuators} actuators")]
    ControlCount { given: usize, actuators: usize },
    #[error("control {index} (actuator '{name}') is {value}: not a finite number")]
    ControlNotFinite {
        index: usize,
        name: String,
        value: f64,
    },
    #[error("a lock needs two bodies; both are {0}")]
    SameBody(usize),
    #[error("{command} on body {body} is {value}: not a finite number")]
    NotFinite {
        command: &'static str,
        body: usize,
        value: f64,
    },
}

impl Actuation {
    /// Checks every command against `model` (see [`ActuationError`]); the stepper relies on
    /// this (an index out of range would be a panic).
    pub fn validate(&self, model: &Model) -> Result<(), ActuationError> {
        let body = |command, b| check_body(model, command, b);
        for t in &self.torques {
            body("torque", t.body)?;
            t.reaction.map_or(Ok(()), |r| body("torque", r))?;
            check_finite("torque", t.body, t.torque)?;
        }
        for f in &self.joint_forces {
            body("joint_force", f.body)?;
            if model.bodies()[f.body].joint.is_none() {
                return Err(ActuationError::NoJoint(f.body));
            }
            check_finite("joint_force", f.body, f.force)?;
        }
        for i in &self.impulses {
            match *i {
                ImpulseCommand::Point {
                    body: b,
                    offset,
                    impulse,
                } => {
                    body("impulse", b)?;
                    for v in [offset.x, offset.y, impulse.x, impulse.y] {
                        check_finite("impulse", b, v)?;
                    }
                }
                ImpulseCommand::Rotational {
                    body: b,
                    reaction,
                    impulse,
                } => {
                    body("impulse", b)?;
                    reaction.map_or(Ok(()), |r| body("impulse", r))?;
                    check_finite("impulse", b, impulse)?;
                }
            }
        }
        for &(b, other) in &self.locks {
            check_lock(model, "lock", b, other)?;
        }
        check_controls(model, &self.controls)
    }
}

/// `controls` are at most one finite number per actuator of `model`.
pub fn check_controls(model: &Model, controls: &[f64]) -> Result<(), ActuationError> {
    let actuators = model.actuators();
    if controls.len() > actuators.len() {
        return Err(ActuationError::ControlCount {
            given: controls.len(),
            actuators: actuators.len(),
        });
    }
    match controls.iter().position(|c| !c.is_finite()) {
        Some(index) => Err(ActuationError::ControlNotFinite {
            index,
            name: actuators[index].name.clone(),
            value: controls[index],
        }),
        None => Ok(()),
    }
}

/// `body` is one of `model`'s bodies.
fn check_body(model: &Model, command: &'static str, body: usize) -> Result<(), ActuationError> {
    let bodies = model.bodies().len();
    if body < bodies {
        Ok(())
    } else {
        Err(ActuationError::NoSuchBody {
            command,
            body,
            bodies,
        })
    }
}

fn check_finite(command: &'static str, body: usize, value: f64) -> Result<(), ActuationError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ActuationError::NotFinite {
            command,
            body,
            value,
        })
    }
}

/// A lock (or brake) `command` of `body` to `other`: two different bodies of `model`.
pub fn check_lock(
    model: &Model,
    command: &'static str,
    body: usize,
    other: usize,
) -> Result<(), ActuationError> {
    check_body(model, command, body)?;
    check_body(model, command, other)?;
    if body == other {
        return Err(ActuationError::SameBody(body));
    }
    Ok(())
}
