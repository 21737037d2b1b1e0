//! Forward kinematics of the body tree: poses, Jacobians and velocity-product
//! accelerations of every body, evaluated into reused buffers.

use crate::contact::lever;
use crate::{rotate, JointCoordinate, Model, Vec2};
use nalgebra::{DMatrix, DVector};

/// Reused buffers for evaluating a [`Model`] at one `(q, u)`; allocated once per model.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Centre-of-mass position of each body, world frame, m.
    pub position: Vec<Vec2>,
    /// Absolute angle of each body, rad.
    pub angle: Vec<f64>,
    /// Absolute angular velocity of each body, rad/s.
    pub angular_velocity: Vec<f64>,
    /// Centre-of-mass velocity of each body, m/s.
    pub velocity: Vec<Vec2>,
    /// Rows `3b, 3b+1, 3b+2` hold `∂(x_b, y_b, θ_b)/∂q` of body `b`.
    pub jacobian: DMatrix<f64>,
    /// `J̇_b u` of each body's centre of mass (centripetal terms), m/s².
    pub bias: Vec<Vec2>,
}

impl Workspace {
    /// Buffers sized for `model`.
    pub fn new(model: &Model) -> Self {
        let nb = model.bodies.len();
        Self {
            position: vec![Vec2::zeros(); nb],
            angle: vec![0.0; nb],
            angular_velocity: vec![0.0; nb],
            velocity: vec![Vec2::zeros(); nb],
            jacobian: DMatrix::zeros(3 * nb, model.dof()),
            bias: vec![Vec2::zeros(); nb],
        }
    }

    /// Evaluates poses, Jacobians, velocities and bias accelerations at `(q, u)`.
    pub fn update(&mut self, model: &Model, q: &DVector<f64>, u: &DVector<f64>) {
        self.jacobian.fill(0.0);
        self.position[0] = Vec2::new(q[0], q[1]);
        self.angle[0] = q[2];
        for k in 0..3 {
            self.jacobian[(k, k)] = 1.0;
        }
        self.bias[0] = Vec2::zeros();
        for (b, body) in model.bodies.iter().enumerate().skip(1) {
            let joint = body.joint.as_ref().expect("non-base bodies have joints");
            let p = joint.parent;
            let coord = 2 + b;
            self.angle[b] = match joint.coordinate {
                JointCoordinate::Absolute => q[coord],
                JointCoordinate::Relative => self.angle[p] + q[coord],
            };
            // θ_b row: copy the parent's for a relative coordinate.
            if joint.coordinate == JointCoordinate::Relative {
                for j in 0..model.dof() {
                    self.jacobian[(3 * b + 2, j)] = self.jacobian[(3 * p + 2, j)];
                }
            }
            self.jacobian[(3 * b + 2, coord)] += 1.0;
            let r_pivot = rotate(self.angle[p], joint.pivot_in_parent);
            let r_com = rotate(self.angle[b], joint.com_in_child);
            self.position[b] = self.position[p] + r_pivot + r_com;
            let (lp, lc) = (lever(r_pivot), lever(r_com));
            for j in 0..model.dof() {
                let (jp, jb) = (self.jacobian[(3 * p + 2, j)], self.jacobian[(3 * b + 2, j)]);
                self.jacobian[(3 * b, j)] = self.jacobian[(3 * p, j)] + lp.x * jp + lc.x * jb;
                self.jacobian[(3 * b + 1, j)] =
                    self.jacobian[(3 * p + 1, j)] + lp.y * jp + lc.y * jb;
            }
        }
        for b in 0..model.bodies.len() {
            let row_dot = |r: usize| (0..u.len()).map(|j| self.jacobian[(r, j)] * u[j]).sum();
            self.velocity[b] = Vec2::new(row_dot(3 * b), row_dot(3 * b + 1));
            self.angular_velocity[b] = row_dot(3 * b + 2);
        }
        for (b, body) in model.bodies.iter().enumerate().skip(1) {
            let joint = body.joint.as_ref().expect("non-base bodies have joints");
            let p = joint.parent;
            let r_pivot = rotate(self.angle[p], joint.pivot_in_parent);
            let r_com = rotate(self.angle[b], joint.com_in_child);
            let (wp, wb) = (self.angular_velocity[p], self.angular_velocity[b]);
            self.bias[b] = self.bias[p] - r_pivot * (wp * wp) - r_com * (wb * wb);
        }
    }

    /// Adds `scale · J_Pᵀ f` to `out`, where `J_P` is the Jacobian of the material point of
    /// body `b` at world offset `r` from its centre of mass and `f` a world force.
    pub fn add_point_force(&self, b: usize, r: Vec2, f: Vec2, out: &mut DVector<f64>) {
        let l = lever(r);
        let torque = l.dot(&f);
        for j in 0..out.len() {
            out[j] += self.jacobian[(3 * b, j)] * f.x
                + self.jacobian[(3 * b + 1, j)] * f.y
                + self.jacobian[(3 * b + 2, j)] * torque;
        }
    }

    /// Writes `J_Pᵀ f` into `out` (the generalised direction of a point force, e.g. `w_N`).
    pub fn point_force_direction(
        &self,
        b: usize,
        r: Vec2,
        f: Vec2,
        mut out: nalgebra::DVectorViewMut<'_, f64>,
    ) {
        let torque = lever(r).dot(&f);
        for j in 0..out.len() {
            out[j] = self.jacobian[(3 * b, j)] * f.x
                + self.jacobian[(3 * b + 1, j)] * f.y
                + self.jacobian[(3 * b + 2, j)] * torque;
        }
    }

    /// Adds a torque `tau` on body `b` (and `-tau` on `reaction`, if any) to `out`.
    pub fn add_torque(&self, b: usize, reaction: Option<usize>, tau: f64, out: &mut DVector<f64>) {
        for j in 0..out.len() {
            let mut g = self.jacobian[(3 * b + 2, j)];
            if let Some(r) = reaction {
                g -= self.jacobian[(3 * r + 2, j)];
            }
            out[j] += g * tau;
        }
    }

    /// Velocity of the material point of body `b` at world offset `r` from its CoM.
    pub fn point_velocity(&self, b: usize, r: Vec2) -> Vec2 {
        self.velocity[b] + lever(r) * self.angular_velocity[b]
    }
}
