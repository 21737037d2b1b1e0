//! `[[loops]]` of a model's `<connect>` and `<weld>` equalities (docs/mjcf.md, "Closed
//! loops"): a connect is a revolute loop joint, a weld a weld, each between the carrying
//! links of its bodies (or the fixed body `world`), its points in the links' frames.

use std::fmt::Write as _;

use super::{num, pair, quote, rotate, Link};
use crate::model::{PlanarModel, Vec2};
use crate::EqualityKind;

/// Appends one `[[loops]]` table per equality; `carrier[b]` is the link carrying body `b`.
pub(super) fn write_loops(model: &PlanarModel, links: &[Link], carrier: &[usize], t: &mut String) {
    let mut names: Vec<String> = Vec::with_capacity(model.equalities.len());
    for (i, eq) in model.equalities.iter().enumerate() {
        // A side: the link's name, the point in its frame and its angle at reference.
        let side = |body: Option<usize>, point: Vec2| match body {
            Some(b) => {
                let link = &links[carrier[b]];
                let world = model.bodies[b].origin + point;
                (
                    link.name.as_str(),
                    rotate(-link.turn, world - link.center),
                    link.turn,
                )
            }
            None => ("world", point, 0.0),
        };
        let (name_a, point_a, turn_a) = side(eq.body1, eq.point1);
        let (name_b, point_b, turn_b) = side(eq.body2, eq.point2);
        let base = eq.name.clone().unwrap_or_else(|| format!("equality{i}"));
        let mut name = base.clone();
        let mut k = 1;
        while names.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        let _ = writeln!(
            t,
            "[[loops]]\nname = {}\nbody_a = {}\npoint_a = {}\nbody_b = {}\npoint_b = {}",
            quote(&name),
            quote(name_a),
            pair(point_a),
            quote(name_b),
            pair(point_b)
        );
        names.push(name);
        match eq.kind {
            EqualityKind::Connect => t.push_str("type = \"revolute\"\n"),
            EqualityKind::Weld { angle } => {
                // The links' angles are the bodies' plus their turns at reference.
                let _ = writeln!(
                    t,
                    "type = \"weld\"\nangle = {}",
                    num(angle + turn_a - turn_b)
                );
            }
        }
        t.push('\n');
    }
}
