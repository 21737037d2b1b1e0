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
    for dir in ["scenes", "scenes/classic"] {
        for entry in std::fs::read_dir(repo(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                hopsim_scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
                count += 1;
            }
        }
    }
    assert!(count >= 6, "{count} scenes");
}

/// Several trees in one scene (docs/physics.md §7): coordinates in body order, named by kind;
/// a fixed base without mass; a pinned base's pivot in the world; a prismatic joint's axis
/// scaled to unit length; joint springs and limits as written.
#[test]
fn several_trees_with_floating_pinned_and_fixed_bases() {
    use hopsim_model::{JointKind, JointLimits, Vec2};
    let text = r#"
[simulation]
duration = 1.0
dt = 1e-3

[[bodies]]
name = "hip"
mass = 1.0
inertia = 0.01

[[bodies]]
name = "leg"
parent = "hip"
joint = "prismatic"
axis = [0.0, -2.0]
mass = 0.1
inertia = 1e-4
stiffness = 800.0
rest_position = 0.4
damping = 2.0
limits = [0.2, 0.4]
limit_restitution = 0.3

[[bodies]]
name = "wall"
base = "fixed"
position = [2.0, 0.5]
angle = 0.1

[[bodies]]
name = "arm"
base = "pinned"
pivot = [1.0, 1.0]
com = [0.0, -0.3]
mass = 0.5
inertia = 0.004

[[bodies]]
name = "puck"
base = "floating"
mass = 0.2
inertia = 1e-3

[[shapes]]
body = "wall"
type = "box"
half_width = 0.1
half_height = 0.5

[initial]
q = [0.0, 1.0, 0.0, 0.4, 0.2, 3.0, 1.0, 0.0]
"#;
    let scene = hopsim_scene::parse(text, Path::new("trees.toml"), &[]).unwrap();
    assert_eq!(
        scene.coordinates,
        [
            "x",
            "y",
            "phi",
            "s_leg",
            "theta_arm",
            "x_puck",
            "y_puck",
            "phi_puck"
        ]
    );
    let model = &scene.model;
    assert_eq!(model.dof(), 8);
    let leg = model.bodies()[1].joint.as_ref().unwrap();
    assert_eq!(
        leg.kind,
        JointKind::Prismatic {
            axis: Vec2::new(0.0, -1.0)
        }
    );
    assert_eq!(
        (leg.stiffness, leg.rest_position, leg.damping),
        (800.0, 0.4, 2.0)
    );
    assert_eq!(
        leg.limits,
        Some(JointLimits {
            lower: 0.2,
            upper: 0.4,
            restitution: 0.3
        })
    );
    assert!(model.bodies()[2].is_fixed() && model.bodies()[2].mass == 0.0);
    let arm = model.bodies()[3].joint.as_ref().unwrap();
    assert_eq!(
        (arm.parent, arm.pivot_in_parent),
        (None, Vec2::new(1.0, 1.0))
    );
    assert_eq!(model.bodies()[4].joint, None);
    // The wall's box has no terrain contacts (it is fixed); the limits are two stops.
    assert!(model.contacts().is_empty());
    assert_eq!(model.limits().len(), 2);
}

#[test]
fn robbit_has_the_parameters_of_table_5_1() {
    let s = load("scenes/robbit.toml", &[]).unwrap();
    let m = &s.model;
    assert_eq!(s.coordinates, ["x", "y", "phi", "psi"]);
    assert_eq!(
        (m.bodies()[0].mass, m.bodies()[0].inertia),
        (0.974, 3.004e-3)
    );
    assert_eq!(
        (m.bodies()[1].mass, m.bodies()[1].inertia),
        (0.431, 1.543e-3)
    );
    assert_eq!((s.settings.dt, s.settings.duration), (2e-4, 20.0));
    let ControllerConfig::MomentumImpulse(c) = &s.controller else {
        panic!("{:?}", s.controller)
    };
    assert_eq!(c.impulse_limit, 0.059);
    assert!(m.contacts().iter().all(|c| c.material.friction == 1.0));
    assert!(m
        .contacts()
        .iter()
        .all(|c| c.material.restitution_normal == 0.0));
}

/// The thesis' control (docs/physics.md §5.3): 0.16 N m read as the motor's torque, driving the
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
    assert_eq!(a.bodies(), b.bodies());
    assert_eq!(a.shapes(), b.shapes());
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
        match load(name, overrides)?.setup.controller {
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

/// `cane_schedule` picks the windowed (default) or the thesis' triggered schedule of a
/// timed cane; the permanent modes ignore it, so a thesis scene's cane can be set
/// retracted or extended by `--set`.
#[test]
fn cane_schedules_of_a_timed_cane() {
    use hopsim_control::CaneMode;
    let cane = |overrides: &[&str]| -> Result<CaneMode, String> {
        match load("scenes/canebot-timed.toml", overrides)?
            .setup
            .controller
        {
            ControllerConfig::Pulse(c) => Ok(c.cane),
            other => panic!("{other:?}"),
        }
    };
    let (delay, duration) = (0.1, 0.5);
    assert_eq!(cane(&[]), Ok(CaneMode::Timed { delay, duration }));
    assert_eq!(
        cane(&["controller.cane_schedule=windowed"]),
        Ok(CaneMode::Timed { delay, duration })
    );
    let thesis = "controller.cane_schedule=thesis";
    assert_eq!(cane(&[thesis]), Ok(CaneMode::Triggered { delay, duration }));
    for (mode, expected) in [
        ("retracted", CaneMode::Retracted),
        ("extended", CaneMode::Extended),
    ] {
        let set = format!("controller.cane_mode={mode}");
        assert_eq!(cane(&[thesis, &set]), Ok(expected));
    }
    let e = cane(&["controller.cane_schedule=theses"]).unwrap_err();
    assert!(e.contains("did you mean 'thesis'"), "{e}");
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
    assert_eq!(s.model.bodies()[1].mass, 0.5);
    assert!(s
        .model
        .contacts()
        .iter()
        .all(|c| c.material.friction == 0.6));
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
    // centre of mass at φ = 0, then touches y = 0 (docs/physics.md §2: g_N = y + a cos φ − R).
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

/// `document` gives the file with its overrides applied: written out as TOML and read
/// without overrides, it makes the scene the file makes with them, for every bundled scene.
#[test]
fn the_overridden_document_reads_as_the_file_with_its_overrides() {
    let overrides: Vec<Override> = ["simulation.duration=0.5", "environment.friction=0.7"]
        .iter()
        .map(|o| o.parse().unwrap())
        .collect();
    let mut count = 0;
    for dir in ["scenes", "scenes/classic"] {
        for entry in std::fs::read_dir(repo(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let document = hopsim_scene::document(&text, &path, &overrides).unwrap();
            let written = toml::to_string(&document).unwrap();
            let a = hopsim_scene::parse(&text, &path, &overrides).unwrap();
            let b = hopsim_scene::parse(&written, &path, &[]).unwrap();
            assert_eq!(b.settings.duration, 0.5, "{}", path.display());
            assert_eq!(
                format!(
                    "{:?}",
                    (&a.meta, &a.settings, &a.model, &a.initial, &a.controller)
                ),
                format!(
                    "{:?}",
                    (&b.meta, &b.settings, &b.model, &b.initial, &b.controller)
                ),
                "{}",
                path.display()
            );
            count += 1;
        }
    }
    assert!(count >= 6, "{count} scenes");
    // A bad override path is the error `parse` gives.
    let bad: Override = "bodies.nobody.mass=1".parse().unwrap();
    let text = std::fs::read_to_string(repo("scenes/robbit.toml")).unwrap();
    let e = hopsim_scene::document(&text, Path::new("r.toml"), &[bad]).unwrap_err();
    assert!(
        e.to_string().starts_with("--set bodies.nobody.mass=1:"),
        "{e}"
    );
}
