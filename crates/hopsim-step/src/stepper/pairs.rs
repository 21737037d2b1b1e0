//! The body–body contacts of stage 4 (docs/physics.md §7): they enter the index set, the LCP
//! and the records like terrain contacts, numbered after them (see `Model::pairs`). A
//! model without them never calls into this module.

use super::Stepper;
use hopsim_model::Model;

impl Stepper {
    /// Adds the enabled body–body contacts with `g_N(q^M) ≤ 0` to the index set, with
    /// `w_N = J_Bᵀ n − J_Aᵀ n`, `w_T` likewise, and `γ^A` (docs/physics.md §7).
    pub(super) fn pair_index_set(&mut self, model: &Model) {
        let n = self.n;
        let first = model.contacts().len();
        for p in 0..model.pairs().len() {
            if !self.enabled[first + p] {
                continue;
            }
            let Some(geometry) = model.pair_geometry(&self.kinematics, p) else {
                continue;
            };
            if geometry.gap > 0.0 {
                continue;
            }
            let c = self.active.len();
            let rows = c * n..(c + 1) * n;
            model.pair_directions_to(
                &self.kinematics,
                p,
                &geometry,
                &mut self.w_n[rows.clone()],
                &mut self.w_t[rows],
            );
            self.close_contact::<0>(first + p, geometry.as_contact());
        }
    }
}
