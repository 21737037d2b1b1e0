//! Planar multibody model in minimal (generalised) coordinates.
//!
//! A model is one or more trees of bodies (docs/physics.md §1, §7). A tree's root is a floating
//! base `(x, y, φ)`, pinned to a world point by a revolute joint, or fixed to the world;
//! its other bodies hang on revolute or prismatic joints, each with optional damping, a
//! joint spring and end stops (joint limits). It knows its mass matrix `M(q)`, the force vector `h(q, u, t)` and the
//! contact kinematics (gaps `g_N`, directions `w_N`, `w_T`) of every potential contact
//! between a body's contact shape and the terrain, or between shapes of two bodies. The
//! model is immutable once built;
//! [`Kinematics`] is the model evaluated at one state `(q, u)`, in buffers reused from one
//! evaluation to the next.

mod actuators;
mod body;
mod capsule;
mod contact;
mod dampers;
mod ellipse;
mod forces;
mod kinematics;
mod loops;
mod model;
mod pairs;
mod shape;
mod structure;
mod terrain;
mod trig;

pub use actuators::{Actuator, ActuatorForce, ActuatorKind};
pub use body::{Body, Joint, JointCoordinate, JointKind, JointLimits};
pub use contact::{ContactCandidate, ContactGeometry, ContactMaterial, ShapeFeature};
pub use forces::Spring;
pub use kinematics::Kinematics;
pub use loops::{LoopJoint, LoopKind};
pub use model::{Energies, LimitCandidate, Model, ModelBuilder, ModelError};
pub use pairs::{pair_features, PairCandidate, PairGeometry};
pub use shape::{Shape, ShapeInstance};
pub use terrain::{Terrain, TerrainFeature};
pub use trig::sin_cos;

/// A 2-vector in the world or a body frame, metres.
pub type Vec2 = nalgebra::Vector2<f64>;

/// Rotates a body-frame vector by the angle `theta` (counter-clockwise).
#[inline]
pub fn rotate(theta: f64, v: Vec2) -> Vec2 {
    kinematics::Rotation::new(theta).apply(v)
}

/// The vector `v` turned by +90°: `ω × v` for unit `ω` out of the plane.
#[inline]
pub fn perp(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}
