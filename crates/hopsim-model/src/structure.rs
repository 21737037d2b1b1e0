//! What a model's structure decides once, when it is built (as MuJoCo's `mj_setConst`):
//! which bodies need their rotation, which pivot at their parent's centre of mass, the
//! sparsity of the Jacobian rows and whether they are constant, the generalised weight
//! then, and the contacts that take the circle-on-a-line shortcut. [`crate::Kinematics`]
//! reads them at every evaluation and keeps per-state data only.

use crate::contact::DiscOnLine;
use crate::{Joint, JointCoordinate, JointKind, Model, Vec2};

/// The constants of one body.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyConstants {
    /// Whether the body's rotation is needed (shapes, springs, offsets on it).
    pub needs_rotation: bool,
    /// Whether the body pivots at its parent's centre of mass, which is also its own (a
    /// revolute joint with zero pivot and centre-of-mass offsets, as Robbit's flywheel).
    pub centred: bool,
}

/// The per-model constants (see the module doc).
#[derive(Clone, Debug)]
pub(crate) struct Structure {
    pub bodies: Vec<BodyConstants>,
    /// Sorted columns of the structurally non-zero entries of Jacobian row `r`:
    /// `pattern[pattern_start[r]..pattern_start[r + 1]]` (a body depends on the base and
    /// its ancestors' joints only); every other entry stays zero.
    pub pattern: Vec<usize>,
    pub pattern_start: Vec<usize>,
    /// See [`Model::jacobian_is_constant`].
    pub jacobian_constant: bool,
    /// `Σ_b J_bᵀ m_b g` when the Jacobian is constant (see [`Model::constant_weight`]).
    pub constant_weight: Option<Vec<f64>>,
    /// The shortcut of each potential terrain contact that is a circle on a line without
    /// ends (see [`Model::contact_geometry`]).
    pub discs_on_lines: Vec<Option<DiscOnLine>>,
    /// The bodies whose joint coordinate carries an armature, with it (kg m² or kg): the
    /// mass matrix and the kinetic energy add `armature · rate²` for these only.
    pub armatures: Vec<(usize, f64)>,
    /// The bodies whose joint has dry friction, with its bound (N m or N; see
    /// [`Model::dry_frictions`]).
    pub dry_frictions: Vec<(usize, f64)>,
}

impl Structure {
    /// Nothing yet: the structure of a model still being built.
    pub fn empty() -> Self {
        Self {
            bodies: Vec::new(),
            pattern: Vec::new(),
            pattern_start: Vec::new(),
            jacobian_constant: false,
            constant_weight: None,
            discs_on_lines: Vec::new(),
            armatures: Vec::new(),
            dry_frictions: Vec::new(),
        }
    }

    /// The constants of `model`, whose structure field is not read (it is being built).
    pub fn of(model: &Model) -> Self {
        let bodies = model.bodies();
        let mut needs_rotation = vec![false; bodies.len()];
        for s in model.shapes() {
            needs_rotation[s.body] = true;
        }
        for s in model.springs() {
            needs_rotation[s.body_a] |= s.point_a != Vec2::zeros();
            needs_rotation[s.body_b] |= s.point_b != Vec2::zeros();
        }
        for l in model.loops() {
            needs_rotation[l.body_a] = true;
            if let Some(b) = l.body_b {
                needs_rotation[b] = true;
            }
        }
        for (b, body) in bodies.iter().enumerate() {
            if let Some(j) = &body.joint {
                needs_rotation[b] |= j.com_in_child != Vec2::zeros();
                let prismatic = matches!(j.kind, JointKind::Prismatic { .. });
                if let Some(p) = j.parent {
                    // A prismatic axis turns with the parent.
                    needs_rotation[p] |= j.pivot_in_parent != Vec2::zeros() || prismatic;
                }
            }
        }
        let bodies = bodies
            .iter()
            .zip(needs_rotation)
            .map(|(body, needs_rotation)| BodyConstants {
                needs_rotation,
                centred: body.joint.as_ref().is_some_and(|j| {
                    matches!(j.kind, JointKind::Revolute)
                        && is_zero(j.pivot_in_parent)
                        && is_zero(j.com_in_child)
                }),
            })
            .collect();
        let (pattern, pattern_start, jacobian_constant) = jacobian_pattern(model);
        Self {
            bodies,
            pattern,
            pattern_start,
            jacobian_constant,
            constant_weight: None,
            discs_on_lines: (0..model.contacts().len())
                .map(|i| DiscOnLine::new(model, i))
                .collect(),
            armatures: joints_with(model, |joint| joint.armature),
            dry_frictions: joints_with(model, |joint| joint.dry_friction),
        }
    }
}

/// The bodies whose moving joint has a non-zero `value`, with it.
fn joints_with(model: &Model, value: impl Fn(&Joint) -> f64) -> Vec<(usize, f64)> {
    model
        .bodies()
        .iter()
        .enumerate()
        .filter_map(|(b, body)| {
            let joint = body.joint.as_ref()?;
            let v = value(joint);
            (v != 0.0 && joint.has_coordinate()).then_some((b, v))
        })
        .collect()
}

/// The structural sparsity of the Jacobian rows (see [`Model::jacobian_pattern`]) and
/// whether every Jacobian is constant (see [`Model::jacobian_is_constant`]).
fn jacobian_pattern(model: &Model) -> (Vec<usize>, Vec<usize>, bool) {
    let bodies = model.bodies();
    let mut rows: Vec<Vec<usize>> = Vec::with_capacity(3 * bodies.len());
    let union = |a: &[usize], b: &[usize]| {
        let mut u: Vec<usize> = a.iter().chain(b).copied().collect();
        u.sort_unstable();
        u.dedup();
        u
    };
    let empty: [Vec<usize>; 3] = Default::default();
    // Whether body `b`'s Jacobian depends on `q`: through a lever arm turned by an angle
    // that depends on `q` (a non-empty angle row), its own or inherited from its parent.
    let mut varies = vec![false; bodies.len()];
    for (b, body) in bodies.iter().enumerate() {
        let coord = model.first_coordinate[b];
        let Some(joint) = body.joint.as_ref() else {
            rows.extend([vec![coord], vec![coord + 1], vec![coord + 2]]);
            continue;
        };
        let parent_varies = joint.parent.is_some_and(|p| varies[p]);
        let parent = |k: usize| match joint.parent {
            Some(p) => rows[3 * p + k].clone(),
            None => empty[k].clone(),
        };
        let (px, py, pt) = (parent(0), parent(1), parent(2));
        let (x, y, theta) = match joint.kind {
            JointKind::Revolute => {
                let theta = match joint.coordinate {
                    JointCoordinate::Absolute => vec![coord],
                    JointCoordinate::Relative | JointCoordinate::Clockwise => union(&pt, &[coord]),
                };
                let mut levers: Vec<usize> = Vec::new();
                if joint.pivot_in_parent != Vec2::zeros() {
                    levers = union(&levers, &pt);
                    varies[b] |= !pt.is_empty();
                }
                if joint.com_in_child != Vec2::zeros() {
                    levers = union(&levers, &theta);
                    varies[b] = true;
                }
                varies[b] |= parent_varies;
                (union(&px, &levers), union(&py, &levers), theta)
            }
            JointKind::Prismatic { .. } => {
                // The axis turns with the parent, and the lever of its rotation grows with s.
                varies[b] = parent_varies || !pt.is_empty();
                let levers = union(&pt, &[coord]);
                (union(&px, &levers), union(&py, &levers), pt)
            }
            JointKind::Fixed { .. } => (Vec::new(), Vec::new(), Vec::new()),
        };
        rows.extend([x, y, theta]);
    }
    let mut start = vec![0];
    let mut pattern = Vec::new();
    for row in rows {
        pattern.extend(row);
        start.push(pattern.len());
    }
    (pattern, start, !varies.contains(&true))
}

/// `v = 0`, compared by components.
#[inline(always)]
pub(crate) fn is_zero(v: Vec2) -> bool {
    v.x == 0.0 && v.y == 0.0
}
