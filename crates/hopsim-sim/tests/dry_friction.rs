//! Dry friction in the joints (docs/physics.md §7.5) against its closed forms: a spinning
//! wheel stops at `t* = I ω0 / F` after turning `I ω0² / (2F)` and stays stopped; a slider
//! on an incline holds when `F ≥ m g sin α` and otherwise accelerates at `g sin α − F/m`; a
//! pendulum held by its joint's friction; every run's energy account closes.

use hopsim_scene::Scene;
use hopsim_sim::Simulation;
use std::path::Path;

fn scene(text: &str, overrides: &[String]) -> Scene {
    let overrides: Vec<_> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::parse(text, Path::new("dry_friction.toml"), &overrides).unwrap()
}

/// Steps `sim` `steps` times, checking the energy account after each step to `tolerance`
/// J; returns the joint friction's work.
fn run(sim: &mut Simulation, steps: usize, tolerance: f64) -> f64 {
    for _ in 0..steps {
        sim.step(&mut ()).unwrap();
        let e = sim.stepper().record().energy;
        assert!(e.balance_error().abs() <= tolerance, "{e:?}");
        assert_eq!(sim.stepper().lcp_stats().failures, 0);
    }
    sim.stepper().record().energy.dry_friction_work
}

/// A wheel pinned at its centre of mass (`I = 1e-4 kg m²`, no gravity torque) spun at
/// 10 rad/s with a joint friction `F = 0.01 N m`.
const WHEEL: &str = r#"
[simulation]
duration = 1.0
dt = 7e-4

[[bodies]]
name = "wheel"
base = "pinned"
pivot = [0.0, 1.0]
mass = 0.1
inertia = 1e-4
dry_friction = 0.01

[initial]
q = [0.0]
u = [10.0]
"#;

/// The midpoint scheme decelerates by exactly `F Δt / I` per slipping step, so the rate is
/// the closed form's on the grid; the stopping step ends at rest, and the wheel stays
/// there. The angle is the closed form's to `O(Δt²)` (the stop falls inside a step); the
/// friction's work is the whole kinetic energy.
#[test]
fn a_spinning_wheel_stops_where_and_when_coulomb_says() {
    let (inertia, friction, omega0) = (1e-4, 0.01, 10.0);
    let s = scene(WHEEL, &[]);
    let dt = s.settings.dt;
    let mut sim = Simulation::new(&s);
    let stop = inertia * omega0 / friction;
    let deceleration = friction / inertia;
    let mut step = 0;
    while sim.state().t + dt < stop {
        sim.step(&mut ()).unwrap();
        step += 1;
        let t = sim.state().t;
        let exact = omega0 - deceleration * t;
        assert!(
            (sim.state().u[0] - exact).abs() <= 1e-9,
            "step {step}: ω {} vs {exact}",
            sim.state().u[0]
        );
    }
    let work = run(&mut sim, 1000, 1e-12);
    assert!(sim.state().u[0].abs() < 1e-12, "ω = {}", sim.state().u[0]);
    let angle = inertia * omega0 * omega0 / (2.0 * friction);
    assert!(
        (sim.state().q[0] - angle).abs() <= deceleration * dt * dt,
        "stopped at {} rad, closed form {angle} rad",
        sim.state().q[0]
    );
    let kinetic = 0.5 * inertia * omega0 * omega0;
    assert!(
        (work + kinetic).abs() <= 1e-12,
        "work {work} J vs −{kinetic} J"
    );
}

/// A slider of 2 kg on a rail inclined at `α = 0.3 rad`; its joint's friction is `ratio`
/// times the weight's component along the rail.
fn incline(ratio: f64) -> Scene {
    let (m, g, alpha) = (2.0_f64, 9.81, 0.3_f64);
    let friction = ratio * m * g * alpha.sin();
    let text = format!(
        r#"
[simulation]
duration = 1.0
dt = 1e-3

[[bodies]]
name = "rail"
base = "fixed"

[[bodies]]
name = "slider"
parent = "rail"
joint = "prismatic"
axis = [{}, {}]
mass = {m}
inertia = 0.01
dry_friction = {friction}

[initial]
q = [0.0]
u = [0.0]
"#,
        alpha.cos(),
        alpha.sin()
    );
    scene(&text, &[])
}

/// At rest on the incline: a friction bound above the weight's pull holds the slider
/// exactly (a bound just below lets it go); below it, the slider accelerates down at
/// `g sin α − F/m`, on the closed form `s = −a t²/2` (the midpoint scheme is exact for a
/// constant acceleration).
#[test]
fn a_slider_on_an_incline_holds_or_slips_at_its_bound() {
    let (g, alpha) = (9.81_f64, 0.3_f64);
    let mut held = Simulation::new(&incline(1.001));
    run(&mut held, 1000, 1e-12);
    assert!(held.state().q[0].abs() < 1e-12 && held.state().u[0].abs() < 1e-12);
    for ratio in [0.999, 0.5, 0.0] {
        let mut sim = Simulation::new(&incline(ratio));
        let work = run(&mut sim, 1000, 1e-9);
        let a = g * alpha.sin() * (1.0 - ratio);
        let t = sim.state().t;
        let exact = -0.5 * a * t * t;
        assert!(
            (sim.state().q[0] - exact).abs() <= 1e-9 * (1.0 + exact.abs()),
            "ratio {ratio}: s = {} m vs {exact} m",
            sim.state().q[0]
        );
        // The friction's work is the bound times the distance slid.
        let bound = ratio * 2.0 * g * alpha.sin();
        assert!(
            (work + bound * exact.abs()).abs() <= 1e-9,
            "ratio {ratio}: {work} J"
        );
    }
}

/// A pendulum (a point mass 0.5 kg at 0.3 m, pinned) released at 0.4 rad from the
/// vertical: gravity's torque is `m g l sin θ`; the joint's friction holds it above that
/// torque, and it swings below.
#[test]
fn a_pendulum_is_held_by_its_joints_friction_above_the_gravity_torque() {
    let (m, g, l, theta) = (0.5_f64, 9.81, 0.3, 0.4_f64);
    let torque = m * g * l * theta.sin();
    let text = |friction: f64| {
        format!(
            r#"
[simulation]
duration = 1.0
dt = 1e-3

[[bodies]]
name = "pendulum"
base = "pinned"
pivot = [0.0, 1.0]
com = [0.0, -{l}]
mass = {m}
inertia = 1e-6
dry_friction = {friction}

[initial]
q = [{theta}]
u = [0.0]
"#
        )
    };
    let mut held = Simulation::new(&scene(&text(1.01 * torque), &[]));
    run(&mut held, 500, 1e-12);
    assert!((held.state().q[0] - theta).abs() < 1e-12);
    let mut swings = Simulation::new(&scene(&text(0.5 * torque), &[]));
    let work = run(&mut swings, 500, 1e-6);
    assert!(swings.state().q[0] < theta - 0.1, "{}", swings.state().q[0]);
    assert!(work < 0.0);
}

/// The gallery's four-bar (scenes/classic/four-bar.toml, a 10 kg m² flywheel on its crank)
/// with friction in its three joints: one coordinate's worth of motion against three
/// friction rows, through the loop joint's rows. It comes to rest and stays there, the
/// friction's work is the energy it lost, and the loop stays closed.
#[test]
fn a_four_bar_with_friction_in_every_joint_comes_to_rest_on_its_loop() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/classic/four-bar.toml"),
    )
    .unwrap();
    let overrides: Vec<String> = ["crank", "coupler", "rocker"]
        .iter()
        .map(|b| format!("bodies.{b}.dry_friction=5.0"))
        .collect();
    let s = scene(&text, &overrides);
    let mut sim = Simulation::new(&s);
    let e0 = sim.stepper().record().energy.total();
    let work = run(&mut sim, 8000, 1e-6 * e0.abs().max(1.0));
    let record = sim.stepper().record();
    assert!(
        sim.state().u.iter().all(|u| u.abs() < 1e-9),
        "still moving: {:?}",
        sim.state().u
    );
    assert!(
        record.loop_error <= 1e-10,
        "loop error {}",
        record.loop_error
    );
    let lost = e0 - record.energy.total();
    assert!(lost > 100.0, "lost {lost} J");
    assert!(
        (work + lost).abs() <= 1e-3 * lost,
        "friction's work {work} J, energy lost {lost} J"
    );
}
