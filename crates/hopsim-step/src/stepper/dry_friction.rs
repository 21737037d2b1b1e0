//! Dry (Coulomb) friction in the joints (docs/physics.md §7.5): each joint with a bound `F`
//! (N m or N) takes a percussion `Λ_F` with `|Λ_F| ≤ β = F Δt` on its rate `w_Fᵀ u`,
//! opposing the rate at the end of the step, as two rows of the step's LCP beside the
//! contacts' (the same pair of rows a contact's friction has, with the constant bound `β`
//! in place of `μ Λ_N`):
//!
//! `ξ_F + ξ_D ⟂ Λ_F + β ≥ 0`, `s (β − Λ_F) ⟂ ξ_D / s ≥ 0`, `ξ_F = w_Fᵀ u^E`.
//!
//! The unknown `Λ_F + β` is every velocity's percussion shifted by `−β`: the right-hand
//! side of every row carries `−Σ β_j (w_X G w_Fj)`.

use super::{at, dof, row, Layout, Stepper};
use crate::linalg::{axpy, dot};
use hopsim_model::Model;

/// The joints with dry friction of a model and their rows in one step.
pub(super) struct DryFriction {
    /// Each joint's child body.
    pub bodies: Vec<usize>,
    /// Each joint's bound `β = F Δt` on its friction percussion, N m s or N s.
    pub bound: Vec<f64>,
    /// Row-major `f × n`: each joint's row `w_F` at `q^M`.
    pub w: Vec<f64>,
    /// Each joint's friction percussion `Λ_F` of the step.
    pub lambda: Vec<f64>,
}

impl DryFriction {
    /// The joints of `model` with dry friction, for steps of `dt`.
    pub fn new(model: &Model, dt: f64) -> Self {
        let joints = model.dry_frictions();
        Self {
            bodies: joints.iter().map(|&(b, _)| b).collect(),
            bound: joints.iter().map(|&(_, f)| f * dt).collect(),
            w: vec![0.0; joints.len() * model.dof()],
            lambda: vec![0.0; joints.len()],
        }
    }

    /// Joints with dry friction `f`.
    #[inline(always)]
    pub fn count(&self) -> usize {
        self.bodies.len()
    }

    /// The friction percussions from a certified answer `z`, projected onto `|Λ_F| ≤ β`
    /// (within the answer's tolerance, like the contacts' onto their cones).
    pub fn percussions(&mut self, layout: Layout, z: &[f64]) {
        for j in 0..layout.frictions {
            let beta = self.bound[j];
            self.lambda[j] = (z[layout.joint_sliding(j)] - beta).clamp(-beta, beta);
        }
    }
}

impl Stepper {
    /// Stage 4 for the joints with dry friction: their rows `w_F` at `q^M`.
    #[inline(never)]
    pub(super) fn dry_friction_rows<const N: usize>(&mut self, model: &Model) {
        let n = dof::<N>(self.n);
        for (j, &body) in self.dry.bodies.iter().enumerate() {
            let w = &mut self.dry.w[j * n..(j + 1) * n];
            w.fill(0.0);
            model.add_joint_force_to(&self.kinematics, body, 1.0, w);
        }
    }

    /// The largest `w_F G w_F` of the joints with dry friction (0 without), for the scale of
    /// the bound rows.
    pub(super) fn dry_friction_scale<const N: usize>(&self, layout: Layout) -> f64 {
        let n = dof::<N>(self.n);
        (0..layout.frictions)
            .map(|j| {
                let gw = row(&self.solved, n, layout.solved_friction(j));
                dot(row(&self.dry.w, n, j), gw)
            })
            .fold(0.0, f64::max)
    }

    /// Stage 6: the rows and columns of the joints' dry friction in the LCP (after the
    /// contacts' and the stops', which are complete), and the shift `Λ_F = z − β` in every
    /// right-hand side.
    #[inline(never)]
    pub(super) fn dry_friction_lcp_rows<const N: usize>(&mut self, layout: Layout, scale: f64) {
        let n = dof::<N>(self.n);
        let ld = self.lcp_a.nrows();
        let a = self.lcp_a.as_mut_slice();
        let b = self.lcp_b.as_mut_slice();
        let (k, l, f) = (layout.contacts, layout.limits, layout.frictions);
        for j in 0..f {
            let w_f = row(&self.dry.w, n, j);
            let gw_f = row(&self.solved, n, layout.solved_friction(j));
            let (fs, fc) = (layout.joint_sliding(j), layout.joint_cone(j));
            for c in 0..k {
                let (gw_n, gw_t) = (
                    row(&self.solved, n, layout.solved_normal(c)),
                    row(&self.solved, n, layout.solved_tangent(c)),
                );
                let (cn, cs, cc) = (layout.normal(c), layout.sliding(c), layout.cone(c));
                // The joint's rate through `Λ_T = Λ_R − μ Λ_N`, as in a stop's row.
                let g_ft = dot(w_f, gw_t);
                a[at(ld, fs, cn)] = dot(w_f, gw_n) - g_ft * self.friction[c];
                a[at(ld, fs, cs)] = g_ft;
                a[at(ld, cn, fs)] = dot(row(&self.w_n, n, c), gw_f);
                a[at(ld, cs, fs)] = dot(row(&self.w_t, n, c), gw_f);
                for (r, col) in [(fs, cc), (fc, cn), (fc, cs), (fc, cc), (cc, fs)] {
                    a[at(ld, r, col)] = 0.0;
                }
                for r in [cn, cs, cc] {
                    a[at(ld, r, fc)] = 0.0;
                }
            }
            for r in 0..l {
                let rj = layout.limit(r);
                let gw_j = row(&self.solved, n, layout.solved_limit(r));
                a[at(ld, fs, rj)] = dot(w_f, gw_j);
                a[at(ld, rj, fs)] = dot(row(&self.w_limit, n, r), gw_f);
                a[at(ld, fc, rj)] = 0.0;
                a[at(ld, rj, fc)] = 0.0;
            }
            for i in 0..f {
                let gw_i = row(&self.solved, n, layout.solved_friction(i));
                let own = i == j;
                a[at(ld, fs, layout.joint_sliding(i))] = dot(w_f, gw_i);
                a[at(ld, fs, layout.joint_cone(i))] = if own { scale } else { 0.0 };
                a[at(ld, fc, layout.joint_sliding(i))] = if own { -scale } else { 0.0 };
                a[at(ld, fc, layout.joint_cone(i))] = 0.0;
            }
            // No restitution: the joint's rate at the end of the step.
            b[fs] = dot(w_f, &self.u_tilde[..n]);
            b[fc] = 2.0 * scale * self.dry.bound[j];
        }
        self.shift_rows_by_bounds(layout, -1.0);
    }

    /// Adds `sign Σ_j β_j A[x, joint_sliding(j)]` to the right-hand side of every velocity
    /// row `x` (normal, sliding, stop and joint rows): `−1` shifts the unknowns to
    /// `Λ_F + β`, `+1` undoes it (for the frictionless fallback, which drops the joints'
    /// friction with the contacts').
    pub(super) fn shift_rows_by_bounds(&mut self, layout: Layout, sign: f64) {
        let ld = self.lcp_a.nrows();
        let a = self.lcp_a.as_slice();
        let b = self.lcp_b.as_mut_slice();
        let k = layout.contacts;
        let rows = (0..k)
            .flat_map(|c| [layout.normal(c), layout.sliding(c)])
            .chain((0..layout.limits).map(|r| layout.limit(r)))
            .chain((0..layout.frictions).map(|j| layout.joint_sliding(j)));
        for x in rows {
            let shift: f64 = (0..layout.frictions)
                .map(|j| self.dry.bound[j] * a[at(ld, x, layout.joint_sliding(j))])
                .sum();
            b[x] += sign * shift;
        }
    }

    /// Stage 7: adds `G w_F Λ_F` of every joint to `u^E`.
    pub(super) fn add_dry_friction_velocity<const N: usize>(&mut self, layout: Layout) {
        let n = dof::<N>(self.n);
        for j in 0..layout.frictions {
            let gw_f = row(&self.solved, n, layout.solved_friction(j));
            axpy(self.dry.lambda[j], gw_f, &mut self.u_end[..n]);
        }
    }

    /// The joints' friction work `Σ Λ_F w_Fᵀ ū` over the step (the mean velocity `ū` in
    /// `scratch`), ≤ 0.
    pub(super) fn dry_friction_work<const N: usize>(&self) -> f64 {
        let n = dof::<N>(self.n);
        let mean = &self.scratch[..n];
        (0..self.dry.count())
            .map(|j| self.dry.lambda[j] * dot(row(&self.dry.w, n, j), mean))
            .sum()
    }
}
