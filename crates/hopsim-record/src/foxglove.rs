//! The robot's geometry in Foxglove's own message types, for the MCAP recorder
//! (docs/recording.md): a `foxglove.SceneUpdate` with the terrain and every body's shapes
//! in the body's frame, sent when it changes (first frame, the terrain drawn further, a
//! shape switched), and a `foxglove.FrameTransforms` per frame placing the body frames.
//!
//! The plane of the simulation is the x–z plane of Foxglove's 3D world: a planar point
//! `(x, y)` (y up, docs/physics.md §1) is `(x, 0, y)`, so gravity points along −z, Foxglove's
//! down. A counter-clockwise planar rotation by `θ` is then a rotation by `−θ` about +y.

use crate::geometry::{
    palette, terrain_pieces, Outline, Point, RobotShapes, TerrainCover, INACTIVE_COLOR, RAIL_COLOR,
    TERRAIN_COLOR,
};
use crate::loops::{markers, rods, LOOP_COLOR};
use crate::{Frame, JointInfo, LoopInfo, RecordingInfo};
use hopsim_model::Terrain;
use serde::ser::SerializeSeq;
use serde::{Serialize, Serializer};
use serde_json::{json, Value};

/// Topic of the `foxglove.SceneUpdate` messages.
pub const SCENE_TOPIC: &str = "/foxglove/scene";
/// Topic of the `foxglove.FrameTransforms` messages.
pub const TRANSFORMS_TOPIC: &str = "/foxglove/transforms";
/// The scene entity of the loop joints' world parts (frame `world`).
pub const LOOPS_ENTITY: &str = "loops";
/// The fixed frame: the ground.
pub const WORLD_FRAME: &str = "world";
/// Schema name and JSON Schema (vendored from Foxglove's schema repository) of
/// [`SCENE_TOPIC`].
pub(crate) const SCENE_SCHEMA: (&str, &str) = (
    "foxglove.SceneUpdate",
    include_str!("../schemas/foxglove/SceneUpdate.json"),
);
/// Schema name and JSON Schema of [`TRANSFORMS_TOPIC`].
pub(crate) const TRANSFORMS_SCHEMA: (&str, &str) = (
    "foxglove.FrameTransforms",
    include_str!("../schemas/foxglove/FrameTransforms.json"),
);
/// Line thickness of outlines and terrain, in screen pixels.
const LINE_PIXELS: f64 = 2.0;
/// `LINE_STRIP` and `LINE_LIST` of `foxglove.LineType`.
const LINE_STRIP: u8 = 0;
const LINE_LIST: u8 = 2;

/// The frame of body `name`.
pub fn body_frame(name: &str) -> String {
    format!("body/{name}")
}

/// What the scene messages need between frames.
pub(crate) struct FoxgloveScene {
    shapes: RobotShapes,
    frames: Vec<String>,
    terrain: Terrain,
    cover: TerrainCover,
    /// Per body, the rails of the prismatic joints it carries (docs/physics.md §7): from
    /// the anchor plus the lower to the upper extension along the axis, in its frame.
    rails: Vec<Vec<[Point; 2]>>,
    /// Per body, the points of loop joints on it (its frame); the world points of loops
    /// to the world; the loops drawn as segments (docs/physics.md §8).
    pins: Vec<Vec<Point>>,
    world_pins: Vec<Point>,
    rods: Vec<LoopInfo>,
    /// The shapes' activity in the last scene update (none before the first).
    active: Option<Vec<bool>>,
}

impl FoxgloveScene {
    pub(crate) fn new(info: &RecordingInfo) -> Self {
        let shapes = RobotShapes::of(info);
        let (pins, world_pins) = markers(info);
        Self {
            pins,
            world_pins,
            rods: rods(info),
            cover: TerrainCover::new(shapes.size_m),
            shapes,
            frames: info.bodies.iter().map(|b| body_frame(&b.name)).collect(),
            terrain: info.terrain.clone(),
            rails: rails(info),
            active: None,
        }
    }

    /// The scene update due at `frame`, if the scene changed: the whole scene (terrain,
    /// every body and the loop joints), so that the latest update alone shows it after a
    /// seek. A model with rods (distance or slot loops) changes at every frame.
    pub(crate) fn update(&mut self, frame: &Frame<'_>) -> Option<Value> {
        let grew = self.cover.cover(frame.com[0]);
        let switched = self.active.as_deref() != Some(frame.shapes_active);
        if !grew && !switched && self.rods.is_empty() {
            return None;
        }
        self.active = Some(frame.shapes_active.to_vec());
        let stamp = timestamp(frame.t);
        let mut entities = vec![self.terrain_entity(&stamp)];
        let mut first = 0;
        for (b, outlines) in self.shapes.outlines.iter().enumerate() {
            let active = &frame.shapes_active[first..first + outlines.len()];
            first += outlines.len();
            entities.push(self.body_entity(b, active, &stamp));
        }
        if !self.world_pins.is_empty() || !self.rods.is_empty() {
            entities.push(self.loops_entity(frame, &stamp));
        }
        Some(json!({ "deletions": [], "entities": entities }))
    }

    fn terrain_entity(&self, stamp: &Value) -> Value {
        let (lo, hi) = self.cover.range;
        let (segments, _) = terrain_pieces(&self.terrain, lo, hi);
        let points: Vec<Value> = segments.iter().flatten().map(|p| vector(*p)).collect();
        let line = line(LINE_LIST, points, TERRAIN_COLOR);
        entity("terrain", WORLD_FRAME, stamp, vec![line], vec![])
    }

    /// The loops' parts in the world: markers at the world points of loops to the world,
    /// and each rod from point A to point B at `frame`.
    fn loops_entity(&self, frame: &Frame<'_>, stamp: &Value) -> Value {
        let marker = 0.04 * self.shapes.size_m;
        let spheres = self
            .world_pins
            .iter()
            .map(|p| sphere(*p, 1.5 * marker, LOOP_COLOR))
            .collect();
        let lines = self
            .rods
            .iter()
            .map(|l| {
                line(
                    LINE_STRIP,
                    l.ends(frame.bodies).map(vector).to_vec(),
                    LOOP_COLOR,
                )
            })
            .collect();
        entity(LOOPS_ENTITY, WORLD_FRAME, stamp, lines, spheres)
    }

    /// Body `b` in its frame: shape outlines as lines, point shapes as small spheres (grey
    /// when inactive), a spoke along its x axis and a sphere at its centre of mass.
    fn body_entity(&self, b: usize, active: &[bool], stamp: &Value) -> Value {
        let color = |on: bool| if on { palette(b) } else { INACTIVE_COLOR };
        let marker = 0.04 * self.shapes.size_m;
        let spoke = [[0.0, 0.0], [self.shapes.spokes_m[b], 0.0]];
        let mut lines = vec![line(LINE_STRIP, spoke.map(vector).to_vec(), palette(b))];
        let mut spheres = vec![sphere([0.0, 0.0], marker, palette(b))];
        for rail in &self.rails[b] {
            lines.push(line(LINE_STRIP, rail.map(vector).to_vec(), RAIL_COLOR));
        }
        for pin in &self.pins[b] {
            spheres.push(sphere(*pin, 1.5 * marker, LOOP_COLOR));
        }
        for (outline, &on) in self.shapes.outlines[b].iter().zip(active) {
            match outline {
                Outline::Strip(points) => {
                    let points = points.iter().map(|p| vector(*p)).collect();
                    lines.push(line(LINE_STRIP, points, color(on)));
                }
                Outline::Marker(p) => spheres.push(sphere(*p, marker, color(on))),
            }
        }
        let frame = &self.frames[b];
        entity(frame, frame, stamp, lines, spheres)
    }

    /// The `foxglove.FrameTransforms` of `frame`: every body frame in the world frame.
    pub(crate) fn transforms<'a>(&'a self, frame: &'a Frame<'a>) -> Transforms<'a> {
        Transforms {
            frames: &self.frames,
            frame,
        }
    }
}

/// Per body, the rails of the prismatic joints hanging on it, in its frame.
fn rails(info: &RecordingInfo) -> Vec<Vec<[Point; 2]>> {
    let mut rails = vec![Vec::new(); info.bodies.len()];
    for (parent, rail) in info.joints.iter().filter_map(JointInfo::rail) {
        rails[parent].push(rail);
    }
    rails
}

/// A `foxglove.FrameTransforms` message, serialised without building a JSON tree.
pub(crate) struct Transforms<'a> {
    frames: &'a [String],
    frame: &'a Frame<'a>,
}

impl Serialize for Transforms<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Time {
            sec: u64,
            nsec: u32,
        }
        // Single precision (µm, 1e-7 rad at the robot's scale) is plenty for display and
        // writes shorter numbers than double.
        #[derive(Serialize)]
        struct Xyz {
            x: f32,
            y: f32,
            z: f32,
        }
        #[derive(Serialize)]
        struct Xyzw {
            x: f32,
            y: f32,
            z: f32,
            w: f32,
        }
        #[derive(Serialize)]
        struct Transform<'a> {
            timestamp: &'a Time,
            parent_frame_id: &'a str,
            child_frame_id: &'a str,
            translation: Xyz,
            rotation: Xyzw,
        }
        struct List<'a>(&'a Transforms<'a>);
        impl Serialize for List<'_> {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                let (sec, nsec) = sec_nsec(self.0.frame.t);
                let time = Time { sec, nsec };
                let mut seq = serializer.serialize_seq(Some(self.0.frames.len()))?;
                for (name, pose) in self.0.frames.iter().zip(self.0.frame.bodies) {
                    let [x, y] = pose.position.map(|v| v as f32);
                    let (sin, cos) = (0.5 * pose.angle).sin_cos();
                    let (sin, cos) = (sin as f32, cos as f32);
                    seq.serialize_element(&Transform {
                        timestamp: &time,
                        parent_frame_id: WORLD_FRAME,
                        child_frame_id: name,
                        translation: Xyz { x, y: 0.0, z: y },
                        rotation: Xyzw {
                            x: 0.0,
                            y: -sin,
                            z: 0.0,
                            w: cos,
                        },
                    })?;
                }
                seq.end()
            }
        }
        #[derive(Serialize)]
        struct Message<'a> {
            transforms: List<'a>,
        }
        Message {
            transforms: List(self),
        }
        .serialize(serializer)
    }
}

/// Simulation time `t` as whole seconds and nanoseconds (negative and NaN times map to 0).
fn sec_nsec(t: f64) -> (u64, u32) {
    let ns = crate::mcap_write::nanoseconds(t);
    (ns / 1_000_000_000, (ns % 1_000_000_000) as u32)
}

fn timestamp(t: f64) -> Value {
    let (sec, nsec) = sec_nsec(t);
    json!({ "sec": sec, "nsec": nsec })
}

/// A planar point as a Foxglove `Vector3` in the x–z plane.
fn vector([x, y]: Point) -> Value {
    json!({ "x": x, "y": 0.0, "z": y })
}

fn color(c: [u8; 3]) -> Value {
    let [r, g, b] = c.map(|v| f64::from(v) / 255.0);
    json!({ "r": r, "g": g, "b": b, "a": 1.0 })
}

fn identity_pose() -> Value {
    json!({
        "position": { "x": 0.0, "y": 0.0, "z": 0.0 },
        "orientation": { "x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0 },
    })
}

fn line(kind: u8, points: Vec<Value>, c: [u8; 3]) -> Value {
    json!({
        "type": kind,
        "pose": identity_pose(),
        "thickness": LINE_PIXELS,
        "scale_invariant": true,
        "points": points,
        "color": color(c),
        "colors": [],
        "indices": [],
    })
}

fn sphere(at: Point, diameter: f64, c: [u8; 3]) -> Value {
    let mut pose = identity_pose();
    pose["position"] = vector(at);
    json!({
        "pose": pose,
        "size": { "x": diameter, "y": diameter, "z": diameter },
        "color": color(c),
    })
}

/// A `foxglove.SceneEntity` that stays until replaced (zero lifetime) and follows its frame.
fn entity(id: &str, frame: &str, stamp: &Value, lines: Vec<Value>, spheres: Vec<Value>) -> Value {
    json!({
        "timestamp": stamp,
        "frame_id": frame,
        "id": id,
        "lifetime": { "sec": 0, "nsec": 0 },
        "frame_locked": true,
        "metadata": [],
        "arrows": [],
        "cubes": [],
        "spheres": spheres,
        "cylinders": [],
        "lines": lines,
        "triangles": [],
        "texts": [],
        "models": [],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps_split_into_seconds_and_nanoseconds() {
        assert_eq!(sec_nsec(0.0), (0, 0));
        assert_eq!(sec_nsec(1.25), (1, 250_000_000));
        assert_eq!(sec_nsec(19.9998), (19, 999_800_000));
        assert_eq!(sec_nsec(f64::NAN), (0, 0));
    }

    /// The rotation of a frame transform turns the body's x axis (Foxglove x) into the
    /// planar direction (cos θ, sin θ), i.e. Foxglove (cos θ, 0, sin θ).
    #[test]
    fn a_planar_rotation_is_a_rotation_about_y_in_the_x_z_plane() {
        for theta in [0.3_f64, 2.0, -1.0, 7.0] {
            let (s, c) = (0.5 * theta).sin_cos();
            let (qx, qy, qz, qw) = (0.0, -s, 0.0, c);
            // v' = v + 2w (q × v) + 2 q × (q × v) for v = (1, 0, 0).
            let qv = [
                qy * 0.0 - qz * 0.0,
                qz * 1.0 - qx * 0.0,
                qx * 0.0 - qy * 1.0,
            ];
            let qqv = [
                qy * qv[2] - qz * qv[1],
                qz * qv[0] - qx * qv[2],
                qx * qv[1] - qy * qv[0],
            ];
            let v = [
                1.0 + 2.0 * qw * qv[0] + 2.0 * qqv[0],
                2.0 * qw * qv[1] + 2.0 * qqv[1],
                2.0 * qw * qv[2] + 2.0 * qqv[2],
            ];
            let expected = [theta.cos(), 0.0, theta.sin()];
            for (a, b) in v.iter().zip(expected) {
                assert!((a - b).abs() < 1e-14, "θ = {theta}: {v:?}");
            }
        }
    }
}
