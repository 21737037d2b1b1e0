//! Golden contact-impulse trace of a short eccentric-disc drop and roll.
//!
//! The disc of docs/physics.md §2 (`R = 0.2 m`, `a = 0.1 m`, Robbit's mass and locked
//! inertia, `μ = 1`, `ε = 0`) is dropped from 3 cm moving forward and spinning fast; it
//! touches down sliding, rolls, is flung off the ground by its whirling eccentric mass
//! (`ε = 0`: no bounce from restitution), lands again and rolls; 0.5 s at `Δt = 5e-4 s`. Every
//! step's `Λ_N`, `Λ_T` is compared with `tests/golden/eccentric_disc_drop_and_roll.csv`
//! (repository root) within [`TraceTolerance::default`]: `|a − b| ≤ 1e-9 N s + 1e-6 ·
//! max(|a|, |b|)`, far above round-off differences between builds, far below any change
//! of the physics (a 1 % change of `μ` moves them by more than 1e-4 N s, checked below).
//!
//! A deliberate change of the physics regenerates the file with
//! `HOPSIM_BLESS=1 cargo test -p hopsim-record --release --test golden_trace`; review the
//! diff before committing it (docs/validation.md).

use hopsim_model::{ContactMaterial, Model, Shape, Terrain, Vec2};
use hopsim_record::{ImpulseTrace, TraceTolerance};
use hopsim_step::{Actuation, State, StepSettings, Stepper};
use nalgebra::DVector;
use std::path::Path;

/// The drop-and-roll run with friction `mu`: its trace and the number of touchdowns.
fn drop_and_roll(mu: f64) -> (ImpulseTrace, usize) {
    let (r, a) = (0.2, 0.1);
    let disc = Shape::Circle {
        center: Vec2::new(0.0, a),
        radius: r,
    };
    let material = ContactMaterial::inelastic(mu);
    let model = Model::single_body(
        1.405,
        3.004e-3 + 1.543e-3,
        disc,
        Terrain::flat(0.0),
        material,
    )
    .unwrap();
    let dt = 5e-4;
    let mut stepper = Stepper::new(&model, StepSettings::strict(dt));
    let phi: f64 = 0.3;
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![0.0, r - a * phi.cos() + 0.03, phi]),
        u: DVector::from_vec(vec![4.0, 0.0, -20.0]),
    };
    let mut trace = ImpulseTrace::default();
    let mut touchdowns = 0;
    let mut was_in_contact = false;
    let passive = Actuation::default();
    stepper.start(&model, &state);
    for _ in 0..(0.5 / dt).round() as usize {
        let rec = stepper.step(&model, &mut state, &passive).expect("step");
        trace.push_record(&model, rec);
        touchdowns += usize::from(rec.in_contact() && !was_in_contact);
        was_in_contact = rec.in_contact();
    }
    (trace, touchdowns)
}

#[test]
fn eccentric_disc_drop_and_roll_matches_the_golden_trace() {
    let (trace, touchdowns) = drop_and_roll(1.0);
    assert!(
        touchdowns >= 2,
        "the disc should bounce and land again ({touchdowns} touchdowns)"
    );
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/golden/eccentric_disc_drop_and_roll.csv");
    if let Err(e) = trace.check_golden(&path, TraceTolerance::default()) {
        panic!("{e}");
    }
    // The comparison can fail: a 1 % change of μ is far outside the tolerance.
    let (other, _) = drop_and_roll(0.99);
    let difference = trace
        .first_difference(&other, TraceTolerance::default())
        .expect("μ = 0.99 differs from μ = 1");
    assert!(difference.max_abs > 1e-4, "{difference}");
}
