//! The bundled scenes load, and `--set` overrides are applied and checked like file values.

use hopsim_control::{ControllerConfig, Release};
use hopsim_scene::{Override, Scene};
use std::path::{Path, PathBuf};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn load(name: &str, overrides: &[&str]) -> Result<Scene, String> {
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::load(&repo(name), &overrides).map_err(|e| e.to_string())
}

#[test]
fn every_bundled_scene_loads() {
    let mut count = 0;
    for entry in std::fs::read_dir(repo("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            hopsim_scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
            count += 1;
        }
    }
    assert!(count >= 4, "{count} scenes");
}

#[test]
fn robbit_has_the_parameters_of_table_5_1() {
    let s = load("scenes/robbit.toml", &[]).unwrap();
    let m = &s.model;
    assert_eq!(s.coordinates, ["x", "y", "phi", "psi"]);
    assert_eq!((m.bodies[0].mass, m.bodies[0].inertia), (0.974, 3.004e-3));
    assert_eq!((m.bodies[1].mass, m.bodies[1].inertia), (0.431, 1.543e-3));
    assert_eq!((s.settings.dt, s.settings.duration), (2e-4, 20.0));
    let ControllerConfig::MomentumImpulse(c) = &s.controller else {
        panic!("{:?}", s.controller)
    };
    assert_eq!(c.impulse_limit, 0.059);
    assert!(m.contacts.iter().all(|c| c.material.friction == 1.0));
    assert!(m
        .contacts
        .iter()
        .all(|c| c.material.restitution_normal == 0.0));
}

/// The thesis' control (physics.md §5.3): 0.16 N m read as the motor's torque, driving the
/// flywheel through the gear of ratio 2.4.
const MOTOR_TORQUE: f64 = 0.16;
const GEAR_RATIO: f64 = 2.4;

/// The default scene runs the thesis' simulation's cycle (motor off until touchdown), the
/// experiment's scene the experiment's (motor off for 100 ms after each brake); both at the
/// flywheel torque of the thesis' control and on the same robot.
#[test]
fn robbit_scenes_run_the_thesis_controls() {
    let default = load("scenes/robbit.toml", &[]).unwrap();
    let experiment = load("scenes/robbit-experiment.toml", &[]).unwrap();
    let (a, b) = (&default.model, &experiment.model);
    assert_eq!(a.bodies, b.bodies);
    assert_eq!(a.shapes, b.shapes);
    assert_eq!(default.initial, experiment.initial);
    for (scene, release) in [
        (&default, Release::Touchdown { rearm_timeout: 1.0 }),
        (&experiment, Release::OffTime { off_time: 0.1 }),
    ] {
        let ControllerConfig::MomentumImpulse(c) = &scene.controller else {
            panic!("{:?}", scene.controller)
        };
        assert!(
            (c.torque - GEAR_RATIO * MOTOR_TORQUE).abs() < 1e-12,
            "{}",
            c.torque
        );
        assert_eq!(
            (c.impulse_limit, c.release, c.hold_brake),
            (0.059, release, false)
        );
    }
}

/// `release` picks the mode; each mode's timing key has its bounds; zero is allowed for
/// the off time, not for the rearm timeout.
#[test]
fn release_modes_and_their_timing_keys() {
    let release_of = |name: &str, overrides: &[&str]| -> Result<Release, String> {
        match load(name, overrides)?.controller {
            ControllerConfig::MomentumImpulse(c) => Ok(c.release),
            other => panic!("{other:?}"),
        }
    };
    let release = |overrides: &[&str]| release_of("scenes/robbit.toml", overrides);
    let experiment = |overrides: &[&str]| release_of("scenes/robbit-experiment.toml", overrides);
    assert_eq!(
        release(&["controller.rearm_timeout=0.25"]),
        Ok(Release::Touchdown {
            rearm_timeout: 0.25
        })
    );
    // The file's rearm_timeout belongs to the touchdown mode: switching modes needs it gone.
    let e = release(&["controller.release=off_time", "controller.off_time=0"]).unwrap_err();
    assert!(
        e.contains("controller.rearm_timeout: applies to release = \"touchdown\" only"),
        "{e}"
    );
    assert_eq!(
        experiment(&["controller.off_time=0"]),
        Ok(Release::OffTime { off_time: 0.0 })
    );
    let e = experiment(&["controller.off_time=-0.1"]).unwrap_err();
    assert!(
        e.contains("controller.off_time: expected a non-negative number in s"),
        "{e}"
    );
    let e = experiment(&["controller.release=touchdown"]).unwrap_err();
    assert!(
        e.contains("controller.off_time: applies to release = \"off_time\" only"),
        "{e}"
    );
    let e = release(&["controller.rearm_timeout=0"]).unwrap_err();
    assert!(
        e.contains("controller.rearm_timeout: expected a positive number in s"),
        "{e}"
    );
    let e = release(&["controller.release=offtime"]).unwrap_err();
    assert!(e.contains("did you mean 'off_time'"), "{e}");
}

#[test]
fn overrides_change_values_by_path_and_by_name() {
    let s = load(
        "scenes/robbit.toml",
        &[
            "controller.torque=0.2",
            "initial.q.1=0.15",
            "bodies.flywheel.mass=0.5",
            "environment.friction=0.6",
            "simulation.duration=5",
        ],
    )
    .unwrap();
    let ControllerConfig::MomentumImpulse(c) = &s.controller else {
        panic!()
    };
    assert_eq!(c.torque, 0.2);
    assert_eq!(s.initial.q[1], 0.15);
    assert_eq!(s.model.bodies[1].mass, 0.5);
    assert!(s.model.contacts.iter().all(|c| c.material.friction == 0.6));
    assert_eq!(s.settings.duration, 5.0);
    // The window of the summary shrinks with the run.
    assert_eq!(s.settings.speed_window, 5.0);
}

#[test]
fn overridden_values_are_checked_like_file_values() {
    let e = load("scenes/robbit.toml", &["controller.torque=fast"]).unwrap_err();
    assert_eq!(
        e,
        "--set controller.torque=fast: controller.torque: expected a finite number in N m, \
         found the string \"fast\""
    );
    let e = load("scenes/robbit.toml", &["bodies.disc.mass=-1"]).unwrap_err();
    assert!(
        e.starts_with("--set bodies.disc.mass=-1: bodies[0].mass: expected a positive"),
        "{e}"
    );
    let e = load("scenes/robbit.toml", &["controller.torqe=0.2"]).unwrap_err();
    assert!(
        e.contains("controller.torqe: unknown key; did you mean 'torque'?"),
        "{e}"
    );
    let e = load("scenes/robbit.toml", &["simulation.dt=30"]).unwrap_err();
    assert!(e.contains("must be smaller than the duration"), "{e}");
    let e = load("scenes/robbit.toml", &["bodies.rotor.mass=1"]).unwrap_err();
    assert!(e.contains("'rotor' is neither an index"), "{e}");
}

#[test]
fn rest_on_ground_places_the_lowest_shape_on_the_terrain() {
    // Start high, let the scene lower the robot: the disc's lowest point, R − a below the
    // centre of mass at φ = 0, then touches y = 0 (physics.md §2: g_N = y + a cos φ − R).
    let s = load(
        "scenes/robbit.toml",
        &["initial.q.1=0.5", "initial.rest_on_ground=true"],
    )
    .unwrap();
    assert!(
        (s.initial.q[1] - 0.1).abs() < 1e-12,
        "y = {}",
        s.initial.q[1]
    );
    // Tilted: y = R − a cos φ.
    let s = load(
        "scenes/robbit.toml",
        &[
            "initial.q.2=0.7",
            "initial.q.1=0.0",
            "initial.rest_on_ground=true",
        ],
    )
    .unwrap();
    assert!((s.initial.q[1] - (0.2 - 0.1 * 0.7_f64.cos())).abs() < 1e-12);
}
