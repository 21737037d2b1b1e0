//! Collision matrix and applied impulses (docs/physics.md §3) against independent mechanics.

use hopsim_theory::impact::{
    apply_impulse, collision_matrix, impulse_for_energy_gain, inelastic_impact, kinetic_energy,
};
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use proptest::prelude::*;

fn diag(m: f64, inertia: f64) -> DMatrix<f64> {
    DMatrix::from_diagonal(&DVector::from_vec(vec![m, m, inertia]))
}

/// Flat-ground contact Jacobian of an eccentric disc (rows w_T, w_N), docs/physics.md §2.
fn ground_jacobian(radius: f64, a: f64, phi: f64) -> DMatrix<f64> {
    DMatrix::from_row_slice(
        2,
        3,
        &[1.0, 0.0, radius - a * phi.cos(), 0.0, 1.0, -a * phi.sin()],
    )
}

#[test]
fn point_mass_normal_impact_loses_half_m_vn_squared() {
    // A point mass (here: a body whose Jacobian does not involve rotation) hitting a
    // frictionless floor keeps v_t and loses ½ m v_n².
    let (m, vt, vn) = (3.2, 0.7, -2.1);
    let mass = diag(m, 1.0);
    let jac = DMatrix::from_row_slice(1, 3, &[0.0, 1.0, 0.0]);
    let hit = inelastic_impact(&mass, &jac, &DVector::from_vec(vec![vt, vn, 0.4])).unwrap();
    assert!((hit.energy_change + 0.5 * m * vn * vn).abs() < 1e-12);
    assert!((hit.velocity_after[0] - vt).abs() < 1e-14);
    assert!(hit.velocity_after[1].abs() < 1e-14);
    // Λ_N = m |v_n| pushes (positive).
    assert!((hit.percussion[0] - m * vn.abs()).abs() < 1e-12);
}

proptest! {
    /// No-slip touchdown of an eccentric disc: the impulse acts at the contact point P, so
    /// the angular momentum about P is conserved, and afterwards the disc rolls about P:
    /// `ω⁺ = L_P / I_P`, `I_P = I + m |r_CoM − r_P|²`, `T⁺ = ½ I_P ω⁺²`.
    #[test]
    fn disc_touchdown_conserves_angular_momentum_about_contact(
        m in 0.1f64..50.0,
        radius in 0.1f64..2.0,
        ecc_fraction in -0.9f64..0.9,
        alpha in 0.05f64..1.0,
        phi in -3.0f64..3.0,
        vx in -5.0f64..5.0,
        vy in -5.0f64..0.0,
        w in -10.0f64..10.0,
    ) {
        let a = ecc_fraction * radius;
        let inertia = alpha * m * radius * radius;
        let mass = diag(m, inertia);
        let jac = ground_jacobian(radius, a, phi);
        let u = DVector::from_vec(vec![vx, vy, w]);
        let hit = inelastic_impact(&mass, &jac, &u).unwrap();
        // r = CoM − P: CoM relative to the disc centre is (a sin φ, −a cos φ), P is R below it.
        let r = [a * phi.sin(), radius - a * phi.cos()];
        let l_p = inertia * w + m * (r[0] * vy - r[1] * vx);
        let i_p = inertia + m * (r[0] * r[0] + r[1] * r[1]);
        let w_after = l_p / i_p;
        let scale = 1.0 + kinetic_energy(&mass, &u);
        prop_assert!((hit.velocity_after[2] - w_after).abs() < 1e-9 * (1.0 + w_after.abs()));
        let t_after = 0.5 * i_p * w_after * w_after;
        let loss_independent = kinetic_energy(&mass, &u) - t_after;
        prop_assert!((-hit.energy_change - loss_independent).abs() < 1e-9 * scale);
        prop_assert!(hit.energy_change <= 1e-12 * scale);
        // The contact point is at rest afterwards.
        prop_assert!((&jac * &hit.velocity_after).norm() < 1e-9 * (1.0 + u.norm()));
    }

    /// M_c is symmetric negative semidefinite for any SPD mass matrix and full-rank J.
    #[test]
    fn collision_matrix_is_negative_semidefinite(
        masses in proptest::collection::vec(0.05f64..20.0, 3),
        entries in proptest::collection::vec(-3.0f64..3.0, 6),
        rows in 1usize..3,
    ) {
        let mass = DMatrix::from_diagonal(&DVector::from_vec(masses));
        let jac = DMatrix::from_row_slice(2, 3, &entries).rows(0, rows).into_owned();
        // Skip (nearly) rank-deficient Jacobians.
        let gram = &jac * jac.transpose();
        prop_assume!(gram.determinant().abs() > 1e-3);
        let mc = collision_matrix(&mass, &jac).unwrap();
        prop_assert!((&mc - mc.transpose()).norm() < 1e-9 * (1.0 + mc.norm()));
        let eig = SymmetricEigen::new(mc.clone());
        for λ in eig.eigenvalues.iter() {
            prop_assert!(*λ <= 1e-9 * (1.0 + mc.norm()));
        }
    }

    /// The [3.6] magnitude raises the kinetic energy by exactly ΔE.
    #[test]
    fn impulse_for_energy_gain_adds_exactly_delta_e(
        u in proptest::collection::vec(-4.0f64..4.0, 3),
        rho_angle in -3.1f64..3.1,
        phi in -1.0f64..1.0,
        delta_e in 0.0f64..50.0,
    ) {
        let mass = diag(7.0, 0.4);
        let jac = ground_jacobian(0.5, 0.2, phi);
        let rho = DVector::from_vec(vec![-rho_angle.sin(), rho_angle.cos()]);
        let u = DVector::from_vec(u);
        let s = impulse_for_energy_gain(&mass, &jac, &rho, &u, delta_e).unwrap();
        prop_assert!(s >= 0.0);
        let after = apply_impulse(&mass, &jac, &u, &(&rho * s)).unwrap();
        let gain = kinetic_energy(&mass, &after) - kinetic_energy(&mass, &u);
        prop_assert!((gain - delta_e).abs() < 1e-9 * (1.0 + delta_e + kinetic_energy(&mass, &u)));
    }
}
