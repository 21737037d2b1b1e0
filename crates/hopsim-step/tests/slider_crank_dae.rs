//! The slider–crank with ideal joints (docs/physics.md §8, docs/classics.md): hopsim's crank
//! angle against an independent solution of the mechanism's reduced equation of motion in
//! the crank angle (Lagrange's equation of the one-degree-of-freedom mechanism, integrated
//! by RK4 at a tiny step): first-order agreement at two `Δt`, the error halving with `Δt`.

mod common;

use hopsim_model::{Body, Joint, JointKind, LoopJoint, LoopKind, Model, Vec2};
use hopsim_step::{Actuation, State, StepSettings, Stepper};
use nalgebra::DVector;

const G: f64 = 9.81;
/// Crank `a`, connecting rod `b` (m), masses of crank, rod and slider (kg); the bars uniform.
const A: f64 = 0.1;
const B: f64 = 0.3;
const M1: f64 = 1.0;
const M2: f64 = 1.0;
const M3: f64 = 0.5;
/// The crank's speed at the start (crank along +x), rad/s, and the run's length, s.
const OMEGA: f64 = 20.0;
const DURATION: f64 = 1.0;

/// Crank pinned at the origin, rod on the crank's end, slider on a prismatic joint along x,
/// the rod's end pinned to the slider by a revolute loop joint. Coordinates
/// `(θ, φ − θ, x)`: crank angle, rod angle relative to the crank, slider position.
fn model() -> Model {
    let mut crank = Body::base("crank", M1, M1 * A * A / 12.0);
    crank.joint = Some(Joint::revolute(
        None,
        Vec2::zeros(),
        Vec2::new(A / 2.0, 0.0),
    ));
    let mut rod = Body::base("rod", M2, M2 * B * B / 12.0);
    rod.joint = Some(Joint::revolute(
        Some(0),
        Vec2::new(A / 2.0, 0.0),
        Vec2::new(B / 2.0, 0.0),
    ));
    let mut slider = Body::base("slider", M3, 1e-3);
    let mut slide = Joint::revolute(None, Vec2::zeros(), Vec2::zeros());
    slide.kind = JointKind::Prismatic { axis: Vec2::x() };
    slider.joint = Some(slide);
    common::closed_chain(
        vec![crank, rod, slider],
        G,
        vec![LoopJoint {
            name: "wrist pin".into(),
            body_a: 1,
            point_a: Vec2::new(B / 2.0, 0.0),
            body_b: Some(2),
            point_b: Vec2::zeros(),
            kind: LoopKind::Revolute,
        }],
    )
}

/// The mechanism's kinetic-energy inertia `I(θ)` (`T = ½ I θ̇²`) and potential slope
/// `V'(θ)`, from its closed-form position analysis: `sin φ = −a sin θ / b`,
/// `x = a cos θ + √(b² − a² sin² θ)`.
fn inertia_and_slope(theta: f64) -> (f64, f64) {
    let (s, c) = theta.sin_cos();
    let root = (B * B - A * A * s * s).sqrt();
    let phi = (-A * s / B).asin();
    let dphi = -A * c / root;
    let dx = -A * s - A * A * s * c / root;
    let crank_com = Vec2::new(-s, c) * (A / 2.0);
    let rod_com = Vec2::new(-A * s, A * c) + Vec2::new(-phi.sin(), phi.cos()) * (B / 2.0 * dphi);
    let inertia = M1 * crank_com.norm_squared()
        + M1 * A * A / 12.0
        + M2 * rod_com.norm_squared()
        + M2 * B * B / 12.0 * dphi * dphi
        + M3 * dx * dx;
    let slope = G * (M1 * crank_com.y + M2 * rod_com.y);
    (inertia, slope)
}

/// Lagrange's equation `I θ̈ + ½ I'(θ) θ̇² + V'(θ) = 0` (`I'` by central differences).
fn acceleration(theta: f64, rate: f64) -> f64 {
    let h = 1e-5;
    let (i, slope) = inertia_and_slope(theta);
    let di = (inertia_and_slope(theta + h).0 - inertia_and_slope(theta - h).0) / (2.0 * h);
    -(0.5 * di * rate * rate + slope) / i
}

/// The reference crank angle at the times `k · every` (RK4 at `h`).
fn reference(every: f64, samples: usize) -> Vec<f64> {
    let h = 1e-6;
    let per = (every / h).round() as usize;
    let (mut theta, mut rate) = (0.0, OMEGA);
    let mut out = vec![theta];
    for _ in 0..samples {
        for _ in 0..per {
            let f = |t: f64, r: f64| (r, acceleration(t, r));
            let k1 = f(theta, rate);
            let k2 = f(theta + h / 2.0 * k1.0, rate + h / 2.0 * k1.1);
            let k3 = f(theta + h / 2.0 * k2.0, rate + h / 2.0 * k2.1);
            let k4 = f(theta + h * k3.0, rate + h * k3.1);
            theta += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            rate += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        out.push(theta);
    }
    out
}

/// hopsim's largest crank-angle error against `reference` over the run at step `dt`, and
/// its largest loop error.
fn error_at(dt: f64, every: f64, reference: &[f64]) -> (f64, f64) {
    let model = model();
    // The consistent start: crank along +x at `OMEGA`, the rod's rate `−a ω / b` absolute.
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![0.0, 0.0, A + B]),
        u: DVector::from_vec(vec![OMEGA, -A * OMEGA / B - OMEGA, 0.0]),
    };
    let mut stepper = Stepper::new(&model, StepSettings::strict(dt));
    assert!(stepper.assemble(&model, &mut state).unwrap() < 1e-15);
    stepper.start(&model, &state);
    let per = (every / dt).round() as usize;
    let (mut worst, mut loop_error) = (0.0_f64, 0.0_f64);
    for expected in &reference[1..] {
        for _ in 0..per {
            let record = stepper
                .step(&model, &mut state, &Actuation::default())
                .unwrap();
            loop_error = loop_error.max(record.loop_error);
        }
        worst = worst.max((state.q[0] - expected).abs());
    }
    (worst, loop_error)
}

#[test]
fn the_ideal_slider_crank_agrees_with_its_reduced_equation_to_first_order() {
    let every = 0.01;
    let samples = (DURATION / every).round() as usize;
    let reference = reference(every, samples);
    // The reference turns the crank more than once (it is not a standstill).
    assert!(
        reference[samples] > std::f64::consts::TAU,
        "{}",
        reference[samples]
    );
    let (coarse, loop_coarse) = error_at(1e-3, every, &reference);
    let (fine, loop_fine) = error_at(5e-4, every, &reference);
    eprintln!(
        "slider-crank crank-angle error: {coarse:.3e} rad at dt = 1e-3, {fine:.3e} rad at 5e-4 \
         (ratio {:.3}); loop error {:.1e} m",
        fine / coarse,
        loop_coarse.max(loop_fine)
    );
    assert!(loop_coarse.max(loop_fine) <= 1e-10);
    // The scheme is first order (docs/physics.md §4.6): the phase error grows over the
    // crank's three turns to about 0.36 rad at 1e-3 s.
    assert!(coarse < 0.5, "{coarse}");
    let ratio = fine / coarse;
    assert!((0.35..0.65).contains(&ratio), "{ratio}");
}
