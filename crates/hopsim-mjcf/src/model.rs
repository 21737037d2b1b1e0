//! The planar model read from an MJCF file: plain data, in the plane's coordinates.
//!
//! **Frames.** The plane of motion has the unit normal `n` and the in-plane axes `e1`, `e2`
//! (world vectors, [`Plane`]); a world point `w` has the planar coordinates `(w·e1, w·e2)`.
//! Every body's frame is its MuJoCo body frame's origin, turned to the plane's axes in the
//! model's reference configuration (MuJoCo's `qpos0`, every joint at its `ref`): all bodies
//! have the angle 0 there, and a vector in a body's frame is a planar world vector at
//! reference. Angles are counter-clockwise about `n`.
//!
//! **Coordinates.** Joints are listed in MuJoCo's order, and joint `k`'s coordinate is
//! MuJoCo's `qpos[joints[k].qpos]` itself (radians or metres, `ref` included). The joint
//! moves its body by the displacement `s = sign · (qpos − reference)`: a counter-clockwise
//! turn by `s` about the joint's anchor (hinge), or a translation by `s` along its axis
//! (slide, `sign` = 1). The joints of one body act in their order, as in MuJoCo's
//! kinematics: each turns or moves the body as the joints before it left it.

use nalgebra::{Vector2, Vector3};

use crate::error::Notice;

pub type Vec2 = Vector2<f64>;

/// The plane of motion, found from the joints (docs/mjcf.md).
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    /// Unit normal: every hinge axis is `±n`, every slide axis is perpendicular to it.
    pub normal: Vector3<f64>,
    /// The planar `x` axis (MuJoCo's world `x` in its x–z and x–y planes).
    pub e1: Vector3<f64>,
    /// The planar `y` axis, "up": MuJoCo's world `z` in the plane, if it lies in it.
    pub e2: Vector3<f64>,
}

impl Plane {
    /// The planar coordinates of the world vector `w`.
    pub fn project(&self, w: &Vector3<f64>) -> Vec2 {
        Vec2::new(w.dot(&self.e1), w.dot(&self.e2))
    }

    /// The planar coordinates `(x, y)` of the plane's vector as a world vector.
    pub fn lift(&self, p: &Vec2) -> Vector3<f64> {
        self.e1 * p.x + self.e2 * p.y
    }
}

/// The whole model.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarModel {
    /// `<mujoco model="…">`.
    pub name: String,
    pub plane: Plane,
    pub options: Options,
    /// Moving bodies, parents before children (MuJoCo's order); bodies without joints are
    /// welded into their parent ([`Body::parts`]); those welded to the world are [`Self::world`].
    pub bodies: Vec<Body>,
    /// The MJCF bodies fixed to the world (MuJoCo's world body and its jointless subtrees).
    pub world: Vec<Part>,
    /// In MuJoCo's order: joint `k` is the coordinate `k`.
    pub joints: Vec<Joint>,
    /// Every geom, of the bodies and of the world.
    pub geoms: Vec<Geom>,
    pub actuators: Vec<Actuator>,
    /// `<connect>` and `<weld>` equalities: loop closures between bodies (or a body and
    /// the world).
    pub equalities: Vec<crate::Equality>,
    /// What was read and left without effect, with the reason.
    pub notices: Vec<Notice>,
}

/// `<option>` and its flags, as they bear on a planar model.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Δt in s.
    pub timestep: f64,
    /// Gravity in the plane (m/s²), zero when gravity is disabled.
    pub gravity: Vec2,
    /// Gravity's component along the normal: no effect on planar motion.
    pub gravity_normal: f64,
    /// Contacts on (`contact` and `constraint` flags).
    pub contact: bool,
    /// Joint stops on (`limit` and `constraint` flags).
    pub limits: bool,
    /// Joint friction on (`frictionloss` and `constraint` flags).
    pub frictionloss: bool,
    /// Joint springs on (`spring` flag).
    pub springs: bool,
    /// Joint damping on (`damper` flag).
    pub dampers: bool,
    /// Actuator forces on (`actuation` flag).
    pub actuation: bool,
    /// Controls clamped to `ctrlrange` (`clampctrl` flag).
    pub clamp_controls: bool,
    /// A body's geoms do not collide with its parent's (`filterparent` flag).
    pub filter_parent: bool,
}

/// A moving body: one MJCF body with joints and the jointless bodies welded into it.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The MJCF body's name (MuJoCo's `body_N` when it has none).
    pub name: String,
    /// The parent body, `None` for the world.
    pub parent: Option<usize>,
    /// Its joints, in order (indices into [`PlanarModel::joints`]).
    pub joints: Vec<usize>,
    /// The frame's origin at reference, in the world.
    pub origin: Vec2,
    /// The frame's origin's offset along the normal (out of the plane; no effect on motion).
    pub depth: f64,
    /// Mass (kg), centre of mass (body frame) and moment of inertia about it (kg m², about
    /// the normal), of all its parts.
    pub mass: f64,
    pub com: Vec2,
    pub inertia: f64,
    /// The MJCF bodies it is made of: itself first, then those welded into it.
    pub parts: Vec<Part>,
}

/// One MJCF body's own mass properties, in the frame of the body it belongs to.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    pub name: String,
    pub mass: f64,
    pub com: Vec2,
    /// About its own centre of mass and the normal.
    pub inertia: f64,
}

/// A hinge or slide joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
    /// The body it moves.
    pub body: usize,
    /// MuJoCo's `qpos` (and `qvel`) index of this joint's coordinate.
    pub qpos: usize,
    /// `±1`: MuJoCo's hinge axis is `sign · n`; 1 for slides.
    pub sign: f64,
    /// The pivot of a hinge (body frame); the point on the axis for a slide.
    pub anchor: Vec2,
    /// `ref` (qpos units): the coordinate's value in the reference configuration.
    pub reference: f64,
    /// `springref` (qpos units): the spring's rest value.
    pub spring_reference: f64,
    /// N m/rad or N/m; the spring acts as `−stiffness (qpos − spring_reference)`.
    pub stiffness: f64,
    /// N m s/rad or N s/m.
    pub damping: f64,
    /// Added to the coordinate's diagonal of the mass matrix (kg m² or kg).
    pub armature: f64,
    /// Dry friction's bound on the joint force (N m or N).
    pub frictionloss: f64,
    /// The limits on the coordinate (qpos units), when limited.
    pub range: Option<[f64; 2]>,
    /// Bounds on the actuators' summed force at this joint, when limited.
    pub actuator_force_range: Option<[f64; 2]>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    Hinge,
    /// A slide along the unit axis (body frame).
    Slide {
        axis: Vec2,
    },
}

/// A geom as a planar shape, with its contact properties.
#[derive(Debug, Clone, PartialEq)]
pub struct Geom {
    /// The MJCF name, if any.
    pub name: Option<String>,
    /// The moving body it belongs to (in that body's frame), or `None` for the world (in
    /// world coordinates).
    pub body: Option<usize>,
    /// The MJCF body that holds it (differs from the body's name when welded).
    pub mjcf_body: String,
    pub shape: Shape,
    /// Its centre's offset along the normal (out of the plane).
    pub depth: f64,
    /// Its own mass (kg), part of its body's.
    pub mass: f64,
    pub contype: u32,
    pub conaffinity: u32,
    /// 1: frictionless, 3: sliding friction, 4: also torsional friction, which has no
    /// effect in the plane (docs/mjcf.md).
    pub condim: u32,
    pub priority: i32,
    /// MuJoCo's `friction`: sliding, torsional, rolling.
    pub friction: [f64; 3],
    /// Newton's coefficient of restitution; MJCF has none, so 0 (docs/mjcf.md).
    pub restitution: f64,
    pub rgba: [f64; 4],
}

/// What a geom is in the plane: its section through the plane, or its projection onto it
/// (they agree for the shapes accepted).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A MuJoCo plane: the line through `point` whose side away from `normal` is solid.
    Line {
        point: Vec2,
        normal: Vec2,
    },
    Circle {
        center: Vec2,
        radius: f64,
    },
    /// The points within `radius` of the segment `a`–`b`.
    Capsule {
        a: Vec2,
        b: Vec2,
        radius: f64,
    },
    /// Convex, counter-clockwise.
    Polygon {
        vertices: Vec<Vec2>,
    },
    /// Semi-axes along `(cos angle, sin angle)` and perpendicular to it.
    Ellipse {
        center: Vec2,
        semi_axes: [f64; 2],
        angle: f64,
    },
}

/// A motor or servo on one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Actuator {
    pub name: Option<String>,
    pub joint: usize,
    pub kind: ActuatorKind,
    /// The generalised force on the joint's coordinate is `gear · force`, and the servos
    /// see the length `gear · qpos` and velocity `gear · qvel`.
    pub gear: f64,
    /// Control bounds, when limited.
    pub ctrl_range: Option<[f64; 2]>,
    /// Force bounds, when limited.
    pub force_range: Option<[f64; 2]>,
}

/// MuJoCo's actuator shortcuts: the force from the control `u`, length `l` and velocity `v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActuatorKind {
    /// `force = u`.
    Motor,
    /// `force = kp (u − l) − kv v`.
    Position { kp: f64, kv: f64 },
    /// `force = kv (u − v)`.
    Velocity { kv: f64 },
}
