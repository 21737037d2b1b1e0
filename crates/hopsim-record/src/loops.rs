//! Loop joints as recordings describe and draw them (docs/physics.md §8, docs/recording.md):
//! a marker at each of a loop's two points, on its body (they coincide for a revolute loop
//! or a weld, as a tree joint's pivot), and for a distance loop (a massless rod) or a slot
//! the segment between the two points.

use crate::frame::world_point;
use crate::geometry::Point;
use crate::{BodyPose, RecordingInfo};
use serde::Serialize;
use serde_json::Value;

/// The colour of the loop joints' markers and rods.
pub(crate) const LOOP_COLOR: [u8; 3] = [40, 40, 40];

/// A loop joint: point A on body A held on point B of body B (or of the world).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LoopInfo {
    pub name: String,
    pub kind: LoopInfoKind,
    /// Index of body A (in `RecordingInfo::bodies`).
    pub body_a: usize,
    /// Point A in body A's frame relative to its centre of mass, m.
    pub point_a_m: [f64; 2],
    /// Index of body B; `None`: the world.
    pub body_b: Option<usize>,
    /// Point B in body B's frame relative to its centre of mass (the world: a world
    /// point), m.
    pub point_b_m: [f64; 2],
}

/// What a recorded loop joint holds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LoopInfoKind {
    /// The two points coincide.
    Revolute,
    /// The two points coincide and `θ_A − θ_B = angle_rad`.
    Weld { angle_rad: f64 },
    /// A massless rod: the points stay `length_m` apart.
    Distance { length_m: f64 },
    /// Point A stays on the line through point B along `axis` (B's frame).
    Slot { axis: [f64; 2] },
}

impl LoopInfo {
    /// Whether the loop's two points coincide (revolute, weld): then it is drawn by its
    /// markers alone; otherwise also by the segment between them.
    pub fn is_pin(&self) -> bool {
        matches!(
            self.kind,
            LoopInfoKind::Revolute | LoopInfoKind::Weld { .. }
        )
    }

    /// Points A and B in the world at `poses` (one per body).
    pub fn ends(&self, poses: &[BodyPose]) -> [[f64; 2]; 2] {
        let b = match self.body_b {
            Some(b) => world_point(&poses[b], self.point_b_m),
            None => self.point_b_m,
        };
        [world_point(&poses[self.body_a], self.point_a_m), b]
    }
}

/// The markers of every loop: per body, the loop points on it (its frame), and the world
/// points of loops to the world.
pub(crate) fn markers(info: &RecordingInfo) -> (Vec<Vec<Point>>, Vec<Point>) {
    let mut on_bodies = vec![Vec::new(); info.bodies.len()];
    let mut on_world = Vec::new();
    for l in &info.loops {
        on_bodies[l.body_a].push(l.point_a_m);
        match l.body_b {
            Some(b) => on_bodies[b].push(l.point_b_m),
            None => on_world.push(l.point_b_m),
        }
    }
    (on_bodies, on_world)
}

/// The loops that are drawn as a segment between their points (distance, slot).
pub(crate) fn rods(info: &RecordingInfo) -> Vec<LoopInfo> {
    info.loops.iter().filter(|l| !l.is_pin()).cloned().collect()
}

/// The metadata `loops`: a JSON list of `{name, kind, body_a, point_a_m, body_b,
/// point_b_m}` (bodies by name, `body_b` null for the world) with each kind's parameter.
pub(crate) fn loops_json(info: &RecordingInfo) -> String {
    let name = |b: usize| info.bodies.get(b).map_or("", |body| body.name.as_str());
    let loops: Vec<Value> = info
        .loops
        .iter()
        .map(|l| {
            let mut v = serde_json::to_value(l).unwrap_or(Value::Null);
            if let Value::Object(map) = &mut v {
                let kind = map.remove("kind").unwrap_or(Value::Null);
                if let Value::Object(fields) = kind {
                    map.extend(fields);
                }
                map.insert("body_a".into(), name(l.body_a).into());
                map.insert("body_b".into(), l.body_b.map(name).into());
            }
            v
        })
        .collect();
    Value::from(loops).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rods_ends_follow_its_bodies() {
        let rod = LoopInfo {
            name: "rod".into(),
            kind: LoopInfoKind::Distance { length_m: 1.0 },
            body_a: 0,
            point_a_m: [0.5, 0.0],
            body_b: None,
            point_b_m: [2.0, 1.0],
        };
        assert!(!rod.is_pin());
        let pose = BodyPose {
            position: [1.0, 2.0],
            angle: std::f64::consts::FRAC_PI_2,
        };
        let [a, b] = rod.ends(&[pose]);
        assert!(
            (a[0] - 1.0).abs() < 1e-15 && (a[1] - 2.5).abs() < 1e-15,
            "{a:?}"
        );
        assert_eq!(b, [2.0, 1.0]);
    }
}
