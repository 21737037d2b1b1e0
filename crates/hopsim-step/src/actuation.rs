//! What a controller asks of one step: torques, impulses and velocity locks.

use hopsim_model::Vec2;

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
}

impl Actuation {
    /// Removes every command, keeping the buffers.
    pub fn clear(&mut self) {
        self.torques.clear();
        self.joint_forces.clear();
        self.impulses.clear();
        self.locks.clear();
    }
}
