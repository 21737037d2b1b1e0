//! Failures are values, never silent: uncertified LCPs (counted, flagged, an error in
//! strict mode, a frictionless fallback otherwise), non-finite and runaway states (errors
//! naming the step and the time), and the record's gap bookkeeping.

mod common;
use common::*;
use hopsim_lcp::LemkeOptions;
use hopsim_model::Vec2;
use hopsim_step::{Actuation, State, StepError, StepSettings, Stepper};

const R: f64 = 0.2;
const A: f64 = 0.1;
const PHI: f64 = 0.4;

/// An eccentric disc touching down at `φ = 0.4` (gravity off), and a stepper whose Lemke
/// runs may take `pivots` pivots and have no fallbacks.
fn touchdown(strict: bool, pivots: usize) -> (hopsim_model::Model, Stepper, State) {
    let model = eccentric_disc(1.3, 0.012, R, A, material(0.5, 0.0)).with_gravity(Vec2::zeros());
    let dt = 1e-3;
    let u = [0.3, -1.2, -2.0];
    let phi_a = PHI - 0.5 * dt * u[2];
    let y_a = R - A * PHI.cos() - 1e-12 - 0.5 * dt * u[1];
    let settings = StepSettings {
        dt,
        strict,
        lcp: LemkeOptions {
            max_pivots: Some(pivots),
            fallback: false,
            ..LemkeOptions::default()
        },
        ..StepSettings::default()
    };
    let stepper = Stepper::new(&model, settings);
    (model, stepper, state(&[0.0, y_a, phi_a], &u))
}

/// The touchdown LCP needs 3 pivots; with 2 it cannot be certified.
#[test]
fn an_uncertified_lcp_is_an_error_in_strict_mode() {
    let (model, mut st, mut s) = touchdown(true, 2);
    st.start(&model, &s);
    let err = st.step(&model, &mut s, &Actuation::default()).unwrap_err();
    assert!(
        matches!(
            err,
            StepError::Lcp {
                step: 1,
                size: 3,
                contacts: 1,
                status: "pivot_limit",
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("step 1 (t = 0.000000 s)"), "{err}");
    assert_eq!(st.lcp_stats().failures, 1);
    assert_eq!(st.lcp_stats().solves, 1);
}

/// Outside strict mode the step is counted and flagged and uses the frictionless
/// normal-contact LCP: the impulse is the frictionless impact map's
/// `Λ_N = -γ_N / (w_Nᵀ M⁻¹ w_N)`, not zero and not silently the frictional one.
#[test]
fn an_uncertified_lcp_falls_back_to_frictionless_contact_counted_and_flagged() {
    let (model, mut st, mut s) = touchdown(false, 2);
    st.start(&model, &s);
    let u = s.u.clone();
    let rec = st.step(&model, &mut s, &Actuation::default()).unwrap();
    assert!(rec.lcp_failed);
    let c = rec.contacts[0];
    let w_n = [0.0, 1.0, -A * PHI.sin()];
    let gamma_n: f64 = (0..3).map(|i| w_n[i] * u[i]).sum();
    let delassus = w_n[1] * w_n[1] / 1.3 + w_n[2] * w_n[2] / 0.012;
    let expected = -gamma_n / delassus;
    assert!(
        (c.impulse_normal - expected).abs() < 1e-9 * expected,
        "Λ_N {} vs frictionless {expected}",
        c.impulse_normal
    );
    assert_eq!(c.impulse_tangent, 0.0);
    // ξ_T is reported from the end velocity: the contact slides.
    assert!(c.slip_velocity.abs() > 1e-3, "{}", c.slip_velocity);
    assert_eq!(st.lcp_stats().failures, 1);
    // With a certified solve the same step has friction.
    let (model, mut st, mut s) = touchdown(false, 100);
    st.start(&model, &s);
    let rec = st.step(&model, &mut s, &Actuation::default()).unwrap();
    assert!(!rec.lcp_failed && rec.contacts[0].impulse_tangent != 0.0);
    assert_eq!(st.lcp_stats().failures, 0);
}

/// When even the frictionless LCP fails, the step is an error in either mode.
#[test]
fn a_failed_fallback_is_an_error() {
    let (model, mut st, mut s) = touchdown(false, 0);
    st.start(&model, &s);
    let err = st.step(&model, &mut s, &Actuation::default()).unwrap_err();
    assert!(matches!(err, StepError::Lcp { step: 1, .. }), "{err:?}");
}

/// A non-finite state stops the run with an error naming the step and the time.
#[test]
fn non_finite_states_are_errors_naming_step_and_time() {
    let model = robbit();
    let mut st = stepper(&model, 2e-4);
    let mut s = state(&[0.0, 1.0, 0.0, 0.0], &[0.0; 4]);
    st.start(&model, &s);
    for _ in 0..10 {
        st.step(&model, &mut s, &Actuation::default()).unwrap();
    }
    s.u[2] = f64::NAN;
    let err = st.step(&model, &mut s, &Actuation::default()).unwrap_err();
    assert_eq!(
        err,
        StepError::NonFinite {
            step: 11,
            t: s.t,
            what: "u at the start of the step"
        }
    );
    assert!(
        err.to_string().starts_with("step 11 (t = 0.002000 s)"),
        "{err}"
    );
    // A non-finite command poisons the velocities within the step.
    let mut s = state(&[0.0, 1.0, 0.0, 0.0], &[0.0; 4]);
    st.start(&model, &s);
    let mut act = Actuation::default();
    act.torques.push(hopsim_step::TorqueCommand {
        body: 1,
        reaction: None,
        torque: f64::NAN,
    });
    let err = st.step(&model, &mut s, &act).unwrap_err();
    assert!(
        matches!(
            err,
            StepError::NonFinite {
                step: 1,
                what: "q",
                ..
            }
        ),
        "{err:?}"
    );
}

/// A speed above `max_speed` is a runaway error with the offending coordinate.
#[test]
fn runaway_states_are_errors() {
    let model = robbit();
    let mut st = Stepper::new(
        &model,
        StepSettings {
            dt: 2e-4,
            max_speed: 50.0,
            ..StepSettings::default()
        },
    );
    let mut s = state(&[0.0, 1.0, 0.0, 0.0], &[0.0; 4]);
    st.start(&model, &s);
    let mut act = Actuation::default();
    act.torques.push(motor(1.0));
    let err = loop {
        match st.step(&model, &mut s, &act) {
            Ok(_) => continue,
            Err(e) => break e,
        }
    };
    let StepError::Runaway {
        step, index, speed, ..
    } = err
    else {
        panic!("{err:?}")
    };
    // ψ̇ = T t / I_R reaches 50 rad/s after 50 I_R / T = 0.077 s.
    assert_eq!(index, 3);
    assert!(speed > 50.0 && (step as f64 * 2e-4 - 50.0 * 1.543e-3).abs() < 1e-3);
    assert!(
        err.to_string().contains(&format!("step {step} (t = ")),
        "{err}"
    );
}

/// `min_gap` and `max_penetration` are the extreme gaps over the enabled contacts at the
/// end of the step; `+∞` and 0 when no contact can touch.
#[test]
fn the_record_carries_the_smallest_gap_of_the_enabled_contacts() {
    let model = two_body_hopper(0.8);
    let mut st = stepper(&model, 1e-4);
    let mut s = two_body_hopper_state(&model, 0.05);
    st.start(&model, &s);
    let act = Actuation::default();
    for _ in 0..3 {
        st.step(&model, &mut s, &act).unwrap();
        let min = (0..model.contacts().len())
            .filter_map(|i| model.contact_geometry(st.kinematics(), i))
            .map(|g| g.gap)
            .fold(f64::INFINITY, f64::min);
        let rec = st.record();
        assert_eq!(rec.min_gap, min);
        assert!(rec.min_gap > 0.04 && rec.max_penetration == 0.0);
    }
    for i in 0..model.contacts().len() {
        st.set_contact_enabled(i, false);
    }
    let rec = st.step(&model, &mut s, &act).unwrap();
    assert_eq!((rec.min_gap, rec.max_penetration), (f64::INFINITY, 0.0));
    // Sunk 1 mm into the ground: the penetration is the negative gap.
    for i in 0..model.contacts().len() {
        st.set_contact_enabled(i, true);
    }
    let mut s = two_body_hopper_state(&model, -1e-3);
    let rec = st.start(&model, &s);
    assert!((rec.min_gap + 1e-3).abs() < 1e-12 && (rec.max_penetration - 1e-3).abs() < 1e-12);
    let rec = st.step(&model, &mut s, &act).unwrap();
    assert!((rec.max_penetration + rec.min_gap).abs() < 1e-15);
}
