//! Synthetic runs shared by the recorder tests: a Robbit-like robot (disc with a cane, a
//! flywheel without shapes, a spring) over a step, with contacts and every event kind.

#![allow(dead_code)]

use hopsim_model::{Shape, Terrain, Vec2};
use hopsim_record::{
    BodyInfo, BodyPose, ContactSample, EnergySample, Event, EventKind, Frame, JointInfo,
    JointInfoKind, RecordingInfo,
};
use std::process::Command;

/// The scene file text stored in recordings (with non-ASCII to check the round trip).
pub const SCENE_TEXT: &str = "[meta]\ntitle = \"robbit test\" # φ, ψ\n\n[simulation]\ndt = 2e-4\n";

pub fn info() -> RecordingInfo {
    RecordingInfo {
        scene: "robbit test".into(),
        scene_path: "scenes/robbit-test.toml".into(),
        scene_text: SCENE_TEXT.into(),
        coordinates: ["x", "y", "phi", "psi"].map(String::from).to_vec(),
        coordinate_units: {
            use hopsim_record::CoordinateUnit::{Metre, Radian};
            vec![Metre, Metre, Radian, Radian]
        },
        bodies: vec![
            BodyInfo {
                name: "disc".into(),
                shapes: vec![
                    (
                        "rim".into(),
                        Shape::Circle {
                            center: Vec2::new(0.0, 0.1),
                            radius: 0.2,
                        },
                    ),
                    (
                        "cane".into(),
                        Shape::Point {
                            position: Vec2::new(0.15, -0.15),
                        },
                    ),
                ],
            },
            BodyInfo {
                name: "flywheel".into(),
                shapes: vec![],
            },
        ],
        contacts: vec!["disc/ground".into(), "cane/ground".into()],
        joints: vec![JointInfo {
            body: 1,
            parent: Some(0),
            anchor_m: [0.0, 0.0],
            child_point_m: [0.0, 0.0],
            kind: JointInfoKind::Revolute,
        }],
        loops: vec![],
        springs: vec!["spring".into()],
        terrain: Terrain::step(1.0, 0.05),
        dt: 2e-4,
        weight_newtons: 1.405 * 9.81,
        actuated: true,
        actuator: hopsim_record::ActuatorQuantity::Torque,
        actuators: vec![hopsim_record::ActuatorInfo {
            name: "flywheel_motor".into(),
            effort: hopsim_record::ActuatorQuantity::Torque,
        }],
    }
}

/// Owned storage of one frame.
#[derive(Clone, Debug)]
pub struct OwnedFrame {
    pub t: f64,
    pub step: u64,
    pub q: Vec<f64>,
    pub u: Vec<f64>,
    pub bodies: Vec<BodyPose>,
    pub com: [f64; 2],
    pub contacts: Vec<ContactSample>,
    pub springs: Vec<([f64; 2], [f64; 2])>,
    pub shapes_active: Vec<bool>,
    pub energy: EnergySample,
    pub actuator_torque: f64,
    pub controls: Vec<f64>,
    pub actuator_efforts: Vec<f64>,
}

impl OwnedFrame {
    pub fn frame(&self) -> Frame<'_> {
        Frame {
            t: self.t,
            step: self.step,
            q: &self.q,
            u: &self.u,
            bodies: &self.bodies,
            com: self.com,
            contacts: &self.contacts,
            springs: &self.springs,
            shapes_active: &self.shapes_active,
            energy: self.energy,
            actuator_torque: self.actuator_torque,
            controls: &self.controls,
            actuator_efforts: &self.actuator_efforts,
        }
    }
}

/// Frames every 10 steps; contacts at some, with awkward floats (0.1 + 0.2, 1/3, 1e-300).
pub fn frames(count: u64) -> Vec<OwnedFrame> {
    let dt = info().dt;
    (0..count)
        .map(|k| {
            let step = 10 * k + 1;
            let t = step as f64 * dt;
            let x = 0.01 * k as f64 + (0.1 + 0.2);
            let phi = -0.3 * t + 1.0 / 3.0;
            let psi = 50.0 * t;
            let in_contact = k % 3 != 2;
            let mut contacts = Vec::new();
            if in_contact {
                contacts.push(ContactSample {
                    contact: 0,
                    point: [x, 0.0],
                    normal: [0.0, 1.0],
                    impulse_normal: 2.7e-3 + 1e-6 * k as f64,
                    impulse_tangent: -1.0 / 3.0 * 1e-4,
                    state: "stick",
                    friction_indeterminate: false,
                });
            }
            if k % 5 == 4 {
                contacts.push(ContactSample {
                    contact: 1,
                    point: [x + 0.15, 0.0],
                    normal: [0.0, 1.0],
                    impulse_normal: if k == 4 { 1e-300 } else { 0.0 },
                    impulse_tangent: 0.0,
                    state: "open",
                    friction_indeterminate: true,
                });
            }
            OwnedFrame {
                t,
                step,
                q: vec![x, 0.1, phi, psi],
                u: vec![0.05, -0.0, -0.3, 50.0],
                bodies: vec![
                    BodyPose {
                        position: [x, 0.1],
                        angle: phi,
                    },
                    BodyPose {
                        position: [x, 0.1],
                        angle: psi,
                    },
                ],
                com: [x, 0.1],
                contacts,
                springs: vec![([x, 0.1], [x + 0.1, 0.05])],
                shapes_active: vec![true, k % 2 == 0],
                energy: EnergySample {
                    kinetic: 0.5 + t,
                    potential: 1.378,
                    spring: 1e-3,
                    actuator_work: t,
                    dissipated: 0.25 * t,
                    balance_error: -1e-12,
                },
                actuator_torque: if k % 4 < 2 { 0.3 } else { 0.0 },
                controls: vec![(0.1 * k as f64).sin()],
                actuator_efforts: vec![0.4 * (0.1 * k as f64).sin() - 1.0 / 3.0],
            }
        })
        .collect()
}

/// One event of every kind, at frame steps.
pub fn events() -> Vec<Event> {
    let dt = info().dt;
    let at = |step: u64, kind| Event {
        t: (step - 1) as f64 * dt,
        step,
        kind,
    };
    vec![
        at(11, EventKind::TakeOff),
        at(
            21,
            EventKind::Touchdown {
                contact: "disc/ground".into(),
            },
        ),
        at(31, EventKind::Brake { impulse: 0.059 }),
        at(
            41,
            EventKind::ShapeSwitch {
                shape: "cane".into(),
                active: false,
            },
        ),
        at(51, EventKind::AppliedImpulse { magnitude: 0.25 }),
    ]
}

/// Feeds frames and events in time order (events before the frame of their step, as the
/// simulation loop does).
pub fn feed(recorder: &mut dyn hopsim_record::Recorder, frames: &[OwnedFrame], events: &[Event]) {
    for f in frames {
        for e in events.iter().filter(|e| e.step == f.step) {
            recorder.event(e).unwrap();
        }
        recorder.frame(&f.frame()).unwrap();
    }
}

/// Files left in `dir`, sorted.
pub fn files_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Whether an external check that needs Python packages must run (`HOPSIM_REQUIRE_PYTHON=1`,
/// set by CI) or may be skipped with a notice.
pub fn python_required() -> bool {
    std::env::var("HOPSIM_REQUIRE_PYTHON").is_ok_and(|v| v == "1")
}

/// Skips (with a notice) or fails, following [`python_required`].
pub fn skip_or_fail(what: &str) {
    assert!(
        !python_required(),
        "{what}; HOPSIM_REQUIRE_PYTHON=1 requires it (pip install mcap jsonschema rerun-sdk==0.36.3)"
    );
    eprintln!("notice: skipping: {what} (set HOPSIM_REQUIRE_PYTHON=1 to make this an error)");
}

/// Runs a command; `None` when its program is missing.
pub fn run(command: &mut Command) -> Option<std::process::Output> {
    match command.output() {
        Ok(output) => Some(output),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => panic!("could not run {command:?}: {e}"),
    }
}
