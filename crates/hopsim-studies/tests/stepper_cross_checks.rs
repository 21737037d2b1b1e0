//! The reduced models of docs/physics.md §5 against the Moreau time-stepper (§4): the same
//! mechanics computed two independent ways. Every tolerance is stated next to its check,
//! and the measured differences are printed (`cargo test -- --nocapture`) and recorded in
//! docs/analysis.md §10.

use hopsim_model::{ContactMaterial, Model, Shape, Terrain, TerrainFeature, Vec2};
use hopsim_step::{Actuation, ImpulseCommand, State, StepSettings, Stepper};
use hopsim_studies::robbit_gait::{
    convergence_to_prediction, section_state, simulate, simulate_from_rest, GaitTolerance,
    StepperSettings,
};
use hopsim_theory::fixed_points::{find_fixed_point, FixedPoint, SolverSettings};
use hopsim_theory::obstacle::{self, Wheel};
use hopsim_theory::robbit::{return_map, Control, FlywheelAtTouchdown, RobbitParams, SectionState};
use hopsim_theory::template::{self, BodyState, TemplateCase, TemplateParams};
use nalgebra::DVector;
use std::f64::consts::PI;

fn single_body(mass: f64, inertia: f64, shape: Shape, terrain: Terrain, friction: f64) -> Model {
    Model::single_body(
        mass,
        inertia,
        shape,
        terrain,
        ContactMaterial::inelastic(friction),
    )
    .expect("model")
}

fn stepper(model: &Model, dt: f64) -> Stepper {
    Stepper::new(model, StepSettings::strict(dt))
}

/// (a) The template (§5.1) in the time-stepper: an eccentric disc with no-slip friction
/// (μ = 10) and ε = 0, kicked at its contact point by the [3.6] impulse whenever `φ`
/// passes `φ_TO` downwards in stance. Its mean speed over the last 10 of 100 hops agrees
/// with `hopsim analyze template --case cargo-2` within 1 % at Δt = 1e-4 s.
#[test]
fn template_cargo_2_speed_matches_the_time_stepper() {
    let p: TemplateParams = TemplateCase::Cargo2.params();
    let reduced = template::simulate(&p, false).unwrap();
    let expected = reduced.summary.expect("cargo-2 has a gait");
    assert!(expected.converged);
    let a = p.eccentricity();
    let model = single_body(
        p.mass,
        p.inertia,
        Shape::Circle {
            center: Vec2::new(0.0, a),
            radius: p.radius,
        },
        Terrain::flat(0.0),
        10.0,
    );
    let dt = 1e-4;
    let mut st = stepper(&model, dt);
    let phi0 = p.takeoff_angle;
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![0.0, template::stance_height(&p, phi0), phi0]),
        u: DVector::zeros(3),
    };
    st.start(&model, &state);
    let mut actuation = Actuation::default();
    let mut takeoffs: Vec<(f64, f64)> = Vec::new();
    let (mut airborne_since_kick, mut in_contact, mut kick_now) = (true, true, true);
    let mut previous_phi = phi0;
    while takeoffs.len() < p.hops + 1 && state.t < 200.0 {
        actuation.clear();
        let phi = state.q[2];
        // φ passes φ_TO + 2πk downwards while rolling (the template's trigger).
        let k = ((previous_phi - phi0) / (2.0 * PI)).floor();
        let target = phi0 + 2.0 * PI * k;
        if airborne_since_kick && in_contact && previous_phi > target && phi <= target {
            kick_now = true;
        }
        if kick_now {
            let body = BodyState {
                q: [state.q[0], state.q[1], phi],
                u: [state.u[0], state.u[1], state.u[2]],
            };
            let kick = template::takeoff_impulse(&p, &body).unwrap();
            actuation.impulses.push(ImpulseCommand::Point {
                body: 0,
                offset: Vec2::new(-a * phi.sin(), a * phi.cos() - p.radius),
                impulse: Vec2::new(kick.impulse_vector[0], kick.impulse_vector[1]),
            });
            takeoffs.push((state.t, state.q[0]));
            airborne_since_kick = false;
            kick_now = false;
        }
        previous_phi = phi;
        let rec = st.step(&model, &mut state, &actuation).expect("step");
        in_contact = rec.in_contact();
        // Airborne: no contact in the index set (g_N(q^M) > 0 for all).
        if rec.contacts.is_empty() {
            airborne_since_kick = true;
        }
    }
    assert!(takeoffs.len() > p.hops, "only {} take-offs", takeoffs.len());
    let (t0, x0) = takeoffs[p.hops - p.window];
    let (t1, x1) = takeoffs[p.hops];
    let speed = (x1 - x0) / (t1 - t0);
    let relative = (speed - expected.mean_speed_mps).abs() / expected.mean_speed_mps;
    println!(
        "template cargo-2: stepper {speed:.5} m/s, closed form {:.5} m/s, difference {:.3} % (Δt = {dt})",
        expected.mean_speed_mps,
        100.0 * relative
    );
    assert!(relative < 0.01, "relative difference {relative}");
}

/// (b) A centred wheel rolling into a step (§5.2) loses at the corner what the collision
/// matrix says, `T₀ (1 − k²)`, within 1 % at Δt = 1e-4 s. The loss is the drop of the
/// stepper's mechanical energy from before the first corner contact to 20 steps later
/// (the wheel then pivots on the edge, which conserves energy).
#[test]
fn rolling_into_a_step_loses_the_collision_matrix_energy() {
    let wheel = Wheel {
        mass: 1.0,
        radius: 0.5,
        inertia: 0.125,
        gravity: 9.81,
    };
    let (speed, height, face) = (1.5, 0.1, 1.0);
    let closed = obstacle::corner_impact_loss(&wheel, speed, height).unwrap();
    // The wheel stays on the edge (Fr k² < 1 − h/R) and climbs without assistance.
    let crossing = obstacle::rolling_cost(&wheel, speed, height).unwrap();
    assert_eq!(crossing.climb_assist_j, 0.0);
    let model = single_body(
        wheel.mass,
        wheel.inertia,
        Shape::Circle {
            center: Vec2::zeros(),
            radius: wheel.radius,
        },
        Terrain::step(face, height),
        10.0,
    );
    let corner = model
        .contacts()
        .iter()
        .position(|c| {
            matches!(
                model.terrain().features[c.terrain],
                TerrainFeature::Corner { .. }
            )
        })
        .expect("corner contact");
    for dt in [1e-4] {
        let mut st = stepper(&model, dt);
        let mut state = State {
            t: 0.0,
            q: DVector::from_vec(vec![0.0, wheel.radius, 0.0]),
            u: DVector::from_vec(vec![speed, 0.0, -speed / wheel.radius]),
        };
        let mut energy = st.start(&model, &state).energy.total();
        let none = Actuation::default();
        let mut before = None;
        let mut after = None;
        let mut steps_after = 0;
        for _ in 0..200_000 {
            let previous = energy;
            let rec = st.step(&model, &mut state, &none).expect("step");
            energy = rec.energy.total();
            if before.is_none() && rec.contacts.iter().any(|c| c.contact == corner) {
                before = Some(previous);
            }
            if before.is_some() {
                steps_after += 1;
                if steps_after == 20 {
                    after = Some(energy);
                    break;
                }
            }
        }
        let loss = before.expect("reached the step") - after.expect("20 steps after");
        let relative = (loss - closed).abs() / closed;
        println!(
            "step corner loss: stepper {loss:.6} J, collision matrix {closed:.6} J, difference {:.3} % (Δt = {dt})",
            100.0 * relative
        );
        assert!(relative < 0.01, "relative difference {relative}");
    }
}

fn robbit(touchdown: FlywheelAtTouchdown) -> RobbitParams {
    RobbitParams {
        touchdown,
        ..RobbitParams::default()
    }
}

/// A stable fixed point of the default grid (docs/analysis.md §9.9).
fn stable_fixed_point(p: &RobbitParams) -> FixedPoint {
    let z = SectionState::from_energy(p, -0.8, 0.08).unwrap();
    let fp = find_fixed_point(p, &z, &SolverSettings::default())
        .unwrap()
        .expect("fixed point");
    assert!(fp.stable, "max |λ| = {}", fp.spectral_radius);
    fp
}

/// (c) One cycle of the time-stepper from a section state equals one application of the
/// return map, and the difference vanishes with Δt: from Δt = 4e-4 s to 2.5e-5 s it shrinks
/// by more than 4 (first order would give 16; where the touchdown falls inside a step
/// makes the decrease irregular), to below 1e-3 rad and 2e-3 rad/s. Checked for both
/// flywheel models: `Free` with hopsim-control's `MomentumImpulse` as is, `Locked` with the
/// brake held until touchdown.
#[test]
fn one_robbit_cycle_matches_the_return_map() {
    for touchdown in [FlywheelAtTouchdown::Locked, FlywheelAtTouchdown::Free] {
        let p = robbit(touchdown);
        let z = SectionState::from_energy(&p, -0.8, 0.08).unwrap();
        let control = Control {
            torque: 0.25,
            impulse_limit: 0.056,
        };
        let predicted = return_map(&p, &z, &control).unwrap();
        let mut errors = Vec::new();
        for dt in [4e-4, 1e-4, 2.5e-5] {
            // Start a hair above ζ0 so that the controller brakes in the first step.
            let start = section_state(&p, &z, control.impulse_limit * (1.0 + 1e-9));
            let settings = StepperSettings {
                dt,
                duration: 1.0,
                ..StepperSettings::default()
            };
            let run = simulate(&p, &control, &settings, start).unwrap();
            assert!(run.brakes.len() >= 2);
            assert_eq!(run.brakes[0].t, 0.0);
            let next = run.brakes[1].state;
            let da = next.angle - predicted.angle;
            let dr = next.angular_velocity - predicted.angular_velocity;
            println!(
                "one cycle ({}, Δt = {dt}): stepper ({:.5}, {:.5}), map ({:.5}, {:.5}), Δ = ({da:+.2e} rad, {dr:+.2e} rad/s)",
                touchdown.name(),
                next.angle,
                next.angular_velocity,
                predicted.angle,
                predicted.angular_velocity
            );
            errors.push((da.abs(), dr.abs()));
        }
        let (a_coarse, r_coarse) = errors[0];
        let (a_fine, r_fine) = errors[2];
        assert!(a_fine < 1e-3 && r_fine < 2e-3, "{touchdown:?}: {errors:?}");
        assert!(
            a_fine < a_coarse / 4.0 && r_fine < r_coarse / 4.0,
            "{touchdown:?}: {errors:?}"
        );
    }
}

/// (c) From rest with a stable β* at Δt = 2e-4 s (docs/physics.md §5.3), the stepper's take-off
/// states converge to the predicted fixed point: over the last 10 of the brakes in 20 s
/// within [`GaitTolerance::default`] (0.02 rad, 0.05 rad/s), and the speed between them
/// within 2 % of `stride / period`. This is the model of the brief: flywheel locked at
/// touchdown (the brake held until the motor restarts).
#[test]
fn robbit_from_rest_converges_to_the_predicted_gait() {
    let p = robbit(FlywheelAtTouchdown::Locked);
    let fp = stable_fixed_point(&p);
    let run = simulate_from_rest(&p, &fp.control, &StepperSettings::default()).unwrap();
    let c = convergence_to_prediction(&fp, &run, 10, &GaitTolerance::default()).expect("brakes");
    let first = c.takeoffs[0];
    println!(
        "from rest (locked): β* = ({:.4}, {:.5}), {} brakes, first Δ = ({:+.3}, {:+.3}), last 10 max |Δφ| {:.2e} rad, |Δφ̇| {:.2e} rad/s, speed {:.4} vs {:.4} m/s, max |λ| {:.3}",
        fp.control.torque,
        fp.control.impulse_limit,
        run.brakes.len(),
        first.angle_error,
        first.rate_error,
        c.max_angle_error,
        c.max_rate_error,
        c.simulated_speed,
        c.predicted_speed,
        fp.spectral_radius
    );
    assert!(c.converged, "{c:?}");
    // It starts far away and approaches: the first take-off is off by more than the
    // tolerance, so this is convergence, not a start on the fixed point.
    assert!(first.angle_error.abs() > 0.02 || first.rate_error.abs() > 0.05);
    let speed_error = (c.simulated_speed - c.predicted_speed).abs() / c.predicted_speed;
    assert!(speed_error < 0.02, "speed {speed_error}");
    assert!(run.energy_balance_error.abs() < 1e-6 * run.actuator_work.abs().max(1.0));
}

/// (c) With the flywheel free at touchdown (hopsim-control's one-step brake), the
/// predicted stable gait is stable in the stepper too: started on the section 0.05 rad and
/// 0.25 rad/s away from the fixed point, the take-off states return to it (last 10 of 10 s
/// within the default tolerance). From rest this robot does *not* reach this gait: its
/// second brake falls at `φ > 0`, where the brake cannot lift the disc, and the
/// controller's rearm timeout takes over (printed here; docs/analysis.md §10.3).
#[test]
fn free_flywheel_gait_is_stable_in_the_stepper() {
    let p = robbit(FlywheelAtTouchdown::Free);
    let fp = stable_fixed_point(&p);
    let z = fp.state;
    let offset = SectionState {
        angle: z.angle + 0.05,
        angular_velocity: z.angular_velocity + 0.25,
    };
    let start = section_state(&p, &offset, fp.control.impulse_limit * (1.0 + 1e-9));
    let settings = StepperSettings {
        duration: 10.0,
        ..StepperSettings::default()
    };
    let run = simulate(&p, &fp.control, &settings, start).unwrap();
    let c = convergence_to_prediction(&fp, &run, 10, &GaitTolerance::default()).expect("brakes");
    println!(
        "near the section (free): {} brakes, last 10 max |Δφ| {:.2e} rad, |Δφ̇| {:.2e} rad/s, speed {:.4} vs {:.4} m/s",
        run.brakes.len(),
        c.max_angle_error,
        c.max_rate_error,
        c.simulated_speed,
        c.predicted_speed
    );
    assert!(c.converged, "{c:?}");
    let rest = simulate_from_rest(&p, &fp.control, &StepperSettings::default()).unwrap();
    let no_lift = rest
        .brakes
        .iter()
        .filter(|b| b.state.angle.sin() >= 0.0)
        .count();
    println!(
        "from rest (free): {} brakes in 20 s, {no_lift} of them at sin φ ≥ 0 (no lift-off), final x {:.3} m",
        rest.brakes.len(),
        rest.final_x
    );
}

/// (c) An unstable fixed point is unstable in the stepper, with the predicted multiplier:
/// started on it, the stepper's own discretisation error grows cycle by cycle by the factor
/// λ₁ = −1.50 (alternating sign), measured over brakes 5–10 (above the discretisation level,
/// still linear) to within 15 %.
#[test]
fn unstable_fixed_point_diverges_with_the_predicted_multiplier() {
    let p = robbit(FlywheelAtTouchdown::Locked);
    let z = SectionState::from_energy(&p, -0.45, 0.01).unwrap();
    let fp = find_fixed_point(&p, &z, &SolverSettings::default())
        .unwrap()
        .expect("fixed point");
    assert!(!fp.stable);
    let lambda = fp.eigenvalues[0];
    assert_eq!(lambda.im, 0.0);
    let start = section_state(&p, &z, fp.control.impulse_limit * (1.0 + 1e-9));
    let settings = StepperSettings {
        duration: 5.0,
        ..StepperSettings::default()
    };
    let run = simulate(&p, &fp.control, &settings, start).unwrap();
    let c = convergence_to_prediction(&fp, &run, 10, &GaitTolerance::default()).expect("brakes");
    let rates: Vec<f64> = c.takeoffs.iter().map(|d| d.rate_error).collect();
    assert!(rates.len() > 11, "{} brakes", rates.len());
    let ratios: Vec<f64> = (5..10).map(|k| rates[k + 1] / rates[k]).collect();
    let log_mean = ratios.iter().map(|r| r.abs().ln()).sum::<f64>() / ratios.len() as f64;
    let measured = log_mean.exp();
    println!(
        "unstable fixed point: predicted λ₁ = {:.3}, stepper ratios {ratios:.3?}, geometric mean |ratio| {measured:.3}",
        lambda.re
    );
    assert!(ratios.iter().all(|r| r.signum() == lambda.re.signum()));
    assert!((measured - lambda.re.abs()).abs() < 0.15 * lambda.re.abs());
    assert!(!c.converged);
}

/// The from-rest behaviour over the default grid (10 × 10), both flywheel models: how many
/// stable fixed points the stepper reaches from rest (docs/analysis.md §10.3). Slow
/// (≈ 200 stepper runs); `cargo test --release -- --ignored`.
#[test]
#[ignore]
fn from_rest_convergence_over_the_default_grid() {
    use hopsim_theory::fixed_points::{FixedPointGrid, DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE};
    for touchdown in [FlywheelAtTouchdown::Locked, FlywheelAtTouchdown::Free] {
        let p = robbit(touchdown);
        let grid = FixedPointGrid::new(p, DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE, 10, 10);
        let points = grid.run(hopsim_theory::grid::NO_PROGRESS).unwrap();
        let (mut stable, mut converged, mut consistent, mut consistent_converged) = (0, 0, 0, 0);
        for fp in points
            .iter()
            .filter_map(|q| q.fixed_point.as_ref())
            .filter(|f| f.stable)
        {
            let run = simulate_from_rest(&p, &fp.control, &StepperSettings::default()).unwrap();
            let ok = convergence_to_prediction(fp, &run, 10, &GaitTolerance::default())
                .is_some_and(|c| c.converged);
            stable += 1;
            converged += usize::from(ok);
            if fp.warnings(&p).is_empty() {
                consistent += 1;
                consistent_converged += usize::from(ok);
            }
        }
        println!(
            "{}: {converged} of {stable} stable fixed points reached from rest; {consistent_converged} of the {consistent} without model warnings",
            touchdown.name()
        );
        if touchdown == FlywheelAtTouchdown::Locked {
            assert!(consistent_converged * 4 >= consistent * 3);
        }
    }
}
