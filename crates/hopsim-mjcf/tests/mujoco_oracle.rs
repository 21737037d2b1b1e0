//! MuJoCo itself as the oracle: every planar model shipped in the `gymnasium` and
//! `dm_control` Python packages, read by hopsim-mjcf, against what MuJoCo compiles from the
//! same file (`tests/mujoco_oracle.py`): body masses, centres of mass and in-plane inertias
//! (MuJoCo's principal inertias turned back into the world, then about the plane's normal)
//! to 1e-10 relative, welded bodies against MuJoCo's `fusestatic` composition, and every
//! joint's `qpos` address, axis sign, anchor, range and parameters, the actuators and the
//! options.
//!
//! Needs `python3` (or `HOPSIM_PYTHON`) with `mujoco`, `gymnasium` and `dm_control`
//! installed (test-only; .ci/run installs them). Without them the test is skipped with a
//! notice, unless HOPSIM_REQUIRE_PYTHON=1, which makes it fail.

use std::path::Path;
use std::process::Command;

use hopsim_mjcf::{read_file, ActuatorKind, JointKind, NoticeKind, PlanarModel, ReadOptions, Vec2};
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;

const RELATIVE: f64 = 1e-10;

/// A notice that the oracle is missing, or a failure when CI requires it.
fn unavailable(why: &str) {
    let required = std::env::var("HOPSIM_REQUIRE_PYTHON").is_ok_and(|v| v == "1");
    assert!(
        !required,
        "the MuJoCo oracle is unavailable: {why} (HOPSIM_REQUIRE_PYTHON=1)"
    );
    eprintln!("notice: MuJoCo oracle skipped: {why}; install them with `python3 -m pip install mujoco gymnasium dm_control`");
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= RELATIVE * a.abs().max(b.abs()).max(scale)
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn vector(v: &Value) -> Vector3<f64> {
    let a: Vec<f64> = v.as_array().expect("a list").iter().map(number).collect();
    Vector3::new(a[0], a[1], a[2])
}

fn matrix(v: &Value) -> Matrix3<f64> {
    let rows: Vec<Vector3<f64>> = v.as_array().expect("rows").iter().map(vector).collect();
    Matrix3::from_rows(&[
        rows[0].transpose(),
        rows[1].transpose(),
        rows[2].transpose(),
    ])
}

/// MuJoCo's mass properties of one body as (mass, planar centre of mass, in-plane inertia).
fn mujoco_body(model: &PlanarModel, b: &Value) -> (f64, Vec2, f64) {
    let n = model.plane.normal;
    (
        number(&b["mass"]),
        model.plane.project(&vector(&b["xipos"])),
        n.dot(&(matrix(&b["inertia"]) * n)),
    )
}

/// Checks one body; returns the relative difference of the in-plane inertias.
fn check_mass(what: &str, mine: (f64, Vec2, f64), theirs: (f64, Vec2, f64), length: f64) -> f64 {
    assert!(
        close(mine.0, theirs.0, 0.0),
        "{what}: mass {} against MuJoCo's {}",
        mine.0,
        theirs.0
    );
    if theirs.0 > 0.0 {
        let inertia_scale = theirs.0 * length * length;
        assert!(
            close(mine.2, theirs.2, 0.0) || (mine.2 - theirs.2).abs() <= 1e-14 * inertia_scale,
            "{what}: in-plane inertia {} against MuJoCo's {} (difference {:e})",
            mine.2,
            theirs.2,
            mine.2 - theirs.2
        );
        for k in 0..2 {
            assert!(
                close(mine.1[k], theirs.1[k], length),
                "{what}: centre of mass {:?} against MuJoCo's {:?}",
                mine.1,
                theirs.1
            );
        }
        return (mine.2 - theirs.2).abs() / theirs.2.abs().max(f64::MIN_POSITIVE);
    }
    0.0
}

/// Checks one model; returns the largest relative difference of in-plane inertias.
fn check_model(path: &str, oracle: &Value) -> f64 {
    let mut worst: f64 = 0.0;
    let name = Path::new(path)
        .file_name()
        .unwrap()
        .to_string_lossy()
        .to_string();
    let lenient = ReadOptions { unmodelled: true };
    let model = match read_file(path, &ReadOptions::default()) {
        Ok(m) => m,
        Err(e) if name == "swimmer.xml" => {
            // The swimmer swims in a viscous fluid, which the planar model leaves out: an
            // error, located at the option that asks for it, unless the caller allows it.
            assert!(
                e.to_string().contains("<option> attribute `density`")
                    && e.to_string().contains("fluid"),
                "{e}"
            );
            let m = read_file(path, &lenient).unwrap();
            assert!(m.notices.iter().any(|n| n.kind == NoticeKind::Unmodelled));
            m
        }
        Err(e) => panic!("{path}: {e}"),
    };
    let length = 1.0; // metres: the scale of the models' centres of mass

    // Each MJCF body against MuJoCo's unfused body.
    let parts: Vec<(&str, Vec2, (f64, Vec2, f64))> = model
        .bodies
        .iter()
        .flat_map(|b| {
            b.parts.iter().map(move |p| {
                (
                    p.name.as_str(),
                    b.origin,
                    (p.mass, b.origin + p.com, p.inertia),
                )
            })
        })
        .collect();
    for b in oracle["bodies"].as_array().unwrap() {
        let body = b["name"].as_str().unwrap();
        let Some((_, _, mine)) = parts.iter().find(|(n, _, _)| *n == body) else {
            // Welded to the world: its mass has no effect; it must be a world part.
            assert!(
                model.world.iter().any(|p| p.name == body),
                "{name}: body `{body}` missing"
            );
            continue;
        };
        worst = worst.max(check_mass(
            &format!("{name}: body `{body}`"),
            *mine,
            mujoco_body(&model, b),
            length,
        ));
    }
    // Welded bodies against MuJoCo's fusestatic composition; frames against MuJoCo's.
    let moving: Vec<&Value> = oracle["fused"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| b["dofs"].as_i64() > Some(0))
        .collect();
    assert_eq!(moving.len(), model.bodies.len(), "{name}: moving bodies");
    for (mine, b) in model.bodies.iter().zip(&moving) {
        assert_eq!(mine.name, b["name"].as_str().unwrap(), "{name}: body order");
        let what = format!("{name}: welded body `{}`", mine.name);
        worst = worst.max(check_mass(
            &what,
            (mine.mass, mine.origin + mine.com, mine.inertia),
            mujoco_body(&model, b),
            length,
        ));
        let origin = model.plane.project(&vector(&b["xpos"]));
        assert!(
            (mine.origin - origin).norm() <= 1e-12,
            "{what}: origin {:?} against {:?}",
            mine.origin,
            origin
        );
    }

    // Joints: order, qpos address, sign, anchor, parameters.
    let joints = oracle["joints"].as_array().unwrap();
    assert_eq!(joints.len(), model.joints.len(), "{name}: joints");
    for (k, (mine, j)) in model.joints.iter().zip(joints).enumerate() {
        let what = format!("{name}: joint `{}`", mine.name);
        assert_eq!(mine.name, j["name"].as_str().unwrap(), "{name}: joint {k}");
        assert_eq!(
            mine.qpos as i64,
            j["qpos"].as_i64().unwrap(),
            "{what}: qpos address"
        );
        let axis = vector(&j["xaxis"]);
        match mine.kind {
            JointKind::Hinge => {
                assert_eq!(j["type"], 3, "{what}: a hinge");
                assert!(
                    (axis.dot(&model.plane.normal) - mine.sign).abs() < 1e-12,
                    "{what}: sign {} against axis {axis:?}",
                    mine.sign
                );
            }
            JointKind::Slide { axis: a } => {
                assert_eq!(j["type"], 2, "{what}: a slide");
                assert!(
                    (model.plane.project(&axis) - a).norm() < 1e-12 && mine.sign == 1.0,
                    "{what}: axis"
                );
            }
        }
        let anchor = model.plane.project(&vector(&j["xanchor"]));
        let body = &model.bodies[mine.body];
        assert!(
            (body.origin + mine.anchor - anchor).norm() < 1e-12,
            "{what}: anchor {:?} against {anchor:?}",
            body.origin + mine.anchor
        );
        let range = j["range"]
            .as_array()
            .unwrap()
            .iter()
            .map(number)
            .collect::<Vec<_>>();
        match mine.range {
            Some(r) => assert!(
                j["limited"] == true && close(r[0], range[0], 1.0) && close(r[1], range[1], 1.0),
                "{what}: range {r:?} against {range:?}"
            ),
            None => assert!(j["limited"] == false, "{what}: limited in MuJoCo"),
        }
        for (mine, key) in [
            (mine.reference, "ref"),
            (mine.spring_reference, "springref"),
            (mine.stiffness, "stiffness"),
            (mine.damping, "damping"),
            (mine.armature, "armature"),
            (mine.frictionloss, "frictionloss"),
        ] {
            assert!(
                close(mine, number(&j[key]), 1e-300),
                "{what}: {key} {mine} against {}",
                j[key]
            );
        }
    }

    // Actuators.
    let actuators = oracle["actuators"].as_array().unwrap();
    assert_eq!(actuators.len(), model.actuators.len(), "{name}: actuators");
    for (mine, a) in model.actuators.iter().zip(actuators) {
        let what = format!("{name}: actuator on `{}`", model.joints[mine.joint].name);
        assert_eq!(
            model.joints[mine.joint].name,
            a["joint"].as_str().unwrap(),
            "{what}"
        );
        assert_eq!(mine.gear, number(&a["gear"]), "{what}: gear");
        let pair = |key: &str| {
            a[key]
                .as_array()
                .unwrap()
                .iter()
                .map(number)
                .collect::<Vec<_>>()
        };
        assert_eq!(
            mine.ctrl_range.map(|r| r.to_vec()),
            (a["ctrllimited"] == true).then(|| pair("ctrlrange")),
            "{what}: ctrlrange"
        );
        assert_eq!(
            mine.force_range.map(|r| r.to_vec()),
            (a["forcelimited"] == true).then(|| pair("forcerange")),
            "{what}: forcerange"
        );
        let (gain, bias) = match mine.kind {
            ActuatorKind::Motor => (1.0, [0.0, 0.0, 0.0]),
            ActuatorKind::Position { kp, kv } => (kp, [0.0, -kp, -kv]),
            ActuatorKind::Velocity { kv } => (kv, [0.0, 0.0, -kv]),
        };
        assert_eq!(
            (gain, bias.to_vec()),
            (number(&a["gain"]), pair("bias")),
            "{what}: gain and bias"
        );
    }

    assert_eq!(
        model.options.timestep,
        number(&oracle["timestep"]),
        "{name}: timestep"
    );
    let g = vector(&oracle["gravity"]);
    assert!(
        (model.options.gravity - model.plane.project(&g)).norm() < 1e-12,
        "{name}: gravity"
    );
    worst
}

#[test]
fn planar_models_of_gymnasium_and_dm_control_match_mujoco() {
    let python = std::env::var("HOPSIM_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("mujoco_oracle.py");
    // MuJoCo writes MUJOCO_LOG.TXT into its working directory: keep it out of the tree.
    let scratch = tempfile::tempdir().unwrap();
    let out = match Command::new(&python)
        .arg(&script)
        .current_dir(scratch.path())
        .output()
    {
        Ok(out) => out,
        Err(e) => return unavailable(&format!("cannot run {python}: {e}")),
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).expect("the oracle prints JSON");
    if let Some(why) = report["skip"].as_str() {
        return unavailable(why);
    }
    let missing = report["missing"].as_array().unwrap();
    if !missing.is_empty() {
        unavailable(&format!("not installed: {missing:?}"));
    }
    let models = report["models"].as_array().unwrap();
    let worst = models
        .iter()
        .map(|m| check_model(m["path"].as_str().unwrap(), m))
        .fold(0.0, f64::max);
    eprintln!(
        "checked {} models against MuJoCo {}; largest relative difference of in-plane inertias {worst:.1e}",
        models.len(),
        report["mujoco"]
    );
}
