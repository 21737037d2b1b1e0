//! Python's `mcap` reader (what researchers use) decodes every message of a hopsim
//! recording, and `jsonschema` validates each against its channel's schema.
//! Without the packages the test is skipped with a notice, unless HOPSIM_REQUIRE_PYTHON=1.

mod common;

use common::{events, feed, frames, info, run, skip_or_fail, SCENE_TEXT};
use hopsim_record::{McapRecorder, Recorder};
use serde_json::Value;
use std::process::Command;

/// Exit status of the script when `mcap` or `jsonschema` cannot be imported.
const MISSING_PACKAGE: i32 = 77;

const SCRIPT: &str = r#"
import json, os, sys
try:
    from mcap.reader import make_reader
    import jsonschema
except ImportError as e:
    print(e, file=sys.stderr)
    sys.exit(77)

counts, states, impulses, events, poses, scenes = {}, [], [], [], [], []
with open(sys.argv[1], "rb") as f:
    reader = make_reader(f)
    for schema, channel, message in reader.iter_messages():
        assert channel.message_encoding == "json", channel.message_encoding
        assert schema.encoding == "jsonschema", schema.encoding
        schema_doc = json.loads(schema.data)
        validator = jsonschema.validators.validator_for(schema_doc)
        validator.check_schema(schema_doc)
        data = json.loads(message.data)
        validator(schema_doc).validate(data)
        assert "t_s" in data or channel.topic.startswith("/foxglove/"), channel.topic
        if "t_s" in data:
            assert message.log_time == round(data["t_s"] * 1e9), (message.log_time, data["t_s"])
        assert message.publish_time == message.log_time
        counts[channel.topic] = counts.get(channel.topic, 0) + 1
        if channel.topic.startswith("/foxglove/"):
            # Foxglove's own schema, as vendored, with {sec, nsec} stamps at the log time.
            name = schema.name.removeprefix("foxglove.")
            with open(os.path.join(sys.argv[2], name + ".json")) as vendored:
                assert json.load(vendored) == schema_doc, schema.name
            stamped = data.get("transforms", data.get("entities"))
            for item in stamped:
                stamp = item["timestamp"]
                assert stamp["sec"] * 10**9 + stamp["nsec"] == message.log_time
        if channel.topic == "/foxglove/transforms":
            poses.append([data["transforms"][1]["child_frame_id"],
                          data["transforms"][1]["translation"],
                          data["transforms"][1]["rotation"]])
        elif channel.topic == "/foxglove/scene":
            scenes.append({e["id"]: (e["frame_id"], [l["color"]["r"] for l in e["lines"]],
                                     len(e["spheres"]))
                           for e in data["entities"]})
        if channel.topic == "/hopsim/state":
            states.append([data["step"], data["t_s"], data["q"]["x"], data["q"]["phi"],
                           data["u"]["psi"], data["bodies"]["flywheel"]["angle_rad"]])
        elif channel.topic == "/hopsim/contacts":
            for c in data["contacts"]:
                impulses.append([data["step"], c["name"], c["normal_impulse_Ns"],
                                 c["tangent_impulse_Ns"]])
        elif channel.topic == "/hopsim/events":
            events.append([data["step"], data["kind"]])
    attachments = [(a.name, a.media_type, a.data.decode("utf-8"))
                   for a in reader.iter_attachments()]
    metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
print(json.dumps({"counts": counts, "states": states, "impulses": impulses,
                  "events": events, "attachments": attachments, "metadata": metadata,
                  "poses": poses, "scenes": scenes}))
"#;

#[test]
fn python_mcap_reader_decodes_every_message() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let (frames, events) = (frames(20), events());
    let mut recorder = Box::new(McapRecorder::create(&path, &info()).unwrap());
    feed(recorder.as_mut(), &frames, &events);
    recorder.finish().unwrap();

    let script = dir.path().join("read.py");
    std::fs::write(&script, SCRIPT).unwrap();
    let schemas = concat!(env!("CARGO_MANIFEST_DIR"), "/schemas/foxglove");
    let python = run(Command::new("python3").arg(&script).arg(&path).arg(schemas));
    let Some(output) = python else {
        return skip_or_fail("python3 is not installed");
    };
    let stderr = String::from_utf8_lossy(&output.stderr);
    if output.status.code() == Some(MISSING_PACKAGE) {
        return skip_or_fail(&format!(
            "Python packages mcap/jsonschema missing ({})",
            stderr.trim()
        ));
    }
    assert!(output.status.success(), "python reader failed:\n{stderr}");
    let result: Value = serde_json::from_slice(&output.stdout).unwrap();

    let n = frames.len() as u64;
    assert_eq!(result["counts"]["/hopsim/state"], n);
    assert_eq!(result["counts"]["/hopsim/contacts"], n);
    assert_eq!(result["counts"]["/hopsim/energy"], n);
    assert_eq!(result["counts"]["/hopsim/events"], events.len() as u64);

    let states = result["states"].as_array().unwrap();
    for (s, f) in states.iter().zip(&frames) {
        let expected = serde_json::json!([f.step, f.t, f.q[0], f.q[2], f.u[3], f.bodies[1].angle]);
        assert_eq!(*s, expected, "Python reads the same numbers, bit for bit");
    }
    let contact_count: usize = frames.iter().map(|f| f.contacts.len()).sum();
    assert_eq!(result["impulses"].as_array().unwrap().len(), contact_count);
    let kinds: Vec<&str> = result["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e[1].as_str().unwrap())
        .collect();
    assert_eq!(
        kinds,
        [
            "take_off",
            "touchdown",
            "brake",
            "shape_switch",
            "applied_impulse"
        ]
    );
    // Foxglove: one transform message per frame placing the flywheel's frame at its pose
    // in the x-z plane, rotated by -angle about y (in single precision, as written); the
    // scene sent at the first frame and again at every shape switch (the cane alternates),
    // with the terrain in the world.
    assert_eq!(result["counts"]["/foxglove/transforms"], n);
    for (pose, f) in result["poses"].as_array().unwrap().iter().zip(&frames) {
        let [x, y] = f.bodies[1].position.map(|v| v as f32);
        let (s, c) = (0.5 * f.bodies[1].angle).sin_cos();
        let (s, c) = (s as f32, c as f32);
        assert_eq!(pose[0], "body/flywheel");
        // Python reads the shortest single-precision text as a double: back to single.
        let read = |v: &Value, key: &str| v[key].as_f64().unwrap() as f32;
        let (t, r) = (&pose[1], &pose[2]);
        assert_eq!([read(t, "x"), read(t, "y"), read(t, "z")], [x, 0.0, y]);
        assert_eq!(
            [read(r, "x"), read(r, "y"), read(r, "z"), read(r, "w")],
            [0.0, -s, 0.0, c]
        );
    }
    let scenes = result["scenes"].as_array().unwrap();
    let switches = frames
        .windows(2)
        .filter(|w| w[0].shapes_active != w[1].shapes_active)
        .count();
    assert!(
        scenes.len() > switches && scenes.len() <= switches + 1 + 10,
        "{} scene updates for {switches} switches",
        scenes.len()
    );
    for scene in scenes {
        assert_eq!(scene["terrain"][0], "world");
        assert_eq!(scene["body/disc"][0], "body/disc");
        // The disc: its spoke and rim; the cane tip a sphere beside the CoM marker.
        assert_eq!(scene["body/disc"][1].as_array().unwrap().len(), 2);
        assert_eq!(scene["body/disc"][2], 2);
    }
    assert_eq!(
        result["attachments"],
        serde_json::json!([["robbit-test.toml", "application/toml", SCENE_TEXT]])
    );
    assert_eq!(result["metadata"]["hopsim"]["scene"], "robbit test");
}
