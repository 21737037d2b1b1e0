//! Loop joints: bilateral constraints that close kinematic loops between bodies of the
//! trees (docs/physics.md §8). Each is a few scalar equations `φ(q) = 0`, its *rows*, with
//! their gradients `∂φ/∂q`; the stepper holds them on velocity level in every step and
//! projects the end state back onto `φ = 0`.

use crate::{perp, Kinematics, Model, ModelError, Vec2};

/// What a loop joint holds (docs/physics.md §8.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LoopKind {
    /// A revolute closure: the two points coincide (two rows, `p_A − p_B = 0`).
    Revolute,
    /// A massless rod: the points stay `length` apart (one row, `|p_A − p_B| − L = 0`).
    Distance {
        /// Rod length `L`, m (> 0).
        length: f64,
    },
    /// A weld: the points coincide and the relative angle stays `angle` (three rows,
    /// `p_A − p_B = 0`, `θ_A − θ_B − angle = 0`).
    Weld {
        /// `θ_A − θ_B` held, rad (`θ_B = 0` for the world).
        angle: f64,
    },
    /// A slot: point A stays on the line through point B along `axis` (in B's frame, or the
    /// world's): one row, `n · (p_A − p_B) = 0` with `n` the line's normal.
    Slot {
        /// The line's direction in B's frame (non-zero; normalised when built).
        axis: Vec2,
    },
}

impl LoopKind {
    /// The number of scalar equations (rows) of this kind.
    pub fn rows(&self) -> usize {
        match self {
            LoopKind::Revolute => 2,
            LoopKind::Distance { .. } | LoopKind::Slot { .. } => 1,
            LoopKind::Weld { .. } => 3,
        }
    }

    /// The kind's name in messages and scene files.
    pub fn as_str(&self) -> &'static str {
        match self {
            LoopKind::Revolute => "revolute",
            LoopKind::Distance { .. } => "distance",
            LoopKind::Weld { .. } => "weld",
            LoopKind::Slot { .. } => "slot",
        }
    }
}

/// A loop joint between a point of body `body_a` and a point of body `body_b` or of the
/// world (docs/physics.md §8.1).
#[derive(Clone, Debug, PartialEq)]
pub struct LoopJoint {
    /// Name in records and messages.
    pub name: String,
    /// The first body.
    pub body_a: usize,
    /// The point on A in A's frame, relative to its centre of mass, m.
    pub point_a: Vec2,
    /// The second body, `None` for the world.
    pub body_b: Option<usize>,
    /// The point on B in B's frame relative to its centre of mass (world coordinates for
    /// the world), m.
    pub point_b: Vec2,
    /// What the joint holds.
    pub kind: LoopKind,
}

/// Checks loop joint `joint` against a model with `count` bodies, of which those `fixed`
/// have no coordinate; returns it with a slot's axis normalised.
pub(crate) fn check_loop(
    mut joint: LoopJoint,
    count: usize,
    fixed: impl Fn(usize) -> bool,
) -> Result<LoopJoint, ModelError> {
    let bad = |reason: &str| ModelError::BadLoop {
        name: joint.name.clone(),
        reason: reason.to_string(),
    };
    for body in std::iter::once(joint.body_a).chain(joint.body_b) {
        if body >= count {
            return Err(ModelError::UnknownBody {
                owner: "loop",
                name: joint.name.clone(),
                body,
                count,
            });
        }
    }
    if joint.body_b == Some(joint.body_a) {
        return Err(bad("body_a and body_b are the same body"));
    }
    if fixed(joint.body_a) && joint.body_b.is_none_or(&fixed) {
        return Err(bad(
            "it joins nothing that moves (fixed bodies or the world)",
        ));
    }
    let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
    if !finite(joint.point_a) || !finite(joint.point_b) {
        return Err(bad("its points must be finite"));
    }
    match &mut joint.kind {
        LoopKind::Revolute => {}
        LoopKind::Distance { length } => {
            if !(length.is_finite() && *length > 0.0) {
                return Err(bad(&format!(
                    "a distance constraint's length must be positive and finite, got {length}"
                )));
            }
        }
        LoopKind::Weld { angle } => {
            if !angle.is_finite() {
                return Err(bad("a weld's angle must be finite"));
            }
        }
        LoopKind::Slot { axis } => {
            let norm = axis.norm();
            if !(norm.is_finite() && norm > 0.0) {
                return Err(bad("a slot's axis must be a non-zero finite vector"));
            }
            *axis /= norm;
        }
    }
    Ok(joint)
}

/// A loop joint's end on one side, evaluated: the body (if any), the world offset of the
/// point from its centre of mass, and the point's world position.
struct End {
    body: Option<usize>,
    offset: Vec2,
    position: Vec2,
}

impl Model {
    /// The loop joints (docs/physics.md §8), in the order they were added.
    #[inline]
    pub fn loops(&self) -> &[LoopJoint] {
        &self.loops
    }

    /// The number of loop rows, summed over the loop joints (0: a tree model).
    #[inline]
    pub fn loop_row_count(&self) -> usize {
        self.loop_rows
    }

    /// The loop joint that owns loop row `row`.
    pub fn loop_of_row(&self, mut row: usize) -> usize {
        for (j, joint) in self.loops.iter().enumerate() {
            let rows = joint.kind.rows();
            if row < rows {
                return j;
            }
            row -= rows;
        }
        self.loops.len().saturating_sub(1)
    }

    fn loop_end(&self, kinematics: &Kinematics, body: Option<usize>, point: Vec2) -> End {
        match body {
            Some(b) => {
                let offset = kinematics.rotation(b).apply(point);
                End {
                    body,
                    offset,
                    position: kinematics.position(b) + offset,
                }
            }
            None => End {
                body,
                offset: Vec2::zeros(),
                position: point,
            },
        }
    }

    /// The residuals `φ(q)` of every loop row at `kinematics` into `phi` (length
    /// [`Model::loop_row_count`]): m, or rad for a weld's angle row (docs/physics.md §8.1).
    pub fn loop_residuals_to(&self, kinematics: &Kinematics, phi: &mut [f64]) {
        let mut r = 0;
        for joint in &self.loops {
            let a = self.loop_end(kinematics, Some(joint.body_a), joint.point_a);
            let b = self.loop_end(kinematics, joint.body_b, joint.point_b);
            let d = a.position - b.position;
            match joint.kind {
                LoopKind::Revolute => phi[r..r + 2].copy_from_slice(&[d.x, d.y]),
                LoopKind::Distance { length } => phi[r] = d.norm() - length,
                LoopKind::Weld { angle } => {
                    let turn = self.loop_angle(kinematics, joint) - angle;
                    phi[r..r + 3].copy_from_slice(&[d.x, d.y, turn]);
                }
                LoopKind::Slot { axis } => {
                    phi[r] = self.slot_normal(kinematics, joint, axis).dot(&d)
                }
            }
            r += joint.kind.rows();
        }
    }

    /// The gradients `∂φ/∂q` of every loop row at `kinematics` into `rows` (row-major,
    /// [`Model::loop_row_count`] rows of length `n`): the relative velocity of the two
    /// material points along the row's direction (docs/physics.md §8.1).
    pub fn loop_rows_to(&self, kinematics: &Kinematics, rows: &mut [f64]) {
        let n = self.dof();
        let mut r = 0;
        for joint in &self.loops {
            let a = self.loop_end(kinematics, Some(joint.body_a), joint.point_a);
            let b = self.loop_end(kinematics, joint.body_b, joint.point_b);
            let d = a.position - b.position;
            let mut point_row = |r: usize, direction: Vec2, b_offset: Vec2| {
                let row = &mut rows[r * n..(r + 1) * n];
                row.fill(0.0);
                kinematics.add_point_force_to(joint.body_a, a.offset, direction, row);
                if let Some(body) = b.body {
                    kinematics.add_point_force_to(body, b_offset, -direction, row);
                }
            };
            match joint.kind {
                LoopKind::Revolute | LoopKind::Weld { .. } => {
                    point_row(r, Vec2::x(), b.offset);
                    point_row(r + 1, Vec2::y(), b.offset);
                }
                LoopKind::Distance { .. } => {
                    let length = d.norm();
                    let e = if length > 0.0 {
                        d / length
                    } else {
                        Vec2::zeros()
                    };
                    point_row(r, e, b.offset);
                }
                LoopKind::Slot { axis } => {
                    // The material point of B under A's point: `φ̇ = n · (v_A − v_B(p_A))`.
                    let normal = self.slot_normal(kinematics, joint, axis);
                    point_row(r, normal, b.offset + d);
                }
            }
            if let LoopKind::Weld { .. } = joint.kind {
                let row = &mut rows[(r + 2) * n..(r + 3) * n];
                row.fill(0.0);
                kinematics.add_torque_to(joint.body_a, joint.body_b, 1.0, row);
            }
            r += joint.kind.rows();
        }
    }

    /// The largest loop error `max |φ|` at `kinematics` (m, or rad for a weld's angle),
    /// with the residuals left in the first [`Model::loop_row_count`] entries of `phi`; 0
    /// without loops.
    pub fn loop_error(&self, kinematics: &Kinematics, phi: &mut [f64]) -> f64 {
        self.loop_residuals_to(kinematics, phi);
        phi[..self.loop_rows]
            .iter()
            .fold(0.0, |m: f64, v| m.max(v.abs()))
    }

    /// `θ_A − θ_B` of `joint` (`θ_B = 0` for the world).
    fn loop_angle(&self, kinematics: &Kinematics, joint: &LoopJoint) -> f64 {
        kinematics.angle(joint.body_a) - joint.body_b.map_or(0.0, |b| kinematics.angle(b))
    }

    /// The world normal of a slot's line: its axis turned with B and by +90°.
    fn slot_normal(&self, kinematics: &Kinematics, joint: &LoopJoint, axis: Vec2) -> Vec2 {
        perp(match joint.body_b {
            Some(b) => kinematics.rotation(b).apply(axis),
            None => axis,
        })
    }
}
