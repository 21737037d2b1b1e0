//! The gallery's closed kinematic chains (docs/classics.md §7, docs/physics.md §8): the
//! four-bar crank–rocker against its closed-form position analysis, and the slider–crank
//! with ideal joints against the reduced equation's reference numbers of docs/classics.md
//! §4.

mod common;

use common::{sampled, scene};
use std::f64::consts::TAU;

/// One step of a run: time, coordinates, velocities, loop error and the energy account.
struct Sample {
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    loop_error: f64,
    balance: f64,
    scale: f64,
    total: f64,
}

fn samples(name: &str) -> (Vec<Sample>, f64) {
    let scene = scene(&format!("classic/{name}"), &[]);
    let (initial, potential) = {
        let mut stepper = hopsim_step::Stepper::new(&scene.model, Default::default());
        let e = stepper.start(&scene.model, &scene.initial).energy;
        (e.total(), e.potential)
    };
    let samples = sampled(&scene, |v| Sample {
        t: v.state.t,
        q: v.state.q.as_slice().to_vec(),
        u: v.state.u.as_slice().to_vec(),
        loop_error: v.record.loop_error,
        balance: v.record.energy.balance_error(),
        scale: v.record.energy.scale(potential),
        total: v.record.energy.total(),
    });
    (samples, initial)
}

/// The four-bar's closed-form position analysis: the rocker angle at crank angle `θ_2` on
/// the scene's (open) branch, from the triangle crank end – rocker pivot – pin.
fn rocker_angle([a, b, c, d]: [f64; 4], theta2: f64) -> f64 {
    let (ax, ay) = (a * theta2.cos(), a * theta2.sin());
    let (ex, ey) = (d - ax, -ay);
    let f = ex.hypot(ey);
    ey.atan2(ex) + ((b * b - f * f - c * c) / (2.0 * c * f)).acos()
}

/// `x − y` wrapped into `(−π, π]`.
fn wrapped(x: f64, y: f64) -> f64 {
    let d = (x - y).rem_euclid(TAU);
    if d > TAU / 2.0 {
        d - TAU
    } else {
        d
    }
}

/// docs/classics.md §7: over 10 s of cranking (about ten revolutions) the rocker follows
/// the closed form at the crank's angle, swinging between its two limit angles; the loop
/// stays closed to 1e-10 m at every step; the energy account closes (no friction, no
/// actuation: the projection's and the loop's share booked).
#[test]
fn the_four_bar_rocker_follows_the_closed_form() {
    let links = [0.1, 0.35, 0.25, 0.3];
    let (samples, initial) = samples("four-bar.toml");
    let (mut worst, mut lowest, mut highest) = (0.0_f64, f64::INFINITY, f64::NEG_INFINITY);
    for s in &samples {
        assert!(s.loop_error <= 1e-10, "t = {}: {}", s.t, s.loop_error);
        worst = worst.max(wrapped(s.q[2], rocker_angle(links, s.q[0])).abs());
        lowest = lowest.min(s.q[2]);
        highest = highest.max(s.q[2]);
        assert!(
            s.balance.abs() <= 1e-2 * s.scale,
            "t = {}: {}",
            s.t,
            s.balance
        );
    }
    let last = samples.last().unwrap();
    eprintln!(
        "four-bar: {:.2} revolutions, rocker error {worst:.2e} rad, rocker {:.3}°..{:.3}°, \
         energy {:.6} -> {:.6} J",
        last.q[0] / TAU,
        lowest.to_degrees(),
        highest.to_degrees(),
        initial,
        last.total
    );
    assert!(last.q[0] / TAU > 9.0);
    assert!(worst <= 1e-9, "{worst}");
    // The rocker's limit angles of the closed form (70.529° and 126.870°).
    assert!(
        (lowest.to_degrees() - 70.529).abs() < 0.01
            && (highest.to_degrees() - 126.870).abs() < 0.01
    );
}

/// docs/classics.md §4, ideal joint: the free crank's first revolution takes 0.067887 s and
/// its slowest speed is 64.907 rad/s at 68.2°, energy conserved (a reduced-equation
/// quadrature); hopsim at the scene's `Δt = 1e-5 s` agrees to its first-order error (7e-5 s,
/// 0.06 rad/s), the slider's pin stays on the guide to 1e-10 m.
#[test]
fn the_ideal_slider_crank_matches_the_reduced_equation() {
    let (samples, initial) = samples("slider-crank-ideal.toml");
    assert!(samples.iter().all(|s| s.loop_error <= 1e-10));
    // The first revolution: the step crossing θ1 = 2π, interpolated.
    let k = samples.iter().position(|s| s.q[0] >= TAU).unwrap();
    let (a, b) = (&samples[k - 1], &samples[k]);
    let revolution = a.t + (TAU - a.q[0]) / (b.q[0] - a.q[0]) * (b.t - a.t);
    let slowest = samples[..k]
        .iter()
        .min_by(|x, y| x.u[0].total_cmp(&y.u[0]))
        .unwrap();
    let drift = samples
        .iter()
        .map(|s| (s.total - initial).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "ideal slider-crank: first revolution {revolution:.6} s, slowest {:.3} rad/s at \
         {:.2}°, energy {initial:.6} J, largest drift {drift:.2e} J",
        slowest.u[0],
        slowest.q[0].to_degrees()
    );
    assert!((initial - 7.495549).abs() < 1e-5, "{initial}");
    assert!((revolution - 0.067887).abs() < 1e-4, "{revolution}");
    assert!((slowest.u[0] - 64.907).abs() < 0.1, "{}", slowest.u[0]);
    assert!((slowest.q[0].to_degrees() - 68.2).abs() < 0.5);
    // The midpoint rule's own first-order error at 150 rad/s (0.084 J at Δt = 1e-5 s,
    // 0.043 J at 5e-6 s; the clearance scene's balance error is −0.074 J, §4).
    assert!(drift < 2e-2 * initial, "{drift}");
    // Nothing turns the slider.
    assert!(samples.iter().all(|s| s.q[2].abs() < 1e-12));
}
