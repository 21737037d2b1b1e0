//! Actuators against physics (docs/physics.md §7.4): a motor holding a pendulum where its
//! torque balances gravity, a position servo settling with the offset its gravity load
//! predicts, a velocity servo's first-order response on a free wheel (and its stability far
//! beyond the explicit bound), control and force ranges clamping, and the energy account.

use hopsim_scene::Scene;
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use std::path::Path;

const G: f64 = 9.81;

/// A rod of mass `M` pinned to the world at its top, centre of mass `L` below the pin,
/// inertia `I_C` about its centre of mass, with joint damping (so that it settles) and one
/// actuator `actuator` (the keys of an `[[actuators]]` table) driving its pin.
const M: f64 = 2.0;
const L: f64 = 0.5;
const I_C: f64 = 0.1;

fn scene(body: &str, actuator: &str, duration: f64, dt: f64, gravity: f64) -> Scene {
    let text = format!(
        r#"
[simulation]
duration = {duration:?}
dt = {dt:?}
gravity = {gravity:?}

[environment]
terrain = "none"

[[bodies]]
name = "rod"
base = "pinned"
mass = {M:?}
inertia = {I_C:?}
{body}

[[actuators]]
name = "pin"
joint = "rod"
{actuator}

[initial]
q = [0.0]
"#
    );
    hopsim_scene::parse(&text, Path::new("actuated.toml"), &[])
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The hanging rod (critically damped about its hanging position).
fn pendulum(actuator: &str) -> Scene {
    scene(
        &format!("com = [0.0, {:?}]\ndamping = 5.0", -L),
        actuator,
        20.0,
        1e-3,
        G,
    )
}

/// A wheel turning about its centre of mass: inertia `I_C`, no load.
fn wheel(actuator: &str, duration: f64, dt: f64) -> Scene {
    scene("", actuator, duration, dt, G)
}

/// The coordinate and velocity after every step.
fn trajectory(scene: &Scene) -> Vec<(f64, f64, f64)> {
    struct Collect(Vec<(f64, f64, f64)>);
    impl Observer for Collect {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            self.0.push((v.state.t, v.state.q[0], v.state.u[0]));
            Ok(())
        }
    }
    let mut sim = Simulation::new(scene);
    let mut c = Collect(Vec::new());
    let steps = (scene.settings.duration / scene.settings.dt).round() as u64;
    for _ in 0..steps {
        sim.step(&mut c).unwrap();
    }
    c.0
}

fn settled(scene: &Scene) -> f64 {
    let &(_, q, u) = trajectory(scene).last().unwrap();
    assert!(u.abs() < 1e-9, "still moving: {u}");
    q
}

/// The root of the increasing function `f` on `[lo, hi]` by bisection.
fn root(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn a_motor_holds_the_pendulum_where_its_torque_balances_gravity() {
    // τ = m g l sin q: the rest angle is asin(τ / (m g l)). With gear 2 the torque is 2 ctrl.
    for (gear, ctrl) in [(1.0, 3.0), (2.0, 1.5), (-1.0, -4.0)] {
        let q = settled(&pendulum(&format!(
            "kind = \"motor\"\ngear = {gear:?}\ncontrol = {{ kind = \"constant\", value = {ctrl:?} }}"
        )));
        let expected = (gear * ctrl / (M * G * L)).asin();
        assert!(
            (q - expected).abs() < 1e-9,
            "gear {gear}, control {ctrl}: rest at {q}, expected {expected}"
        );
    }
}

#[test]
fn a_position_servo_settles_with_the_offset_its_gravity_load_predicts() {
    // gear · kp (ctrl − gear q) = m g l sin q: the servo stops short of its target
    // `ctrl / gear` by the angle whose spring torque carries the weight.
    for (gear, kp, ctrl) in [(1.0, 20.0, 0.5), (2.0, 5.0, 0.8), (1.0, 200.0, -0.3)] {
        let q = settled(&pendulum(&format!(
            "kind = \"position\"\ngear = {gear:?}\nkp = {kp:?}\n\
             control = {{ kind = \"constant\", value = {ctrl:?} }}"
        )));
        let balance = |q: f64| M * G * L * q.sin() - gear * kp * (ctrl - gear * q);
        let expected = root(balance, -1.5, 1.5);
        let target = ctrl / gear;
        assert!(
            (q - expected).abs() < 1e-9,
            "kp {kp}: rest at {q}, expected {expected}"
        );
        // The offset is the gravity load's: toward hanging, never zero.
        assert!((target - q) * target > 0.0 && (target - q).abs() > 1e-3);
    }
}

/// The velocity servo `k_v (ω* − ω)` on the free wheel from rest: in the step it is a
/// damper at the mean velocity (§4.9), so the error shrinks by `r = (1 − x/2)/(1 + x/2)`
/// per step (`x = k_v Δt / I`), the continuous `exp(−t k_v / I)` to `O(x³)` per step.
#[test]
fn a_velocity_servo_reaches_its_speed_with_time_constant_inertia_over_gain() {
    let (kv, target, dt) = (2.0, 5.0, 1e-3);
    let time_constant = I_C / kv;
    let runs = trajectory(&wheel(
        &format!(
            "kind = \"velocity\"\nkv = {kv:?}\ncontrol = {{ kind = \"constant\", value = {target:?} }}"
        ),
        1.0,
        dt,
    ));
    let x = kv * dt / I_C;
    let r = (1.0 - 0.5 * x) / (1.0 + 0.5 * x);
    for (k, &(t, _, u)) in runs.iter().enumerate() {
        let scheme = target * (1.0 - r.powi(k as i32 + 1));
        assert!(
            (u - scheme).abs() < 1e-12 * target,
            "step {k}: {u} vs {scheme}"
        );
        // `|r − e^{−x}| ≤ x³/12` per step, `k + 1` steps.
        let exact = target * (1.0 - (-t / time_constant).exp());
        let bound = target * (k + 1) as f64 * x.powi(3) / 12.0;
        assert!((u - exact).abs() <= bound, "t = {t}: {u} vs {exact}");
    }
    // The time constant measured: the first time at 1 − 1/e of the target.
    let reached = runs
        .iter()
        .find(|&&(_, _, u)| u >= target * (1.0 - (-1.0f64).exp()))
        .unwrap()
        .0;
    assert!(
        (reached - time_constant).abs() <= dt,
        "1 − 1/e reached at {reached} s, time constant {time_constant} s"
    );
}

/// Taken explicitly at `u^A`, a velocity servo with `k_v Δt / I > 2` would grow without
/// bound; at the mean velocity it alternates while decaying, and never adds energy.
#[test]
fn a_stiff_velocity_servo_stays_stable_beyond_the_explicit_bound() {
    let (kv, target, dt) = (2000.0, 5.0, 1e-3);
    let x = kv * dt / I_C;
    assert!(x > 2.0);
    let r = ((1.0 - 0.5 * x) / (1.0 + 0.5 * x)).abs();
    let runs = trajectory(&wheel(
        &format!(
            "kind = \"velocity\"\nkv = {kv:?}\ncontrol = {{ kind = \"constant\", value = {target:?} }}"
        ),
        0.2,
        dt,
    ));
    for (k, &(_, _, u)) in runs.iter().enumerate() {
        let bound = target * r.powi(k as i32 + 1) * (1.0 + 1e-12) + 1e-12;
        assert!((u - target).abs() <= bound, "step {k}: {u}");
    }
    assert!((runs.last().unwrap().2 - target).abs() < 1e-9);
}

/// A clamped force no longer depends on the velocity: the wheel turns at the constant
/// acceleration `F_max / I`, which the midpoint scheme integrates exactly.
#[test]
fn force_and_control_ranges_clamp() {
    let dt = 1e-3;
    let cases = [
        // A motor asked for 10 N m with forces limited to [−2, 2] N m.
        (
            "kind = \"motor\"\nforce_range = [-2.0, 2.0]\ncontrol = { kind = \"constant\", value = 10.0 }",
            2.0,
        ),
        // A motor whose control is limited to [−1, 1].
        (
            "kind = \"motor\"\nctrl_range = [-1.0, 1.0]\ncontrol = { kind = \"constant\", value = -7.0 }",
            -1.0,
        ),
        // A velocity servo far from its speed, its force saturated at 1 N m throughout
        // (k_v (5 − ω) ≥ 100 · 2.5 > 1 while ω ≤ 2.5).
        (
            "kind = \"velocity\"\nkv = 100.0\nforce_range = [-1.0, 1.0]\ncontrol = { kind = \"constant\", value = 5.0 }",
            1.0,
        ),
        // Gear 3 on the clamped force: 3 · 2 N m at the joint.
        (
            "kind = \"motor\"\ngear = 3.0\nforce_range = [-2.0, 2.0]\ncontrol = { kind = \"constant\", value = 10.0 }",
            6.0,
        ),
    ];
    for (keys, torque) in cases {
        let runs = trajectory(&wheel(keys, 0.5, dt));
        for &(t, q, u) in &runs {
            let (u_exact, q_exact) = (torque * t / I_C, 0.5 * torque * t * t / I_C);
            assert!(
                (u - u_exact).abs() < 1e-11,
                "{keys}: u({t}) = {u}, expected {u_exact}"
            );
            assert!(
                (q - q_exact).abs() < 1e-11,
                "{keys}: q({t}) = {q}, expected {q_exact}"
            );
        }
    }
}

/// The servo's damping term is booked as damping work, the rest as actuator work: the
/// account closes to rounding on the free wheel (constant `M`, no gravity torque).
#[test]
fn the_energy_account_closes_with_servos() {
    struct Worst(f64);
    impl Observer for Worst {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            let e = &v.record.energy;
            self.0 = self
                .0
                .max(e.balance_error().abs() / e.scale(0.0).max(1e-12));
            Ok(())
        }
    }
    for keys in [
        "kind = \"velocity\"\nkv = 3.0\ncontrol = { kind = \"sine\", amplitude = 4.0, frequency = 2.0 }",
        "kind = \"position\"\nkp = 50.0\nkv = 2.0\ncontrol = { kind = \"pulse\", period = 0.4, width = 0.1, value = 1.0 }",
    ] {
        let s = wheel(keys, 2.0, 1e-3);
        let mut sim = Simulation::new(&s);
        let mut worst = Worst(0.0);
        for _ in 0..2000 {
            sim.step(&mut worst).unwrap();
        }
        assert!(worst.0 < 1e-12, "{keys}: relative balance error {}", worst.0);
    }
}

/// Controls set in code hold from step to step; the scene's signals set theirs before each
/// step the scene's controller takes; invalid controls are refused.
#[test]
fn controls_are_held_set_and_checked() {
    let s = wheel("kind = \"motor\"", 0.1, 1e-3);
    let mut sim = Simulation::new(&s);
    assert_eq!(sim.controls(), &[0.0]);
    sim.set_control(0, 0.5).unwrap();
    struct Nothing;
    impl Observer for Nothing {
        fn on_step(&mut self, _: &StepView<'_>) -> Result<(), RunError> {
            Ok(())
        }
    }
    for _ in 0..10 {
        sim.step(&mut Nothing).unwrap();
    }
    assert_eq!(sim.controls(), &[0.5]);
    let u = sim.state().u[0];
    assert!((u - 0.5 * 0.01 / I_C).abs() < 1e-12, "{u}");
    let mut forces = vec![0.0; 1];
    sim.actuator_forces_to(&mut forces);
    assert_eq!(forces, [0.5]);
    assert!(sim.set_control(1, 0.0).is_err());
    assert!(sim.set_control(0, f64::NAN).is_err());
    assert!(sim.set_controls(&[1.0, 2.0]).is_err());
    assert_eq!(sim.controls(), &[0.5]);
}
