//! `[[actuators]]` (docs/scene-format.md): the model's actuators as written, their control
//! signals (a CSV file relative to the scene, with errors at its line), and `--set` on
//! their keys.

use hopsim_model::ActuatorKind;
use hopsim_scene::Override;
use std::path::Path;

const SCENE: &str = r#"
[simulation]
duration = 1.0
dt = 1e-3

[environment]
terrain = "none"

[[bodies]]
name = "rod"
base = "pinned"
com = [0.0, -0.5]
mass = 1.0
inertia = 0.0833

[[actuators]]
name = "hip"
joint = "rod"
kind = "position"
kp = 80.0
gear = 2.0
ctrl_range = [-0.5, 0.5]
force_range = [-30.0, 30.0]
control = { kind = "csv", file = "hip.csv" }

[initial]
q = [0.0]
"#;

fn load(dir: &Path, csv: &str, overrides: &[&str]) -> Result<hopsim_scene::Scene, String> {
    std::fs::write(dir.join("hip.csv"), csv).unwrap();
    let path = dir.join("arm.toml");
    std::fs::write(&path, SCENE).unwrap();
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::load(&path, &overrides).map_err(|e| e.to_string())
}

#[test]
fn an_actuator_reads_as_written_with_its_csv_signal() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load(dir.path(), "time,angle\n0,0\n# hold\n1,0.4\n2,0.4\n", &[]).unwrap();
    let a = &scene.model.actuators()[0];
    assert_eq!((a.name.as_str(), a.body, a.gear), ("hip", 0, 2.0));
    assert_eq!(a.kind, ActuatorKind::Position { kp: 80.0, kv: 0.0 });
    assert_eq!(
        (a.ctrl_range, a.force_range),
        (Some([-0.5, 0.5]), Some([-30.0, 30.0]))
    );
    let (index, signal) = &scene.control_signals[0];
    assert_eq!(*index, 0);
    assert_eq!(signal.value(0.5), 0.2);
    assert_eq!(signal.value(1.5), 0.4);
}

#[test]
fn set_reaches_an_actuators_keys() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load(
        dir.path(),
        "0,0\n",
        &[
            "actuators.hip.kp=5",
            "actuators.hip.kind=velocity",
            "actuators.hip.kv=3",
        ],
    );
    let err = scene.unwrap_err();
    // A velocity servo has no kp: the key left over is refused by name.
    assert!(err.contains("actuators[0].kp: unknown key"), "{err}");
    let scene = load(dir.path(), "0,0\n", &["actuators.hip.kp=5"]).unwrap();
    assert_eq!(
        scene.model.actuators()[0].kind,
        ActuatorKind::Position { kp: 5.0, kv: 0.0 }
    );
}

#[test]
fn a_bad_csv_row_is_named_by_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    for (csv, expected) in [
        ("time,value\n0,1\n1,x\n", "hip.csv:3: expected two finite numbers `time,value`, found `1,x`"),
        ("0,1\n0,2\n", "hip.csv:2: expected two finite numbers `time,value`, found `0,2` (times must increase strictly)"),
        ("0,1,2\n", "hip.csv:1:"),
        ("# nothing\n", "hip.csv: no rows `time,value`"),
    ] {
        let err = load(dir.path(), csv, &[]).unwrap_err();
        assert!(err.contains(expected), "{csv:?}: {err}");
        assert!(err.contains("actuators[0].control.file"), "{err}");
    }
}
