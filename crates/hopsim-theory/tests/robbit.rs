//! Robbit's reduced model (docs/physics.md §5.3) against independent mechanics: momentum and
//! energy balances, the template's rigid-body impact, the iterated return map.

use hopsim_theory::fixed_points::{
    find_fixed_point, residual, return_map_jacobian, FixedPoint, FixedPointGrid, NoFixedPoint,
    SolverSettings,
};
use hopsim_theory::robbit::{
    brake, cycle, return_map, stance, touchdown, Control, FlywheelAtTouchdown, NoCycle,
    RobbitParams, SectionState,
};
use hopsim_theory::template::{self, BodyState};
use hopsim_theory::AnalysisError;
use proptest::prelude::*;

fn table_5_1() -> RobbitParams {
    RobbitParams::default()
}

fn free() -> RobbitParams {
    RobbitParams {
        touchdown: FlywheelAtTouchdown::Free,
        ..RobbitParams::default()
    }
}

/// Mechanical energy with the flywheel's spin, computed here from `(y, φ)` and
/// `u = (ẋ, ẏ, φ̇, ψ̇)`: ½ m v² + ½ I_S φ̇² + ½ I_R ψ̇² + m g y.
fn energy(p: &RobbitParams, y: f64, u: [f64; 4]) -> f64 {
    let m = p.body_mass + p.flywheel_mass;
    0.5 * m * (u[0] * u[0] + u[1] * u[1])
        + 0.5 * p.body_inertia * u[2] * u[2]
        + 0.5 * p.flywheel_inertia * u[3] * u[3]
        + m * p.gravity * y
}

/// Energy of a section state with `ψ̇ = φ̇ + ζ0 / I_red`, from the rolling kinematics [3.16].
fn section_energy(p: &RobbitParams, z: &SectionState, zeta0: f64) -> f64 {
    let (a, r) = (p.eccentricity, p.radius);
    let (s, c) = z.angle.sin_cos();
    let w = z.angular_velocity;
    let i_red = p.body_inertia * p.flywheel_inertia / (p.body_inertia + p.flywheel_inertia);
    energy(
        p,
        r - a * c,
        [w * (a * c - r), w * a * s, w, w + zeta0 / i_red],
    )
}

/// Angular momentum about the ground point below the disc centre, `(x_c, 0)`:
/// `I_S φ̇ + I_R ψ̇ + m (r × v)`, `r` from that point to the CoM.
fn momentum_about_contact(p: &RobbitParams, phi: f64, u: [f64; 4], body_only: bool) -> f64 {
    let m = p.body_mass + p.flywheel_mass;
    let (a, r) = (p.eccentricity, p.radius);
    let rel = [a * phi.sin(), r - a * phi.cos()];
    let spin = p.body_inertia * u[2]
        + if body_only {
            0.0
        } else {
            p.flywheel_inertia * u[3]
        };
    spin + m * (rel[0] * u[1] - rel[1] * u[0])
}

proptest! {
    /// The brake with the contact open transfers exactly ζ0 to the body, leaves the CoM
    /// velocity alone, locks ψ̇ = φ̇ and dissipates ζ0² / (2 I_red); it lifts the disc off
    /// exactly when sin φ < 0 (docs/analysis.md §9.3).
    #[test]
    fn brake_transfers_zeta0_and_lifts_only_behind(
        phi in -3.1f64..3.1, rate in -8.0f64..2.0, zeta0 in 0.005f64..0.2,
    ) {
        prop_assume!(phi.sin().abs() > 1e-3);
        let p = table_5_1();
        let z = SectionState { angle: phi, angular_velocity: rate };
        let i_red = p.reduced_inertia();
        match brake(&p, &z, zeta0) {
            Ok(b) => {
                prop_assert!(phi.sin() < 0.0);
                let before = z.velocities(&p, zeta0);
                let u = b.velocity_after;
                prop_assert!((b.impulse - zeta0).abs() < 1e-12);
                prop_assert!((u[2] - (rate + zeta0 / p.body_inertia)).abs() < 1e-9 * (1.0 + u[2].abs()));
                prop_assert!((u[3] - u[2]).abs() < 1e-9 * (1.0 + u[2].abs()));
                prop_assert!((u[0] - before[0]).abs() < 1e-12 && (u[1] - before[1]).abs() < 1e-12);
                prop_assert!((b.energy_loss - zeta0 * zeta0 / (2.0 * i_red)).abs() < 1e-9 * b.energy_loss);
                // Contact point: -a sin φ ζ0 / I_S upwards.
                prop_assert!((b.normal_velocity + p.eccentricity * phi.sin() * zeta0 / p.body_inertia).abs() < 1e-9);
            }
            Err(NoCycle::NoLiftOff { normal_percussion }) => {
                prop_assert!(phi.sin() > 0.0);
                // Closed contact: one rigid body rolling; momentum about the contact point
                // is conserved, Λ_N = m a sin φ (ω' − φ̇).
                let m = p.total_mass();
                let psi_dot = rate + zeta0 / i_red;
                let omega = (p.rolling_inertia(phi) * rate + p.flywheel_inertia * psi_dot)
                    / (p.rolling_inertia(phi) + p.flywheel_inertia);
                let expected = m * p.eccentricity * phi.sin() * (omega - rate);
                prop_assert!((normal_percussion - expected).abs() < 1e-9 * expected.abs().max(1e-6));
            }
            Err(other) => prop_assert!(false, "unexpected {other}"),
        }
    }

    /// Touchdown with the flywheel locked is the template's rigid-body impact with
    /// I = I_S + I_R; either way it conserves the angular momentum about the contact point
    /// (the flywheel's own when it is free), leaves the disc rolling and never adds energy.
    #[test]
    fn touchdown_matches_rigid_body_and_momentum(
        phi in -1.5f64..1.5, vx in -1.0f64..1.0, vy in -2.0f64..-0.05, w in -5.0f64..25.0,
    ) {
        let u = [vx, vy, w, w];
        let locked = touchdown(&table_5_1(), phi, &u).unwrap();
        let rigid = template::touchdown(&table_5_1().locked_template(), &BodyState {
            q: [0.0, table_5_1().stance_height(phi), phi], u: [vx, vy, w],
        }).unwrap();
        for i in 0..3 {
            prop_assert!((locked.velocity_after[i] - rigid.velocity_after[i]).abs() < 1e-10);
        }
        prop_assert!((locked.velocity_after[3] - locked.velocity_after[2]).abs() < 1e-10);
        prop_assert!((locked.energy_loss - rigid.energy_loss).abs() < 1e-10);
        let p = table_5_1();
        let l0 = momentum_about_contact(&p, phi, u, false);
        prop_assert!((momentum_about_contact(&p, phi, locked.velocity_after, false) - l0).abs() < 1e-10);
        let q = free();
        let f = touchdown(&q, phi, &u).unwrap();
        prop_assert!((f.velocity_after[3] - w).abs() < 1e-12, "free flywheel keeps its speed");
        let l0 = momentum_about_contact(&q, phi, u, true);
        prop_assert!((momentum_about_contact(&q, phi, f.velocity_after, true) - l0).abs() < 1e-10);
        for t in [&locked, &f] {
            let [vx, vy, w, _] = t.velocity_after;
            let rolling = q.rolling_velocity(phi, w);
            prop_assert!((vx - rolling[0]).abs() < 1e-10 && (vy - rolling[1]).abs() < 1e-10);
            prop_assert!(t.energy_loss >= -1e-12);
        }
    }
}

/// The stance ODE with the motor: the energy gained equals the motor's work `T Δ(ψ − φ)`,
/// with the flywheel's `Δψ` integrated here in closed form, and the stance ends at ζ = ζ0.
#[test]
fn stance_energy_balance_and_event() {
    let p = table_5_1();
    let control = Control {
        torque: 0.22,
        impulse_limit: 0.055,
    };
    let start = SectionState {
        angle: 0.35,
        angular_velocity: 2.5,
    };
    let psi_dot0 = 3.0;
    let st = stance(&p, &control, &start, psi_dot0).unwrap();
    let t = st.duration;
    let psi_dot = psi_dot0 + control.torque * t / p.flywheel_inertia;
    assert!((st.flywheel_speed - psi_dot).abs() < 1e-12);
    let zeta = p.reduced_inertia() * (psi_dot - st.end.angular_velocity);
    assert!((zeta - control.impulse_limit).abs() < 1e-10, "ζ = {zeta}");
    let rolling_energy = |s: &SectionState, psi_dot: f64| {
        let [vx, vy] = p.rolling_velocity(s.angle, s.angular_velocity);
        energy(
            &p,
            p.stance_height(s.angle),
            [vx, vy, s.angular_velocity, psi_dot],
        )
    };
    let delta_psi = psi_dot0 * t + 0.5 * control.torque * t * t / p.flywheel_inertia;
    let work = control.torque * (delta_psi - (st.end.angle - start.angle));
    let gained = rolling_energy(&st.end, psi_dot) - rolling_energy(&start, psi_dot0);
    assert!((gained - work).abs() < 1e-9, "ΔE {gained} vs W {work}");
    assert!((st.motor_work - work).abs() < 1e-12);
    assert!(st.reversals >= 1, "the disc rolls back first, then forward");
}

/// One cycle's energy account closes for any section state and control: the energy at the
/// next section state equals the start's plus the motor's work minus the brake and
/// touchdown losses (flight is ballistic).
#[test]
fn cycle_energy_account_closes() {
    for p in [table_5_1(), free()] {
        for (phi, e, t, zeta0) in [
            (-0.8, 0.08, 0.25, 0.056),
            (-0.3, 0.02, 0.15, 0.04),
            (-1.2, 0.1, 0.35, 0.07),
        ] {
            let z = SectionState::from_energy(&p, phi, e).unwrap();
            assert!((z.energy(&p) - e).abs() < 1e-15);
            let control = Control {
                torque: t,
                impulse_limit: zeta0,
            };
            let c = cycle(&p, &z, &control).unwrap();
            let before = section_energy(&p, &z, zeta0);
            let end = SectionState {
                angle: c.stance.end.angle,
                angular_velocity: c.stance.end.angular_velocity,
            };
            let after = section_energy(&p, &end, zeta0);
            let account =
                before + c.stance.motor_work - c.brake.energy_loss - c.touchdown.energy_loss;
            assert!(
                (after - account).abs() < 1e-9,
                "{:?}: {after} vs {account}",
                p.touchdown
            );
            assert!(c.flight_time > 0.0 && c.stance.duration > 0.0);
            assert!(
                (c.next.angle - (end.angle - 2.0 * std::f64::consts::PI * c.revolutions as f64))
                    .abs()
                    < 1e-12
            );
        }
    }
}

fn fixed_point(p: &RobbitParams, phi: f64, e: f64) -> FixedPoint {
    let z = SectionState::from_energy(p, phi, e).unwrap();
    find_fixed_point(p, &z, &SolverSettings::default())
        .unwrap()
        .unwrap_or_else(|r| panic!("no fixed point at ({phi}, {e}): {r}"))
}

/// A fixed point maps its section state to itself (checked by a separate evaluation of the
/// map); on it the motor's work equals the brake and touchdown losses.
#[test]
fn fixed_point_is_a_fixed_point_with_balanced_energy() {
    for p in [table_5_1(), free()] {
        let fp = fixed_point(&p, -0.8, 0.08);
        let next = return_map(&p, &fp.state, &fp.control).unwrap();
        assert!((next.angle - fp.state.angle).abs() < 1e-8);
        assert!((next.angular_velocity - fp.state.angular_velocity).abs() < 1e-7);
        let c = &fp.cycle;
        let losses = c.brake.energy_loss + c.touchdown.energy_loss;
        assert!((c.stance.motor_work - losses).abs() < 1e-7 * losses);
        assert!(fp.speed() > 0.0 && fp.control.torque > 0.0 && fp.control.impulse_limit > 0.0);
        let r = residual(&p, &fp.state, &fp.control).unwrap();
        assert!(r[0].hypot(r[1]) <= 1e-9);
    }
}

/// The eigenvalues describe what iterating the map does: a deviation `δ` from the fixed
/// point becomes `J^k δ` after `k` cycles (checked against the nonlinear map), it decays
/// when max |λ| < 1 and grows when max |λ| > 1.
#[test]
fn linearisation_predicts_the_iterated_map() {
    let p = table_5_1();
    // One stable and one unstable point of the default grid (docs/analysis.md §9.9).
    for (phi, e) in [(-0.8, 0.08), (-0.45, 0.01)] {
        let fp = fixed_point(&p, phi, e);
        let j = fp.jacobian;
        let delta = [1e-5, -2e-5];
        let mut linear = delta;
        let mut z = SectionState {
            angle: fp.state.angle + delta[0],
            angular_velocity: fp.state.angular_velocity + delta[1],
        };
        for _ in 0..6 {
            linear = [
                j[0][0] * linear[0] + j[0][1] * linear[1],
                j[1][0] * linear[0] + j[1][1] * linear[1],
            ];
            z = return_map(&p, &z, &fp.control).unwrap();
        }
        let actual = [
            z.angle - fp.state.angle,
            z.angular_velocity - fp.state.angular_velocity,
        ];
        let size = linear[0].hypot(linear[1]);
        let err = (actual[0] - linear[0]).hypot(actual[1] - linear[1]);
        assert!(
            err < 0.05 * size,
            "({phi}, {e}): J^6 δ = {linear:?}, map {actual:?}"
        );
        let grew = size > delta[0].hypot(delta[1]);
        assert_eq!(
            grew, !fp.stable,
            "({phi}, {e}): max |λ| = {}",
            fp.spectral_radius
        );
        // The finite-difference Jacobian does not depend on its step (1e-6 vs 1e-5).
        let coarse = return_map_jacobian(&p, &fp.state, &fp.control, 1e-5).unwrap();
        for r in 0..2 {
            for c in 0..2 {
                assert!((coarse[r][c] - j[r][c]).abs() < 1e-4 * (1.0 + j[r][c].abs()));
            }
        }
    }
}

/// Section states with the CoM ahead of the contact point cannot hop (the brake does not
/// lift the disc), whatever the control; invalid parameters are errors.
#[test]
fn no_lift_off_and_invalid_parameters() {
    let p = table_5_1();
    let z = SectionState::from_energy(&p, 0.4, 0.05).unwrap();
    match find_fixed_point(&p, &z, &SolverSettings::default()).unwrap() {
        Err(NoFixedPoint::NoCycle {
            reason: NoCycle::NoLiftOff { normal_percussion },
        }) => assert!(normal_percussion > 0.0),
        other => panic!("expected no lift-off, got {other:?}"),
    }
    let bad = RobbitParams {
        eccentricity: 0.3,
        ..table_5_1()
    };
    assert!(matches!(
        bad.validate(),
        Err(AnalysisError::InvalidParameter { .. })
    ));
    assert!(matches!(
        SectionState::from_energy(&p, -0.5, -1.0),
        Err(AnalysisError::InvalidParameter { .. })
    ));
    let grid = FixedPointGrid::new(bad, (-1.0, -0.1), (0.01, 0.1), 2, 2);
    assert!(grid.run(hopsim_theory::grid::NO_PROGRESS).is_err());
}

/// A small grid: every point is classified (fixed point or a reason), fixed points are
/// fixed points, and the grid is row-major with `E_TO` outer.
#[test]
fn small_grid_classifies_every_point() {
    let p = table_5_1();
    let grid = FixedPointGrid::new(p, (-1.2, 0.3), (0.01, 0.1), 4, 3);
    let points = grid.run(hopsim_theory::grid::NO_PROGRESS).unwrap();
    assert_eq!(points.len(), 12);
    for (k, q) in points.iter().enumerate() {
        assert_eq!(q.angle, grid.angles[k % 4]);
        assert_eq!(q.energy, grid.energies[k / 4]);
        assert!(q.fixed_point.is_some() != q.no_fixed_point.is_some());
        if let Some(fp) = &q.fixed_point {
            let r = residual(&p, &fp.state, &fp.control).unwrap();
            assert!(r[0].hypot(r[1]) <= 1e-9);
        }
        // φ_TO = 0.3 lies ahead of the contact point: no lift-off.
        if q.angle > 0.0 {
            assert!(matches!(
                q.no_fixed_point,
                Some(NoFixedPoint::NoCycle {
                    reason: NoCycle::NoLiftOff { .. }
                })
            ));
        }
    }
    assert!(points.iter().filter(|q| q.fixed_point.is_some()).count() >= 6);
}
