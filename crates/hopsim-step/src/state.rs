//! The plain-data simulation state.

use nalgebra::DVector;

/// Time, generalised coordinates `q` and velocities `u` (docs/physics.md §1).
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time, s.
    pub t: f64,
    /// Generalised coordinates `(x, y, φ, joint coordinates…)`.
    pub q: DVector<f64>,
    /// Generalised velocities `u = q̇`.
    pub u: DVector<f64>,
}

impl State {
    /// A state at rest at `q`, time zero.
    pub fn at_rest(q: DVector<f64>) -> Self {
        let u = DVector::zeros(q.len());
        Self { t: 0.0, q, u }
    }
}
