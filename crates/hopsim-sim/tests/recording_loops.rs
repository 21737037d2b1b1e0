//! Recordings draw the loop joints (docs/recording.md): in the MCAP recording of the
//! gallery's four-bar (a revolute loop) each body's scene entity carries a marker at its
//! loop point, and the two markers, placed by the recorded body poses, coincide at every
//! recorded frame; the ideal slider–crank's slot to the world is drawn as a world marker
//! and a segment from it to the slider's pin, updated each frame. The metadata lists the
//! loops. (The Rerun recorder's loop entities: `crates/hopsim-record/tests/rerun_loops.rs`.)

use hopsim_record::{McapRecorder, RecorderSet, FOXGLOVE_SCENE_TOPIC, METADATA_NAME};
use hopsim_scene::{Override, Scene};
use hopsim_sim::{recording_info, RecordingObserver};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/classic/{name}"));
    hopsim_scene::load(&path, &[Override::new("simulation.duration", "0.5")]).unwrap()
}

/// Runs `scene` into `recorders` built by `make` in a new folder.
fn record(
    scene: &Scene,
    make: impl Fn(&Path) -> Box<dyn hopsim_record::Recorder>,
) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut set = RecorderSet::default();
    set.push(make(dir.path()));
    let mut observer = RecordingObserver::new(set, scene);
    hopsim_sim::run(scene, &mut observer).unwrap();
    observer.finish().unwrap();
    dir
}

/// The MCAP file's scene updates (JSON), its body states per scene update's time, and
/// its metadata.
struct Mcap {
    scenes: Vec<Value>,
    /// Per recorded state: `bodies` {name: {x_m, y_m, angle_rad}} at the time (ns).
    states: BTreeMap<u64, Value>,
    metadata: BTreeMap<String, String>,
}

fn read_mcap(path: &Path) -> Mcap {
    let bytes = std::fs::read(path).unwrap();
    let mut scenes = Vec::new();
    let mut states = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let json: Value = serde_json::from_slice(&m.data).unwrap();
        match m.channel.topic.as_str() {
            FOXGLOVE_SCENE_TOPIC => scenes.push(json),
            hopsim_record::STATE_TOPIC => {
                states.insert(m.log_time, json["bodies"].clone());
            }
            _ => {}
        }
    }
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let index = summary
        .metadata_indexes
        .iter()
        .find(|i| i.name == METADATA_NAME)
        .unwrap();
    let metadata = mcap::read::metadata(&bytes, index).unwrap().metadata;
    Mcap {
        scenes,
        states,
        metadata,
    }
}

fn entity<'a>(update: &'a Value, id: &str) -> Option<&'a Value> {
    update["entities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["id"] == id)
}

/// The positions `(x, y)` (Foxglove's `(x, z)`) of an entity's spheres.
fn spheres(entity: &Value) -> Vec<[f64; 2]> {
    entity["spheres"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let p = &s["pose"]["position"];
            [p["x"].as_f64().unwrap(), p["z"].as_f64().unwrap()]
        })
        .collect()
}

/// A body-frame point in the world at a recorded body state.
fn world(body: &Value, [x, y]: [f64; 2]) -> [f64; 2] {
    let (s, c) = body["angle_rad"].as_f64().unwrap().sin_cos();
    [
        body["x_m"].as_f64().unwrap() + c * x - s * y,
        body["y_m"].as_f64().unwrap() + s * x + c * y,
    ]
}

#[test]
fn the_four_bars_mcap_draws_its_loop_as_markers_that_coincide() {
    let scene = scene("four-bar.toml");
    let l = &scene.model.loops()[0];
    let dir = record(&scene, |d| {
        Box::new(McapRecorder::create(&d.join("run.mcap"), &recording_info(&scene)).unwrap())
    });
    let mcap = read_mcap(&dir.path().join("run.mcap"));

    let loops: Value = serde_json::from_str(&mcap.metadata["loops"]).unwrap();
    assert_eq!(loops[0]["name"], "coupler-rocker");
    assert_eq!(loops[0]["kind"], "revolute");
    assert_eq!(loops[0]["body_a"], "coupler");
    assert_eq!(loops[0]["body_b"], "rocker");

    let update = mcap.scenes.first().expect("a scene update");
    let pin = |body: &str, p: hopsim_model::Vec2| {
        let e = entity(update, &format!("body/{body}")).unwrap();
        let s = spheres(e);
        assert!(
            s.iter()
                .any(|q| (q[0] - p.x).abs() < 1e-15 && (q[1] - p.y).abs() < 1e-15),
            "no marker at {p} on {body}: {s:?}"
        );
        [p.x, p.y]
    };
    let (a, b) = (pin("coupler", l.point_a), pin("rocker", l.point_b));
    assert!(mcap.states.len() > 50, "{} states", mcap.states.len());
    for bodies in mcap.states.values() {
        let (pa, pb) = (world(&bodies["coupler"], a), world(&bodies["rocker"], b));
        let gap = (pa[0] - pb[0]).hypot(pa[1] - pb[1]);
        assert!(gap < 1e-10, "the markers are {gap:e} m apart");
    }
}

#[test]
fn the_slider_cranks_slot_is_drawn_as_a_world_marker_and_a_segment_per_frame() {
    let scene = scene("slider-crank-ideal.toml");
    let slot = scene
        .model
        .loops()
        .iter()
        .find(|l| l.name == "guide")
        .unwrap();
    let dir = record(&scene, |d| {
        Box::new(McapRecorder::create(&d.join("run.mcap"), &recording_info(&scene)).unwrap())
    });
    let mcap = read_mcap(&dir.path().join("run.mcap"));
    assert!(
        mcap.scenes.len() > 50,
        "a rod's segment is updated with every frame: {} updates",
        mcap.scenes.len()
    );
    let slider = scene.model.bodies()[slot.body_a].name.clone();
    let mut moved = false;
    for update in &mcap.scenes {
        let loops = entity(update, "loops").expect("the loops' entity");
        assert_eq!(loops["frame_id"], "world");
        let world_marker = [slot.point_b.x, slot.point_b.y];
        assert!(spheres(loops).contains(&world_marker));
        let time = update["entities"][0]["timestamp"].clone();
        let ns = time["sec"].as_u64().unwrap() * 1_000_000_000 + time["nsec"].as_u64().unwrap();
        let line = loops["lines"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| {
                let p = l["points"].as_array().unwrap();
                let at = |i: usize| [p[i]["x"].as_f64().unwrap(), p[i]["z"].as_f64().unwrap()];
                [at(0), at(1)]
            })
            .next()
            .expect("the slot's segment");
        assert_eq!(line[1], world_marker);
        if let Some(bodies) = mcap.states.get(&ns) {
            let pin = world(&bodies[&slider], [slot.point_a.x, slot.point_a.y]);
            assert!((pin[0] - line[0][0]).abs() < 1e-12 && (pin[1] - line[0][1]).abs() < 1e-12);
            // The pin stays on the guide (the line y = 0 through the world point).
            assert!(pin[1].abs() < 1e-10, "{pin:?}");
            moved |= (pin[0] - line[1][0]).abs() > 1e-3;
        }
    }
    assert!(moved, "the slider's pin never left the world point");
}
