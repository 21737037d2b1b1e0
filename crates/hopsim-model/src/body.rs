//! Rigid bodies and the joints that attach them to a parent body or to the world
//! (docs/physics.md §1, §7).

use crate::Vec2;

/// How a revolute joint's generalised coordinate measures its rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointCoordinate {
    /// The coordinate is the body's absolute angle (Robbit's flywheel angle `ψ`, §5.3).
    Absolute,
    /// The coordinate is the angle relative to the parent (a joint angle, §5.4).
    Relative,
    /// The coordinate is the angle relative to the parent measured clockwise: the child
    /// turns by `−q` against its parent (MuJoCo's hinge whose axis points against the
    /// plane's normal, docs/mjcf.md). Springs, limits and joint forces act on `q` itself.
    Clockwise,
}

/// What a joint lets the child do relative to its parent (docs/physics.md §7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// Rotation about the pivot; one coordinate, an angle (rad).
    Revolute,
    /// Translation along `axis` (a unit vector fixed in the parent's frame), no relative
    /// rotation; one coordinate, the extension `s` (m): the pivot moves to
    /// `pivot_in_parent + s axis` in the parent's frame.
    Prismatic { axis: Vec2 },
    /// Welded to the world at angle `angle` (rad): no coordinate. Only a tree's root may be
    /// fixed (its parent is the world); the pivot is then its centre of mass in the world.
    Fixed { angle: f64 },
}

/// End stops `lower ≤ s ≤ upper` of a joint's position (rad or m), with their own
/// restitution: two unilateral frictionless rows of the contact LCP (docs/physics.md §7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Lower stop (may be `-∞`: none).
    pub lower: f64,
    /// Upper stop (may be `+∞`: none).
    pub upper: f64,
    /// Newton restitution `ε` of both stops, in [0, 1].
    pub restitution: f64,
}

/// A joint attaching a child body to its parent body, or to the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Index of the parent body (smaller than the child's index); `None`: the world (a
    /// pinned or fixed base, docs/physics.md §7).
    pub parent: Option<usize>,
    /// The pivot in the parent's body frame, relative to the parent's centre of mass (for
    /// the world: the pivot's world position), m.
    pub pivot_in_parent: Vec2,
    /// The child's centre of mass relative to the pivot, in the child's frame, m.
    pub com_in_child: Vec2,
    /// What a revolute joint's coordinate measures (prismatic and fixed joints: `Relative`).
    pub coordinate: JointCoordinate,
    /// Revolute, prismatic or fixed.
    pub kind: JointKind,
    /// Viscous damping in the joint: N m s/rad (torque `-c (θ̇_child - θ̇_parent)`) or, for a
    /// prismatic joint, N s/m (force `-c ṡ` along the axis).
    pub damping: f64,
    /// Joint spring: N m/rad or N/m, generalised force `-k (s - rest_position)` on the
    /// joint position `s` (the relative angle, or the extension).
    pub stiffness: f64,
    /// The joint spring's rest position, rad or m.
    pub rest_position: f64,
    /// End stops of the joint position, if any.
    pub limits: Option<JointLimits>,
    /// Armature (rotor inertia reflected through a gear): kg m² or kg, added to the
    /// mass matrix's diagonal at the joint's coordinate (MuJoCo's `armature`).
    pub armature: f64,
    /// Dry (Coulomb) friction in the joint: the largest torque (N m) or, for a prismatic
    /// joint, force (N) it transmits before slipping (MuJoCo's `frictionloss`); bounded
    /// rows of the step's LCP (docs/physics.md §7.5). 0: none.
    pub dry_friction: f64,
}

impl Joint {
    /// A revolute joint on `parent` with a relative coordinate, no damping, spring or
    /// limits.
    pub fn revolute(parent: Option<usize>, pivot_in_parent: Vec2, com_in_child: Vec2) -> Self {
        Self {
            parent,
            pivot_in_parent,
            com_in_child,
            coordinate: JointCoordinate::Relative,
            kind: JointKind::Revolute,
            damping: 0.0,
            stiffness: 0.0,
            rest_position: 0.0,
            limits: None,
            armature: 0.0,
            dry_friction: 0.0,
        }
    }

    /// Whether the joint adds a generalised coordinate (every kind but `Fixed`).
    pub fn has_coordinate(&self) -> bool {
        !matches!(self.kind, JointKind::Fixed { .. })
    }
}

/// A rigid body: mass, inertia about its centre of mass, and how it is attached.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name used in scenes, records and viewers.
    pub name: String,
    /// Mass, kg (> 0; ≥ 0 for a fixed base or a body with children, a massless link).
    pub mass: f64,
    /// Moment of inertia about the centre of mass, kg m² (> 0; ≥ 0 for a fixed base or a
    /// body with children).
    pub inertia: f64,
    /// `None` for a floating base `(x, y, φ)`, the joint for every other body.
    pub joint: Option<Joint>,
}

impl Body {
    /// A floating base: a body without a joint.
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
    /// `ψ`, docs/physics.md §5.3).
    pub fn flywheel(name: impl Into<String>, mass: f64, inertia: f64, parent: usize) -> Self {
        Self {
            name: name.into(),
            mass,
            inertia,
            joint: Some(Joint {
                coordinate: JointCoordinate::Absolute,
                ..Joint::revolute(Some(parent), Vec2::zeros(), Vec2::zeros())
            }),
        }
    }

    /// Whether the body is fixed to the world (a fixed base).
    pub fn is_fixed(&self) -> bool {
        self.joint
            .as_ref()
            .is_some_and(|j| matches!(j.kind, JointKind::Fixed { .. }))
    }

    /// Number of generalised coordinates the body adds: 3 for a floating base, 0 when
    /// fixed, else 1.
    pub fn coordinate_count(&self) -> usize {
        match &self.joint {
            None => 3,
            Some(j) if j.has_coordinate() => 1,
            Some(_) => 0,
        }
    }
}
