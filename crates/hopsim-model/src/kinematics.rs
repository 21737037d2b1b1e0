//! Forward kinematics of the body tree: poses, Jacobians and velocity-product
//! accelerations of every body, evaluated into reused buffers (docs/physics.md §1).
//!
//! One pass over the bodies (parents before children) computes everything; each body's
//! rotation `(sin θ, cos θ)` is evaluated once and only for bodies whose geometry needs it.
//! What the model's structure decides (which bodies need a rotation, the Jacobian's
//! sparsity and constancy) is the model's (`crate::structure`); a `Kinematics` holds
//! per-state data only.

use crate::structure::is_zero;
use crate::{perp, JointCoordinate, JointKind, Model, Vec2};
use nalgebra::{DVector, DVectorViewMut};

/// A planar rotation by `θ`, kept as `(sin θ, cos θ)` so one `sin_cos` serves every use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rotation {
    pub sin: f64,
    pub cos: f64,
}

impl Rotation {
    /// The rotation by `theta` ([`crate::sin_cos`]).
    #[inline]
    pub fn new(theta: f64) -> Self {
        let (sin, cos) = crate::trig::sin_cos(theta);
        Self { sin, cos }
    }

    /// `R(θ) v`.
    #[inline]
    pub fn apply(self, v: Vec2) -> Vec2 {
        Vec2::new(
            self.cos * v.x - self.sin * v.y,
            self.sin * v.x + self.cos * v.y,
        )
    }

    /// `R(θ)ᵀ v = R(-θ) v`.
    #[inline]
    pub fn inverse(self, v: Vec2) -> Vec2 {
        Vec2::new(
            self.cos * v.x + self.sin * v.y,
            -self.sin * v.x + self.cos * v.y,
        )
    }
}

/// What [`Kinematics`] keeps of one body, in one record (one bounds check per body).
#[derive(Clone, Copy, Debug)]
struct BodyFrame {
    /// Centre-of-mass position, world frame, m.
    position: Vec2,
    /// Absolute angle, rad.
    angle: f64,
    /// Absolute angular velocity, rad/s.
    angular_velocity: f64,
    /// Centre-of-mass velocity, m/s.
    velocity: Vec2,
    /// The body's rotation; NaN for bodies whose geometry never needs it.
    rotation: Rotation,
    /// `J̇_b u` of the body's centre of mass (centripetal terms), m/s².
    bias: Vec2,
    /// Joint position and velocity (see [`Kinematics::joint_position`]).
    joint_position: f64,
    joint_rate: f64,
}

/// The kinematics of a [`Model`] at one `(q, u)`: poses, velocities, Jacobians and
/// velocity-product accelerations of every body, in buffers allocated once per model.
///
/// After [`Kinematics::update`] every field and method describes that `(q, u)`.
#[derive(Clone, Debug)]
pub struct Kinematics {
    /// Number of generalised coordinates `n`.
    dof: usize,
    /// Pose, velocity, rotation, bias and joint state of each body.
    frames: Vec<BodyFrame>,
    /// Row-major `3B × n`: rows `3b, 3b+1, 3b+2` hold `∂(x_b, y_b, θ_b)/∂q` of body `b`;
    /// entries outside the model's pattern stay zero.
    jacobian: Vec<f64>,
    /// The Jacobian rows have been written once (a constant Jacobian is not rewritten).
    jacobian_written: bool,
    /// Three zero rows of length `n`: the world's Jacobian.
    zero_rows: Vec<f64>,
}

impl Kinematics {
    /// Buffers sized for `model`.
    pub fn new(model: &Model) -> Self {
        let frame = BodyFrame {
            position: Vec2::zeros(),
            angle: 0.0,
            angular_velocity: 0.0,
            velocity: Vec2::zeros(),
            rotation: Rotation {
                sin: f64::NAN,
                cos: f64::NAN,
            },
            bias: Vec2::zeros(),
            joint_position: 0.0,
            joint_rate: 0.0,
        };
        let (nb, n) = (model.bodies().len(), model.dof());
        Self {
            dof: n,
            frames: vec![frame; nb],
            jacobian: vec![0.0; 3 * nb * n],
            jacobian_written: false,
            zero_rows: vec![0.0; 3 * n],
        }
    }

    /// Evaluates poses, Jacobians, velocities and bias accelerations at `(q, u)`.
    pub fn update(&mut self, model: &Model, q: &DVector<f64>, u: &DVector<f64>) {
        self.update_slices(model, q.as_slice(), u.as_slice());
    }

    /// [`Kinematics::update`] on plain slices.
    ///
    /// # Panics
    /// If `q` or `u` does not have [`Model::dof`] entries (the stepper checks the state
    /// first and returns an error instead).
    pub fn update_slices(&mut self, model: &Model, q: &[f64], u: &[f64]) {
        let n = self.dof;
        assert!(q.len() == n && u.len() == n, "q and u need {n} entries");
        // Entries outside the sparsity pattern are never written: they stay zero. A
        // constant Jacobian is written once.
        let structure = &model.structure;
        let jacobian_constant = structure.jacobian_constant;
        let write_jacobian = !(jacobian_constant && self.jacobian_written);
        self.jacobian_written = true;
        for ((b, body), constants) in model.bodies().iter().enumerate().zip(&structure.bodies) {
            let coord = model.first_coordinate[b];
            let Some(joint) = body.joint.as_ref() else {
                // A floating base: (x, y, φ) are its own coordinates.
                let frame = &mut self.frames[b];
                frame.position = Vec2::new(q[coord], q[coord + 1]);
                frame.angle = q[coord + 2];
                if constants.needs_rotation {
                    frame.rotation = Rotation::new(q[coord + 2]);
                }
                frame.bias = Vec2::zeros();
                frame.velocity = Vec2::new(u[coord], u[coord + 1]);
                frame.angular_velocity = u[coord + 2];
                if write_jacobian {
                    for k in 0..3 {
                        self.jacobian[(3 * b + k) * n + coord + k] = 1.0;
                    }
                }
                continue;
            };
            // The parent's pose and motion; the world's is the identity at rest.
            let (p_position, p_angle, wp, p_rotation, p_bias, p_velocity) = match joint.parent {
                Some(p) => {
                    let parent = &self.frames[p];
                    (
                        parent.position,
                        parent.angle,
                        parent.angular_velocity,
                        parent.rotation,
                        parent.bias,
                        parent.velocity,
                    )
                }
                None => (
                    Vec2::zeros(),
                    0.0,
                    0.0,
                    Rotation { sin: 0.0, cos: 1.0 },
                    Vec2::zeros(),
                    Vec2::zeros(),
                ),
            };
            match joint.kind {
                JointKind::Revolute => {
                    let (angle, rate) = match joint.coordinate {
                        JointCoordinate::Absolute => (q[coord], u[coord]),
                        JointCoordinate::Relative => (p_angle + q[coord], wp + u[coord]),
                        JointCoordinate::Clockwise => (p_angle - q[coord], wp - u[coord]),
                    };
                    let frame = &mut self.frames[b];
                    (frame.joint_position, frame.joint_rate) = match joint.coordinate {
                        JointCoordinate::Absolute => (q[coord] - p_angle, u[coord] - wp),
                        JointCoordinate::Relative | JointCoordinate::Clockwise => {
                            (q[coord], u[coord])
                        }
                    };
                    if constants.needs_rotation {
                        frame.rotation = Rotation::new(angle);
                    }
                    let centred = constants.centred;
                    let (r_pivot, r_com) = if centred {
                        (Vec2::zeros(), Vec2::zeros())
                    } else {
                        (
                            rotated(p_rotation, joint.pivot_in_parent),
                            rotated(frame.rotation, joint.com_in_child),
                        )
                    };
                    // J̇_b u: the centripetal accelerations of the pivot and of the CoM about it
                    // (with a constant Jacobian `J̇ = 0`: the bias keeps its zeros).
                    if !jacobian_constant {
                        frame.bias = p_bias - r_pivot * (wp * wp) - r_com * (rate * rate);
                    }
                    frame.angle = angle;
                    frame.angular_velocity = rate;
                    let (lp, lc) = (perp(r_pivot), perp(r_com));
                    if centred {
                        // Pivoting at the parent's centre of mass, which is its own.
                        frame.position = p_position;
                        frame.velocity = p_velocity;
                    } else {
                        frame.position = p_position + r_pivot + r_com;
                        frame.velocity = p_velocity + lp * wp + lc * rate;
                    }
                    if !write_jacobian {
                        continue;
                    }
                    let (parent, bx, by, bt) = self.rows_of(b, joint.parent);
                    let (px, py, pt) = parent;
                    match joint.coordinate {
                        // Only entry `coord` of an absolute angle's row is in its pattern.
                        JointCoordinate::Absolute => bt[coord] = 1.0,
                        JointCoordinate::Relative => {
                            bt.copy_from_slice(pt);
                            bt[coord] += 1.0;
                        }
                        JointCoordinate::Clockwise => {
                            bt.copy_from_slice(pt);
                            bt[coord] -= 1.0;
                        }
                    }
                    let bt = &*bt;
                    for ((bx, by), ((px, py), (pt, bt))) in bx
                        .iter_mut()
                        .zip(by.iter_mut())
                        .zip(px.iter().zip(py).zip(pt.iter().zip(bt)))
                    {
                        *bx = px + lp.x * pt + lc.x * bt;
                        *by = py + lp.y * pt + lc.y * bt;
                    }
                }
                JointKind::Prismatic { axis } => {
                    // No relative rotation; the pivot slides to `pivot + s axis` (§7).
                    let (s, rate_s) = (q[coord], u[coord]);
                    let frame = &mut self.frames[b];
                    (frame.joint_position, frame.joint_rate) = (s, rate_s);
                    if constants.needs_rotation {
                        frame.rotation = p_rotation;
                    }
                    frame.angle = p_angle;
                    frame.angular_velocity = wp;
                    let e = p_rotation.apply(axis);
                    let r = p_rotation.apply(joint.pivot_in_parent + axis * s)
                        + rotated(p_rotation, joint.com_in_child);
                    let lever = perp(r);
                    frame.position = p_position + r;
                    frame.velocity = p_velocity + lever * wp + e * rate_s;
                    // Centripetal and Coriolis accelerations: −ω² r + 2 ω ṡ perp(e) (zero with
                    // a constant Jacobian).
                    if !jacobian_constant {
                        frame.bias = p_bias - r * (wp * wp) + perp(e) * (2.0 * wp * rate_s);
                    }
                    if !write_jacobian {
                        continue;
                    }
                    let (parent, bx, by, bt) = self.rows_of(b, joint.parent);
                    let (px, py, pt) = parent;
                    bt.copy_from_slice(pt);
                    for ((bx, by), ((px, py), pt)) in bx
                        .iter_mut()
                        .zip(by.iter_mut())
                        .zip(px.iter().zip(py).zip(pt.iter()))
                    {
                        *bx = px + lever.x * pt;
                        *by = py + lever.y * pt;
                    }
                    bx[coord] += e.x;
                    by[coord] += e.y;
                }
                JointKind::Fixed { angle } => {
                    // Welded to the world: the Jacobian rows stay zero.
                    let rotation = Rotation::new(angle);
                    let frame = &mut self.frames[b];
                    frame.rotation = rotation;
                    frame.bias = Vec2::zeros();
                    (frame.joint_position, frame.joint_rate) = (0.0, 0.0);
                    frame.angle = angle;
                    frame.angular_velocity = 0.0;
                    frame.position = joint.pivot_in_parent + rotated(rotation, joint.com_in_child);
                    frame.velocity = Vec2::zeros();
                }
            }
        }
    }

    /// The parent's Jacobian rows `(x, y, θ)` (zero rows for the world) and body `b`'s
    /// rows, mutable (`parent < b`, so the parent's rows come first).
    #[allow(clippy::type_complexity)]
    #[inline]
    fn rows_of(
        &mut self,
        b: usize,
        parent: Option<usize>,
    ) -> ((&[f64], &[f64], &[f64]), &mut [f64], &mut [f64], &mut [f64]) {
        let n = self.dof;
        let (before, rest) = self.jacobian.split_at_mut(3 * b * n);
        let parent = match parent {
            Some(p) => &before[3 * p * n..3 * p * n + 3 * n],
            None => &self.zero_rows[..],
        };
        let (px, rest_p) = parent.split_at(n);
        let (py, pt) = rest_p.split_at(n);
        let (bx, rest_b) = rest[..3 * n].split_at_mut(n);
        let (by, bt) = rest_b.split_at_mut(n);
        ((px, py, pt), bx, by, bt)
    }

    /// Centre-of-mass position of body `b`, world frame, m.
    #[inline]
    pub fn position(&self, b: usize) -> Vec2 {
        self.frames[b].position
    }

    /// Absolute angle of body `b`, rad.
    #[inline]
    pub fn angle(&self, b: usize) -> f64 {
        self.frames[b].angle
    }

    /// Absolute angular velocity of body `b`, rad/s.
    #[inline]
    pub fn angular_velocity(&self, b: usize) -> f64 {
        self.frames[b].angular_velocity
    }

    /// Centre-of-mass velocity of body `b`, m/s.
    #[inline]
    pub fn velocity(&self, b: usize) -> Vec2 {
        self.frames[b].velocity
    }

    /// Number of bodies.
    #[inline]
    pub fn bodies(&self) -> usize {
        self.frames.len()
    }

    /// The joint position `s` of body `b` (rad or m): its angle relative to the parent (or
    /// the world), or its prismatic extension; 0 for a floating or fixed body.
    #[inline]
    pub fn joint_position(&self, b: usize) -> f64 {
        self.frames[b].joint_position
    }

    /// The joint velocity `ṡ` of body `b` (rad/s or m/s).
    #[inline]
    pub fn joint_rate(&self, b: usize) -> f64 {
        self.frames[b].joint_rate
    }

    /// Number of generalised coordinates.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Rotation of body `b` (only for bodies with geometry on them).
    #[inline]
    pub(crate) fn rotation(&self, b: usize) -> Rotation {
        self.frames[b].rotation
    }

    /// `J̇_b u` of body `b`'s centre of mass, m/s².
    #[inline]
    pub fn bias(&self, b: usize) -> Vec2 {
        self.frames[b].bias
    }

    /// Jacobian row `row` (`3b + k`: `∂x_b/∂q`, `∂y_b/∂q`, `∂θ_b/∂q` for `k` = 0, 1, 2).
    #[inline(always)]
    pub fn jacobian_row(&self, row: usize) -> &[f64] {
        &self.jacobian[row * self.dof..(row + 1) * self.dof]
    }

    /// The Jacobian rows `∂x_b/∂q`, `∂y_b/∂q`, `∂θ_b/∂q` of body `b`.
    #[inline(always)]
    pub fn jacobian_rows(&self, b: usize) -> (&[f64], &[f64], &[f64]) {
        let n = self.dof;
        let rows = &self.jacobian[3 * b * n..3 * b * n + 3 * n];
        let (x, rest) = rows.split_at(n);
        let (y, t) = rest.split_at(n);
        (x, y, t)
    }

    /// Adds `J_Pᵀ f` to `out` (length `n`), where `J_P` is the Jacobian of the material
    /// point of body `b` at world offset `r` from its centre of mass and `f` a world force.
    #[inline]
    pub fn add_point_force_to(&self, b: usize, r: Vec2, f: Vec2, out: &mut [f64]) {
        let torque = perp(r).dot(&f);
        let (x, y, t) = self.jacobian_rows(b);
        for (o, ((x, y), t)) in out.iter_mut().zip(x.iter().zip(y).zip(t)) {
            *o += x * f.x + y * f.y + t * torque;
        }
    }

    /// Writes `J_Pᵀ n` into `w_n` and `J_Pᵀ t` into `w_t` (length `n`) in one pass: the
    /// contact directions `w_N`, `w_T` of a contact frame `(n, t)` at the material point of
    /// body `b` at world offset `r` from its centre of mass (docs/physics.md §1, [2.5-2.7]).
    #[inline(always)]
    pub fn frame_directions_to(
        &self,
        b: usize,
        r: Vec2,
        (n, t): (Vec2, Vec2),
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) {
        let lever = perp(r);
        let (torque_n, torque_t) = (lever.dot(&n), lever.dot(&t));
        let (x, y, th) = self.jacobian_rows(b);
        for ((wn, wt), ((x, y), th)) in w_n.iter_mut().zip(w_t).zip(x.iter().zip(y).zip(th)) {
            *wn = x * n.x + y * n.y + th * torque_n;
            *wt = x * t.x + y * t.y + th * torque_t;
        }
    }

    /// Adds a torque `tau` on body `b` (and `-tau` on `reaction`, if any) to `out`.
    #[inline(always)]
    pub fn add_torque_to(&self, b: usize, reaction: Option<usize>, tau: f64, out: &mut [f64]) {
        let (_, _, t) = self.jacobian_rows(b);
        for (o, t) in out.iter_mut().zip(t) {
            *o += t * tau;
        }
        if let Some(r) = reaction {
            let (_, _, t) = self.jacobian_rows(r);
            for (o, t) in out.iter_mut().zip(t) {
                *o -= t * tau;
            }
        }
    }

    /// Adds `J_Pᵀ f` to `out`, see [`Kinematics::add_point_force_to`].
    pub fn add_point_force(&self, b: usize, r: Vec2, f: Vec2, out: &mut DVector<f64>) {
        self.add_point_force_to(b, r, f, out.as_mut_slice());
    }

    /// Writes `J_Pᵀ f` into `out` (the generalised direction of a point force, e.g. `w_N`).
    pub fn point_force_direction(
        &self,
        b: usize,
        r: Vec2,
        f: Vec2,
        mut out: DVectorViewMut<'_, f64>,
    ) {
        let torque = perp(r).dot(&f);
        let (x, y, t) = self.jacobian_rows(b);
        for (j, o) in out.iter_mut().enumerate() {
            *o = x[j] * f.x + y[j] * f.y + t[j] * torque;
        }
    }

    /// Adds a torque `tau` on body `b` (and `-tau` on `reaction`, if any) to `out`.
    pub fn add_torque(&self, b: usize, reaction: Option<usize>, tau: f64, out: &mut DVector<f64>) {
        self.add_torque_to(b, reaction, tau, out.as_mut_slice());
    }

    /// Velocity of the material point of body `b` at world offset `r` from its CoM.
    #[inline]
    pub fn point_velocity(&self, b: usize, r: Vec2) -> Vec2 {
        let frame = &self.frames[b];
        frame.velocity + perp(r) * frame.angular_velocity
    }
}

/// `R v`, skipping the (possibly NaN) rotation of a body without geometry when `v = 0`.
#[inline]
fn rotated(rotation: Rotation, v: Vec2) -> Vec2 {
    if is_zero(v) {
        Vec2::zeros()
    } else {
        rotation.apply(v)
    }
}
