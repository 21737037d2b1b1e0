//! The loop joints' projection after a step (docs/physics.md §8.4): the end positions onto
//! the constraint manifold `φ(q) = 0` by Gauss–Newton in the mass-matrix metric, the end
//! velocities onto its tangent space, in buffers sized once.

use crate::linalg::{axpy, dot, Factor, PivotedFactor};
use crate::StepError;
use hopsim_model::{Kinematics, Model};

/// The loop error the projection reaches, m (rad for a weld's angle row).
pub const LOOP_TOLERANCE: f64 = 1e-12;
/// Gauss–Newton iterations before a projection that has not converged is an error.
const MAX_ITERATIONS: usize = 12;
/// Rows whose part independent of the others is below this fraction of the largest (in
/// `J M⁻¹ Jᵀ`, a squared quantity: angles of about 3e-5 rad) are dependent
/// (docs/physics.md §8.3).
pub const DEPENDENT_LOOP_ROWS: f64 = 1e-9;

/// Why the projection failed: the loop joint (index into `Model::loops`) and whether it
/// went singular (else it did not converge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ProjectionFailure {
    pub loop_index: usize,
    pub singular: bool,
    pub error: f64,
}

impl ProjectionFailure {
    /// The step's error.
    pub fn into_error(self, step: u64, t: f64) -> StepError {
        StepError::Loop {
            step,
            t,
            loop_index: self.loop_index,
            singular: self.singular,
            error: self.error,
        }
    }
}

/// Buffers of the projection: `φ`, the rows `J` (`m × n`), `Y = M⁻¹ Jᵀ`, `S = J M⁻¹ Jᵀ`
/// with its pivoted factor, and `M` with its factor.
pub(crate) struct LoopProjection {
    n: usize,
    m: usize,
    phi: Vec<f64>,
    rows: Vec<f64>,
    y: Vec<f64>,
    s: Vec<f64>,
    s_factor: PivotedFactor,
    mass: Vec<f64>,
    factor: Factor,
    /// The rank of `J` at the run's start: fewer independent rows later is a singular
    /// configuration.
    pub rank: usize,
}

impl LoopProjection {
    /// The projection of `model`'s loop joints; `None` without loops.
    pub fn new(model: &Model) -> Option<Self> {
        let (n, m) = (model.dof(), model.loop_row_count());
        (m > 0).then(|| Self {
            n,
            m,
            phi: vec![0.0; m],
            rows: vec![0.0; m * n],
            y: vec![0.0; m * n],
            s: vec![0.0; m * m],
            s_factor: PivotedFactor::new(m),
            mass: vec![0.0; n * n],
            factor: Factor::new(n, false),
            rank: m,
        })
    }

    /// `J`, `Y = M⁻¹ Jᵀ` and the factor of `S = J Y` at `kinematics`; returns the rank of
    /// `S` (0 when `M` is not positive definite).
    fn metric(&mut self, model: &Model, kinematics: &Kinematics) -> usize {
        let (n, m) = (self.n, self.m);
        model.mass_matrix_to(kinematics, &mut self.mass);
        if !self.factor.factor(&self.mass, n) {
            return 0;
        }
        model.loop_rows_to(kinematics, &mut self.rows);
        self.y.copy_from_slice(&self.rows);
        self.factor.solve(&mut self.y);
        for r in 0..m {
            for c in 0..m {
                self.s[r * m + c] =
                    dot(&self.rows[r * n..(r + 1) * n], &self.y[c * n..(c + 1) * n]);
            }
        }
        self.s_factor.factor(&self.s, m, DEPENDENT_LOOP_ROWS)
    }

    /// The rank of the loop rows at `kinematics`, kept as the rank the run must keep.
    pub fn start(&mut self, model: &Model, kinematics: &Kinematics) {
        self.rank = self.metric(model, kinematics);
    }

    /// The loop owning the row the last factor left out first (or the largest residual's).
    fn culprit(&self, model: &Model) -> usize {
        let row = match self.s_factor.dependent().first() {
            Some(&r) => r,
            None => (0..self.m)
                .max_by(|&a, &b| self.phi[a].abs().total_cmp(&self.phi[b].abs()))
                .unwrap_or(0),
        };
        model.loop_of_row(row)
    }

    /// Projects `(q, u)` onto the manifold and its tangent space (docs/physics.md §8.4):
    /// `q ← q − Y S⁺ φ(q)` until `|φ| ≤ LOOP_TOLERANCE`, then `u ← u − Y S⁺ J u`, the metric
    /// `M` taken where the rows are. `kinematics` is left at the projected state. Returns
    /// the loop error reached.
    pub fn project(
        &mut self,
        model: &Model,
        kinematics: &mut Kinematics,
        q: &mut [f64],
        u: &mut [f64],
    ) -> Result<f64, ProjectionFailure> {
        let (n, m) = (self.n, self.m);
        let mut iteration = 0;
        let error = loop {
            kinematics.update_slices(model, q, u);
            let error = model.loop_error(kinematics, &mut self.phi);
            if !error.is_finite() || iteration == MAX_ITERATIONS {
                return Err(ProjectionFailure {
                    loop_index: self.culprit(model),
                    singular: false,
                    error,
                });
            }
            let rank = self.metric(model, kinematics);
            if rank < self.rank {
                return Err(ProjectionFailure {
                    loop_index: self.culprit(model),
                    singular: true,
                    error,
                });
            }
            if error <= LOOP_TOLERANCE {
                break error;
            }
            self.s_factor.solve(&mut self.phi);
            for (r, x) in self.phi.iter().enumerate() {
                axpy(-x, &self.y[r * n..(r + 1) * n], q);
            }
            iteration += 1;
        };
        // The metric is that of the projected `q`: the velocity onto the tangent space.
        for r in 0..m {
            self.phi[r] = dot(&self.rows[r * n..(r + 1) * n], u);
        }
        self.s_factor.solve(&mut self.phi);
        for (r, x) in self.phi.iter().enumerate() {
            axpy(-x, &self.y[r * n..(r + 1) * n], u);
        }
        kinematics.update_slices(model, q, u);
        Ok(error)
    }
}
