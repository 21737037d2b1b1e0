//! `hopsim compare`: identical runs exit 0, an injected difference exits 1 naming the step,
//! time and contact, an unreadable input exits 2 naming the file.

use hopsim_record::{
    BodyInfo, BodyPose, ContactSample, EnergySample, Frame, ImpulseSample, ImpulseTrace,
    McapRecorder, Recorder, RecordingInfo, Terrain,
};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn hopsim(args: &[&Path], options: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .arg("compare")
        .args(args)
        .args(options)
        .output()
        .expect("run hopsim")
}

fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A per-step trace of one contact and a brake, as the stepper writes golden files.
fn trace() -> ImpulseTrace {
    let mut trace = ImpulseTrace::default();
    for step in 1..=40 {
        let t = step as f64 * 2e-4;
        trace.samples.push(ImpulseSample {
            step,
            t,
            channel: "disc/ground".into(),
            normal: 2.7e-3 + 1e-7 * step as f64,
            tangent: -1e-5 / 3.0,
        });
    }
    trace.samples.push(ImpulseSample {
        step: 20,
        t: 20.0 * 2e-4,
        channel: "lock:disc-flywheel".into(),
        normal: 0.059,
        tangent: 0.0,
    });
    trace
}

fn write_trace(dir: &Path, name: &str, trace: &ImpulseTrace) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, trace.to_csv()).unwrap();
    path
}

#[test]
fn identical_traces_exit_0() {
    let dir = tempfile::tempdir().unwrap();
    let a = write_trace(dir.path(), "a.csv", &trace());
    let b = write_trace(dir.path(), "b.csv", &trace());
    let out = hopsim(&[&a, &b], &[]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert_eq!(stdout, "identical within tolerance (41 samples)\n");
}

#[test]
fn an_injected_difference_exits_1_and_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let a = write_trace(dir.path(), "a.csv", &trace());
    // Edit one impulse in a copy of the file's text.
    let text_a = std::fs::read_to_string(&a).unwrap();
    let line = text_a.lines().find(|l| l.starts_with("17,")).unwrap();
    let fields: Vec<&str> = line.split(',').collect();
    let edited = format!(
        "{},{},{},0.0028,{}",
        fields[0], fields[1], fields[2], fields[4]
    );
    let b = dir.path().join("b.csv");
    std::fs::write(&b, text_a.replace(line, &edited)).unwrap();

    let out = hopsim(&[&a, &b], &[]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("first difference at step 17 (t = 0.003400 s), disc/ground normal"),
        "{stdout}"
    );
    assert!(
        stdout.contains("found 2.8e-3") && stdout.contains("(1 of 41 samples differ"),
        "{stdout}"
    );
    // A loose enough tolerance accepts it.
    let out = hopsim(&[&a, &b], &["--abs-tol", "1e-3"]);
    assert_eq!(out.status.code(), Some(0), "{:?}", text(&out));
}

#[test]
fn unreadable_inputs_exit_2_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let a = write_trace(dir.path(), "a.csv", &trace());
    let garbage = dir.path().join("garbage.csv");
    std::fs::write(&garbage, "this is not a trace\n1,2,3\n").unwrap();
    for bad in [garbage, dir.path().join("missing.mcap")] {
        let out = hopsim(&[&a, &bad], &[]);
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{stdout}{stderr}");
        assert!(stderr.contains(&bad.display().to_string()), "{stderr}");
    }
    let out = hopsim(&[&a, &a], &["--states"]);
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--states needs two .mcap recordings"),
        "{stderr}"
    );
}

/// A recording of a one-body robot whose contact percussion is `impulse(step)`.
fn record(path: &Path, impulse: impl Fn(u64) -> f64) {
    let info = RecordingInfo {
        scene: "wheel".into(),
        scene_path: "wheel.toml".into(),
        scene_text: "[meta]\ntitle = \"wheel\"\n".into(),
        coordinates: ["x", "y", "phi"].map(String::from).to_vec(),
        coordinate_units: {
            use hopsim_record::CoordinateUnit::{Metre, Radian};
            vec![Metre, Metre, Radian]
        },
        bodies: vec![BodyInfo {
            name: "wheel".into(),
            shapes: vec![],
        }],
        contacts: vec!["wheel/ground".into()],
        joints: vec![],
        loops: vec![],
        springs: vec![],
        terrain: Terrain::flat(0.0),
        dt: 1e-3,
        weight_newtons: 9.81,
        actuated: false,
        actuator: hopsim_record::ActuatorQuantity::Torque,
        actuators: vec![],
    };
    let mut recorder = Box::new(McapRecorder::create(path, &info).unwrap());
    for step in (1..=50).step_by(5) {
        let t = step as f64 * 1e-3;
        let q = [t, 0.5, -t / 0.5];
        let contacts = [ContactSample {
            contact: 0,
            point: [t, 0.0],
            normal: [0.0, 1.0],
            impulse_normal: impulse(step),
            impulse_tangent: 0.0,
            state: "stick",
            friction_indeterminate: false,
        }];
        let bodies = [BodyPose {
            position: [t, 0.5],
            angle: q[2],
        }];
        let frame = Frame {
            t,
            step,
            q: &q,
            u: &[1.0, 0.0, -2.0],
            bodies: &bodies,
            com: [t, 0.5],
            contacts: &contacts,
            springs: &[],
            shapes_active: &[],
            energy: EnergySample::default(),
            actuator_torque: 0.0,
            controls: &[],
            actuator_efforts: &[],
        };
        recorder.frame(&frame).unwrap();
    }
    recorder.finish().unwrap();
}

#[test]
fn recordings_are_compared_too() {
    let dir = tempfile::tempdir().unwrap();
    let [a, b, c] = ["a", "b", "c"].map(|n| dir.path().join(format!("{n}.mcap")));
    record(&a, |_| 9.81e-3);
    record(&b, |_| 9.81e-3);
    record(&c, |step| if step == 26 { 1e-2 } else { 9.81e-3 });
    let out = hopsim(&[&a, &b], &["--states"]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert_eq!(
        stdout,
        "identical within tolerance (10 samples)\nstates identical within tolerance (10 steps)\n"
    );
    let out = hopsim(&[&a, &c], &[]);
    let (stdout, _) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("step 26 (t = 0.026000 s), wheel/ground normal"),
        "{stdout}"
    );
}
