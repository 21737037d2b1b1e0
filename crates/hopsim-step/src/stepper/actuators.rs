//! The model's actuators in stage 2 (docs/physics.md §7.4): their forces at `(q^M, u^A)`
//! as applied forces, and the velocity term of each unclamped servo as a damper taken at
//! the step's mean velocity (§4.9), appended after the model's own dampers.

use super::{dof, row, Stepper};
use crate::linalg::{axpy, dot};
use crate::Actuation;
use hopsim_model::Model;

impl Stepper {
    /// Adds the actuators' forces to `applied` and their dampers after the first
    /// `damper_count` (the model's); returns how many dampers they add.
    #[inline]
    pub(super) fn actuator_forces<const N: usize>(
        &mut self,
        model: &Model,
        actuation: &Actuation,
    ) -> usize {
        let n = dof::<N>(self.n);
        let first = self.damper_count;
        model.actuator_forces_split(
            &self.kinematics,
            &actuation.controls,
            &mut self.applied[..n],
            &mut self.damper_c[first..],
            &mut self.damper_rows[first * n..],
        )
    }

    /// Adds the explicit part `−c w (wᵀ u^A)` of the actuators' dampers (from `first` on)
    /// to `h`; `M + Δt/2 C` carries the rest (§4.9).
    #[inline]
    pub(super) fn explicit_actuator_damping<const N: usize>(&mut self, first: usize) {
        let n = dof::<N>(self.n);
        for d in first..self.damper_count {
            let w = row(&self.damper_rows, n, d);
            let rate = dot(w, &self.u_start[..n]);
            axpy(-self.damper_c[d] * rate, w, &mut self.h[..n]);
        }
    }
}
