//! A wheel over a wall (docs/physics.md §5.2) against independent mechanics.

use hopsim_theory::impact::{apply_impulse, inelastic_impact, kinetic_energy};
use hopsim_theory::obstacle::{
    compare_strategies, corner_impact_loss, corner_jacobian, rolling_cost, rotational_hop,
    rotational_hop_cost, trivial_hop_cost, RollingPath, Strategy, Wheel,
};
use hopsim_theory::AnalysisError;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

fn mass_matrix(w: &Wheel) -> DMatrix<f64> {
    DMatrix::from_diagonal(&DVector::from_vec(vec![w.mass, w.mass, w.inertia]))
}

/// Angular momentum about the corner is conserved in the corner impact of a centred wheel:
/// before, `L = I ω⁻ − m (R − h) u` (ω⁻ = −u/R); after, pure rotation about the corner,
/// `L = (I + m R²) ω⁺`. So `ω⁺ = ω⁻ (I + m R (R − h)) / (I + m R²)`.
fn corner_loss_by_angular_momentum(w: &Wheel, u: f64, h: f64) -> f64 {
    let (m, r, i) = (w.mass, w.radius, w.inertia);
    let omega_before = -u / r;
    let omega_after = omega_before * (i + m * r * (r - h)) / (i + m * r * r);
    0.5 * (i + m * r * r) * (omega_before * omega_before - omega_after * omega_after)
}

proptest! {
    #[test]
    fn corner_loss_matches_angular_momentum(
        m in 0.01f64..100.0,
        r in 0.05f64..3.0,
        alpha in 0.01f64..1.0,
        eta in 0.01f64..0.95,
        fr in 0.01f64..10.0,
    ) {
        let w = Wheel { mass: m, radius: r, inertia: alpha * m * r * r, gravity: 9.81 };
        let u = w.speed_from_froude(fr);
        let h = eta * r;
        let loss = corner_impact_loss(&w, u, h).unwrap();
        let expected = corner_loss_by_angular_momentum(&w, u, h);
        prop_assert!((loss - expected).abs() < 1e-10 * (1.0 + w.rolling_kinetic_energy(u)));
        // docs/physics.md prints [4.12] with −sqrt(2Rh − h²): the mirror image gives the same loss.
        let s = (2.0 * r * h - h * h).sqrt();
        let mirrored = DMatrix::from_row_slice(2, 3, &[1.0, 0.0, r - h, 0.0, 1.0, -s]);
        let before = DVector::from_vec(vec![u, 0.0, -u / r]);
        let hit = inelastic_impact(&mass_matrix(&w), &mirrored, &before).unwrap();
        prop_assert!((-hit.energy_change - loss).abs() < 1e-10 * (1.0 + w.rolling_kinetic_energy(u)));
    }

    /// Costs in units of m g R depend only on α, Fr and h/R.
    #[test]
    fn costs_scale_with_m_g_r(alpha in 0.02f64..1.0, fr in 0.05f64..5.0, eta in 0.1f64..0.5, m in 0.1f64..50.0, r in 0.1f64..2.0) {
        let unit = Wheel::dimensionless(alpha);
        let real = Wheel { mass: m, radius: r, inertia: alpha * m * r * r, gravity: 9.81 };
        let a = compare_strategies(&unit, unit.speed_from_froude(fr), eta).unwrap();
        let b = compare_strategies(&real, real.speed_from_froude(fr), eta * r).unwrap();
        let tol = 1e-7;
        prop_assert!((a.rolling.cost_j / unit.energy_unit() - b.rolling.cost_j / real.energy_unit()).abs() < tol);
        prop_assert!((a.trivial_hop_j / unit.energy_unit() - b.trivial_hop_j / real.energy_unit()).abs() < tol);
        match (a.rotational_hop, b.rotational_hop) {
            (Some(x), Some(y)) => prop_assert!((x.cost_j / unit.energy_unit() - y.cost_j / real.energy_unit()).abs() < 1e-5),
            (None, None) => {}
            _ => prop_assert!(false, "feasibility differs"),
        }
    }
}

#[test]
fn trivial_hop_costs_m_g_h_and_its_landing_removes_it() {
    let w = Wheel {
        mass: 2.0,
        radius: 0.4,
        inertia: 0.5 * 2.0 * 0.16,
        gravity: 9.81,
    };
    let (u, h) = (1.3, 0.1);
    assert!((trivial_hop_cost(&w, h) - w.mass * w.gravity * h).abs() < 1e-15);
    // A vertical impulse at the contact point of the rolling wheel that makes it rise by h
    // (v_y = sqrt(2 g h)) adds m g h; the no-slip landing from that height removes it again.
    let rolling = DVector::from_vec(vec![u, 0.0, -u / w.radius]);
    let normal = DMatrix::from_row_slice(1, 3, &[0.0, 1.0, 0.0]);
    let vy = (2.0 * w.gravity * h).sqrt();
    let kicked = apply_impulse(
        &mass_matrix(&w),
        &normal,
        &rolling,
        &DVector::from_vec(vec![w.mass * vy]),
    )
    .unwrap();
    let added =
        kinetic_energy(&mass_matrix(&w), &kicked) - kinetic_energy(&mass_matrix(&w), &rolling);
    assert!((added - trivial_hop_cost(&w, h)).abs() < 1e-12);
    let landing_velocity = DVector::from_vec(vec![u, -vy, -u / w.radius]);
    let ground = DMatrix::from_row_slice(2, 3, &[1.0, 0.0, w.radius, 0.0, 1.0, 0.0]);
    let landing = inelastic_impact(&mass_matrix(&w), &ground, &landing_velocity).unwrap();
    assert!((-landing.energy_change - trivial_hop_cost(&w, h)).abs() < 1e-12);
    assert!((landing.velocity_after[0] - u).abs() < 1e-12);
}

#[test]
fn slow_rolling_over_the_edge_loses_one_minus_k_to_the_fourth() {
    // Enough speed to climb, too little to leave the edge: the wheel pivots over the edge and
    // lands behind the wall in the mirror configuration, so both impacts scale the spin by
    // k = (α + 1 − h/R) / (α + 1): cost = T₀ (1 − k⁴).
    let w = Wheel::dimensionless(0.5);
    let (eta, fr) = (0.1, 0.5);
    let u = w.speed_from_froude(fr);
    let crossing = rolling_cost(&w, u, eta).unwrap();
    assert_eq!(crossing.path, RollingPath::PivotOver);
    assert_eq!(crossing.climb_assist_j, 0.0);
    assert_eq!(crossing.impacts, 2);
    let k = (0.5 + 1.0 - eta) / 1.5;
    let t0 = w.rolling_kinetic_energy(u);
    assert!((crossing.cost_j - t0 * (1.0 - k.powi(4))).abs() < 1e-10 * t0);
    assert!((crossing.corner_loss_j - t0 * (1.0 - k * k)).abs() < 1e-10 * t0);
    assert!((crossing.final_speed_mps - u * k * k).abs() < 1e-10 * u);
    assert!(
        (crossing.corner_loss_j + crossing.landing_loss_j - crossing.cost_j).abs() < 1e-10 * t0
    );
}

#[test]
fn fast_rolling_flies_off_the_edge_and_still_balances_energy() {
    let w = Wheel::dimensionless(0.5);
    let u = w.speed_from_froude(4.0);
    let crossing = rolling_cost(&w, u, 0.3).unwrap();
    assert_eq!(crossing.path, RollingPath::FlewOff);
    let t0 = w.rolling_kinetic_energy(u);
    let t_final = w.rolling_kinetic_energy(crossing.final_speed_mps);
    assert!((t0 - t_final - crossing.corner_loss_j - crossing.landing_loss_j).abs() < 1e-9 * t0);
    assert!(crossing.corner_loss_j > 0.0 && crossing.landing_loss_j > 0.0);
}

#[test]
fn slow_wheel_needs_a_climb_assist() {
    let w = Wheel::dimensionless(0.5);
    let u = w.speed_from_froude(0.05);
    let crossing = rolling_cost(&w, u, 0.3).unwrap();
    assert!(crossing.climb_assist_j > 0.0);
    // The assist is what the wheel lacks after the corner impact to lift its centre by h.
    let k = (0.5 + 1.0 - 0.3) / 1.5;
    let expected = w.mass * w.gravity * 0.3 - k * k * w.rolling_kinetic_energy(u);
    assert!((crossing.climb_assist_j - expected).abs() < 1e-10);
}

#[test]
fn rotational_hop_energy_account_closes() {
    // Flight conserves energy, so after touchdown E = E_approach − braking + spin − loss and
    // the deficit is max(0, braking − spin + loss) (for a wheel rolling forward afterwards).
    let w = Wheel::dimensionless(0.05);
    for (fr, eta, phi0) in [(1.0, 0.3, -1.2), (2.0, 0.2, -0.9), (0.5, 0.4, -1.6)] {
        let hop = rotational_hop(&w, w.speed_from_froude(fr), eta, phi0).expect("clears the wall");
        assert!(hop.clearance_m >= 0.0);
        // φ = 0 at the apex t = v_y / g, v_y = −(u/R) a sin φ₀.
        let vy = -(w.speed_from_froude(fr) / w.radius) * 0.5 * w.radius * phi0.sin();
        assert!((phi0 + hop.spin_rad_s * vy / w.gravity).abs() < 1e-12);
        let deficit = (hop.braking_j - hop.spin_j + hop.touchdown_loss_j).max(0.0);
        assert!((hop.deficit_j - deficit).abs() < 1e-9, "{hop:?}");
        assert!((hop.cost_j - hop.braking_j - hop.spin_j - hop.deficit_j).abs() < 1e-12);
    }
    // Too low a take-off phase cannot clear a high wall.
    assert!(rotational_hop(&w, w.speed_from_froude(0.1), 0.5, -0.2).is_none());
}

#[test]
fn optimal_rotational_hop_is_no_worse_than_any_scanned_phase() {
    let w = Wheel::dimensionless(0.05);
    let u = w.speed_from_froude(1.0);
    let best = rotational_hop_cost(&w, u, 0.3).unwrap().unwrap();
    for i in 1..200 {
        let phi = -std::f64::consts::PI * i as f64 / 200.0;
        if let Some(hop) = rotational_hop(&w, u, 0.3, phi) {
            assert!(
                best.cost_j <= hop.cost_j + 1e-9,
                "φ₀ {phi}: {} < {}",
                hop.cost_j,
                best.cost_j
            );
        }
    }
}

#[test]
fn rolling_wins_slow_and_hopping_wins_fast() {
    // The thesis' qualitative result: hopping outperforms rolling at large Froude numbers.
    let w = Wheel::dimensionless(0.5);
    let slow = compare_strategies(&w, w.speed_from_froude(0.05), 0.2).unwrap();
    let fast = compare_strategies(&w, w.speed_from_froude(5.0), 0.2).unwrap();
    assert_eq!(slow.cheapest, Strategy::Rolling);
    assert_ne!(fast.cheapest, Strategy::Rolling);
    // A light-inertia wheel profits from the rotational hop at moderate speed.
    let light = Wheel::dimensionless(0.02);
    assert_eq!(
        compare_strategies(&light, light.speed_from_froude(1.0), 0.3)
            .unwrap()
            .cheapest,
        Strategy::RotationalHop
    );
}

#[test]
fn invalid_obstacles_are_errors() {
    let w = Wheel::dimensionless(0.5);
    assert!(matches!(
        rolling_cost(&w, 1.0, 1.5),
        Err(AnalysisError::InvalidParameter { .. })
    ));
    assert!(matches!(
        compare_strategies(&w, -1.0, 0.2),
        Err(AnalysisError::InvalidParameter { .. })
    ));
    let bad = Wheel { mass: 0.0, ..w };
    assert!(compare_strategies(&bad, 1.0, 0.2).is_err());
    let j = corner_jacobian(1.0, 0.2);
    assert!((j[(1, 2)] - (2.0 * 0.2 - 0.04f64).sqrt()).abs() < 1e-15);
}

/// Tables print the rolling path by the name the JSON gives it.
#[test]
fn rolling_path_names_match_the_json() {
    for path in [RollingPath::PivotOver, RollingPath::FlewOff] {
        assert_eq!(serde_json::to_value(path).unwrap(), path.name());
    }
}
