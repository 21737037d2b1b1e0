//! MuJoCo itself as the oracle of imported scenes (docs/mjcf.md, "Checked against
//! MuJoCo"): every planar model shipped in the `gymnasium` and `dm_control` Python packages
//! loads as a scene whose coordinates are MuJoCo's `qpos`, and at 100 random states its
//! mass matrix equals MuJoCo's `mj_fullM` (armature included) and its generalised forces
//! (gravity, velocity products, joint springs and damping) equal `qfrc_passive −
//! qfrc_bias`, both to 1e-10 relative to their largest entry. Each model with a floor,
//! dropped 0.1 m onto it, comes to rest: its contacts carry its weight exactly, it sinks
//! in no more than one step's travel (Moreau's scheme closes contacts without pushing
//! positions back) and no further; MuJoCo's soft contact, run on the same drop, is
//! printed beside it.
//!
//! With contacts, joint ranges and joint friction off, a free motion from a random state
//! matches MuJoCo's RK4 at a small step to the midpoint scheme's first-order error: the
//! error at two step sizes shrinks at least in proportion to the step.
//!
//! Needs `python3` (or `HOPSIM_PYTHON`) with `mujoco`, `gymnasium` and `dm_control`
//! (test-only; .ci/run installs them). Without them the test is skipped with a notice,
//! unless HOPSIM_REQUIRE_PYTHON=1, which makes it fail.

mod oracle;

use std::path::Path;

use hopsim_model::Kinematics;
use hopsim_scene::{Override, Scene};
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use nalgebra::{DMatrix, DVector};
use oracle::{numbers, relative, unavailable};
use serde_json::{json, Value};

const RELATIVE: f64 = 1e-10;
const STATES: usize = 100;
/// How far each floor model is dropped, m, and for how long it then runs, s.
const DROP: f64 = 0.1;
const DROP_DURATION: f64 = 15.0;

/// The answer of `tests/mujoco_dynamics.py` to `request`, or why it cannot answer.
fn oracle(request: &Value) -> Result<Value, String> {
    oracle::ask("mujoco_dynamics.py", request)
}

/// A reproducible uniform draw in `[-1, 1)` (xorshift64*).
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        2.0 * (bits as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// hopsim's mass matrix and generalised forces (no actuation) at `(q, u)`.
fn dynamics(scene: &Scene, q: &[f64], u: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let model = &scene.model;
    let n = model.dof();
    let mut kinematics = Kinematics::new(model);
    kinematics.update_slices(model, q, u);
    let mut m = DMatrix::zeros(n, n);
    model.mass_matrix(&kinematics, &mut m);
    let mut h = DVector::zeros(n);
    model.forces(&kinematics, &DVector::zeros(n), &mut h);
    (m, h)
}

/// What the end of a drop looks like.
#[derive(Default)]
struct Rest {
    /// Per step: the largest speed, the vertical percussion of the terrain, the deepest
    /// penetration.
    steps: Vec<(f64, f64, f64)>,
}

impl Observer for Rest {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        let speed = v.state.u.amax();
        let vertical = v
            .record
            .contacts
            .iter()
            .map(|c| c.impulse_normal * c.normal.y)
            .sum();
        self.steps.push((speed, vertical, v.record.max_penetration));
        Ok(())
    }
}

/// For a model with a floor and MuJoCo's root joints `rootz`, `rooty`: `qpos0` turned to
/// lie flat (of the turns by 0 and 90°, the one of least height) and raised to [`DROP`]
/// above the floor.
fn lying_above_the_floor(scene: &Scene) -> Option<Vec<f64>> {
    let model = &scene.model;
    let index = |name: &str| scene.coordinates.iter().position(|c| c == name);
    let (z, turn) = (index("rootz")?, index("rooty")?);
    if model.terrain().features.is_empty() {
        return None;
    }
    // The lowest and highest points of the shapes (the gaps to the floor, and the same
    // from above: the floor's normal is up).
    let extent = |q: &[f64]| {
        let mut kinematics = Kinematics::new(model);
        kinematics.update_slices(model, q, &vec![0.0; q.len()]);
        let gaps: Vec<f64> = (0..model.contacts().len())
            .filter_map(|i| model.contact_geometry(&kinematics, i))
            .map(|g| g.gap)
            .collect();
        let low = gaps.iter().copied().fold(f64::INFINITY, f64::min);
        let high = gaps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (low, high - low)
    };
    let q0 = scene.initial.q.as_slice().to_vec();
    let mut flat = q0.clone();
    flat[turn] += std::f64::consts::FRAC_PI_2;
    let mut q = if extent(&flat).1 < extent(&q0).1 {
        flat
    } else {
        q0
    };
    q[z] += DROP - extent(&q).0;
    Some(q)
}

/// Drops `scene` from `q` (at rest) and checks its rest; returns the final `q`, the
/// penetration and the contact force at rest.
fn drop_on_the_floor(path: &Path, q: &[f64]) -> (Vec<f64>, f64, f64) {
    let mut overrides: Vec<Override> = q
        .iter()
        .enumerate()
        .map(|(i, x)| format!("initial.q.{i}={x:?}").parse().unwrap())
        .collect();
    overrides.push(
        format!("simulation.duration={DROP_DURATION:?}")
            .parse()
            .unwrap(),
    );
    let scene = hopsim_scene::load(path, &overrides).unwrap_or_else(|e| panic!("{e}"));
    let dt = scene.settings.dt;
    let weight = scene.model.total_mass() * scene.settings.gravity;
    let steps = (DROP_DURATION / dt).round() as usize;
    let mut sim = Simulation::new(&scene);
    let mut rest = Rest::default();
    for _ in 0..steps {
        sim.step(&mut rest)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
    let name = path.display();
    let (speed, vertical, penetration) = *rest.steps.last().unwrap();
    assert!(
        speed < 1e-5,
        "{name}: still moving at {speed:e} after {DROP_DURATION} s"
    );
    let force = vertical / dt;
    assert!(
        (force - weight).abs() < 1e-6 * weight,
        "{name}: the floor carries {force} N of its weight {weight} N"
    );
    // Sunk in by at most one step's travel of its fastest coordinate, and no further.
    let fastest = rest.steps.iter().map(|s| s.0).fold(0.0, f64::max);
    let reach = 2.0;
    assert!(
        penetration <= fastest * reach * dt,
        "{name}: {penetration:e} m deep, one step's travel {:e} m",
        fastest * reach * dt
    );
    let second_ago = rest.steps[steps - (1.0 / dt) as usize].2;
    assert!(
        (penetration - second_ago).abs() < 1e-12,
        "{name}: sank from {second_ago:e} m to {penetration:e} m in the last second"
    );
    (sim.state().q.as_slice().to_vec(), penetration, force)
}

#[test]
fn imported_models_have_mujocos_dynamics_and_rest_on_the_floor() {
    let listing = match oracle(&json!({"list": true})) {
        Ok(listing) => listing,
        Err(why) => return unavailable(&why),
    };
    let missing = listing["missing"].as_array().unwrap();
    if !missing.is_empty() {
        unavailable(&format!("not installed: {missing:?}"));
    }
    let paths: Vec<String> = listing["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap().to_string())
        .collect();
    let mut draw = Draw(0x9E37_79B9_7F4A_7C15);
    let mut requests = Vec::new();
    let mut scenes = Vec::new();
    for path in &paths {
        let scene = hopsim_scene::load(Path::new(path), &[]).unwrap_or_else(|e| panic!("{e}"));
        let n = scene.model.dof();
        let q0 = scene.initial.q.as_slice().to_vec();
        let states: Vec<(Vec<f64>, Vec<f64>)> = (0..STATES)
            .map(|_| {
                let q = q0.iter().map(|x| x + draw.next()).collect();
                let u = (0..n).map(|_| 3.0 * draw.next()).collect();
                (q, u)
            })
            .collect();
        let drop =
            lying_above_the_floor(&scene).map(|q| json!({"q": q, "duration": DROP_DURATION}));
        requests.push(json!({"path": path, "states": states, "drop": drop}));
        scenes.push((path.clone(), scene, states, drop));
    }
    let answer = match oracle(&json!({ "models": requests })) {
        Ok(answer) => answer,
        Err(why) => return unavailable(&why),
    };
    let mut worst: (f64, f64) = (0.0, 0.0);
    for ((path, scene, states, drop), theirs) in
        scenes.iter().zip(answer["models"].as_array().unwrap())
    {
        let n = scene.model.dof();
        for ((q, u), theirs) in states.iter().zip(theirs["states"].as_array().unwrap()) {
            let (m, h) = dynamics(scene, q, u);
            let m_theirs: Vec<f64> = theirs["mass_matrix"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(numbers)
                .collect();
            // Row-major against M's column-major storage: M is symmetric.
            let dm = relative(m.as_slice(), &m_theirs);
            let dh = relative(h.as_slice(), &numbers(&theirs["forces"]));
            assert!(
                dm < RELATIVE,
                "{path}: mass matrix differs by {dm:e} at q = {q:?}:\n{m}\nMuJoCo: {m_theirs:?}"
            );
            assert!(
                dh < RELATIVE,
                "{path}: forces differ by {dh:e} at q = {q:?}, u = {u:?}:\n{h}\nMuJoCo: {}",
                theirs["forces"]
            );
            worst = (worst.0.max(dm), worst.1.max(dh));
        }
        assert_eq!(n, numbers(&theirs["states"][0]["forces"]).len());
        if let Some(drop) = drop {
            let (q, penetration, force) = drop_on_the_floor(Path::new(path), &numbers(&drop["q"]));
            let mj = &theirs["drop"];
            eprintln!(
                "{path}: at rest after a {DROP} m drop: hopsim {penetration:.2e} m deep, floor \
                 {force:.4} N; MuJoCo {:.2e} m deep, floor {:.4} N of {:.4} N; rootz {:.5} vs \
                 {:.5} m",
                -mj["deepest"].as_f64().unwrap(),
                mj["vertical_force"].as_f64().unwrap(),
                mj["weight"].as_f64().unwrap(),
                q[scene.coordinates.iter().position(|c| c == "rootz").unwrap()],
                numbers(&mj["qpos"])[scene.coordinates.iter().position(|c| c == "rootz").unwrap()],
            );
        }
    }
    eprintln!(
        "checked {} models at {STATES} states each against MuJoCo {}: largest relative \
         difference of the mass matrices {:.1e}, of the forces {:.1e}",
        scenes.len(),
        listing["mujoco"],
        worst.0,
        worst.1
    );
}

/// Free motion of every model (no terrain, joint ranges opened), from `qpos0` plus a draw,
/// after [`FREE_DURATION`], by hopsim at `dt` and `dt / 2` against MuJoCo's RK4 at
/// [`FREE_REFERENCE_DT`]: each error of `(q, u)`, relative to the motion's scale, stays
/// within a first-order bound and falls at least like the step.
const FREE_DURATION: f64 = 0.2;
const FREE_REFERENCE_DT: f64 = 1e-5;
/// (At 1e-3 s the inverted pendulum's error still falls by 0.66 per halving, its first-
/// and second-order terms partly cancelling; from 5e-4 s on every model's falls by ≤ 0.56.)
const FREE_DT: f64 = 5e-4;

/// hopsim's state after a free motion of the model at `path` from `(q, u)`.
fn free_motion(path: &Path, scene: &Scene, q: &[f64], u: &[f64], dt: f64) -> Vec<f64> {
    let mut overrides: Vec<Override> = vec![
        Override::new("simulation.dt", format!("{dt:?}")),
        Override::new("simulation.duration", format!("{FREE_DURATION:?}")),
    ];
    overrides.push(Override::new("initial.q", format!("{q:?}")));
    overrides.push(Override::new("initial.u", format!("{u:?}")));
    for limit in scene.model.limits() {
        let name = &scene.model.bodies()[limit.body].name;
        overrides.push(Override::new(
            format!("bodies.{name}.limits"),
            "[-1e3, 1e3]",
        ));
    }
    if !scene.model.terrain().features.is_empty() {
        // The floor far below: nothing reaches it in the time.
        overrides.push(Override::new("environment.height", "-1e3"));
    }
    let free = hopsim_scene::load(path, &overrides).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(&free);
    let mut rest = Rest::default();
    for _ in 0..(FREE_DURATION / dt).round() as usize {
        sim.step(&mut rest)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
    assert!(
        rest.steps.iter().all(|&(_, vertical, _)| vertical == 0.0),
        "{}: a contact closed in the free motion",
        path.display()
    );
    let state = sim.state();
    state.q.iter().chain(state.u.iter()).copied().collect()
}

#[test]
fn free_motions_match_mujocos_rk4_to_first_order() {
    let listing = match oracle(&json!({"list": true})) {
        Ok(listing) => listing,
        Err(why) => return unavailable(&why),
    };
    let mut draw = Draw(0x2545_F491_4F6C_DD1D);
    let mut cases = Vec::new();
    for path in listing["models"].as_array().unwrap() {
        let path = Path::new(path.as_str().unwrap()).to_path_buf();
        let scene = hopsim_scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
        let q: Vec<f64> = scene
            .initial
            .q
            .iter()
            .map(|x| x + 0.3 * draw.next())
            .collect();
        let u: Vec<f64> = q.iter().map(|_| 2.0 * draw.next()).collect();
        cases.push((path, scene, q, u));
    }
    let request: Vec<Value> = cases
        .iter()
        .map(|(path, _, q, u)| {
            json!({"path": path, "q": q, "u": u, "duration": FREE_DURATION,
                   "dt": FREE_REFERENCE_DT})
        })
        .collect();
    let answer = match oracle(&json!({ "free": request })) {
        Ok(answer) => answer,
        Err(why) => return unavailable(&why),
    };
    for ((path, scene, q, u), theirs) in cases.iter().zip(answer["free"].as_array().unwrap()) {
        let reference: Vec<f64> = numbers(&theirs["qpos"])
            .into_iter()
            .chain(numbers(&theirs["qvel"]))
            .collect();
        let error = |dt: f64| relative(&free_motion(path, scene, q, u, dt), &reference);
        let (coarse, fine) = (error(FREE_DT), error(FREE_DT / 2.0));
        eprintln!(
            "{}: free motion for {FREE_DURATION} s, error relative to the state's scale: \
             {coarse:.2e} at dt = {FREE_DT:e} s, {fine:.2e} at {:e} s",
            path.display(),
            FREE_DT / 2.0
        );
        assert!(
            coarse < 0.05,
            "{}: {coarse:e} off MuJoCo's RK4 at dt = {FREE_DT:e}",
            path.display()
        );
        assert!(
            fine <= 0.6 * coarse,
            "{}: the error does not fall like the step: {coarse:e} at dt, {fine:e} at dt/2",
            path.display()
        );
    }
}

/// hopsim's actuator forces at `(q, u)` under `controls` (docs/physics.md §7.4).
fn actuator_forces(scene: &Scene, q: &[f64], u: &[f64], controls: &[f64]) -> Vec<f64> {
    let model = &scene.model;
    let mut kinematics = Kinematics::new(model);
    kinematics.update_slices(model, q, u);
    let mut out = vec![0.0; model.dof()];
    model.add_actuator_forces_to(&kinematics, controls, &mut out);
    out
}

/// The imported actuators (motors, position and velocity servos with their gears, control
/// and force ranges) of the shipped models and of `tests/models/servos.xml` (every form the
/// import maps; the shipped planar models have motors only) give MuJoCo's `qfrc_actuator`
/// at 100 random states under random controls, a third of them outside the control range,
/// to 1e-10 relative.
#[test]
fn imported_actuators_have_mujocos_forces() {
    let listing = match oracle(&json!({"list": true})) {
        Ok(listing) => listing,
        Err(why) => return unavailable(&why),
    };
    let mut draw = Draw(0x2545_F491_4F6C_DD1D);
    let mut requests = Vec::new();
    let mut cases = Vec::new();
    let servos = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models/servos.xml");
    let shipped = listing["models"].as_array().unwrap().iter();
    for path in shipped
        .map(|p| p.as_str().unwrap())
        .chain([servos.to_str().unwrap()])
    {
        let scene = hopsim_scene::load(Path::new(path), &[]).unwrap_or_else(|e| panic!("{e}"));
        let actuators = scene.model.actuators();
        if actuators.is_empty() {
            continue;
        }
        let n = scene.model.dof();
        let q0 = scene.initial.q.as_slice().to_vec();
        let states: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..STATES)
            .map(|_| {
                let q = q0.iter().map(|x| x + draw.next()).collect();
                let u = (0..n).map(|_| 3.0 * draw.next()).collect();
                let controls = actuators
                    .iter()
                    .map(|a| match a.ctrl_range {
                        Some([lo, hi]) => 0.5 * (lo + hi) + 0.75 * (hi - lo) * draw.next(),
                        None => 2.0 * draw.next(),
                    })
                    .collect();
                (q, u, controls)
            })
            .collect();
        requests.push(json!({"path": path, "states": states, "drop": null}));
        cases.push((path.to_string(), scene, states));
    }
    let answer = match oracle(&json!({ "models": requests })) {
        Ok(answer) => answer,
        Err(why) => return unavailable(&why),
    };
    let mut worst = 0.0f64;
    let mut kinds = std::collections::BTreeSet::new();
    for ((path, scene, states), theirs) in cases.iter().zip(answer["models"].as_array().unwrap()) {
        for a in scene.model.actuators() {
            kinds.insert(a.kind.name());
        }
        for ((q, u, controls), theirs) in states.iter().zip(theirs["states"].as_array().unwrap()) {
            let mine = actuator_forces(scene, q, u, controls);
            let expected = numbers(&theirs["actuator_forces"]);
            let d = relative(&mine, &expected);
            assert!(
                d < RELATIVE,
                "{path}: actuator forces differ by {d:e} at q = {q:?}, u = {u:?}, ctrl = \
                 {controls:?}:\n{mine:?}\nMuJoCo: {expected:?}"
            );
            worst = worst.max(d);
        }
    }
    assert!(!cases.is_empty(), "no model with actuators");
    eprintln!(
        "checked the actuators of {} models ({kinds:?}) at {STATES} states each against MuJoCo \
         {}: largest relative difference {worst:.1e}",
        cases.len(),
        listing["mujoco"]
    );
}
