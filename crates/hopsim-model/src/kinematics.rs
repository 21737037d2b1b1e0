//! Forward kinematics of the body tree: poses, Jacobians and velocity-product
//! accelerations of every body, evaluated into reused buffers (physics.md §1).
//!
//! One pass over the bodies (parents before children) computes everything; each body's
//! rotation `(sin θ, cos θ)` is evaluated once and only for bodies whose geometry needs it.

use crate::{perp, JointCoordinate, Model, Vec2};
use nalgebra::{DVector, DVectorViewMut};

/// A planar rotation by `θ`, kept as `(sin θ, cos θ)` so one `sin_cos` serves every use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rotation {
    pub sin: f64,
    pub cos: f64,
}

impl Rotation {
    #[inline]
    pub fn new(theta: f64) -> Self {
        let (sin, cos) = theta.sin_cos();
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

/// The kinematics of a [`Model`] at one `(q, u)`: poses, velocities, Jacobians and
/// velocity-product accelerations of every body, in buffers allocated once per model.
///
/// After [`Kinematics::update`] every field and method describes that `(q, u)`.
#[derive(Clone, Debug)]
pub struct Kinematics {
    /// Centre-of-mass position of each body, world frame, m.
    pub position: Vec<Vec2>,
    /// Absolute angle of each body, rad.
    pub angle: Vec<f64>,
    /// Absolute angular velocity of each body, rad/s.
    pub angular_velocity: Vec<f64>,
    /// Centre-of-mass velocity of each body, m/s.
    pub velocity: Vec<Vec2>,
    /// Number of generalised coordinates `n`.
    dof: usize,
    /// Rotation of each body; NaN for bodies whose geometry never needs it.
    rotation: Vec<Rotation>,
    /// Whether body `b`'s rotation is needed (shapes, springs, offsets on it).
    needs_rotation: Vec<bool>,
    /// Row-major `3B × n`: rows `3b, 3b+1, 3b+2` hold `∂(x_b, y_b, θ_b)/∂q` of body `b`.
    jacobian: Vec<f64>,
    /// Sorted columns of the structurally non-zero entries of Jacobian row `r`:
    /// `pattern[pattern_start[r]..pattern_start[r + 1]]` (a body depends on the base and
    /// its ancestors' joints only); every other entry stays zero.
    pattern: Vec<usize>,
    pattern_start: Vec<usize>,
    /// `J̇_b u` of each body's centre of mass (centripetal terms), m/s².
    bias: Vec<Vec2>,
}

impl Kinematics {
    /// Buffers sized for `model`.
    pub fn new(model: &Model) -> Self {
        let nb = model.bodies.len();
        let mut needs_rotation = vec![false; nb];
        for s in &model.shapes {
            needs_rotation[s.body] = true;
        }
        for s in &model.springs {
            needs_rotation[s.body_a] |= s.point_a != Vec2::zeros();
            needs_rotation[s.body_b] |= s.point_b != Vec2::zeros();
        }
        for (b, body) in model.bodies.iter().enumerate() {
            if let Some(j) = &body.joint {
                needs_rotation[b] |= j.com_in_child != Vec2::zeros();
                needs_rotation[j.parent] |= j.pivot_in_parent != Vec2::zeros();
            }
        }
        let (pattern, pattern_start) = jacobian_pattern(model);
        let nan = Rotation {
            sin: f64::NAN,
            cos: f64::NAN,
        };
        Self {
            position: vec![Vec2::zeros(); nb],
            angle: vec![0.0; nb],
            angular_velocity: vec![0.0; nb],
            velocity: vec![Vec2::zeros(); nb],
            dof: model.dof(),
            rotation: vec![nan; nb],
            needs_rotation,
            jacobian: vec![0.0; 3 * nb * model.dof()],
            pattern,
            pattern_start,
            bias: vec![Vec2::zeros(); nb],
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
        // Entries outside the sparsity pattern are never written: they stay zero.
        self.position[0] = Vec2::new(q[0], q[1]);
        self.angle[0] = q[2];
        if self.needs_rotation[0] {
            self.rotation[0] = Rotation::new(q[2]);
        }
        self.velocity[0] = Vec2::new(u[0], u[1]);
        self.angular_velocity[0] = u[2];
        self.bias[0] = Vec2::zeros();
        for k in 0..3 {
            self.jacobian[k * n + k] = 1.0;
        }
        for (b, body) in model.bodies.iter().enumerate().skip(1) {
            let Some(joint) = body.joint.as_ref() else {
                unreachable!("Model::new checks that every body after the first has a joint")
            };
            let p = joint.parent;
            let coord = 2 + b;
            let (angle, rate) = match joint.coordinate {
                JointCoordinate::Absolute => (q[coord], u[coord]),
                JointCoordinate::Relative => (
                    self.angle[p] + q[coord],
                    self.angular_velocity[p] + u[coord],
                ),
            };
            self.angle[b] = angle;
            self.angular_velocity[b] = rate;
            if self.needs_rotation[b] {
                self.rotation[b] = Rotation::new(angle);
            }
            let r_pivot = rotated(self.rotation[p], joint.pivot_in_parent);
            let r_com = rotated(self.rotation[b], joint.com_in_child);
            let (lp, lc) = (perp(r_pivot), perp(r_com));
            let wp = self.angular_velocity[p];
            self.position[b] = self.position[p] + r_pivot + r_com;
            self.velocity[b] = self.velocity[p] + lp * wp + lc * rate;
            // J̇_b u: the centripetal accelerations of the pivot and of the CoM about it.
            self.bias[b] = self.bias[p] - r_pivot * (wp * wp) - r_com * (rate * rate);
            // Jacobian rows of b from those of its parent p (p < b, so p's rows come first).
            let (before, rest) = self.jacobian.split_at_mut(3 * b * n);
            let parent = &before[3 * p * n..3 * p * n + 3 * n];
            let (px, rest_p) = parent.split_at(n);
            let (py, pt) = rest_p.split_at(n);
            let (bx, rest_b) = rest[..3 * n].split_at_mut(n);
            let (by, bt) = rest_b.split_at_mut(n);
            match joint.coordinate {
                // Only entry `coord` of an absolute angle's row is in its pattern.
                JointCoordinate::Absolute => bt[coord] = 1.0,
                JointCoordinate::Relative => {
                    bt.copy_from_slice(pt);
                    bt[coord] += 1.0;
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
    }

    /// Number of generalised coordinates.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Rotation of body `b` (only for bodies with geometry on them).
    #[inline]
    pub(crate) fn rotation(&self, b: usize) -> Rotation {
        self.rotation[b]
    }

    /// `J̇_b u` of body `b`'s centre of mass, m/s².
    #[inline]
    pub fn bias(&self, b: usize) -> Vec2 {
        self.bias[b]
    }

    /// Jacobian row `row` (`3b + k`: `∂x_b/∂q`, `∂y_b/∂q`, `∂θ_b/∂q` for `k` = 0, 1, 2).
    #[inline]
    pub fn jacobian_row(&self, row: usize) -> &[f64] {
        &self.jacobian[row * self.dof..(row + 1) * self.dof]
    }

    /// The Jacobian rows `∂x_b/∂q`, `∂y_b/∂q`, `∂θ_b/∂q` of body `b`.
    #[inline]
    pub fn jacobian_rows(&self, b: usize) -> (&[f64], &[f64], &[f64]) {
        let n = self.dof;
        let rows = &self.jacobian[3 * b * n..3 * b * n + 3 * n];
        let (x, rest) = rows.split_at(n);
        let (y, t) = rest.split_at(n);
        (x, y, t)
    }

    /// The sorted columns where Jacobian row `row` (`3b + k`, `k` = x, y, θ) can be non-zero.
    #[inline]
    pub fn jacobian_pattern(&self, row: usize) -> &[usize] {
        &self.pattern[self.pattern_start[row]..self.pattern_start[row + 1]]
    }

    /// Whether `M(q)` is diagonal at every `q`: every Jacobian row touches at most one
    /// coordinate (a base with bodies pivoting at their own centres of mass, as Robbit).
    pub fn mass_matrix_is_diagonal(&self) -> bool {
        self.pattern_start.windows(2).all(|w| w[1] - w[0] <= 1)
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

    /// Writes `J_Pᵀ f` into `out` (length `n`), e.g. a contact direction `w_N`.
    #[inline]
    pub fn point_force_direction_to(&self, b: usize, r: Vec2, f: Vec2, out: &mut [f64]) {
        let torque = perp(r).dot(&f);
        let (x, y, t) = self.jacobian_rows(b);
        for (o, ((x, y), t)) in out.iter_mut().zip(x.iter().zip(y).zip(t)) {
            *o = x * f.x + y * f.y + t * torque;
        }
    }

    /// Adds a torque `tau` on body `b` (and `-tau` on `reaction`, if any) to `out`.
    #[inline]
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
        self.velocity[b] + perp(r) * self.angular_velocity[b]
    }
}

/// The structural sparsity of the Jacobian rows (see [`Kinematics::jacobian_pattern`]).
fn jacobian_pattern(model: &Model) -> (Vec<usize>, Vec<usize>) {
    let mut rows: Vec<Vec<usize>> = vec![vec![0], vec![1], vec![2]];
    let union = |a: &[usize], b: &[usize]| {
        let mut u: Vec<usize> = a.iter().chain(b).copied().collect();
        u.sort_unstable();
        u.dedup();
        u
    };
    for (b, body) in model.bodies.iter().enumerate().skip(1) {
        let Some(joint) = body.joint.as_ref() else {
            unreachable!("Model::new checks that every body after the first has a joint")
        };
        let p = joint.parent;
        let theta = match joint.coordinate {
            JointCoordinate::Absolute => vec![2 + b],
            JointCoordinate::Relative => union(&rows[3 * p + 2], &[2 + b]),
        };
        let mut levers: Vec<usize> = Vec::new();
        if joint.pivot_in_parent != Vec2::zeros() {
            levers = union(&levers, &rows[3 * p + 2]);
        }
        if joint.com_in_child != Vec2::zeros() {
            levers = union(&levers, &theta);
        }
        let x = union(&rows[3 * p], &levers);
        let y = union(&rows[3 * p + 1], &levers);
        rows.extend([x, y, theta]);
    }
    let mut start = vec![0];
    let mut pattern = Vec::new();
    for row in rows {
        pattern.extend(row);
        start.push(pattern.len());
    }
    (pattern, start)
}

/// `R v`, skipping the (possibly NaN) rotation of a body without geometry when `v = 0`.
#[inline]
fn rotated(rotation: Rotation, v: Vec2) -> Vec2 {
    if v == Vec2::zeros() {
        Vec2::zeros()
    } else {
        rotation.apply(v)
    }
}
