//! Analytic checks: restitution, Coulomb sliding, stick/slip on inclines, rolling discs.

mod common;
use common::*;
use hopsim_model::{Shape, Terrain, Vec2};
use hopsim_step::ContactState;

/// A ball dropped with `ε_N = 0.5` loses a factor `ε_N²` of apex height per bounce.
#[test]
fn ball_apex_heights_fall_by_restitution_squared() {
    let (r, eps) = (0.1, 0.5);
    let model = single_body(
        1.0,
        0.004,
        Shape::Circle {
            center: Vec2::zeros(),
            radius: r,
        },
        Terrain::flat(0.0),
        material(0.0, eps),
    );
    let dt = 2e-5;
    let mut st = stepper(&model, dt);
    let mut s = state(&[0.0, r + 1.0, 0.0], &[0.0, 0.0, 0.0]);
    let mut apexes = vec![];
    let mut prev_vy = 0.0;
    run(&model, &mut st, &mut s, (2.5 / dt) as usize, |s, _| {
        if prev_vy > 0.0 && s.u[1] <= 0.0 {
            apexes.push(s.q[1] - r);
        }
        prev_vy = s.u[1];
    });
    eprintln!("ball apex heights: {apexes:?}");
    assert!(apexes.len() >= 3, "apexes {apexes:?}");
    // Flight is exact (constant acceleration), so the only error is where the touchdown
    // falls between steps: the contact step starts within `v Δt/2` of the ground and
    // restitutes its start velocity, which puts each apex off by at most `v Δt`
    // (v = sqrt(2 g h0) = 4.4 m/s, 8.9e-5 m; earlier bounces' errors shrink by ε_N²).
    // Measured: 1.0e-5, 1.8e-5, 6.3e-6 m. A restitution off by 1 % moves the first apex
    // by 5e-3 m.
    let tol = (2.0 * G * 1.0_f64).sqrt() * dt;
    let mut expected = 1.0;
    for h in &apexes[..3] {
        expected *= eps * eps;
        eprintln!("apex error {:.3e} m (tolerance {tol:.1e} m)", h - expected);
        assert!(
            (h - expected).abs() < tol,
            "apex {h} vs {expected} ({apexes:?})"
        );
    }
}

fn square(half: f64) -> Shape {
    Shape::rectangle(Vec2::zeros(), half, half)
}

/// A block sliding at `v0` decelerates at `μ g` and stops after `v0² / (2 μ g)`.
#[test]
fn sliding_block_decelerates_at_mu_g_and_stops_where_it_should() {
    let (mu, v0, half): (f64, f64, f64) = (0.3, 2.0, 0.05);
    let model = single_body(
        2.0,
        2.0 * (2.0 * half).powi(2) / 6.0,
        square(half),
        Terrain::flat(0.0),
        material(mu, 0.0),
    );
    let dt = 1e-4;
    let mut st = stepper(&model, dt);
    let mut s = state(&[0.0, half, 0.0], &[v0, 0.0, 0.0]);
    let mut samples = vec![];
    run(&model, &mut st, &mut s, 12_000, |s, rec| {
        samples.push((
            s.t,
            s.u[0],
            rec.contacts.iter().map(|c| c.state).collect::<Vec<_>>(),
        ));
    });
    let stop = v0 * v0 / (2.0 * mu * G);
    // The midpoint scheme is exact for constant deceleration; only the stop falls inside
    // a step, which sticks at `q^A + u^A Δt/2` instead of `q^A + u^A²/(2 μ g)`, at most
    // `μ g Δt²/8` = 3.7e-9 m off (measured 2.5e-9 m). A speed error of `μ g Δt` would
    // move the stop by ~2e-4 m.
    eprintln!("stop distance error {:.3e} m", s.q[0] - stop);
    assert!(
        (s.q[0] - stop).abs() < mu * G * dt * dt,
        "stopped at {} vs {stop}",
        s.q[0]
    );
    // Deceleration in the middle of the slide: exact up to the round-off of 2000 steps
    // (~1e-12 relative; measured 1e-13).
    let (t1, v1, states) = &samples[2000];
    let decel = (v0 - v1) / t1;
    eprintln!("deceleration relative error {:.3e}", decel / (mu * G) - 1.0);
    assert!(
        (decel - mu * G).abs() < 1e-10 * mu * G,
        "deceleration {decel}"
    );
    assert!(
        states.iter().all(|c| *c == ContactState::Slip),
        "{states:?}"
    );
    assert!(
        s.u[0].abs() < 1e-9 && s.u[2].abs() < 1e-6,
        "at rest: {}",
        s.u
    );
}

/// On top of a step the block slides exactly as on flat ground: the step's face (whose
/// line extends behind the block's vertices) must not hold it back.
#[test]
fn block_slides_across_the_top_of_a_step_as_on_flat_ground() {
    let (mu, v0, half, height): (f64, f64, f64, f64) = (0.3, 1.0, 0.05, 0.1);
    let model = single_body(
        2.0,
        2.0 * (2.0 * half).powi(2) / 6.0,
        square(half),
        Terrain::step(-0.2, height),
        material(mu, 0.0),
    );
    let dt = 1e-4;
    let mut st = stepper(&model, dt);
    // Start in contact: `height + half` rounds to 1.4e-17 m above the top, the block
    // would drop for one step without friction and land with two steps' worth,
    // `μ g Δt²` = 2.9e-8 m further than the flat-ground slide.
    let mut s = state(&[0.0, height + half - 1e-12, 0.0], &[v0, 0.0, 0.0]);
    run(&model, &mut st, &mut s, 5000, |_, _| {});
    let stop = v0 * v0 / (2.0 * mu * G);
    // As on flat ground: exact but for the stop inside a step (≤ μ g Δt²/8 = 3.7e-9 m);
    // a face holding the block back by one step's worth of speed would move it ~1e-4 m.
    eprintln!("stop distance error on the step {:.3e} m", s.q[0] - stop);
    assert!(
        (s.q[0] - stop).abs() < mu * G * dt * dt && s.u[0].abs() < 1e-9,
        "stopped at {} (speed {}) vs {stop}",
        s.q[0],
        s.u[0]
    );
}

fn block_on_incline(angle: f64, mu: f64) -> (f64, f64) {
    let half: f64 = 0.05;
    let model = single_body(
        1.0,
        (2.0 * half).powi(2) / 6.0,
        square(half),
        Terrain::incline(angle),
        material(mu, 0.0),
    );
    let dt = 1e-4;
    let mut st = stepper(&model, dt);
    // Resting on the incline, rotated with it.
    let n = Vec2::new(-angle.sin(), angle.cos());
    let mut s = state(&[n.x * half, n.y * half, angle], &[0.0; 3]);
    run(&model, &mut st, &mut s, 5000, |_, _| {});
    let along = Vec2::new(angle.cos(), angle.sin());
    let v = Vec2::new(s.u[0], s.u[1]).dot(&along);
    (v, s.t)
}

/// Below the friction angle the block sticks; above it slides at `g (sin θ - μ cos θ)`.
#[test]
fn block_sticks_below_friction_angle_and_slides_above() {
    let mu: f64 = 0.5;
    let friction_angle = mu.atan();
    let (v, _) = block_on_incline(friction_angle - 0.05, mu);
    assert!(v.abs() < 1e-9, "stuck block moves at {v}");
    let theta: f64 = friction_angle + 0.1;
    let (v, t) = block_on_incline(theta, mu);
    let expected = -G * (theta.sin() - mu * theta.cos()) * t;
    assert!(
        (v - expected).abs() < 2e-3 * expected.abs(),
        "{v} vs {expected}"
    );
}

/// A disc rolls without slip on an incline for `tan θ ≤ μ (1 + m r²/I)` and slips above;
/// both sides are tested 0.02 rad from the limit, where the slip rate
/// `g cos θ (tan θ − tan θ_lim)` is small.
#[test]
fn disc_on_incline_rolls_below_the_slip_limit_and_slips_above() {
    let (m, r, inertia, mu): (f64, f64, f64, f64) = (1.0, 0.1, 0.005, 0.2);
    let limit = (mu * (1.0 + m * r * r / inertia)).atan();
    let run_at = |theta: f64| {
        let model = single_body(
            m,
            inertia,
            Shape::Circle {
                center: Vec2::zeros(),
                radius: r,
            },
            Terrain::incline(theta),
            material(mu, 0.0),
        );
        let mut st = stepper(&model, 1e-4);
        let n = Vec2::new(-theta.sin(), theta.cos());
        let mut s = state(&[n.x * r, n.y * r, 0.0], &[0.0; 3]);
        let mut slip_seen = false;
        run(&model, &mut st, &mut s, 5000, |_, rec| {
            slip_seen |= rec.contacts.iter().any(|c| c.state == ContactState::Slip);
        });
        let along = Vec2::new(theta.cos(), theta.sin());
        (
            Vec2::new(s.u[0], s.u[1]).dot(&along),
            s.u[2],
            s.t,
            slip_seen,
        )
    };
    let theta = limit - 0.02;
    let (v, w, t, slip) = run_at(theta);
    let a_roll = G * theta.sin() / (1.0 + inertia / (m * r * r));
    assert!(!slip, "rolling disc slipped");
    // Constant acceleration from rest (the centred disc's rolling constraint is linear):
    // exact up to round-off (measured 1.7e-14 relative).
    eprintln!(
        "rolling speed relative error {:.3e}",
        -v / (a_roll * t) - 1.0
    );
    assert!(
        (v + a_roll * t).abs() < 1e-10 * a_roll * t,
        "{v} vs {}",
        -a_roll * t
    );
    // Rolling down (v < 0 uphill) turns the disc counter-clockwise: v = -r ω.
    assert!(
        (v + r * w).abs() < 1e-9,
        "no-slip: v = {v}, r ω = {}",
        r * w
    );
    let theta = limit + 0.02;
    let (v, w, t, slip) = run_at(theta);
    let a_slide = G * (theta.sin() - mu * theta.cos());
    assert!(slip, "disc above the limit did not slip");
    // Exact up to round-off, as above (measured 3.6e-14 and 1.1e-12 relative; the slip
    // velocity is a difference of two speeds ~15× larger).
    eprintln!(
        "sliding speed relative error {:.3e}",
        -v / (a_slide * t) - 1.0
    );
    assert!(
        (v + a_slide * t).abs() < 1e-10 * a_slide * t,
        "{v} vs {}",
        -a_slide * t
    );
    let slip_rate = G * theta.cos() * (theta.tan() - limit.tan());
    eprintln!(
        "slip velocity relative error {:.3e}",
        -(v + r * w) / (slip_rate * t) - 1.0
    );
    assert!(
        (v + r * w + slip_rate * t).abs() < 1e-10 * slip_rate * t,
        "slip velocity {} vs {}",
        v + r * w,
        -slip_rate * t
    );
}
