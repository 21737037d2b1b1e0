//! Impacts against the closed-form impact map of docs/physics.md §3, dissipation, the energy
//! ledger and the scheme's convergence.

mod common;
use common::*;
use hopsim_model::{Shape, Terrain, Vec2};
use hopsim_step::{Actuation, ContactState, State};
use nalgebra::{Matrix2, Matrix2x3, Matrix3, Vector3};
use proptest::prelude::*;

const M: f64 = 1.3;
const I: f64 = 0.012;
const R: f64 = 0.2;
const A: f64 = 0.1;

/// `Λ = -(J M⁻¹ Jᵀ)⁻¹ J u⁻` and `ΔE = ½ u⁻ᵀ M_c u⁻` for the eccentric disc touching down
/// without slip, with `J = [w_Tᵀ; w_Nᵀ]` of docs/physics.md §2 written out independently.
fn closed_form_touchdown(phi: f64, u: Vector3<f64>) -> (f64, f64, f64) {
    let j = Matrix2x3::new(1.0, 0.0, R - A * phi.cos(), 0.0, 1.0, -A * phi.sin());
    let m_inv = Matrix3::from_diagonal(&Vector3::new(1.0 / M, 1.0 / M, 1.0 / I));
    let d: Matrix2<f64> = j * m_inv * j.transpose();
    let d_inv = d.try_inverse().unwrap();
    let lambda = -d_inv * j * u;
    let m_c = -j.transpose() * d_inv * j;
    let loss = 0.5 * (u.transpose() * m_c * u)[(0, 0)];
    (lambda[1], lambda[0], loss)
}

/// One touchdown step of size `dt`: (Λ_N, Λ_T, contact work) from the stepper.
fn stepped_touchdown(phi: f64, u: Vector3<f64>, dt: f64, gravity: bool) -> (f64, f64, f64) {
    let mut model = eccentric_disc(M, I, R, A, material(50.0, 0.0));
    if !gravity {
        model = model.with_gravity(Vec2::zeros());
    }
    let mut st = stepper(&model, dt);
    // Place the disc so that the midpoint gap is just closed.
    let phi_a = phi - 0.5 * dt * u[2];
    let y_mid = R - A * phi.cos() - 1e-12;
    let y_a = y_mid - 0.5 * dt * u[1];
    let mut s = state(&[0.0, y_a, phi_a], u.as_slice());
    let before = st.start(&model, &s).energy.kinetic;
    let rec = st.step(&model, &mut s, &Actuation::default()).unwrap();
    assert_eq!(rec.contacts.len(), 1);
    let c = rec.contacts[0];
    assert_eq!(c.state, ContactState::Stick);
    let e = rec.energy;
    if !gravity {
        // Without other forces the kinetic energy changes by the contact work alone.
        assert!((e.kinetic - before - e.contact_work).abs() < 1e-12);
    }
    (c.impulse_normal, c.impulse_tangent, e.contact_work)
}

const PHI: f64 = 0.4;

fn pre_impact() -> Vector3<f64> {
    Vector3::new(0.3, -1.2, -2.0)
}

/// Without gravity the step's percussion is exactly the impact map's, at any `Δt`.
#[test]
fn touchdown_step_reproduces_the_impact_map_without_gravity() {
    let (ln, lt, loss) = closed_form_touchdown(PHI, pre_impact());
    assert!(loss < 0.0);
    for dt in [1e-2, 1e-3, 1e-4] {
        let (sn, stan, de) = stepped_touchdown(PHI, pre_impact(), dt, false);
        assert!(
            (sn - ln).abs() < 1e-10 && (stan - lt).abs() < 1e-10,
            "Λ ({sn}, {stan}) vs ({ln}, {lt})"
        );
        assert!((de - loss).abs() < 1e-10, "ΔE {de} vs {loss}");
    }
}

/// With gravity the step also carries `m g Δt`: the percussion and the energy loss converge
/// to the impact map's as `Δt → 0`.
#[test]
fn touchdown_with_gravity_converges_to_the_impact_map_as_dt_shrinks() {
    let (ln, lt, loss) = closed_form_touchdown(PHI, pre_impact());
    let mut previous = (f64::INFINITY, f64::INFINITY);
    for dt in [1e-2, 1e-3, 1e-4, 1e-5] {
        let (sn, stan, de) = stepped_touchdown(PHI, pre_impact(), dt, true);
        let err = ((sn - ln).powi(2) + (stan - lt).powi(2)).sqrt() / ln.abs();
        let loss_err = (de - loss).abs() / loss.abs();
        assert!(
            err < 0.5 * previous.0,
            "impulse error {err} did not shrink at dt = {dt}"
        );
        assert!(
            loss_err < 0.5 * previous.1,
            "loss error {loss_err} did not shrink at dt = {dt}"
        );
        previous = (err, loss_err);
    }
    eprintln!("touchdown with gravity at dt = 1e-5: relative errors (Λ, ΔE) = {previous:?}");
    assert!(
        previous.0 < 1e-3 && previous.1 < 1e-3,
        "errors at dt = 1e-5: {previous:?}"
    );
}

fn shapes() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (0.05..0.3f64, 0.0..0.8f64).prop_map(|(r, e)| Shape::Circle {
            center: Vec2::new(0.0, e * r),
            radius: r
        }),
        (0.05..0.3f64, 0.2..1.0f64, -0.05..0.05f64).prop_map(|(a, ratio, c)| Shape::Ellipse {
            center: Vec2::new(c, -c),
            semi_x: a,
            semi_y: a * ratio
        }),
        (0.05..0.3f64, 0.2..1.5f64).prop_map(|(r, half)| Shape::Arc {
            center: Vec2::new(0.0, 0.5 * r),
            radius: r,
            start: -std::f64::consts::FRAC_PI_2 - half,
            end: -std::f64::consts::FRAC_PI_2 + half,
        }),
        (
            prop::collection::vec(0.0..1.0f64, 3..7),
            0.05..0.3f64,
            0.3..1.0f64
        )
            .prop_filter_map("a proper convex polygon", |(mut f, w, ratio)| {
                // Vertices on an ellipse at sorted, well-spread angles: convex, CCW.
                f.sort_by(f64::total_cmp);
                let angles: Vec<f64> = f.iter().map(|x| x * std::f64::consts::TAU).collect();
                let spread = angles
                    .windows(2)
                    .map(|p| p[1] - p[0])
                    .chain([angles[0] + std::f64::consts::TAU - angles[angles.len() - 1]])
                    .all(|g| g > 0.3 && g < 2.8);
                spread.then(|| Shape::Polygon {
                    vertices: angles
                        .iter()
                        .map(|t| Vec2::new(w * t.cos(), w * ratio * t.sin()))
                        .collect(),
                })
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]
    /// With `ε = 0` no contact step adds kinetic energy (gravity off, any friction, any
    /// shape, random states), on flat ground and at a step's corner.
    #[test]
    fn inelastic_contact_steps_never_gain_energy(
        shape in shapes(),
        on_step in any::<bool>(),
        x in -0.3..0.3f64,
        phi in -3.2..3.2f64,
        depth in 0.0..1e-3f64,
        vx in -3.0..3.0f64, vy in -3.0..1.0f64, w in -20.0..20.0f64,
        mu in 0.0..2.0f64,
        dt in prop_oneof![Just(1e-4), Just(1e-3)],
    ) {
        let terrain = if on_step { Terrain::step(0.0, 0.05) } else { Terrain::flat(0.0) };
        let model = single_body(1.0, 0.01, shape, terrain, material(mu, 0.0))
            .with_gravity(Vec2::zeros());
        let mut st = stepper(&model, dt);
        // Lower the shape from above until its smallest gap is -depth at the midpoint.
        let mut s = state(&[x, 1.0, phi], &[vx, vy, w]);
        let mut placed = false;
        for _ in 0..50 {
            st.start(&model, &s);
            let lowest = (0..model.contacts().len())
                .filter_map(|i| model.contact_geometry(st.kinematics(), i))
                .map(|g| g.gap)
                .fold(f64::INFINITY, f64::min);
            prop_assume!(lowest.is_finite());
            // Aim 1e-12 below -depth, so round-off never opens the contact.
            let target = -depth - 1e-12;
            if (lowest - target).abs() < 1e-13 {
                placed = true;
                break;
            }
            s.q[1] -= lowest - target;
        }
        // Rarely the smallest gap jumps as a corner contact appears (deep) and disappears.
        prop_assume!(placed);
        s.q[0] = x - 0.5 * dt * vx;
        s.q[1] -= 0.5 * dt * vy;
        s.q[2] = phi - 0.5 * dt * w;
        let before = st.start(&model, &s).energy.kinetic;
        let rec = st.step(&model, &mut s, &Actuation::default()).unwrap();
        prop_assert!(!rec.contacts.is_empty(), "no contact to test");
        prop_assert!(rec.energy.kinetic <= before * (1.0 + 1e-12) + 1e-12,
            "kinetic {} -> {}", before, rec.energy.kinetic);
        prop_assert!(rec.energy.contact_work <= 1e-12);
        // Without other forces the kinetic energy changes by the contact work alone.
        prop_assert!((rec.energy.kinetic - before - rec.energy.contact_work).abs()
            < 1e-12 * (1.0 + before));
    }
}

/// Robbit spun up by a motor and braked: the brake transfers angular momentum exactly
/// (equal rates after it, body momentum change = logged impulse), and the energy account
/// closes to the scheme's error over a run with impacts, rolling and flight.
#[test]
fn robbit_brake_exchanges_momentum_and_the_energy_balance_closes() {
    let model = robbit();
    let dt = 2e-4;
    let mut st = stepper(&model, dt);
    let y0 = 0.2 - 0.1;
    let mut s = state(&[0.0, y0, 0.0, 0.0], &[0.0; 4]);
    st.start(&model, &s);
    let torque = 0.16;
    let mut act = Actuation::default();
    let (i_s, i_r) = (3.004e-3, 1.543e-3);
    let mut braked = false;
    let mut max_error: f64 = 0.0;
    for _ in 0..10_000 {
        act.clear();
        let zeta = i_s * i_r / (i_s + i_r) * (s.u[3] - s.u[2]);
        let brake_now = !braked && zeta >= 0.059;
        if brake_now {
            act.locks.push((0, 1));
            braked = true;
        } else if !braked {
            act.torques.push(motor(torque));
        }
        let before = s.clone();
        let rec = st.step(&model, &mut s, &act).unwrap();
        if brake_now {
            assert!(
                (s.u[2] - s.u[3]).abs() < 1e-9,
                "rates after brake {} {}",
                s.u[2],
                s.u[3]
            );
            let p = rec.locks[0].impulse;
            // Angular momentum of the body about its CoM changes by the lock impulse plus
            // the contact percussions' moments; with the disc's contact impulses included:
            let contact_moment: f64 = rec
                .contacts
                .iter()
                .map(|c| {
                    let r = c.point
                        - Vec2::new(
                            before.q[0] + 0.5 * dt * before.u[0],
                            before.q[1] + 0.5 * dt * before.u[1],
                        );
                    let t = Vec2::new(c.normal.y, -c.normal.x);
                    let f = c.normal * c.impulse_normal + t * c.impulse_tangent;
                    r.x * f.y - r.y * f.x
                })
                .sum();
            let d_body = i_s * (s.u[2] - before.u[2]);
            assert!(
                (d_body - p - contact_moment).abs() < 1e-9 * p.abs().max(1.0),
                "ΔL_body {d_body} vs P {p} + contacts {contact_moment}"
            );
            let d_fly = i_r * (s.u[3] - before.u[3]);
            assert!((d_fly + p).abs() < 1e-9, "ΔL_flywheel {d_fly} vs -P {}", -p);
            assert!(p > 0.05 && p < 0.07, "brake impulse {p}");
        }
        max_error = max_error.max(rec.energy.balance_error().abs());
    }
    assert!(braked, "never reached the impulse limit");
    let e = st.record().energy;
    let scale = e.actuator_work.abs() + e.dissipated().abs();
    eprintln!(
        "robbit: max |balance error| {max_error:.3e} J, actuator work {:.4} J, dissipated {:.4} J",
        e.actuator_work,
        e.dissipated()
    );
    assert!(e.dissipated() > 0.0);
    // Robbit's mass matrix is constant and it has no springs, so the midpoint ledger is
    // exact and the balance closes to round-off (measured 1.3e-13 J against flows of
    // ~5 J); one step of motor work mis-booked (T ψ̇ Δt) would be ~1e-3 J.
    assert!(
        max_error < 1e-9,
        "balance error {max_error} J (flows {scale} J)"
    );
}

/// Reference: the no-slip rolling ODE of docs/physics.md §2 with `T = 0`, integrated by RK4.
fn rolling_reference(phi0: f64, t_end: f64) -> f64 {
    let f = |phi: f64, w: f64| {
        -(M * G * A * phi.sin() + M * A * R * w * w * phi.sin())
            / (M * R * R + M * A * A + I - 2.0 * M * R * A * phi.cos())
    };
    let h = 1e-6;
    let (mut phi, mut w) = (phi0, 0.0);
    for _ in 0..(t_end / h).round() as usize {
        let (k1p, k1w) = (w, f(phi, w));
        let (k2p, k2w) = (w + 0.5 * h * k1w, f(phi + 0.5 * h * k1p, w + 0.5 * h * k1w));
        let (k3p, k3w) = (w + 0.5 * h * k2w, f(phi + 0.5 * h * k2p, w + 0.5 * h * k2w));
        let (k4p, k4w) = (w + h * k3w, f(phi + h * k3p, w + h * k3w));
        phi += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
        w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
    }
    phi
}

/// The rolling eccentric disc converges to the rolling ODE at the scheme's order: the
/// midpoint rule with velocity-level contact constraints is first order, so the slope of
/// `log error` against `log Δt` (least squares over four step sizes) is 1.
#[test]
fn rolling_disc_converges_to_the_rolling_ode() {
    let (phi0, t_end) = (0.6, 0.5);
    let reference = rolling_reference(phi0, t_end);
    let steps = [2e-3, 1e-3, 5e-4, 2.5e-4];
    let errors: Vec<f64> = steps
        .iter()
        .map(|&dt| {
            let model = eccentric_disc(M, I, R, A, material(10.0, 0.0));
            let mut st = stepper(&model, dt);
            let mut s: State = state(&[0.0, R - A * phi0.cos(), phi0], &[0.0; 3]);
            run(
                &model,
                &mut st,
                &mut s,
                (t_end / dt).round() as usize,
                |_, _| {},
            );
            (s.q[2] - reference).abs()
        })
        .collect();
    let (xs, ys): (Vec<f64>, Vec<f64>) = steps
        .iter()
        .zip(&errors)
        .map(|(h, e)| (h.ln(), e.ln()))
        .unzip();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mx, my) = (mean(&xs), mean(&ys));
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    eprintln!(
        "rolling disc: |φ - φ_ref| at t = {t_end} s for dt = 2e-3 … 2.5e-4: {errors:?}, \
         observed order {slope:.3}"
    );
    assert!(
        (slope - 1.0).abs() < 0.1,
        "observed order {slope} from errors {errors:?}"
    );
    assert!(errors[3] < 5e-3 * phi0, "errors {errors:?}");
}
