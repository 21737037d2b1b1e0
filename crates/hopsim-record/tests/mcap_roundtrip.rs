//! MCAP recordings read back with the `mcap` crate and with hopsim's reader: every
//! message, time, channel, schema and the scene attachment match what was written.

mod common;

use common::{events, feed, files_in, frames, info, SCENE_TEXT};
use hopsim_record::{
    McapRecorder, McapRecording, RecordError, Recorder, BRAKE_CHANNEL, CONTACTS_TOPIC,
    ENERGY_TOPIC, EVENTS_TOPIC, FOXGLOVE_SCENE_TOPIC, FOXGLOVE_TRANSFORMS_TOPIC, METADATA_NAME,
    STATE_TOPIC,
};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::Path;

fn write_recording(path: &Path, frame_count: u64) {
    let mut recorder = Box::new(McapRecorder::create(path, &info()).unwrap());
    feed(recorder.as_mut(), &frames(frame_count), &events());
    recorder.finish().unwrap();
}

/// Every message of the file: topic → (log time, publish time, sequence, JSON).
fn messages(bytes: &[u8]) -> BTreeMap<String, Vec<(u64, u64, u32, Value)>> {
    let mut out: BTreeMap<String, Vec<_>> = BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        let schema = m
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        assert_eq!(schema.encoding, "jsonschema");
        assert_eq!(m.channel.message_encoding, "json");
        let value: Value = serde_json::from_slice(&m.data).unwrap();
        let schema: Value = serde_json::from_slice(&schema.data).unwrap();
        // Foxglove's schemas use `oneOf`/`const`; tests/python_mcap.rs validates those
        // messages with `jsonschema`.
        if !m.channel.topic.starts_with("/foxglove/") {
            check_against_schema(&value, &schema, &m.channel.topic);
        }
        out.entry(m.channel.topic.clone()).or_default().push((
            m.log_time,
            m.publish_time,
            m.sequence,
            value,
        ));
    }
    out
}

/// A structural JSON Schema check covering the keywords hopsim's schemas use: `type`,
/// `properties`, `required`, `items`, `enum` (the Python test validates with `jsonschema`).
fn check_against_schema(value: &Value, schema: &Value, at: &str) {
    let kind = schema["type"]
        .as_str()
        .unwrap_or_else(|| panic!("{at}: schema without type"));
    let ok = match kind {
        "object" => value.is_object(),
        "array" => value.is_array(),
        "number" => value.is_number(),
        "integer" => value.is_u64() || value.is_i64(),
        "string" => value.is_string(),
        "boolean" => value.is_boolean(),
        other => panic!("{at}: unexpected schema type {other}"),
    };
    assert!(ok, "{at}: {value} is not a {kind}");
    if let Some(options) = schema.get("enum") {
        assert!(
            options.as_array().unwrap().contains(value),
            "{at}: {value} not in {options}"
        );
    }
    if kind == "object" {
        let properties = schema["properties"].as_object().unwrap();
        for required in schema["required"].as_array().into_iter().flatten() {
            let key = required.as_str().unwrap();
            assert!(
                value.get(key).is_some(),
                "{at}: required field {key} missing"
            );
        }
        for (key, v) in value.as_object().unwrap() {
            let sub = properties
                .get(key)
                .unwrap_or_else(|| panic!("{at}: field {key} not in the schema"));
            check_against_schema(v, sub, &format!("{at}.{key}"));
        }
    }
    if kind == "array" {
        for (i, v) in value.as_array().unwrap().iter().enumerate() {
            check_against_schema(v, &schema["items"], &format!("{at}[{i}]"));
        }
    }
}

fn nanos(t: f64) -> u64 {
    (t * 1e9).round() as u64
}

#[test]
fn every_message_reads_back_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let (frames, events) = (frames(12), events());
    write_recording(&path, 12);
    assert_eq!(files_in(dir.path()), ["run.mcap"]);
    let bytes = std::fs::read(&path).unwrap();
    let messages = messages(&bytes);

    let topics: Vec<&str> = messages.keys().map(String::as_str).collect();
    let mut expected_topics = vec![
        STATE_TOPIC,
        CONTACTS_TOPIC,
        ENERGY_TOPIC,
        EVENTS_TOPIC,
        FOXGLOVE_SCENE_TOPIC,
        FOXGLOVE_TRANSFORMS_TOPIC,
    ];
    expected_topics.sort();
    assert_eq!(topics, expected_topics);

    let states = &messages[STATE_TOPIC];
    assert_eq!(states.len(), frames.len());
    for (seq, ((log, publish, sequence, v), f)) in states.iter().zip(&frames).enumerate() {
        assert_eq!(
            (*log, *publish, *sequence),
            (nanos(f.t), nanos(f.t), seq as u32)
        );
        let expected = json!({
            "t_s": f.t,
            "step": f.step,
            "q": {"x": f.q[0], "y": f.q[1], "phi": f.q[2], "psi": f.q[3]},
            "u": {"x": f.u[0], "y": f.u[1], "phi": f.u[2], "psi": f.u[3]},
            "com_m": {"x": f.com[0], "y": f.com[1]},
            "bodies": {
                "disc": {"x_m": f.bodies[0].position[0], "y_m": f.bodies[0].position[1],
                         "angle_rad": f.bodies[0].angle},
                "flywheel": {"x_m": f.bodies[1].position[0], "y_m": f.bodies[1].position[1],
                             "angle_rad": f.bodies[1].angle},
            },
            "actuator_torque_Nm": f.actuator_torque,
            "controls": {"flywheel_motor": f.controls[0]},
            "actuator_efforts": {"flywheel_motor": f.actuator_efforts[0]},
        });
        assert_eq!(*v, expected);
    }

    let contacts = &messages[CONTACTS_TOPIC];
    assert_eq!(contacts.len(), frames.len());
    let names = info().contacts;
    for ((log, _, _, v), f) in contacts.iter().zip(&frames) {
        assert_eq!(*log, nanos(f.t));
        let list: Vec<Value> = f
            .contacts
            .iter()
            .map(|c| {
                json!({
                    "name": names[c.contact],
                    "point_m": {"x": c.point[0], "y": c.point[1]},
                    "normal": {"x": c.normal[0], "y": c.normal[1]},
                    "normal_impulse_Ns": c.impulse_normal,
                    "tangent_impulse_Ns": c.impulse_tangent,
                    "state": c.state,
                })
            })
            .collect();
        assert_eq!(*v, json!({"t_s": f.t, "step": f.step, "contacts": list}));
    }

    let energy = &messages[ENERGY_TOPIC];
    assert_eq!(energy.len(), frames.len());
    for ((log, _, _, v), f) in energy.iter().zip(&frames) {
        assert_eq!(*log, nanos(f.t));
        let e = f.energy;
        let expected = json!({
            "t_s": f.t, "step": f.step, "kinetic_J": e.kinetic, "potential_J": e.potential,
            "spring_J": e.spring, "actuator_work_J": e.actuator_work,
            "dissipated_J": e.dissipated, "balance_error_J": e.balance_error,
        });
        assert_eq!(*v, expected);
    }

    let logged = &messages[EVENTS_TOPIC];
    assert_eq!(logged.len(), events.len());
    let expected_events = [
        json!({"kind": "take_off"}),
        json!({"kind": "touchdown", "contact": "disc/ground"}),
        json!({"kind": "brake", "impulse_Nms": 0.059}),
        json!({"kind": "shape_switch", "shape": "cane", "active": false}),
        json!({"kind": "applied_impulse", "magnitude": 0.25}),
    ];
    for (((log, _, _, v), e), fields) in logged.iter().zip(&events).zip(expected_events) {
        assert_eq!(*log, nanos(e.t), "events are logged at their own time");
        let mut expected = json!({"t_s": e.t, "step": e.step});
        expected
            .as_object_mut()
            .unwrap()
            .extend(fields.as_object().unwrap().clone());
        assert_eq!(*v, expected);
    }

    // Schemas: JSON Schema documents naming their draft, one per channel; Foxglove's
    // channels carry Foxglove's schemas.
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("a summary section");
    assert_eq!(summary.channels.len(), 6);
    for channel in summary.channels.values() {
        let schema = channel.schema.as_ref().unwrap();
        if channel.topic.starts_with("/foxglove/") {
            assert!(schema.name.starts_with("foxglove."), "{}", schema.name);
            continue;
        }
        let schema: Value = serde_json::from_slice(&schema.data).unwrap();
        assert_eq!(
            schema["$schema"],
            "https://json-schema.org/draft/2020-12/schema"
        );
        assert_eq!(schema["type"], "object");
        assert!(schema["required"]
            .as_array()
            .unwrap()
            .contains(&json!("t_s")));
    }
    let stats = summary.stats.unwrap();
    assert_eq!(
        stats.message_count,
        3 * frames.len() as u64
            + events.len() as u64
            + messages[FOXGLOVE_TRANSFORMS_TOPIC].len() as u64
            + messages[FOXGLOVE_SCENE_TOPIC].len() as u64
    );
    assert_eq!(messages[FOXGLOVE_TRANSFORMS_TOPIC].len(), frames.len());
    assert!(!summary.chunk_indexes.is_empty(), "chunked");
    assert!(summary
        .chunk_indexes
        .iter()
        .all(|c| c.compression == "zstd"));

    // The scene attachment and the metadata record.
    assert_eq!(summary.attachment_indexes.len(), 1);
    let attachment = mcap::read::attachment(&bytes, &summary.attachment_indexes[0]).unwrap();
    assert_eq!(attachment.name, "robbit-test.toml");
    assert_eq!(attachment.media_type, "application/toml");
    assert_eq!(&*attachment.data, SCENE_TEXT.as_bytes());
    let index = summary
        .metadata_indexes
        .iter()
        .find(|m| m.name == METADATA_NAME)
        .unwrap();
    let metadata = mcap::read::metadata(&bytes, index).unwrap().metadata;
    assert_eq!(metadata["scene"], "robbit test");
    assert_eq!(metadata["scene_path"], "scenes/robbit-test.toml");
    assert_eq!(metadata["dt_s"], "0.0002");
    assert_eq!(metadata["coordinates"], r#"["x","y","phi","psi"]"#);
    assert_eq!(metadata["hopsim_version"], env!("CARGO_PKG_VERSION"));
}

#[test]
fn the_reader_returns_states_impulses_events_and_scene() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let (frames, events) = (frames(12), events());
    write_recording(&path, 12);
    let rec = McapRecording::read(&path).unwrap();
    assert_eq!(rec.metadata.coordinates, info().coordinates);
    assert_eq!(rec.metadata.bodies, ["disc", "flywheel"]);
    assert_eq!(rec.metadata.contacts, info().contacts);
    assert_eq!(rec.metadata.dt, 2e-4);
    assert_eq!(rec.stop, None, "a complete recording has no stop record");
    let scene = rec.scene.as_ref().unwrap();
    assert_eq!(
        (scene.name.as_str(), scene.text.as_str()),
        ("robbit-test.toml", SCENE_TEXT)
    );

    assert_eq!(rec.states.len(), frames.len());
    for (s, f) in rec.states.iter().zip(&frames) {
        assert_eq!((s.step, s.t, &s.q, &s.u), (f.step, f.t, &f.q, &f.u));
    }
    assert_eq!(rec.events, events);

    // Trace: every contact with a non-zero percussion, bit for bit, plus the brake.
    let mut expected = Vec::new();
    for f in &frames {
        if let Some(e) = events.iter().find(|e| e.step == f.step) {
            if let hopsim_record::EventKind::Brake { impulse } = e.kind {
                expected.push((f.step, e.t, BRAKE_CHANNEL.to_string(), impulse, 0.0));
            }
        }
        for c in f
            .contacts
            .iter()
            .filter(|c| c.impulse_normal != 0.0 || c.impulse_tangent != 0.0)
        {
            let name = info().contacts[c.contact].clone();
            expected.push((f.step, f.t, name, c.impulse_normal, c.impulse_tangent));
        }
    }
    let found: Vec<_> = rec
        .impulses
        .samples
        .iter()
        .map(|s| (s.step, s.t, s.channel.clone(), s.normal, s.tangent))
        .collect();
    assert_eq!(found, expected);
    assert!(
        found.iter().any(|s| s.3 == 1e-300),
        "tiny percussions survive"
    );
}

fn read_error(bytes: &[u8]) -> String {
    match McapRecording::from_bytes(bytes, Path::new("bad.mcap")) {
        Err(e @ RecordError::Format { .. }) => e.to_string(),
        other => panic!("expected a format error, got {other:?}"),
    }
}

#[test]
fn the_reader_says_what_is_wrong_and_with_which_file() {
    let e = read_error(b"step,t_s\n1,0.1\n");
    assert!(e.starts_with("bad.mcap: not an MCAP file"), "{e}");

    // A valid MCAP that is not a hopsim recording.
    let mut foreign = std::io::Cursor::new(Vec::new());
    {
        let mut w = mcap::Writer::new(&mut foreign).unwrap();
        let schema = w.add_schema("x", "jsonschema", b"{}").unwrap();
        w.add_channel(schema, "/other", "json", &Default::default())
            .unwrap();
        w.finish().unwrap();
    }
    let e = read_error(foreign.get_ref());
    assert!(e.contains("not a hopsim recording"), "{e}");

    // A hopsim recording cut short (an interrupted copy) has no summary.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    write_recording(&path, 3);
    let bytes = std::fs::read(&path).unwrap();
    let e = read_error(&bytes[..bytes.len() / 2]);
    assert!(e.starts_with("bad.mcap: ") && e.contains("MCAP"), "{e}");

    // A missing file names it.
    let e = McapRecording::read(&dir.path().join("missing.mcap"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.mcap"), "{e}");
}

#[test]
fn a_message_with_bad_json_is_named() {
    let mut out = std::io::Cursor::new(Vec::new());
    {
        // A recording whose state message is not the expected JSON.
        let mut w = mcap::Writer::new(&mut out).unwrap();
        let meta: BTreeMap<String, String> = [
            ("scene", "s"),
            ("scene_path", "s.toml"),
            ("scene_file", "s.toml"),
            ("dt_s", "0.001"),
            ("coordinates", r#"["x","y","phi","psi"]"#),
            ("bodies", "[]"),
            ("contacts", "[]"),
            ("springs", "[]"),
            ("hopsim_version", "0"),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        w.write_metadata(&mcap::records::Metadata {
            name: METADATA_NAME.into(),
            metadata: meta,
        })
        .unwrap();
        let schema = w.add_schema("x", "jsonschema", b"{}").unwrap();
        let mut ids = Vec::new();
        for topic in [STATE_TOPIC, CONTACTS_TOPIC, ENERGY_TOPIC, EVENTS_TOPIC] {
            ids.push(
                w.add_channel(schema, topic, "json", &Default::default())
                    .unwrap(),
            );
        }
        let header = mcap::records::MessageHeader {
            channel_id: ids[0],
            sequence: 7,
            log_time: 0,
            publish_time: 0,
        };
        w.write_to_known_channel(&header, br#"{"t_s": 0.0, "step": 1, "q": {"x": 1.0}}"#)
            .unwrap();
        w.finish().unwrap();
    }
    let e = read_error(out.get_ref());
    assert!(
        e.contains("/hopsim/state message 7") && e.contains("invalid message JSON"),
        "{e}"
    );
}
