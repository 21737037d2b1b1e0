//! Rigid bodies and the revolute joints that attach children to their parents.

use crate::Vec2;

/// How a child body's generalised coordinate measures its rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointCoordinate {
    /// The coordinate is the body's absolute angle (Robbit's flywheel angle `ψ`, §5.3).
    Absolute,
    /// The coordinate is the angle relative to the parent (a joint angle, §5.4).
    Relative,
}

/// A revolute joint attaching a child body to its parent.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Index of the parent body (smaller than the child's index).
    pub parent: usize,
    /// The pivot in the parent's body frame, relative to the parent's centre of mass, m.
    pub pivot_in_parent: Vec2,
    /// The child's centre of mass relative to the pivot, in the child's frame, m.
    pub com_in_child: Vec2,
    /// What the child's generalised coordinate measures.
    pub coordinate: JointCoordinate,
    /// Viscous damping in the joint, N m s/rad (torque `-c (θ̇_child - θ̇_parent)`).
    pub damping: f64,
}

/// A rigid body: mass, inertia about its centre of mass, and how it is attached.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name used in scenes, records and viewers.
    pub name: String,
    /// Mass, kg (> 0).
    pub mass: f64,
    /// Moment of inertia about the centre of mass, kg m² (> 0).
    pub inertia: f64,
    /// `None` for the floating base (body 0), the joint for every other body.
    pub joint: Option<Joint>,
}

impl Body {
    /// The floating base (body 0): a body without a joint.
    pub fn base(name: impl Into<String>, mass: f64, inertia: f64) -> Self {
        Self {
            name: name.into(),
            mass,
            inertia,
            joint: None,
        }
    }

    /// A flywheel on `parent`: an undamped joint at the parent's centre of mass, which is
    /// also the flywheel's own centre of mass, with an absolute-angle coordinate (Robbit's
    /// `ψ`, physics.md §5.3).
    pub fn flywheel(name: impl Into<String>, mass: f64, inertia: f64, parent: usize) -> Self {
        Self {
            name: name.into(),
            mass,
            inertia,
            joint: Some(Joint {
                parent,
                pivot_in_parent: Vec2::zeros(),
                com_in_child: Vec2::zeros(),
                coordinate: JointCoordinate::Absolute,
                damping: 0.0,
            }),
        }
    }
}
