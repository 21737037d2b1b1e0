//! Closed chains written in MJCF (docs/mjcf.md, "Closed loops"): a planar four-bar whose
//! bodies form two trees closed by a `<connect>` (`tests/models/four_bar.xml`) loads as a
//! scene with a revolute loop joint, its `hopsim import` text runs the same steps bit for
//! bit, and MuJoCo itself (the `mujoco` Python package, `tests/mujoco_loops.py`) is the
//! oracle of the closure's points and of the motion: the connect's anchors on both bodies
//! are where MuJoCo puts them, and the free fall of the linkage from `qpos0` follows
//! MuJoCo's RK4 (its connect made nearly hard by `solref`/`solimp`) to the midpoint
//! scheme's first-order error.
//!
//! Without `mujoco` the oracle test is skipped with a notice, unless
//! HOPSIM_REQUIRE_PYTHON=1, which makes it fail.

mod oracle;

use std::path::{Path, PathBuf};

use hopsim_model::{Kinematics, LoopKind, Vec2};
use hopsim_scene::{Override, Scene};
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use oracle::{numbers, relative};
use serde_json::{json, Value};

/// The free fall compared with MuJoCo: its length (s), hopsim's coarser step (s) and
/// MuJoCo's RK4 step (s).
const FREE_DURATION: f64 = 0.3;
const FREE_DT: f64 = 5e-4;
const REFERENCE_DT: f64 = 1e-5;

fn four_bar() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models/four_bar.xml")
}

fn load(path: &Path, overrides: &[Override]) -> Scene {
    hopsim_scene::load(path, overrides).unwrap_or_else(|e| panic!("{e}"))
}

/// The world positions of each loop's two points at `q` (zero velocities).
fn closure_points(scene: &Scene, q: &[f64]) -> Vec<[Vec2; 2]> {
    let model = &scene.model;
    let mut k = Kinematics::new(model);
    k.update_slices(model, q, &vec![0.0; q.len()]);
    let at = |body: Option<usize>, p: Vec2| match body {
        Some(b) => {
            let (s, c) = k.angle(b).sin_cos();
            k.position(b) + Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
        }
        None => p,
    };
    model
        .loops()
        .iter()
        .map(|l| [at(Some(l.body_a), l.point_a), at(l.body_b, l.point_b)])
        .collect()
}

/// Every step's state and loop error.
#[derive(Default)]
struct Trace {
    states: Vec<Vec<f64>>,
    worst_loop_error: f64,
}

impl Observer for Trace {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        self.states
            .push(v.state.q.iter().chain(v.state.u.iter()).copied().collect());
        self.worst_loop_error = self.worst_loop_error.max(v.record.loop_error);
        Ok(())
    }
}

fn run(scene: &Scene, steps: usize) -> Trace {
    let mut sim = Simulation::new(scene);
    let mut trace = Trace::default();
    for _ in 0..steps {
        sim.step(&mut trace).unwrap_or_else(|e| panic!("{e}"));
    }
    trace
}

/// The `<connect>` becomes a revolute loop joint whose points coincide at `qpos0` on the
/// coupler's end, `(0.1 + 0.25, √(0.35² − 0.25²))` in the x–z plane, and the imported
/// scene's text (with its `[[loops]]`) runs the same steps as the model file, bit for bit,
/// with the loop closed to 1e-10 m throughout.
#[test]
fn an_mjcf_four_bar_imports_as_a_scene_with_its_loop() {
    let path = four_bar();
    let scene = load(&path, &[]);
    assert_eq!(scene.coordinates, ["theta2", "theta3", "theta4"]);
    let loops = scene.model.loops();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].name, "coupler-rocker");
    assert_eq!(loops[0].kind, LoopKind::Revolute);
    let tip = Vec2::new(0.35, (0.35f64.powi(2) - 0.25f64.powi(2)).sqrt());
    for p in closure_points(&scene, scene.initial.q.as_slice())[0] {
        assert!((p - tip).norm() < 1e-15, "{p} against {tip}");
    }

    let text = hopsim_scene::import_mjcf(&path).unwrap();
    assert!(
        text.contains("[[loops]]\nname = \"coupler-rocker\""),
        "{text}"
    );
    assert!(text.contains("type = \"revolute\""), "{text}");
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("four_bar.toml");
    std::fs::write(&toml, &text).unwrap();
    let imported = load(&toml, &[]);
    let steps = 2000;
    let (a, b) = (run(&scene, steps), run(&imported, steps));
    assert_eq!(a.states.len(), steps);
    assert_eq!(a.states, b.states, "the model file and its scene differ");
    assert!(a.worst_loop_error <= 1e-10, "{}", a.worst_loop_error);
    // It moved: gravity folds the linkage.
    let last = a.states.last().unwrap();
    assert!((last[0] - scene.initial.q[0]).abs() > 0.1, "{last:?}");
}

/// MuJoCo's world point in the model's x–z plane.
fn planar(v: &Value) -> Vec2 {
    let p = numbers(v);
    Vec2::new(p[0], p[2])
}

/// hopsim's state after the free fall at `dt`.
fn free_fall(path: &Path, dt: f64) -> (Scene, Vec<f64>) {
    let scene = load(
        path,
        &[
            Override::new("simulation.dt", format!("{dt:?}")),
            Override::new("simulation.duration", format!("{FREE_DURATION:?}")),
        ],
    );
    let trace = run(&scene, (FREE_DURATION / dt).round() as usize);
    assert!(
        trace.worst_loop_error <= 1e-10,
        "{}",
        trace.worst_loop_error
    );
    let last = trace.states.last().unwrap().clone();
    (scene, last)
}

/// The connect's anchors on both bodies are MuJoCo's (at `qpos0` and, after the fall, at
/// each simulator's own end state to its closure), and the fall from rest follows MuJoCo's
/// RK4 with an error that halves with the step.
#[test]
fn the_mjcf_four_bar_moves_as_in_mujoco() {
    let path = four_bar();
    let scene = load(&path, &[]);
    let q0: Vec<f64> = scene.initial.q.iter().copied().collect();
    let request = json!({"path": path, "q": q0, "u": vec![0.0; q0.len()],
                         "duration": FREE_DURATION, "dt": REFERENCE_DT});
    let answer = match oracle::ask("mujoco_loops.py", &request) {
        Ok(answer) => answer,
        Err(why) => return oracle::unavailable(&why),
    };
    let theirs = &answer["start"][0];
    let mine = closure_points(&scene, &q0)[0];
    for (side, p) in mine.iter().enumerate() {
        let d = (p - planar(&theirs[side])).norm();
        assert!(
            d < 1e-15,
            "anchor {side}: {p} against MuJoCo's, {d:e} apart"
        );
    }
    let reference: Vec<f64> = numbers(&answer["qpos"])
        .into_iter()
        .chain(numbers(&answer["qvel"]))
        .collect();
    // MuJoCo's soft connect, made stiff, stays closed far below hopsim's step error.
    let end = &answer["end"][0];
    let gap = (planar(&end[0]) - planar(&end[1])).norm();
    assert!(gap < 1e-8, "MuJoCo's connect opened by {gap:e} m");

    let (coarse_scene, coarse) = free_fall(&path, FREE_DT);
    let (_, fine) = free_fall(&path, FREE_DT / 2.0);
    let (e_coarse, e_fine) = (relative(&coarse, &reference), relative(&fine, &reference));
    eprintln!(
        "four-bar free fall for {FREE_DURATION} s against MuJoCo {} RK4 at {REFERENCE_DT:e} s: \
         error {e_coarse:.2e} at dt = {FREE_DT:e} s, {e_fine:.2e} at {:e} s",
        answer["version"],
        FREE_DT / 2.0
    );
    assert!(
        e_coarse < 0.05,
        "{e_coarse:e} off MuJoCo at dt = {FREE_DT:e}"
    );
    assert!(
        e_fine <= 0.6 * e_coarse,
        "the error does not fall like the step: {e_coarse:e}, {e_fine:e}"
    );
    // Both simulators' anchors coincide at their end states, which are close.
    let q_end = &coarse[..q0.len()];
    let [a, b] = closure_points(&coarse_scene, q_end)[0];
    assert!((a - b).norm() < 1e-10);
    assert!((a - planar(&end[0])).norm() < 0.01, "{a} against MuJoCo's");
}

/// A double pendulum in the x–z plane whose second hinge has a `ref` of 40°, welded by
/// `weld` (body1 the lower link, body2 the upper one).
fn welded_pendulum(weld: &str) -> String {
    format!(
        r#"<mujoco><option timestep="0.001"/><worldbody>
          <body name="upper"><joint name="shoulder" axis="0 -1 0" ref="-30"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
            <body name="lower" pos="0 0 -0.5"><joint name="elbow" axis="0 1 0" ref="40"/>
              <geom type="capsule" fromto="0 0 0 0.3 0 -0.3" size="0.02" mass="1"/>
            </body>
          </body>
        </worldbody><equality>{weld}</equality></mujoco>"#
    )
}

/// A `<weld>` without `relpose` holds the pose at `qpos0`: the imported scene's weld loop
/// (its angle the links' turn by the hinges' `ref`s) keeps the elbow at its `ref` while
/// the pendulum swings from the shoulder's; a `relpose` that does not hold at `qpos0` is
/// refused by the scene with the loop's gap.
#[test]
fn an_mjcf_weld_holds_the_elbow_at_its_reference() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("welded.xml");
    std::fs::write(
        &path,
        welded_pendulum(
            r#"<weld name="elbow-lock" body1="lower" body2="upper" anchor="0 0 -0.5"/>"#,
        ),
    )
    .unwrap();
    let scene = load(&path, &[]);
    assert_eq!(scene.model.loops().len(), 1);
    assert!(matches!(scene.model.loops()[0].kind, LoopKind::Weld { .. }));
    let elbow = scene.initial.q[1];
    assert_eq!(elbow, 40f64.to_radians());
    let trace = run(&scene, 1000);
    assert!(
        trace.worst_loop_error <= 1e-10,
        "{}",
        trace.worst_loop_error
    );
    let swing = trace
        .states
        .iter()
        .fold(0.0f64, |m, s| m.max((s[0] - scene.initial.q[0]).abs()));
    assert!(swing > 0.3, "the pendulum hardly swung: {swing}");
    for s in &trace.states {
        assert!((s[1] - elbow).abs() < 1e-10, "elbow at {} rad", s[1]);
    }

    std::fs::write(
        &path,
        welded_pendulum(
            r#"<weld name="bent" body1="lower" body2="upper" relpose="0 0 0.5 0.98 0 0.2 0"/>"#,
        ),
    )
    .unwrap();
    let e = hopsim_scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        e.contains("loop 'bent' is open") && e.contains("initial.q"),
        "{e}"
    );
}
