//! MuJoCo models imported as scenes (docs/mjcf.md, "From MJCF to a scene") against closed
//! forms written from the MJCF text itself: a pendulum whose hinge has a `ref` and an
//! axis against the plane's normal (its coordinate is `qpos`: its bob where MuJoCo's
//! rotation about `+y` puts it, its mass matrix `I + m l²`, gravity's torque, the spring
//! about `springref`); a slide with a `ref` and an armature; MuJoCo's contact filter and
//! friction rule; and what cannot be imported, said.

use hopsim_model::Kinematics;
use hopsim_scene::Scene;
use nalgebra::{DMatrix, DVector};

fn import(xml: &str) -> Result<Scene, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.xml");
    std::fs::write(&path, xml).unwrap();
    hopsim_scene::load(&path, &[]).map_err(|e| e.to_string())
}

fn evaluate(scene: &Scene, q: &[f64], u: &[f64]) -> (Kinematics, DMatrix<f64>, DVector<f64>) {
    let model = &scene.model;
    let n = model.dof();
    let mut k = Kinematics::new(model);
    k.update_slices(model, q, u);
    let mut m = DMatrix::zeros(n, n);
    model.mass_matrix(&k, &mut m);
    let mut h = DVector::zeros(n);
    model.forces(&k, &DVector::zeros(n), &mut h);
    (k, m, h)
}

/// A rod of mass 2 from the pivot at height 1 down 0.5 m (its centre 0.25 m below),
/// turned about `+y` by `qpos − ref`: MuJoCo's rotation about `+y` by `δ` takes the
/// centre `(0, 0, −0.25)` to `(−0.25 sin δ, 1 − 0.25 cos δ)` in the x–z plane.
#[test]
fn a_pendulum_keeps_mujocos_qpos() {
    let scene = import(
        r#"<mujoco><worldbody><body name="pole" pos="0 0 1">
          <joint name="swing" type="hinge" axis="0 1 0" ref="30" stiffness="3" springref="10"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="2"/>
        </body></worldbody></mujoco>"#,
    )
    .unwrap();
    assert_eq!(scene.coordinates, ["swing"]);
    let reference = 30f64.to_radians();
    assert_eq!(scene.initial.q[0], reference);
    let (mass, inertia) = (
        scene.model.bodies()[1].mass,
        scene.model.bodies()[1].inertia,
    );
    assert_eq!(mass, 2.0);
    for delta in [0.0, 0.4, -1.3, 2.9] {
        let q = reference + delta;
        let (k, m, h) = evaluate(&scene, &[q], &[0.0]);
        let bob = k.position(1);
        assert!(
            (bob.x + 0.25 * delta.sin()).abs() < 1e-15,
            "{bob} at δ = {delta}"
        );
        assert!((bob.y - (1.0 - 0.25 * delta.cos())).abs() < 1e-15, "{bob}");
        assert!((m[(0, 0)] - (inertia + mass * 0.0625)).abs() < 1e-15);
        // V = m g z + ½ k (qpos − springref)²; the force is −∂V/∂qpos.
        let force = -mass * 9.81 * 0.25 * delta.sin() - 3.0 * (q - 10f64.to_radians());
        assert!((h[0] - force).abs() < 1e-12, "{} vs {force}", h[0]);
    }
}

/// Two links whose hinges have `ref`s and opposite axes: the child's frame turned by the
/// parent's `ref` keeps its pivot on the parent. MuJoCo's rotations about `+y` by
/// `δ₁ = q₁ − ref₁` and about `−y` by `δ₂ = q₂ − ref₂` put the child's centre at
/// `(−0.5 sin δ₁ − 0.2 sin(δ₁ − δ₂), 1 − 0.5 cos δ₁ − 0.2 cos(δ₁ − δ₂))`.
#[test]
fn a_double_pendulum_with_refs_keeps_mujocos_qpos() {
    let scene = import(
        r#"<mujoco><worldbody><body name="upper" pos="0 0 1">
          <joint name="shoulder" type="hinge" axis="0 1 0" ref="30"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="2"/>
          <body name="lower" pos="0 0 -0.5">
            <joint name="elbow" type="hinge" axis="0 -1 0" ref="-20"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.02" mass="1"/>
          </body>
        </body></worldbody></mujoco>"#,
    )
    .unwrap();
    let refs = [30f64.to_radians(), -20f64.to_radians()];
    assert_eq!(scene.initial.q.as_slice(), refs);
    for (d1, d2) in [(0.0, 0.0), (0.3, -0.7), (-2.0, 1.1)] {
        let (k, _, _) = evaluate(&scene, &[refs[0] + d1, refs[1] + d2], &[0.0, 0.0]);
        let lower = k.position(2);
        let expected = (
            -0.5 * f64::sin(d1) - 0.2 * f64::sin(d1 - d2),
            1.0 - 0.5 * f64::cos(d1) - 0.2 * f64::cos(d1 - d2),
        );
        assert!(
            (lower.x - expected.0).abs() < 1e-15 && (lower.y - expected.1).abs() < 1e-15,
            "{lower} vs {expected:?}"
        );
    }
}

/// A cart on a slide with `ref` (its position where the body is written) and an armature,
/// the world's gravity tilted: `M = m + armature`, `h = m g_x`.
#[test]
fn a_slide_keeps_its_ref_and_armature() {
    let scene = import(
        r#"<mujoco><option gravity="0.5 0 -9.81"/><worldbody>
          <body name="cart" pos="2 0 0.3">
            <joint name="track" type="slide" axis="1 0 0" ref="0.7" armature="0.25"/>
            <geom type="box" size="0.2 0.1 0.1" mass="3"/>
          </body></worldbody></mujoco>"#,
    )
    .unwrap();
    assert_eq!(scene.initial.q[0], 0.7);
    for x in [0.7, 1.5, -0.2] {
        let (k, m, h) = evaluate(&scene, &[x], &[0.0]);
        let cart = k.position(1);
        assert!((cart.x - (2.0 + x - 0.7)).abs() < 1e-15 && (cart.y - 0.3).abs() < 1e-15);
        assert_eq!(m[(0, 0)], 3.25);
        assert!((h[0] - 1.5).abs() < 1e-15, "{}", h[0]);
    }
}

/// Contacts as MuJoCo filters them: a child never touches its parent, two geoms whose
/// `contype`/`conaffinity` do not meet never touch, the rest are pairs; friction is the
/// larger of two, or the higher priority's; `condim` 1 is frictionless.
#[test]
fn contact_pairs_and_friction_follow_mujocos_rules() {
    let scene = import(
        r#"<mujoco><worldbody>
          <geom name="floor" type="plane" size="5 5 .1" friction="0.6"/>
          <body name="a" pos="0 0 1"><joint name="ja" type="slide" axis="0 0 1"/>
            <geom name="ga" type="sphere" size="0.1" friction="0.9"/>
            <body name="b" pos="0.15 0 0"><joint name="jb" type="hinge" axis="0 1 0"/>
              <geom name="gb" type="sphere" size="0.1" friction="0.3" priority="1"/>
            </body>
          </body>
          <body name="c" pos="1 0 1"><joint name="jc" type="slide" axis="1 0 0"/>
            <geom name="gc" type="sphere" size="0.1" friction="0.2" condim="1"/>
          </body>
          <body name="d" pos="-1 0 1"><joint name="jd" type="slide" axis="1 0 0"/>
            <geom name="gd" type="sphere" size="0.1" contype="2" conaffinity="2"/>
          </body>
        </worldbody></mujoco>"#,
    )
    .unwrap();
    let model = &scene.model;
    let shape = |name: &str| model.shapes().iter().position(|s| s.name == name).unwrap();
    // The floor's friction 0.6 against each: max, priority, condim 1; gd never touches the
    // floor (its contype 2 and conaffinity 2 meet neither of the floor's 1), so it is no
    // shape.
    let terrain_friction = |name: &str| {
        let s = shape(name);
        model
            .contacts()
            .iter()
            .find(|c| c.shape == s)
            .map(|c| c.material.friction)
    };
    assert_eq!(terrain_friction("ga"), Some(0.9));
    assert_eq!(terrain_friction("gb"), Some(0.3));
    assert_eq!(terrain_friction("gc"), Some(0.6));
    assert!(model.shapes().iter().all(|s| s.name != "gd"));
    assert!(scene
        .notices
        .iter()
        .any(|n| n.contains("geom `gd` does not collide with the terrain")));
    // Pairs: a–c and b–c (a–b are parent and child); gd is not a shape.
    let mut pairs: Vec<(String, f64)> = model
        .pairs()
        .iter()
        .map(|p| {
            let mut names = [
                &model.shapes()[p.probe].name,
                &model.shapes()[p.target].name,
            ];
            names.sort();
            (format!("{}-{}", names[0], names[1]), p.material.friction)
        })
        .collect();
    pairs.sort_by(|x, y| x.0.cmp(&y.0));
    pairs.dedup();
    assert_eq!(
        pairs,
        [("ga-gc".to_string(), 0.9), ("gb-gc".to_string(), 0.3)]
    );
    assert!(model
        .contacts()
        .iter()
        .all(|c| c.material.restitution_normal == 0.0));
}

/// What a scene cannot hold is an error or a notice, never dropped silently.
#[test]
fn what_cannot_be_imported_is_said() {
    let body = |joint: &str| {
        format!(
            r#"<mujoco><worldbody><geom name="floor" type="plane" size="5 5 .1"/>
            <geom name="wall" type="plane" size="5 5 .1" pos="3 0 0" zaxis="-1 0 0"/>
            <body name="b" pos="0 0 1">{joint}<geom type="sphere" size="0.1"/></body>
            </worldbody></mujoco>"#
        )
    };
    let error = import(&body(r#"<joint name="j" type="slide" axis="1 0 0"/>"#)).unwrap_err();
    assert!(
        error.contains("the planes `floor` and `wall` both touch the model"),
        "{error}"
    );
    let scene = import(
        r#"<mujoco><worldbody><body name="b" pos="0 0 1">
          <joint name="j" type="hinge" axis="0 1 0" frictionloss="0.2" range="10 20"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body></worldbody>
          <actuator><position name="servo" joint="j" kp="10"/></actuator></mujoco>"#,
    )
    .unwrap();
    let said = |what: &str| scene.notices.iter().any(|n| n.contains(what));
    assert!(!said("frictionloss"));
    let joint = scene.model.bodies()[1].joint.as_ref().unwrap();
    assert_eq!(joint.dry_friction, 0.2);
    // The servo is the scene's actuator, on the body of its joint.
    let servo = &scene.model.actuators()[0];
    assert_eq!((servo.name.as_str(), servo.body), ("servo", 1));
    assert_eq!(
        servo.kind,
        hopsim_model::ActuatorKind::Position { kp: 10.0, kv: 0.0 }
    );
    assert!(!said("actuator"));
    assert!(said("qpos0 = 0.0 lies beyond its range"));
    // It starts on its lower stop.
    assert_eq!(scene.initial.q[0], 10f64.to_radians());
}

/// The plane of Reacher and Swimmer is `x–y`: gravity along the normal has no effect, and
/// a model without a floor has no terrain.
#[test]
fn a_model_in_the_horizontal_plane_has_no_weight_and_no_terrain() {
    let scene = import(
        r#"<mujoco><worldbody><body name="arm" pos="0 0 0.1">
          <joint name="shoulder" type="hinge" axis="0 0 1"/>
          <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.02" mass="1"/>
        </body></worldbody></mujoco>"#,
    )
    .unwrap();
    assert!(scene.model.terrain().features.is_empty());
    assert_eq!(scene.settings.gravity, 0.0);
    let (_, m, h) = evaluate(&scene, &[0.8], &[0.0]);
    assert_eq!(h[0], 0.0);
    let inertia = scene.model.bodies()[1].inertia;
    assert!((m[(0, 0)] - (inertia + 0.04)).abs() < 1e-15);
}
