//! A run's MCAP recording read back matches the simulation's own records: every recorded
//! state, every contact percussion at the recorded steps, and every event.

use hopsim_record::{ImpulseTrace, TraceTolerance};
use hopsim_record::{McapRecorder, McapRecording, RecorderSet};
use hopsim_scene::Override;
use hopsim_sim::{recording_info, Observer, RecordingObserver, RunError, StepView};
use std::path::Path;

/// What the simulation itself produced, step by step.
#[derive(Default)]
struct Truth {
    states: Vec<(u64, Vec<f64>, Vec<f64>)>,
    trace: ImpulseTrace,
    events: Vec<hopsim_record::Event>,
}

/// Feeds the recorder and keeps the truth.
struct Both<'a> {
    recorder: &'a mut RecordingObserver,
    truth: &'a mut Truth,
}

impl Observer for Both<'_> {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        self.truth.states.push((
            v.record.step,
            v.state.q.as_slice().to_vec(),
            v.state.u.as_slice().to_vec(),
        ));
        self.truth.trace.push_record(v.model, v.record);
        self.truth.events.extend(v.events.iter().cloned());
        self.recorder.on_step(v)
    }

    fn on_start(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        self.truth.states.push((
            v.record.step,
            v.state.q.as_slice().to_vec(),
            v.state.u.as_slice().to_vec(),
        ));
        self.recorder.on_start(v)
    }
}

/// The bundled scene `name` run for `duration` seconds, and an observer recording it to
/// `run.mcap` in a new temporary folder.
fn mcap_run(
    name: &str,
    duration: &str,
) -> (hopsim_scene::Scene, tempfile::TempDir, RecordingObserver) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}"));
    let scene =
        hopsim_scene::load(&path, &[Override::new("simulation.duration", duration)]).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut set = RecorderSet::default();
    set.push(Box::new(
        McapRecorder::create(&dir.path().join("run.mcap"), &recording_info(&scene)).unwrap(),
    ));
    let recorder = RecordingObserver::new(set, &scene);
    (scene, dir, recorder)
}

#[test]
fn mcap_of_a_run_matches_the_simulation_records() {
    let (scene, dir, mut recorder) = mcap_run("robbit.toml", "2.0");
    let file = dir.path().join("run.mcap");
    let mut truth = Truth::default();
    hopsim_sim::run(
        &scene,
        &mut Both {
            recorder: &mut recorder,
            truth: &mut truth,
        },
    )
    .unwrap();
    recorder.finish().unwrap();

    let rec = McapRecording::read(&file).unwrap();
    assert_eq!(rec.metadata.coordinates, scene.coordinates);
    // The initial state first, then at 1 kHz with Δt = 0.2 ms every 5th step, plus every
    // step with an event: each recorded state is the simulation's state at that step.
    let first = &rec.states[0];
    assert_eq!((first.step, first.t), (0, 0.0));
    assert_eq!(first.q, scene.initial.q.as_slice());
    let every_fifth = (0..=10_000u64).step_by(5).collect::<Vec<_>>();
    let steps: std::collections::BTreeSet<u64> = rec.states.iter().map(|s| s.step).collect();
    assert!(
        every_fifth.iter().all(|k| steps.contains(k)),
        "a 1 kHz frame is missing"
    );
    let event_steps = truth.events.iter().map(|e| e.step);
    assert!(
        event_steps.clone().all(|k| steps.contains(&k)),
        "an event step is missing"
    );
    let extra = steps.iter().filter(|k| *k % 5 != 0).count();
    assert!(
        extra <= truth.events.len(),
        "{extra} frames off the 1 kHz grid"
    );
    assert_eq!(steps.len(), rec.states.len(), "a step recorded twice");
    for s in &rec.states {
        let (step, q, u) = &truth.states[s.step as usize];
        assert_eq!(*step, s.step);
        assert_eq!((&s.q, &s.u), (q, u), "state at step {}", s.step);
    }
    // Contact percussions: the recording holds exactly the truth's at the recorded steps.
    let recorded: std::collections::HashSet<u64> = rec.states.iter().map(|s| s.step).collect();
    let mut expected = truth.trace.clone();
    expected
        .samples
        .retain(|s| recorded.contains(&s.step) && !s.channel.starts_with("lock:"));
    let mut contacts = rec.impulses.clone();
    contacts
        .samples
        .retain(|s| s.channel != hopsim_record::BRAKE_CHANNEL);
    assert!(!expected.samples.is_empty());
    let exact = TraceTolerance { abs: 0.0, rel: 0.0 };
    assert_eq!(expected.first_difference(&contacts, exact), None);
    // Every event, exactly.
    assert!(truth
        .events
        .iter()
        .any(|e| matches!(e.kind, hopsim_record::EventKind::Brake { .. })));
    assert_eq!(rec.events, truth.events);
}

/// The pendulum on a joint stop (docs/classics.md §3) records one `joint_limit` event per
/// hit of its stop, in the step the stop starts carrying load, with that step's percussion;
/// the first is `I_O (1 + ε) |ω⁻|` (ε = 0.5, `ω⁻` from energy: 2.7124712 N m s).
#[test]
fn mcap_records_every_joint_stop_hit_with_its_impulse() {
    let (scene, dir, mut recorder) = mcap_run("classic/pendulum-stop.toml", "2.5");
    let file = dir.path().join("run.mcap");
    /// Steps where the stop's percussion rises from nothing, with that percussion.
    #[derive(Default)]
    struct Hits {
        loaded: bool,
        hits: Vec<(u64, f64)>,
    }
    impl Observer for Hits {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            let impulse: f64 = v.record.limits.iter().map(|l| l.impulse).sum();
            let loaded = impulse > 1e-9;
            if loaded && !self.loaded {
                self.hits.push((v.record.step, impulse));
            }
            self.loaded = loaded;
            Ok(())
        }
    }
    let mut hits = Hits::default();
    hopsim_sim::run(&scene, &mut (&mut recorder, &mut hits)).unwrap();
    recorder.finish().unwrap();
    let rec = McapRecording::read(&file).unwrap();
    let recorded: Vec<(u64, f64)> = rec
        .events
        .iter()
        .filter_map(|e| match &e.kind {
            hopsim_record::EventKind::JointLimit { limit, impulse } => {
                assert_eq!(limit, "rod/lower");
                Some((e.step, *impulse))
            }
            _ => None,
        })
        .collect();
    assert!(hits.hits.len() >= 3, "{:?}", hits.hits);
    assert_eq!(recorded, hits.hits);
    let expected = (1.0 / 3.0) * 1.5 * (2.0 * 14.715f64).sqrt();
    assert!((recorded[0].1 - expected).abs() < 1e-6, "{recorded:?}");
    // Every event step is a recorded frame.
    let steps: std::collections::BTreeSet<u64> = rec.states.iter().map(|s| s.step).collect();
    assert!(recorded.iter().all(|(k, _)| steps.contains(k)));
}

/// Every coordinate is recorded in its own unit: a floating base's `x`, `y` and a prismatic
/// leg's extension in metres, angles in radians, whatever their place in `q`.
#[test]
fn recordings_name_each_coordinate_with_its_unit() {
    let columns = |name: &str| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}"));
        let scene = hopsim_scene::load(&path, &[]).unwrap();
        let columns = hopsim_record::frame_columns(&recording_info(&scene));
        let coordinates = 2 + scene.coordinates.len();
        columns[2..coordinates].to_vec()
    };
    // The hopper: a floating body (x, y, phi) with a prismatic leg `s` along −y.
    assert_eq!(
        columns("classic/hopper.toml"),
        ["x_m", "y_m", "phi_rad", "s_m"]
    );
    // The pendulum pinned to the world: its one coordinate is an angle.
    assert_eq!(columns("classic/pendulum-stop.toml"), ["theta_rad"]);
    // Robbit: the floating disc and the flywheel's angle.
    assert_eq!(columns("robbit.toml"), ["x_m", "y_m", "phi_rad", "psi_rad"]);
}

/// The hopper's prismatic leg is described in the recording (docs/physics.md §7): its link,
/// drawn from the anchor on the body to the foot's joint point, has length `s` and lies
/// along the body-rotated axis at every step; the MCAP metadata lists the joint and the
/// Foxglove scene draws its rail (the limits `[0.1, 0.5]` m along −y) in the body's frame.
#[test]
fn a_prismatic_leg_is_described_and_drawn_along_its_axis() {
    let (scene, dir, mut recorder) = mcap_run("classic/hopper.toml", "0.5");
    let info = recording_info(&scene);
    let leg = info
        .joints
        .iter()
        .find(|j| j.is_prismatic())
        .unwrap()
        .clone();
    assert_eq!((leg.body, leg.parent), (1, Some(0)));
    /// The largest deviation of the link from `s` along `R(φ) axis`, m.
    struct Links {
        leg: hopsim_record::JointInfo,
        worst: f64,
        steps: usize,
    }
    impl Observer for Links {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            let k = v.kinematics;
            let poses: Vec<hopsim_record::BodyPose> = (0..k.bodies())
                .map(|b| hopsim_record::BodyPose {
                    position: [k.position(b).x, k.position(b).y],
                    angle: k.angle(b),
                })
                .collect();
            let [a, b] = self.leg.link(&poses);
            let (q, (sin, cos)) = (v.state.q.as_slice(), k.angle(0).sin_cos());
            // Anchor at the body's centre of mass (pivot [0, 0]); axis (0, −1) rotated by φ.
            let expected_end = [a[0] + q[3] * sin, a[1] - q[3] * cos];
            let errors = [
                a[0] - q[0],
                a[1] - q[1],
                b[0] - expected_end[0],
                b[1] - expected_end[1],
            ];
            self.worst = errors.iter().fold(self.worst, |w, e| w.max(e.abs()));
            self.steps += 1;
            Ok(())
        }
    }
    let mut links = Links {
        leg,
        worst: 0.0,
        steps: 0,
    };
    hopsim_sim::run(&scene, &mut (&mut recorder, &mut links)).unwrap();
    recorder.finish().unwrap();
    assert!(links.steps > 1000);
    // Round-off of a few additions of numbers below 1 m.
    assert!(
        links.worst < 1e-14,
        "link off its axis by {:e} m",
        links.worst
    );

    let bytes = std::fs::read(dir.path().join("run.mcap")).unwrap();
    let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
    let index = &summary.metadata_indexes[0];
    let meta = mcap::read::metadata(&bytes, index).unwrap();
    let joints: serde_json::Value = serde_json::from_str(&meta.metadata["joints"]).unwrap();
    assert_eq!(
        joints,
        serde_json::json!([{
            "kind": "prismatic", "body": "foot", "parent": "body", "axis": [0.0, -1.0],
            "stroke_m": [0.1, 0.5], "anchor_m": [0.0, 0.0], "child_point_m": [0.0, 0.0]
        }])
    );
    let scene_update = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .find(|m| m.channel.topic == hopsim_record::FOXGLOVE_SCENE_TOPIC)
        .unwrap();
    let update: serde_json::Value = serde_json::from_slice(&scene_update.data).unwrap();
    let body = update["entities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["id"] == "body/body")
        .unwrap();
    // Foxglove's x–z plane: (x, y) is drawn at (x, 0, y).
    let rail = serde_json::json!([
        {"x": 0.0, "y": 0.0, "z": -0.1},
        {"x": 0.0, "y": 0.0, "z": -0.5}
    ]);
    assert!(
        body["lines"]
            .as_array()
            .unwrap()
            .iter()
            .any(|l| l["points"] == rail),
        "no rail in {body}"
    );
}

/// The actuators' controls and efforts are recorded by name (docs/recording.md): in the
/// servo arm's MCAP, each recorded step's controls are the scene's signals at the step's
/// midpoint (docs/physics.md §7.4; a 0.8 rad sine at 0.5 Hz, a 4 rad/s pulse for 0.3 s of every second), and each
/// effort is MuJoCo's force law at the recorded state, written out here: the shoulder's
/// `k_p (u − q) − k_v q̇` and the elbow's `k_v (u − q̇)`, clamped to ±25 and ±3 N m.
#[test]
fn actuator_controls_and_efforts_are_recorded_by_name() {
    let (scene, dir, mut recorder) = mcap_run("classic/servo-arm.toml", "2.0");
    hopsim_sim::run(&scene, &mut recorder).unwrap();
    recorder.finish().unwrap();
    let columns = hopsim_record::frame_columns(&recording_info(&scene));
    assert!(columns.ends_with(&[
        "control_shoulder".to_string(),
        "control_elbow".into(),
        "effort_shoulder_Nm".into(),
        "effort_elbow_Nm".into()
    ]));
    let bytes = std::fs::read(dir.path().join("run.mcap")).unwrap();
    let dt = scene.settings.dt;
    let mut checked = 0;
    for message in mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
    {
        if message.channel.topic != hopsim_record::STATE_TOPIC {
            continue;
        }
        let m: serde_json::Value = serde_json::from_slice(&message.data).unwrap();
        let number = |v: &serde_json::Value| v.as_f64().unwrap();
        let (t, step) = (number(&m["t_s"]), m["step"].as_u64().unwrap());
        if step == 0 {
            continue;
        }
        let mid = t - 0.5 * dt;
        let shoulder = 0.8 * (std::f64::consts::PI * mid).sin();
        let elbow = if mid.rem_euclid(1.0) < 0.3 { 4.0 } else { 0.0 };
        let controls = &m["controls"];
        assert!(
            (number(&controls["shoulder"]) - shoulder).abs() < 1e-9,
            "{m}"
        );
        assert_eq!(number(&controls["elbow"]), elbow, "{m}");
        let (q, u) = (&m["q"], &m["u"]);
        let shoulder_effort = (60.0 * (shoulder - number(&q["shoulder"]))
            - 4.0 * number(&u["shoulder"]))
        .clamp(-25.0, 25.0);
        let elbow_effort = (2.0 * (elbow - number(&u["elbow"]))).clamp(-3.0, 3.0);
        let efforts = &m["actuator_efforts"];
        assert!(
            (number(&efforts["shoulder"]) - shoulder_effort).abs() < 1e-9,
            "{m}"
        );
        assert!(
            (number(&efforts["elbow"]) - elbow_effort).abs() < 1e-9,
            "{m}"
        );
        checked += 1;
    }
    assert!(checked >= 100, "{checked} state messages checked");
}
