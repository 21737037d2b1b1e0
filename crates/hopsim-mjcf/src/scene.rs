//! A planar model as a hopsim scene: the TOML text of `docs/scene-format.md` whose
//! coordinates are MuJoCo's `qpos` (docs/mjcf.md, "From MJCF to a scene").
//!
//! - Every MuJoCo joint is one scene body, in MuJoCo's order, so the scene's coordinates
//!   are `qpos` entry by entry, named by the joints. A body with several joints is a chain
//!   of massless links (named `<joint>_link`) ending in the body itself, which carries the
//!   mass and the shapes; everything hangs on a fixed body `world` at the origin.
//! - Hinges are revolute joints, `coordinate = "clockwise"` when MuJoCo's axis points
//!   against the plane's normal; a hinge's `ref` turns its body's frame, a slide's `ref`
//!   moves its pivot, so that a coordinate equal to `qpos` puts the body where MuJoCo does.
//! - Springs (`stiffness`, `springref`), damping, `armature`, `range` and `frictionloss`
//!   (hard dry friction, docs/physics.md §7.5) act on the coordinate as in MuJoCo.
//! - Actuators are `[[actuators]]` in MuJoCo's order (the order of `ctrl`), on their
//!   joints' bodies: `<motor>`, `<position>` (`kp`, `kv`), `<velocity>` (`kv`) with gear,
//!   control range (when `clampctrl` is on) and force range; a joint's
//!   `actuatorfrcrange` bounds its one actuator's force (divided by the gear).
//! - The one plane that touches the model's geoms is the terrain; the geoms that touch it
//!   are shapes, and every pair of geoms MuJoCo lets collide is a contact pair. Friction
//!   is MuJoCo's combination (the higher priority's, else the larger; frictionless when
//!   the combined `condim` is 1), restitution 0.
//! - `<connect>` and `<weld>` equalities are `[[loops]]` (revolute and weld loop joints)
//!   between their bodies' links.

mod loops;

use std::fmt::Write as _;

use crate::model::{ActuatorKind, Geom, JointKind, PlanarModel, Shape, Vec2};
use crate::overlap::overlap;

/// The seconds an imported scene runs for (MJCF has no duration; `--duration` sets it).
pub const IMPORTED_DURATION: f64 = 1.0;

/// A model as a scene: the TOML text and what the scene leaves out.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneText {
    pub toml: String,
    /// What of the model the scene does not express, or how it expresses it, one
    /// sentence each (the reader's own notices are in [`PlanarModel::notices`]).
    pub notices: Vec<String>,
}

/// Why a model has no scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{model}: {message}")]
pub struct ImportError {
    /// The model's name.
    pub model: String,
    pub message: String,
}

/// `[[actuators]]` of `model`'s actuators (none when the `actuation` flag is off), on the
/// links of their joints.
fn write_actuators(
    model: &PlanarModel,
    links: &[Link],
    t: &mut String,
    notices: &mut Vec<String>,
) -> Result<(), String> {
    if !model.options.actuation && !model.actuators.is_empty() {
        notices.push("actuation is disabled (<flag actuation>): no actuators".into());
        return Ok(());
    }
    for (i, a) in model.actuators.iter().enumerate() {
        let joint = &model.joints[a.joint];
        let link = links
            .iter()
            .find(|l| l.joint == a.joint)
            .map_or("", |l| l.name.as_str());
        let name = a.name.clone().unwrap_or_else(|| format!("actuator{i}"));
        let _ = writeln!(
            t,
            "[[actuators]]\nname = {}\njoint = {}\ngear = {}",
            quote(&name),
            quote(link),
            num(a.gear)
        );
        match a.kind {
            ActuatorKind::Motor => t.push_str("kind = \"motor\"\n"),
            ActuatorKind::Position { kp, kv } => {
                let _ = writeln!(t, "kind = \"position\"\nkp = {}\nkv = {}", num(kp), num(kv));
            }
            ActuatorKind::Velocity { kv } => {
                let _ = writeln!(t, "kind = \"velocity\"\nkv = {}", num(kv));
            }
        }
        if let Some([lo, hi]) = a.ctrl_range.filter(|_| model.options.clamp_controls) {
            let _ = writeln!(t, "ctrl_range = [{}, {}]", num(lo), num(hi));
        }
        // The joint's bound on its actuators' summed generalised force, `gear · force`,
        // is a bound on the force of its one actuator.
        let mut force = a.force_range;
        if let Some([lo, hi]) = joint.actuator_force_range {
            if model
                .actuators
                .iter()
                .filter(|b| b.joint == a.joint)
                .count()
                > 1
            {
                return Err(format!(
                    "joint `{}` bounds the summed force of several actuators \
                     (actuatorfrcrange); a scene bounds each actuator's own",
                    joint.name
                ));
            }
            let (x, y) = (lo / a.gear, hi / a.gear);
            let [jlo, jhi] = [x.min(y), x.max(y)];
            // Clamped into one range, then the other: clamped into the first's bounds
            // clamped into the second.
            force = Some(match force {
                Some([flo, fhi]) => [flo.clamp(jlo, jhi), fhi.clamp(jlo, jhi)],
                None => [jlo, jhi],
            });
        }
        if let Some([lo, hi]) = force {
            let _ = writeln!(t, "force_range = [{}, {}]", num(lo), num(hi));
        }
        t.push('\n');
    }
    Ok(())
}

/// A hopsim body: one MuJoCo joint's link.
struct Link {
    name: String,
    /// Index into the links, `None` for the world body.
    parent: Option<usize>,
    joint: usize,
    /// The link's centre of mass (its frame's origin) in the world at reference.
    center: Vec2,
    /// The angle of its frame at reference (a hinge's `ref` turns it).
    turn: f64,
    mass: f64,
    inertia: f64,
}

/// The scene of `model`, read from `source` (named in `[meta]`).
pub fn scene_toml(model: &PlanarModel, source: &str) -> Result<SceneText, ImportError> {
    let fail = |message: String| ImportError {
        model: model.name.clone(),
        message,
    };
    let mut notices = Vec::new();
    let links = links(model);
    // The last link of each MuJoCo body carries it.
    let carrier: Vec<usize> = (0..model.bodies.len())
        .map(|b| {
            let last = model.bodies[b].joints.last();
            links
                .iter()
                .position(|l| Some(&l.joint) == last)
                .unwrap_or(0)
        })
        .collect();

    let mut t = String::new();
    let _ = writeln!(
        t,
        "# hopsim scene imported from the MJCF model {} ({}); coordinates are MuJoCo's qpos.",
        quote(&model.name),
        quote(source)
    );
    let _ = writeln!(
        t,
        "[meta]\ntitle = {}\nsource = {}\n",
        quote(&model.name),
        quote(source)
    );
    let g = model.options.gravity;
    if g.y > 0.0 {
        return Err(fail(format!(
            "gravity points up the plane ({}, {}) m/s²; a scene's gravity points down",
            num(g.x),
            num(g.y)
        )));
    }
    let _ = writeln!(
        t,
        "[simulation]\nduration = {}\ndt = {}\ngravity = {}\ngravity_x = {}\n",
        num(IMPORTED_DURATION),
        num(model.options.timestep),
        num(-g.y),
        num(g.x)
    );

    // The terrain: the one world plane that touches a moving geom.
    let touches = |a: &Geom, b: &Geom| {
        model.options.contact && ((a.contype & b.conaffinity) | (b.contype & a.conaffinity)) != 0
    };
    let moving: Vec<&Geom> = model.geoms.iter().filter(|g| g.body.is_some()).collect();
    let planes: Vec<&Geom> = model
        .geoms
        .iter()
        .filter(|g| g.body.is_none() && matches!(g.shape, Shape::Line { .. }))
        .filter(|p| moving.iter().any(|g| touches(p, g)))
        .collect();
    let floor = match planes.as_slice() {
        [] => None,
        [floor] => Some(*floor),
        [first, second, ..] => {
            return Err(fail(format!(
                "the planes {} and {} both touch the model; a scene has one terrain",
                geom_name(first),
                geom_name(second)
            )))
        }
    };
    t.push_str("[environment]\n");
    match floor {
        None => t.push_str("terrain = \"none\"\n"),
        Some(Geom {
            shape: Shape::Line { point, normal },
            ..
        }) => {
            let (point, normal) = (*point, *normal);
            if normal.x == 0.0 {
                let _ = writeln!(t, "terrain = \"flat\"\nheight = {}", num(point.y));
            } else {
                if point.dot(&normal).abs() > 1e-12 {
                    return Err(fail(format!(
                        "the inclined plane {} does not pass through the origin; a scene's \
                         incline does",
                        floor.map_or(String::new(), geom_name)
                    )));
                }
                let angle = (-normal.x).atan2(normal.y);
                let _ = writeln!(t, "terrain = \"incline\"\nangle = {}", num(angle));
            }
            if let Some(floor) = floor {
                let _ = writeln!(t, "friction = {}", num(floor.friction[0]));
            }
        }
        Some(_) => t.push_str("terrain = \"none\"\n"),
    }
    t.push('\n');

    // Bodies: the world, then one link per joint.
    t.push_str("[[bodies]]\nname = \"world\"\nbase = \"fixed\"\n\n");
    let limits = model.options.limits;
    for link in &links {
        let joint = &model.joints[link.joint];
        let parent = link
            .parent
            .map_or((Vec2::zeros(), 0.0), |p| (links[p].center, links[p].turn));
        let anchor = model.bodies[joint.body].origin + joint.anchor;
        let into = |turn: f64, v: Vec2| rotate(-turn, v);
        let _ = writeln!(
            t,
            "[[bodies]]\nname = {}\nparent = {}\nmass = {}\ninertia = {}\ncoordinate_name = {}",
            quote(&link.name),
            quote(link.parent.map_or("world", |p| links[p].name.as_str())),
            num(link.mass),
            num(link.inertia),
            quote(&identifier(&joint.name))
        );
        let pivot = match joint.kind {
            JointKind::Hinge => {
                if joint.sign < 0.0 {
                    t.push_str("coordinate = \"clockwise\"\n");
                }
                into(parent.1, anchor - parent.0)
            }
            JointKind::Slide { axis } => {
                let axis = into(parent.1, axis);
                let _ = writeln!(t, "joint = \"prismatic\"\naxis = {}", pair(axis));
                into(parent.1, anchor - parent.0) - joint.reference * axis
            }
        };
        let _ = writeln!(
            t,
            "pivot = {}\ncom = {}",
            pair(pivot),
            pair(into(link.turn, link.center - anchor))
        );
        if model.options.springs && joint.stiffness != 0.0 {
            let _ = writeln!(
                t,
                "stiffness = {}\nrest_position = {}",
                num(joint.stiffness),
                num(joint.spring_reference)
            );
        }
        if model.options.dampers && joint.damping != 0.0 {
            let _ = writeln!(t, "damping = {}", num(joint.damping));
        }
        if joint.armature != 0.0 {
            let _ = writeln!(t, "armature = {}", num(joint.armature));
        }
        if let Some([lower, upper]) = joint.range.filter(|_| limits) {
            let _ = writeln!(t, "limits = [{}, {}]", num(lower), num(upper));
        }
        if joint.frictionloss != 0.0 && model.options.frictionloss {
            let _ = writeln!(t, "dry_friction = {}", num(joint.frictionloss));
        }
        t.push('\n');
    }

    // Shapes: every geom that touches the terrain (all of them without one), on its
    // body's carrying link; world geoms only when they touch a moving geom.
    let mut shapes: Vec<(usize, String, Option<usize>, Shape)> = Vec::new();
    for (i, geom) in model.geoms.iter().enumerate() {
        if matches!(geom.shape, Shape::Line { .. }) {
            if geom.body.is_some() {
                return Err(fail(format!(
                    "the plane {} moves with body `{}`; a scene's terrain is fixed",
                    geom_name(geom),
                    geom.mjcf_body
                )));
            }
            continue;
        }
        let (link, center, turn) = match geom.body {
            Some(b) => {
                let l = carrier[b];
                (Some(l), links[l].center, links[l].turn)
            }
            None => (None, Vec2::zeros(), 0.0),
        };
        let origin = geom.body.map_or(Vec2::zeros(), |b| model.bodies[b].origin);
        let frame = |p: Vec2| rotate(-turn, origin + p - center);
        let wanted = match (geom.body, floor) {
            (None, _) => moving.iter().any(|g| touches(geom, g)),
            (Some(_), Some(floor)) => touches(geom, floor),
            (Some(_), None) => true,
        };
        if !wanted {
            if geom.body.is_some() {
                notices.push(format!(
                    "geom {} does not collide with the terrain: left out of the scene (a \
                     scene's shapes all touch the terrain)",
                    geom_name(geom)
                ));
            }
            continue;
        }
        let shape = match transformed(&geom.shape, frame, -turn) {
            Shape::Ellipse {
                center,
                semi_axes,
                angle,
            } => {
                // A scene's ellipse has its axes along its body's.
                let turned = angle.rem_euclid(std::f64::consts::FRAC_PI_2);
                if turned.min(std::f64::consts::FRAC_PI_2 - turned) > 1e-12 {
                    return Err(fail(format!(
                        "the ellipsoid {} is turned in the plane; a scene's ellipse has its \
                         axes along its body's",
                        geom_name(geom)
                    )));
                }
                let along = angle.cos().abs() > 0.5;
                Shape::Ellipse {
                    center,
                    semi_axes: if along {
                        semi_axes
                    } else {
                        [semi_axes[1], semi_axes[0]]
                    },
                    angle: 0.0,
                }
            }
            shape => shape,
        };
        shapes.push((i, unique_shape_name(model, i, &shapes), link, shape));
    }
    for (i, name, link, shape) in &shapes {
        let geom = &model.geoms[*i];
        let body = link.map_or("world", |l| links[l].name.as_str());
        let _ = writeln!(
            t,
            "[[shapes]]\nname = {}\nbody = {}",
            quote(name),
            quote(body)
        );
        write_shape(&mut t, shape);
        if let Some(floor) = floor.filter(|_| link.is_some()) {
            let _ = writeln!(t, "friction = {}", num(friction(geom, floor)));
        }
        t.push('\n');
    }

    // Contact pairs, as MuJoCo lets them collide.
    let weld_parent = |b: usize| model.bodies[b].parent;
    for (x, (i, name_i, link_i, shape_i)) in shapes.iter().enumerate() {
        for (j, name_j, link_j, shape_j) in &shapes[x + 1..] {
            let (gi, gj) = (&model.geoms[*i], &model.geoms[*j]);
            if gi.body == gj.body || !touches(gi, gj) {
                continue;
            }
            if model.options.filter_parent
                && matches!((gi.body, gj.body), (Some(a), Some(b))
                    if weld_parent(a) == Some(b) || weld_parent(b) == Some(a))
            {
                continue;
            }
            if let Some(why) = inexact(shape_i, shape_j) {
                notices.push(format!(
                    "geoms {} and {}: {why}; their contact is left out",
                    geom_name(gi),
                    geom_name(gj)
                ));
                continue;
            }
            // Back into the world at reference.
            let world = |link: &Option<usize>, shape: &Shape| match link {
                Some(l) => {
                    let (center, turn) = (links[*l].center, links[*l].turn);
                    transformed(shape, |p| center + rotate(turn, p), turn)
                }
                None => shape.clone(),
            };
            if overlap(&world(link_i, shape_i), &world(link_j, shape_j)) {
                notices.push(format!(
                    "geoms {} and {} overlap in the plane at qpos0 (in MuJoCo their contact \
                     pushes across the plane, out of it): their contact is left out",
                    geom_name(gi),
                    geom_name(gj)
                ));
                continue;
            }
            let _ = writeln!(
                t,
                "[[contact_pairs]]\nshapes = [{}, {}]\nfriction = {}\n",
                quote(name_i),
                quote(name_j),
                num(friction(gi, gj))
            );
        }
    }

    write_actuators(model, &links, &mut t, &mut notices).map_err(fail)?;
    loops::write_loops(model, &links, &carrier, &mut t);
    if !model.options.contact {
        notices.push("contacts are disabled (<flag contact>): no terrain, no pairs".into());
    }

    // qpos0, moved onto a stop that it lies beyond (MuJoCo's soft stops allow that start).
    let q: Vec<String> = model
        .joints
        .iter()
        .map(|j| match j.range.filter(|_| limits) {
            Some([lower, upper]) if !(lower..=upper).contains(&j.reference) => {
                let start = j.reference.clamp(lower, upper);
                notices.push(format!(
                    "joint `{}`: qpos0 = {} lies beyond its range [{}, {}]; the scene starts \
                     it at {} (a hard stop cannot start violated)",
                    j.name,
                    num(j.reference),
                    num(lower),
                    num(upper),
                    num(start)
                ));
                num(start)
            }
            _ => num(j.reference),
        })
        .collect();
    let _ = writeln!(t, "[initial]\nq = [{}]", q.join(", "));
    Ok(SceneText { toml: t, notices })
}

/// One link per joint, in MuJoCo's order: the first joints of a body are massless links
/// at the joint's anchor, its last joint's link is the body with its mass.
fn links(model: &PlanarModel) -> Vec<Link> {
    let mut links: Vec<Link> = Vec::with_capacity(model.joints.len());
    let mut last_of: Vec<Option<usize>> = vec![None; model.bodies.len()];
    for (b, body) in model.bodies.iter().enumerate() {
        let mut parent = body.parent.and_then(|p| last_of[p]);
        let mut turn = parent.map_or(0.0, |p: usize| links[p].turn);
        for (k, &j) in body.joints.iter().enumerate() {
            let joint = &model.joints[j];
            if joint.kind == JointKind::Hinge {
                turn += joint.sign * joint.reference;
            }
            let last = k + 1 == body.joints.len();
            links.push(Link {
                name: if last {
                    body.name.clone()
                } else {
                    format!("{}_link", joint.name)
                },
                parent,
                joint: j,
                center: body.origin + if last { body.com } else { joint.anchor },
                turn,
                mass: if last { body.mass } else { 0.0 },
                inertia: if last { body.inertia } else { 0.0 },
            });
            parent = Some(links.len() - 1);
        }
        last_of[b] = parent;
    }
    links
}

/// MuJoCo's friction of a contact between two geoms: the higher priority's, else the
/// larger; none when the contact's `condim` (chosen alike) is 1.
fn friction(a: &Geom, b: &Geom) -> f64 {
    let (mu, condim) = if a.priority != b.priority {
        let winner = if a.priority > b.priority { a } else { b };
        (winner.friction[0], winner.condim)
    } else {
        (a.friction[0].max(b.friction[0]), a.condim.max(b.condim))
    };
    if condim == 1 {
        0.0
    } else {
        mu
    }
}

/// Why hopsim has no exact contact between two planar shapes, if it has none.
fn inexact(a: &Shape, b: &Shape) -> Option<&'static str> {
    match (a, b) {
        (
            Shape::Ellipse { .. },
            Shape::Ellipse { .. } | Shape::Polygon { .. } | Shape::Capsule { .. },
        )
        | (Shape::Polygon { .. } | Shape::Capsule { .. }, Shape::Ellipse { .. }) => {
            Some("an ellipse against a polygon, a capsule or an ellipse has no closed-form contact")
        }
        _ => None,
    }
}

fn write_shape(t: &mut String, shape: &Shape) {
    let _ = match shape {
        Shape::Circle { center, radius } => writeln!(
            t,
            "type = \"circle\"\ncenter = {}\nradius = {}",
            pair(*center),
            num(*radius)
        ),
        Shape::Capsule { a, b, radius } => writeln!(
            t,
            "type = \"capsule\"\nfrom = {}\nto = {}\nradius = {}",
            pair(*a),
            pair(*b),
            num(*radius)
        ),
        Shape::Polygon { vertices } => {
            let v: Vec<String> = vertices.iter().map(|v| pair(*v)).collect();
            writeln!(t, "type = \"polygon\"\nvertices = [{}]", v.join(", "))
        }
        Shape::Ellipse {
            center, semi_axes, ..
        } => writeln!(
            t,
            "type = \"ellipse\"\ncenter = {}\nsemi_x = {}\nsemi_y = {}",
            pair(*center),
            num(semi_axes[0]),
            num(semi_axes[1])
        ),
        Shape::Line { .. } => Ok(()),
    };
}

/// `shape` with every point `p` moved to `point(p)`, a map that turns by `turn`.
fn transformed(shape: &Shape, point: impl Fn(Vec2) -> Vec2, turn: f64) -> Shape {
    match shape {
        Shape::Circle { center, radius } => Shape::Circle {
            center: point(*center),
            radius: *radius,
        },
        Shape::Capsule { a, b, radius } => Shape::Capsule {
            a: point(*a),
            b: point(*b),
            radius: *radius,
        },
        Shape::Polygon { vertices } => Shape::Polygon {
            vertices: vertices.iter().map(|v| point(*v)).collect(),
        },
        Shape::Ellipse {
            center,
            semi_axes,
            angle,
        } => Shape::Ellipse {
            center: point(*center),
            semi_axes: *semi_axes,
            angle: angle + turn,
        },
        Shape::Line { point: p, normal } => Shape::Line {
            point: point(*p),
            normal: rotate(turn, *normal),
        },
    }
}

/// The geom's name for messages: its MJCF name, else its body's.
fn geom_name(geom: &Geom) -> String {
    match &geom.name {
        Some(n) => format!("`{n}`"),
        None => format!("of body `{}`", geom.mjcf_body),
    }
}

/// A shape name from the geom's (or its body's) name, usable in contact names and unique.
fn unique_shape_name(
    model: &PlanarModel,
    i: usize,
    taken: &[(usize, String, Option<usize>, Shape)],
) -> String {
    let geom = &model.geoms[i];
    let base: String = geom
        .name
        .clone()
        .unwrap_or_else(|| format!("{}_geom", geom.mjcf_body))
        .chars()
        .map(|c| if c == '/' || c == '#' { '_' } else { c })
        .collect();
    let base = if base.starts_with("terrain") {
        format!("geom_{base}")
    } else {
        base
    };
    let mut name = base.clone();
    let mut k = 1;
    while taken.iter().any(|(_, n, _, _)| *n == name) {
        name = format!("{base}_{k}");
        k += 1;
    }
    name
}

/// A coordinate name from a joint's: letters, digits and `_`, not starting with a digit.
fn identifier(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        s.insert(0, '_');
    }
    s
}

fn rotate(angle: f64, v: Vec2) -> Vec2 {
    if angle == 0.0 {
        return v;
    }
    let (s, c) = angle.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// A number as TOML, exactly (Rust's shortest representation that reads back the same).
fn num(x: f64) -> String {
    format!("{x:?}")
}

fn pair(v: Vec2) -> String {
    format!("[{}, {}]", num(v.x), num(v.y))
}

/// A TOML basic string.
fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
