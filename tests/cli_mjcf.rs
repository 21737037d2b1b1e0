//! MuJoCo models on the command line (docs/mjcf.md): `hopsim run` and `hopsim scene check`
//! on a `.xml`, `--set` by MJCF names, `hopsim import` (a scene that runs bit for bit as
//! the model does), located errors; and Gymnasium's `hopper.xml` run and recorded when
//! the package is installed.

use hopsim_record::McapRecording;
use std::path::Path;
use std::process::{Command, Output};

fn hopsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("hopsim runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A rod on MuJoCo's root slide–slide–hinge joints with an arm on a damped, limited hinge
/// whose axis points against the plane's normal, above a floor; a motor on the arm.
const ROD: &str = r#"<mujoco model="rod">
  <option timestep="0.001"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 .1" friction="0.8"/>
    <body name="rod" pos="0 0 0.5">
      <joint name="x" type="slide" axis="1 0 0"/>
      <joint name="z" type="slide" axis="0 0 1" ref="0.5"/>
      <joint name="pitch" type="hinge" axis="0 1 0"/>
      <geom name="rod" type="capsule" fromto="-0.3 0 0 0.3 0 0" size="0.05" mass="1"/>
      <body name="arm" pos="0.3 0 0">
        <joint name="elbow" type="hinge" axis="0 -1 0" damping="0.1" range="-60 60" armature="0.01"/>
        <geom name="arm" type="capsule" fromto="0 0 0 0 0 0.3" size="0.03" mass="0.5"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="elbow" gear="2"/></actuator>
</mujoco>
"#;

fn path(p: &Path) -> String {
    p.display().to_string()
}

#[test]
fn a_model_runs_checks_and_imports_as_a_scene_that_runs_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("rod.xml");
    std::fs::write(&model, ROD).unwrap();
    let scene = dir.path().join("rod.toml");

    let check = hopsim(&["scene", "check", &path(&model)]);
    let out = text(&check.stdout);
    assert!(check.status.success(), "{}", text(&check.stderr));
    assert!(out.contains(": ok"), "{out}");
    assert!(!out.contains("notice: actuator"), "{out}");

    let import = hopsim(&["import", &path(&model), "-o", &path(&scene)]);
    assert!(import.status.success(), "{}", text(&import.stderr));
    let err = text(&import.stderr);
    assert!(err.contains("4 coordinates (x, z, pitch, elbow)"), "{err}");
    let toml = std::fs::read_to_string(&scene).unwrap();
    assert!(toml.contains("type = \"capsule\""), "{toml}");
    assert!(
        toml.contains(
            "[[actuators]]\nname = \"actuator0\"\njoint = \"arm\"\ngear = 2.0\nkind = \"motor\""
        ),
        "{toml}"
    );

    // The model and its scene run the same steps, to the bit.
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    for (source, csv) in [(&model, &a), (&scene, &b)] {
        let run = hopsim(&[
            "run",
            &path(source),
            "--csv",
            &path(csv),
            "--duration",
            "0.5",
        ]);
        assert!(run.status.success(), "{}", text(&run.stderr));
    }
    let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert!(
        !a.is_empty() && a == b,
        "the imported scene ran differently"
    );

    // --set by MJCF names; a bad value is named by its argument.
    let heavy = hopsim(&[
        "scene",
        "check",
        &path(&model),
        "--set",
        "bodies.arm.mass=2.0",
        "--set",
        "initial.q.1=0.7",
    ]);
    assert!(heavy.status.success(), "{}", text(&heavy.stderr));
    let bad = hopsim(&["run", &path(&model), "--set", "bodies.arm.mass=-1"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        text(&bad.stderr).contains("--set bodies.arm.mass=-1: bodies[4].mass"),
        "{}",
        text(&bad.stderr)
    );
}

#[test]
fn import_refuses_its_own_model_and_models_outside_the_subset() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("rod.xml");
    std::fs::write(&model, ROD).unwrap();
    let same = hopsim(&["import", &path(&model), "-o", &path(&model)]);
    assert_eq!(same.status.code(), Some(2));
    assert!(text(&same.stderr).contains("that is the model file"));
    assert_eq!(std::fs::read_to_string(&model).unwrap(), ROD);

    let tilted = dir.path().join("tilted.xml");
    std::fs::write(&tilted, ROD.replace("axis=\"0 -1 0\"", "axis=\"1 0 0\"")).unwrap();
    let run = hopsim(&["run", &path(&tilted)]);
    assert_eq!(run.status.code(), Some(2));
    let err = text(&run.stderr);
    assert!(
        err.contains("tilted.xml:11:9: <joint> attribute `axis`: joint `elbow` leaves the plane"),
        "{err}"
    );
}

/// Skips (with a notice) or, with HOPSIM_REQUIRE_PYTHON=1 (CI), fails.
fn skip_or_fail(what: &str) {
    assert!(
        std::env::var("HOPSIM_REQUIRE_PYTHON").as_deref() != Ok("1"),
        "{what}; HOPSIM_REQUIRE_PYTHON=1 requires it (pip install gymnasium)"
    );
    eprintln!("notice: skipping: {what} (set HOPSIM_REQUIRE_PYTHON=1 to make this an error)");
}

/// Gymnasium's Hopper runs for a second and records its joints by name and its capsules'
/// contacts.
#[test]
fn gymnasium_hopper_runs_and_records() {
    let python = std::env::var("HOPSIM_PYTHON").unwrap_or_else(|_| "python3".into());
    let found = Command::new(&python)
        .args([
            "-c",
            "import gymnasium, os; print(os.path.dirname(gymnasium.__file__))",
        ])
        .output();
    let folder = match found {
        Ok(out) if out.status.success() => text(&out.stdout).trim().to_string(),
        _ => return skip_or_fail("the Python package gymnasium is not installed"),
    };
    let hopper = Path::new(&folder).join("envs/mujoco/assets/hopper.xml");
    let dir = tempfile::tempdir().unwrap();
    let (mcap, rrd) = (dir.path().join("h.mcap"), dir.path().join("h.rrd"));
    let run = hopsim(&[
        "run",
        &path(&hopper),
        "--mcap",
        &path(&mcap),
        "--rrd",
        &path(&rrd),
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let out = text(&run.stdout);
    assert!(
        out.contains("1.000 s simulated in 500 steps of 2e-3 s"),
        "{out}"
    );
    assert!(std::fs::metadata(&rrd).unwrap().len() > 0);
    let recording = McapRecording::read(&mcap).unwrap();
    assert_eq!(
        recording.metadata.coordinates,
        [
            "rootx",
            "rootz",
            "rooty",
            "thigh_joint",
            "leg_joint",
            "foot_joint"
        ]
    );
    assert!(recording
        .metadata
        .contacts
        .iter()
        .any(|c| c == "foot_geom#0/terrain0"));
    let scene = recording.scene.expect("the scene is attached");
    assert!(scene.text.contains("type = \"capsule\""));
    assert_eq!(recording.states.last().unwrap().step, 500);
}
