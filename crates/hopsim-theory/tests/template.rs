//! The eccentric-wheel template (docs/physics.md §5.1) against independent mechanics.

use hopsim_theory::template::{
    self, contact_jacobian, flight, gap, rolling_velocity, simulate, stance, stance_height,
    takeoff_impulse, touchdown, BodyState, CargoGrid, NoGaitReason, Phase, TemplateCase,
    TemplateParams, TemplateRun,
};
use hopsim_theory::AnalysisError;
use proptest::prelude::*;

/// Energy computed here, independently of the crate: ½ m v² + ½ I ω² + m g y.
fn energy(p: &TemplateParams, s: &BodyState) -> f64 {
    let [vx, vy, w] = s.u;
    0.5 * p.mass * (vx * vx + vy * vy) + 0.5 * p.inertia * w * w + p.mass * p.gravity * s.q[1]
}

fn kinetic(p: &TemplateParams, u: [f64; 3]) -> f64 {
    0.5 * p.mass * (u[0] * u[0] + u[1] * u[1]) + 0.5 * p.inertia * u[2] * u[2]
}

fn cargo2_run() -> TemplateRun {
    simulate(&TemplateCase::Cargo2.params(), true).unwrap()
}

/// Groups the samples of one phase of one hop.
fn segments(run: &TemplateRun, phase: Phase) -> Vec<Vec<BodyState>> {
    let mut out: Vec<Vec<BodyState>> = Vec::new();
    let mut current = None;
    for s in run.trajectory.iter().filter(|s| s.phase == phase) {
        if current != Some(s.hop) {
            out.push(Vec::new());
            current = Some(s.hop);
        }
        out.last_mut().unwrap().push(s.state);
    }
    out
}

#[test]
fn flight_conserves_energy_and_stays_above_ground() {
    let run = cargo2_run();
    let p = &run.params;
    let flights = segments(&run, Phase::Flight);
    assert_eq!(flights.len(), p.hops);
    for samples in &flights {
        let e0 = energy(p, &samples[0]);
        for s in samples {
            assert!((energy(p, s) - e0).abs() < 1e-9 * e0, "flight energy drift");
        }
        // Airborne in between, touching down at the end.
        for s in &samples[1..samples.len() - 1] {
            assert!(gap(p, s.q[1], s.q[2]) > 0.0);
        }
        let last = samples.last().unwrap();
        assert!(gap(p, last.q[1], last.q[2]).abs() < 1e-12);
    }
}

#[test]
fn stance_ode_conserves_energy() {
    // The stance samples come from integrating docs/physics.md §2's ODE; energy along them is
    // computed here from the rolling constraint's velocities.
    let run = cargo2_run();
    let p = &run.params;
    let stances = segments(&run, Phase::Stance);
    assert_eq!(stances.len(), p.hops);
    for samples in &stances {
        let e0 = energy(p, &samples[0]);
        assert!(samples.len() > 3);
        for s in samples {
            assert!(
                (energy(p, s) - e0).abs() < 1e-8 * e0,
                "stance energy drift {}",
                energy(p, s) - e0
            );
        }
    }
}

#[test]
fn stance_duration_matches_energy_quadrature() {
    // Independent stance time: t = ∫ dφ / |φ̇(φ)| with ½ M(φ) φ̇² + V(φ) = E, valid when φ
    // decreases monotonically from φ_TD to φ_TO (true for cargo-2), by composite Simpson.
    let p = TemplateCase::Cargo2.params();
    let a = p.eccentricity();
    let run = simulate(&p, false).unwrap();
    let hop = run.hops[50];
    let start = {
        // Rebuild the post-touchdown state from the hop record.
        let phi = hop.touchdown_angle_rad;
        let mut s = BodyState {
            q: [0.0, stance_height(&p, p.takeoff_angle), p.takeoff_angle],
            u: rolling_velocity(&p, p.takeoff_angle, hop.takeoff_angular_velocity_rad_s),
        };
        let kick = takeoff_impulse(&p, &s).unwrap();
        s.u = kick.velocity_after;
        let fl = flight(&p, &s).unwrap();
        assert!((fl.touchdown.q[2] - phi).abs() < 1e-9);
        let td = touchdown(&p, &fl.touchdown).unwrap();
        BodyState {
            q: [fl.touchdown.q[0], stance_height(&p, phi), phi],
            u: td.velocity_after,
        }
    };
    let st = stance(&p, &start, false).unwrap();
    let m_eff = |phi: f64| {
        p.mass * (p.radius * p.radius + a * a - 2.0 * p.radius * a * phi.cos()) + p.inertia
    };
    let potential = |phi: f64| p.mass * p.gravity * (p.radius - a * phi.cos());
    let e = 0.5 * m_eff(start.q[2]) * start.u[2] * start.u[2] + potential(start.q[2]);
    let integrand = |phi: f64| (m_eff(phi) / (2.0 * (e - potential(phi)))).sqrt();
    let (lo, hi, n) = (p.takeoff_angle, start.q[2], 2000);
    let h = (hi - lo) / n as f64;
    let mut sum = integrand(lo) + integrand(hi);
    for i in 1..n {
        sum += integrand(lo + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    let t_quad = sum * h / 3.0;
    assert!(start.u[2] < 0.0 && st.duration > 0.0);
    assert!(
        (st.duration - t_quad).abs() < 1e-8 * t_quad,
        "ODE {} vs quadrature {}",
        st.duration,
        t_quad
    );
    // Take-off speed from energy conservation.
    let w_to = -((2.0 * (e - potential(lo))) / m_eff(lo)).sqrt();
    assert!((st.takeoff.u[2] - w_to).abs() < 1e-8 * w_to.abs());
    // Displacement of rolling without slip: x = a sin φ − R φ + const.
    let dx = a * (lo.sin() - hi.sin()) - p.radius * (lo - hi);
    assert!((st.takeoff.q[0] - start.q[0] - dx).abs() < 1e-12);
}

#[test]
fn takeoff_impulse_adds_exactly_delta_e() {
    for case in TemplateCase::ALL {
        let p = case.params();
        for w in [0.0, -0.3, -2.0] {
            let s = BodyState {
                q: [0.0, stance_height(&p, p.takeoff_angle), p.takeoff_angle],
                u: rolling_velocity(&p, p.takeoff_angle, w),
            };
            let kick = takeoff_impulse(&p, &s).unwrap();
            let gain = kinetic(&p, kick.velocity_after) - kinetic(&p, s.u);
            assert!((gain - p.energy_input).abs() < 1e-10 * (p.energy_input + kinetic(&p, s.u)));
            // The impulse acts along ρ = (−sin(φ_TO + τ), cos(φ_TO + τ)).
            let angle = p.takeoff_angle + p.impulse_tilt;
            let [zx, zy] = kick.impulse_vector;
            assert!((zx * angle.cos() + zy * angle.sin()).abs() < 1e-12 * kick.impulse);
            // Momentum change equals the impulse (Newton), angular momentum about the CoM too.
            assert!((p.mass * (kick.velocity_after[0] - s.u[0]) - zx).abs() < 1e-9 * kick.impulse);
            assert!((p.mass * (kick.velocity_after[1] - s.u[1]) - zy).abs() < 1e-9 * kick.impulse);
        }
    }
}

#[test]
fn converged_gait_balances_energy_and_moves_forward() {
    for case in [
        TemplateCase::Cargo1,
        TemplateCase::Cargo2,
        TemplateCase::KangarooRat,
    ] {
        let p = case.params();
        let run = simulate(&p, false).unwrap();
        let s = run.summary.expect("cargo and kangaroo-rat hop");
        assert!(s.converged, "{}", case.name());
        // Periodic gait: the energy put in by the impulse leaves in the touchdown.
        assert!((s.touchdown_loss_j - p.energy_input).abs() < 1e-6 * p.energy_input);
        assert!(s.mean_speed_mps > 0.0 && s.stride_m > 0.0);
        assert!(
            (s.mean_speed_mps - s.stride_m * s.hop_frequency_hz).abs() < 1e-9 * s.mean_speed_mps
        );
        assert!(
            (s.cost_of_transport - p.energy_input / (p.mass * p.gravity * s.stride_m)).abs()
                < 1e-12
        );
    }
}

#[test]
fn flight_root_is_the_first_positive_root() {
    // Fast spin: the gap oscillates; check on a fine grid that it stays positive before the root.
    let p = TemplateParams {
        radius: 0.5,
        leg_length: 0.2,
        ..TemplateCase::Cargo2.params()
    };
    let s = BodyState {
        q: [0.0, stance_height(&p, -0.3), -0.3],
        u: [0.5, 2.0, 25.0],
    };
    let fl = flight(&p, &s).unwrap();
    let n = 20_000;
    for i in 1..n {
        let t = fl.duration * i as f64 / n as f64;
        let st = template::flight_state(&p, &s, t);
        assert!(
            gap(&p, st.q[1], st.q[2]) > -1e-12,
            "gap negative at t = {t}"
        );
    }
    assert!(gap(&p, fl.touchdown.q[1], fl.touchdown.q[2]).abs() < 1e-12);
}

#[test]
fn no_energy_means_no_lift_off() {
    let p = TemplateParams {
        energy_input: 0.0,
        ..TemplateCase::Cargo1.params()
    };
    let run = simulate(&p, false).unwrap();
    let no_gait = run.no_gait.expect("no gait");
    assert!(
        matches!(no_gait.reason, NoGaitReason::NoLiftOff { .. }),
        "{no_gait}"
    );
    assert!(run.summary.is_none());
}

#[test]
fn backward_kick_cannot_return_to_takeoff_angle() {
    // With τ = +π/2 the impulse pushes backwards-up; the wheel never reaches φ_TO rolling forward.
    let p = TemplateParams {
        impulse_tilt: 1.2,
        ..TemplateCase::Cargo2.params()
    };
    let run = simulate(&p, false).unwrap();
    assert!(run.summary.is_none(), "{:?}", run.summary);
    assert!(run.no_gait.is_some());
}

#[test]
fn invalid_parameters_are_errors_not_panics() {
    let base = TemplateCase::Cargo2.params();
    for p in [
        TemplateParams { mass: -1.0, ..base },
        TemplateParams {
            radius: 0.0,
            ..base
        },
        TemplateParams {
            leg_length: 1.0,
            ..base
        },
        TemplateParams {
            inertia: f64::NAN,
            ..base
        },
        TemplateParams { hops: 5, ..base },
        TemplateParams {
            energy_input: -3.0,
            ..base
        },
    ] {
        assert!(matches!(
            simulate(&p, false),
            Err(AnalysisError::InvalidParameter { .. })
        ));
    }
    // The averaging window: the error names `window` with the value given.
    for (window, hops, expected) in [
        (0, 100, "invalid parameter `window` = 0"),
        (200, 100, "invalid parameter `window` = 200"),
    ] {
        let p = TemplateParams {
            window,
            hops,
            ..base
        };
        let err = simulate(&p, false).unwrap_err().to_string();
        assert!(err.contains(expected), "{err}");
    }
    let err = TemplateCase::from_name("kangaroo").unwrap_err().to_string();
    for name in ["cargo-1", "cargo-2", "wallaby", "kangaroo-rat"] {
        assert!(err.contains(name), "{err}");
        assert_eq!(TemplateCase::from_name(name).unwrap().name(), name);
    }
}

/// The Cargo grid of Table 3.1 spans `R` from 5.8 m to 0.3 m whatever the leg length:
/// around another base, the `l/R` axis follows the base's `l`, and each cell keeps the
/// base's other parameters.
#[test]
fn cargo_grid_axes_follow_the_base_leg_length() {
    let table = CargoGrid::table_3_1(4, 3);
    assert_eq!(table, CargoGrid::table_3_1_around(table.base, 4, 3));
    let base = TemplateParams {
        leg_length: 0.6,
        mass: 80.0,
        ..CargoGrid::table_3_1_base()
    };
    let grid = CargoGrid::table_3_1_around(base, 4, 3);
    let radii: Vec<f64> = grid.leg_over_radius.iter().map(|r| 0.6 / r).collect();
    assert!(
        (radii[0] - 5.8).abs() < 1e-12 && (radii[3] - 0.3).abs() < 1e-12,
        "{radii:?}"
    );
    assert_eq!(grid.takeoff_angles, table.takeoff_angles);
    let cells = grid.cells();
    assert_eq!(cells.len(), 12);
    assert!(cells.iter().all(|c| c.leg_length == 0.6 && c.mass == 80.0));
    assert!((cells[5].radius - radii[1]).abs() < 1e-12);
    assert_eq!(cells[5].takeoff_angle, grid.takeoff_angles[1]);
}

proptest! {
    /// No restitution-0 no-slip touchdown adds energy.
    #[test]
    fn touchdown_never_gains_energy(
        phi in -3.1f64..3.1,
        vx in -6.0f64..6.0,
        vy in -6.0f64..1.0,
        w in -20.0f64..20.0,
        case_index in 0usize..4,
    ) {
        let p = TemplateCase::ALL[case_index].params();
        let s = BodyState { q: [0.0, stance_height(&p, phi), phi], u: [vx, vy, w] };
        let td = touchdown(&p, &s).unwrap();
        let before = kinetic(&p, s.u);
        let after = kinetic(&p, td.velocity_after);
        prop_assert!(after <= before * (1.0 + 1e-12) + 1e-15);
        prop_assert!((before - after - td.energy_loss).abs() < 1e-9 * (1.0 + before));
        let j = contact_jacobian(&p, phi);
        let v = &j * nalgebra::DVector::from_row_slice(&td.velocity_after);
        prop_assert!(v.norm() < 1e-9 * (1.0 + s.u.iter().map(|x| x.abs()).sum::<f64>()));
    }
}
