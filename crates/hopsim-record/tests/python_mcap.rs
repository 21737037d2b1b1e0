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
import json, sys
try:
    from mcap.reader import make_reader
    import jsonschema
except ImportError as e:
    print(e, file=sys.stderr)
    sys.exit(77)

counts, states, impulses, events = {}, [], [], []
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
        assert message.log_time == round(data["t_s"] * 1e9), (message.log_time, data["t_s"])
        assert message.publish_time == message.log_time
        counts[channel.topic] = counts.get(channel.topic, 0) + 1
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
                  "events": events, "attachments": attachments, "metadata": metadata}))
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
    let Some(output) = run(Command::new("python3").arg(&script).arg(&path)) else {
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
    assert_eq!(
        result["attachments"],
        serde_json::json!([["robbit-test.toml", "application/toml", SCENE_TEXT]])
    );
    assert_eq!(result["metadata"]["hopsim"]["scene"], "robbit test");
}
