//! `<equality>`: MuJoCo's `connect` and `weld` constraints as loop closures of the planar
//! model (docs/mjcf.md, "Closed loops"; docs/physics.md §8).
//!
//! - `connect`: the point `anchor` of `body1` (in its frame) stays on the point of `body2`
//!   that coincides with it at `qpos0`, as MuJoCo's compiler computes it: a revolute loop.
//! - `weld`: `body2`'s pose relative to `body1` stays `relpose`, or the one at `qpos0` when
//!   its quaternion is zero (MuJoCo's default); `anchor` is the weld point in `body2`'s
//!   frame. In the plane: the two points coincide and `θ₁ − θ₂` stays fixed.
//!
//! MuJoCo's equalities are soft (`solref`, `solimp`, a weld's `torquescale`); hopsim's loop
//! joints are hard, so those are notices. `active="false"` leaves the constraint out (a
//! notice), as does `<flag equality="disable">`. `joint`, `tendon` and `flex` couplings are
//! located errors.

use nalgebra::{UnitQuaternion, Vector3};

use crate::attrs::{Context, Table, Treat, View};
use crate::error::{located, Location, NoticeKind, Result};
use crate::model::{Body, Plane, Vec2};
use crate::planar::PLANE_TOLERANCE;
use crate::read::Body3;
use crate::xml::{Attr, Element};

type V3 = Vector3<f64>;

const SOFT_EQUALITY: &str = "a parameter of MuJoCo's soft equality constraints: hopsim's loop joints are hard (bilateral rows of the step, docs/physics.md §8)";
const SITES: &str =
    "equalities between sites (`site1`, `site2`): give `body1`, `body2` and `anchor`";

/// Attributes of `<connect>` and `<weld>` (`relpose` and `torquescale`: `<weld>` only).
const EQUALITY: Table = &[
    ("name", Treat::Read),
    ("active", Treat::Read),
    ("solref", Treat::Read),
    ("solimp", Treat::Read),
    ("body1", Treat::Read),
    ("body2", Treat::Read),
    ("anchor", Treat::Read),
    ("relpose", Treat::Read),
    ("torquescale", Treat::Read),
    ("site1", Treat::Unless(crate::attrs::Neutral::Never, SITES)),
    ("site2", Treat::Unless(crate::attrs::Neutral::Never, SITES)),
];
/// The attributes of a weld alone.
const WELD_ONLY: [&str; 2] = ["relpose", "torquescale"];
/// Attributes of `<default><equality>`.
pub(crate) const DEFAULTS: Table = &[
    ("active", Treat::Read),
    ("solref", Treat::Read),
    ("solimp", Treat::Read),
];

/// A loop closure read from `<equality>`: a point of one body held on a point of another
/// body (or of the world).
#[derive(Debug, Clone, PartialEq)]
pub struct Equality {
    /// The MJCF name, if any.
    pub name: Option<String>,
    /// `<connect>` or `<weld>`.
    pub element: String,
    pub kind: EqualityKind,
    /// `body1`'s moving body, `None` when it is welded to the world.
    pub body1: Option<usize>,
    /// The point on `body1`: in its frame (a planar world vector from its origin at
    /// reference), or a world point.
    pub point1: Vec2,
    /// `body2`'s moving body (MuJoCo's default: the world, `None`).
    pub body2: Option<usize>,
    /// The point on `body2`, as `point1`.
    pub point2: Vec2,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EqualityKind {
    /// The two points coincide.
    Connect,
    /// The two points coincide and `θ₁ − θ₂ = angle` (rad, counter-clockwise about the
    /// plane's normal; `θ` the bodies' angles, 0 at reference, 0 for the world).
    Weld { angle: f64 },
}

/// `<connect>` or `<weld>` as written, in MuJoCo's 3-D terms.
#[derive(Debug, Clone)]
pub(crate) struct Equality3 {
    pub name: Option<String>,
    pub element: String,
    pub loc: Location,
    pub weld: bool,
    pub body1: Attr,
    /// `None`: the world.
    pub body2: Option<Attr>,
    pub anchor: V3,
    /// A weld's `relpose` (position, orientation of body2 in body1's frame), when its
    /// quaternion is not zero.
    pub relpose: Option<(V3, UnitQuaternion<f64>)>,
}

/// The children of `<equality>` (`defaults` picks an element's class defaults); inactive
/// ones are left out with a notice.
pub(crate) fn read<'d>(
    e: &Element,
    mut defaults: impl FnMut(&Element) -> Result<&'d [Attr]>,
    ctx: &mut Context,
) -> Result<Vec<Equality3>> {
    if let Some(a) = e.attrs.first() {
        return Err(e.error(Some(&a.name), "<equality> takes no attributes"));
    }
    let mut out = Vec::new();
    for child in &e.children {
        if let Some(c) = child.children.first() {
            return Err(c.error(None, format!("<{}> takes no child elements", child.name)));
        }
        let weld = match child.name.as_str() {
            "connect" => false,
            "weld" => true,
            "joint" | "tendon" | "flex" | "distance" => return Err(unsupported(child)),
            other => {
                return Err(child.error(None, format!("unknown element <{other}> in <equality>")))
            }
        };
        let v = View::new(child, defaults(child)?);
        v.check(EQUALITY, ctx)?;
        if let Some(a) = WELD_ONLY
            .iter()
            .find_map(|n| child.attr(n))
            .filter(|_| !weld)
        {
            return Err(v.error_at(a, "applies to <weld> only"));
        }
        for name in ["solref", "solimp", "torquescale"] {
            if let Some(a) = v.get(name) {
                ctx.notice(
                    NoticeKind::NotApplicable,
                    &a.loc,
                    &child.name,
                    Some(name),
                    SOFT_EQUALITY,
                );
            }
        }
        if !v.boolean("active", true)? {
            let a = v.get("active").map_or(&child.loc, |a| &a.loc);
            ctx.notice(
                NoticeKind::Ignored,
                a,
                &child.name,
                Some("active"),
                "inactive at the start: left out (hopsim's loop joints cannot be switched on during a run)",
            );
            continue;
        }
        let body1 = v
            .get("body1")
            .cloned()
            .ok_or_else(|| v.error("missing attribute `body1`"))?;
        let relpose = match v.vector::<7>("relpose")? {
            Some([x, y, z, w, i, j, k]) if [w, i, j, k].iter().any(|c| *c != 0.0) => {
                let q = nalgebra::Quaternion::new(w, i, j, k);
                Some((V3::new(x, y, z), UnitQuaternion::from_quaternion(q)))
            }
            _ => None,
        };
        out.push(Equality3 {
            name: v.string("name").map(str::to_string),
            element: child.name.clone(),
            loc: child.loc.clone(),
            weld,
            body1,
            body2: v.get("body2").cloned(),
            anchor: V3::from(v.vector::<3>("anchor")?.unwrap_or_default()),
            relpose,
        });
    }
    Ok(out)
}

/// The located error of an equality hopsim has no loop joint for.
fn unsupported(e: &Element) -> crate::error::MjcfError {
    let (attribute, what) = match e.name.as_str() {
        "joint" => ("joint1", "a polynomial coupling of two joints"),
        "tendon" => (
            "tendon1",
            "a coupling of tendon lengths (tendons are not supported)",
        ),
        "flex" => ("flex", "a flex's edge lengths (flexes are not supported)"),
        _ => ("geom1", "a distance between geoms (removed from MuJoCo)"),
    };
    let attribute = if e.attr(attribute).is_some() {
        Some(attribute)
    } else {
        None
    };
    e.error(
        attribute,
        format!(
            "not supported: <{}> equality, {what}; hopsim's loop joints are <connect> and <weld>",
            e.name
        ),
    )
}

/// The frames the planar equalities are expressed in.
pub(crate) struct Frames<'a> {
    pub bodies3: &'a [Body3],
    /// MuJoCo's body poses at `qpos0` (world).
    pub xpos: &'a [V3],
    pub xquat: &'a [UnitQuaternion<f64>],
    /// Each MJCF body's moving body, `None` when welded to the world.
    pub owner: &'a [Option<usize>],
    pub bodies: &'a [Body],
    pub plane: &'a Plane,
}

/// The planar loop closures of `raw`; none when `enabled` is false (a notice each).
pub(crate) fn planar(
    raw: &[Equality3],
    frames: &Frames,
    enabled: bool,
    ctx: &mut Context,
) -> Result<Vec<Equality>> {
    let mut out = Vec::new();
    for eq in raw {
        if !enabled {
            ctx.notice(
                NoticeKind::Ignored,
                &eq.loc,
                &eq.element,
                None,
                "equality constraints are disabled (<flag equality> or <flag constraint>): left out",
            );
            continue;
        }
        let b1 = body_index(frames.bodies3, Some(&eq.body1), eq)?;
        let b2 = body_index(frames.bodies3, eq.body2.as_ref(), eq)?;
        let (o1, o2) = (frames.owner[b1], frames.owner[b2]);
        if o1 == o2 {
            return Err(located(
                &eq.loc,
                &eq.element,
                eq.body2.as_ref().map_or(Some("body1"), |_| Some("body2")),
                format!(
                    "`{}` and `{}` move as one body (welded together or both fixed to the \
                     world): the constraint holds nothing",
                    frames.bodies3[b1].name, frames.bodies3[b2].name
                ),
            ));
        }
        let (q1, q2) = (frames.xquat[b1], frames.xquat[b2]);
        // World points at qpos0 of the point on body2 and the point on body1.
        let on2 = frames.xpos[b2] + q2 * eq.anchor;
        let (on1, relative) = if !eq.weld {
            (frames.xpos[b1] + q1 * eq.anchor, None)
        } else {
            match eq.relpose {
                // body2's frame in body1's frame: the anchor of body2 seen from body1.
                Some((p, r)) => (frames.xpos[b1] + q1 * (p + r * eq.anchor), Some(q1 * r)),
                None => (on2, None),
            }
        };
        // A connect's point on body2 is the one on body1 at qpos0 (MuJoCo's compiler).
        let on2 = if eq.weld { on2 } else { on1 };
        let kind = if eq.weld {
            // θ₂ − θ₁ is the turn about the normal from body1's held orientation of body2
            // to body2's orientation at reference (zero without relpose).
            let turn = relative.map_or(Ok(0.0), |held| {
                turn_about(&(held * q2.inverse()), frames.plane).ok_or_else(|| {
                    located(
                        &eq.loc,
                        &eq.element,
                        Some("relpose"),
                        "turns body2 out of the plane of motion",
                    )
                })
            })?;
            EqualityKind::Weld { angle: -turn }
        } else {
            EqualityKind::Connect
        };
        let local = |owner: Option<usize>, w: &V3| {
            let p = frames.plane.project(w);
            owner.map_or(p, |o| p - frames.bodies[o].origin)
        };
        out.push(Equality {
            name: eq.name.clone(),
            element: eq.element.clone(),
            kind,
            body1: o1,
            point1: local(o1, &on1),
            body2: o2,
            point2: local(o2, &on2),
        });
    }
    Ok(out)
}

/// The index of the body named by `attr` (the world when `None`).
fn body_index(bodies: &[Body3], attr: Option<&Attr>, eq: &Equality3) -> Result<usize> {
    let Some(a) = attr else { return Ok(0) };
    bodies
        .iter()
        .position(|b| b.name == a.value)
        .ok_or_else(|| {
            located(
                &a.loc,
                &eq.element,
                Some(&a.name),
                format!("no body named `{}`", a.value),
            )
        })
}

/// The angle of a rotation about the plane's normal (counter-clockwise), `None` when it
/// turns about another axis.
fn turn_about(q: &UnitQuaternion<f64>, plane: &Plane) -> Option<f64> {
    let v = q.as_ref().imag();
    let along = v.dot(&plane.normal);
    if (v - plane.normal * along).norm() > PLANE_TOLERANCE {
        return None;
    }
    Some(2.0 * along.atan2(q.as_ref().w))
}
