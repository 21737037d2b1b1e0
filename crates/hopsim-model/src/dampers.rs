//! The model's linear dampers: joint dampers (`−c ṡ` in a joint, docs/physics.md §7.1) and
//! spring dampers (`−c L̇` along a spring, §5.4). Each is a coefficient `c` and a row `w`
//! of the velocities, its rate `wᵀ u`; together they are the damping matrix
//! `C = Σ c w wᵀ` with the force `−C u` (docs/physics.md §4.9: taken at the step's mean velocity).

use crate::forces::separation;
use crate::{JointCoordinate, JointKind, Kinematics, Model};

/// One damper of a model at one evaluation of its kinematics.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Damper {
    /// The damper in the joint of body `body`.
    Joint { body: usize, c: f64 },
    /// The damper of spring `spring`, with its ends' world offsets and the unit vector
    /// from the second end to the first.
    Spring {
        spring: usize,
        c: f64,
        ra: crate::Vec2,
        rb: crate::Vec2,
        dir: crate::Vec2,
    },
}

impl Damper {
    /// The coefficient `c` (N m s/rad or N s/m).
    pub fn coefficient(&self) -> f64 {
        match *self {
            Damper::Joint { c, .. } | Damper::Spring { c, .. } => c,
        }
    }

    /// The rate `wᵀ u` at the kinematics' velocities: the joint's rate, or the spring's `L̇`.
    pub fn rate(&self, model: &Model, kinematics: &Kinematics) -> f64 {
        match *self {
            Damper::Joint { body, .. } => {
                let joint = model.bodies()[body].joint.as_ref().expect("a jointed body");
                match (joint.kind, joint.parent) {
                    // The rate of a clockwise angle is the joint rate, `−(θ̇_child − θ̇_parent)`.
                    (JointKind::Revolute, Some(p))
                        if joint.coordinate != JointCoordinate::Clockwise =>
                    {
                        kinematics.angular_velocity(body) - kinematics.angular_velocity(p)
                    }
                    _ => kinematics.joint_rate(body),
                }
            }
            Damper::Spring {
                spring,
                ra,
                rb,
                dir,
                ..
            } => {
                let s = &model.springs()[spring];
                dir.dot(
                    &(kinematics.point_velocity(s.body_a, ra)
                        - kinematics.point_velocity(s.body_b, rb)),
                )
            }
        }
    }

    /// Adds `value · w` to `out` (length `n`): a generalised force `value` along the
    /// damper's rate.
    pub fn add_row_to(&self, model: &Model, kinematics: &Kinematics, value: f64, out: &mut [f64]) {
        match *self {
            Damper::Joint { body, .. } => model.add_joint_force_to(kinematics, body, value, out),
            Damper::Spring {
                spring,
                ra,
                rb,
                dir,
                ..
            } => {
                let s = &model.springs()[spring];
                kinematics.add_point_force_to(s.body_a, ra, value * dir, out);
                kinematics.add_point_force_to(s.body_b, rb, -value * dir, out);
            }
        }
    }
}

impl Model {
    /// The dampers acting at the kinematics' positions, in a fixed order: joints (body
    /// order), then springs (a slack tension-only spring's damper does not act).
    pub(crate) fn dampers<'a>(
        &'a self,
        kinematics: &'a Kinematics,
    ) -> impl Iterator<Item = Damper> + 'a {
        let joints = self.bodies().iter().enumerate().filter_map(|(body, b)| {
            let c = b.joint.as_ref()?.damping;
            (c != 0.0).then_some(Damper::Joint { body, c })
        });
        let springs = self
            .springs()
            .iter()
            .enumerate()
            .filter(|(_, s)| s.damping != 0.0)
            .filter_map(move |(spring, s)| {
                let (ra, rb) = self.spring_offsets(kinematics, s);
                let pa = kinematics.position(s.body_a) + ra;
                let pb = kinematics.position(s.body_b) + rb;
                let (dir, length) = separation(pa, pb);
                let slack = s.tension_only && length < s.rest_length;
                (!slack).then_some(Damper::Spring {
                    spring,
                    c: s.damping,
                    ra,
                    rb,
                    dir,
                })
            });
        joints.chain(springs)
    }

    /// The most dampers the model can have acting at once: every joint and spring with a
    /// damping coefficient.
    pub fn damper_capacity(&self) -> usize {
        let joints = self
            .bodies()
            .iter()
            .filter(|b| b.joint.as_ref().is_some_and(|j| j.damping != 0.0))
            .count();
        joints + self.springs().iter().filter(|s| s.damping != 0.0).count()
    }

    /// Whether the damping matrix `C` is the same at every state: no spring damper (whose
    /// row turns with the spring), so with a constant Jacobian `C` is constant too.
    pub fn damping_rows_follow_jacobian(&self) -> bool {
        self.springs().iter().all(|s| s.damping == 0.0)
    }

    /// The dampers acting at the kinematics' positions: their coefficients `c` into
    /// `coefficients` and rows `w` into `rows` (row-major, length `n` each); returns how
    /// many. Both slices must hold [`Model::damper_capacity`] dampers.
    pub fn damper_rows_to(
        &self,
        kinematics: &Kinematics,
        coefficients: &mut [f64],
        rows: &mut [f64],
    ) -> usize {
        let n = self.dof();
        let mut count = 0;
        for (d, damper) in self.dampers(kinematics).enumerate() {
            coefficients[d] = damper.coefficient();
            let row = &mut rows[d * n..(d + 1) * n];
            row.fill(0.0);
            damper.add_row_to(self, kinematics, 1.0, row);
            count = d + 1;
        }
        count
    }
}
