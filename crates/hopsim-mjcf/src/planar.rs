//! From MuJoCo's 3-D terms to the planar model: the plane found from the joints, every
//! frame, joint and geom expressed in it, jointless bodies welded into their parents, and
//! masses composed (docs/mjcf.md).

use nalgebra::{UnitQuaternion, Vector3};

use crate::attrs::Context;
use crate::error::{located, NoticeKind, Result};
use crate::inertia::{body_mass, MassProps};
use crate::model::{
    Actuator, ActuatorKind, Body, Geom, Joint, JointKind, Options, Part, PlanarModel, Plane, Shape,
    Vec2,
};
use crate::read::{Body3, Document, Geom3, GeomType, Joint3, Kind3};

type V3 = Vector3<f64>;

/// How far (in radians, about) an axis may be from parallel or perpendicular.
pub const PLANE_TOLERANCE: f64 = 1e-9;

/// The planar model of the document.
pub(crate) fn build(doc: Document, ctx: &mut Context) -> Result<PlanarModel> {
    let n_bodies = doc.bodies.len();
    // World poses in the reference configuration (MuJoCo's xpos0, xquat0).
    let mut xpos = vec![V3::zeros(); n_bodies];
    let mut xquat = vec![UnitQuaternion::identity(); n_bodies];
    for (b, body) in doc.bodies.iter().enumerate() {
        if let Some(p) = body.parent {
            xpos[b] = xpos[p] + xquat[p] * body.pos;
            xquat[b] = xquat[p] * body.quat;
        }
    }
    unique_names(&doc)?;
    let plane = find_plane(&doc.bodies, &xquat)?;
    let n = plane.normal;

    // Each MJCF body's own mass properties, bounded and scaled as MuJoCo's compiler does.
    let mut props: Vec<MassProps> = Vec::with_capacity(n_bodies);
    for (b, body) in doc.bodies.iter().enumerate() {
        let mut p = if b == 0 {
            MassProps {
                mass: 0.0,
                com: V3::zeros(),
                inertia: 0.0,
            }
        } else {
            body_mass(
                body,
                doc.compiler.inertia_from_geom,
                &(xquat[b].inverse() * n),
            )
            .map_err(|m| {
                located(
                    &body.loc,
                    "body",
                    None,
                    format!("body `{}`: {m}", body.name),
                )
            })?
        };
        if b > 0 {
            p.mass = p.mass.max(doc.compiler.boundmass);
        }
        props.push(p);
    }
    if doc.compiler.settotalmass > 0.0 {
        let total: f64 = props.iter().map(|p| p.mass).sum();
        if total > 0.0 {
            let scale = doc.compiler.settotalmass / total;
            for p in &mut props {
                p.mass *= scale;
                p.inertia *= scale;
            }
        }
    }

    // Welding: each MJCF body belongs to the nearest body with joints at or above it.
    let mut owner: Vec<Option<usize>> = vec![None; n_bodies];
    let mut bodies: Vec<Body> = Vec::new();
    let mut root_of: Vec<usize> = Vec::new();
    for (b, body) in doc.bodies.iter().enumerate().skip(1) {
        let parent = body.parent.and_then(|p| owner[p]);
        owner[b] = if body.joints.is_empty() {
            parent
        } else {
            bodies.push(Body {
                name: body.name.clone(),
                parent,
                joints: Vec::new(),
                origin: plane.project(&xpos[b]),
                depth: xpos[b].dot(&n),
                mass: 0.0,
                com: Vec2::zeros(),
                inertia: 0.0,
                parts: Vec::new(),
            });
            root_of.push(b);
            Some(bodies.len() - 1)
        };
    }
    let mut world = Vec::new();
    for (b, body) in doc.bodies.iter().enumerate() {
        let origin = owner[b].map_or(V3::zeros(), |o| xpos[root_of[o]]);
        let part = Part {
            name: body.name.clone(),
            mass: props[b].mass,
            com: plane.project(&(xpos[b] + xquat[b] * props[b].com - origin)),
            inertia: props[b].inertia,
        };
        match owner[b] {
            Some(o) => bodies[o].parts.push(part),
            None => world.push(part),
        }
    }
    for body in &mut bodies {
        compose(body);
    }

    // Joints in MuJoCo's order: bodies depth first, each body's joints in order.
    let mut joints = Vec::new();
    for (b, body) in doc.bodies.iter().enumerate() {
        for j in &body.joints {
            let Some(o) = owner[b] else { continue };
            bodies[o].joints.push(joints.len());
            joints.push(joint(j, o, joints.len(), &xquat[b], &plane));
        }
    }

    // Geoms, each in its body's frame or the world's.
    let moving: Vec<(u32, u32)> = doc
        .bodies
        .iter()
        .enumerate()
        .filter(|(b, _)| owner[*b].is_some())
        .flat_map(|(_, body)| body.geoms.iter().map(|g| (g.contype, g.conaffinity)))
        .collect();
    let mut geoms = Vec::new();
    for (b, body) in doc.bodies.iter().enumerate() {
        let origin = owner[b].map_or(V3::zeros(), |o| xpos[root_of[o]]);
        let counts = b > 0 && body_uses_geoms(body, doc.compiler.inertia_from_geom);
        for g in &body.geoms {
            let center = xpos[b] + xquat[b] * g.pos;
            let axes = (xquat[b] * g.quat).to_rotation_matrix();
            let Some(shape) = shape(
                g,
                &plane,
                plane.project(&(center - origin)),
                axes.matrix(),
                &moving,
                ctx,
            )?
            else {
                continue;
            };
            geoms.push(Geom {
                name: g.name.clone(),
                body: owner[b],
                mjcf_body: body.name.clone(),
                shape,
                depth: center.dot(&n),
                mass: if counts && g.counted { g.mass } else { 0.0 },
                contype: g.contype,
                conaffinity: g.conaffinity,
                condim: g.condim,
                priority: g.priority,
                friction: g.friction,
                restitution: 0.0,
                rgba: g.rgba,
            });
        }
    }

    let mut actuators = Vec::new();
    for a in &doc.actuators {
        let joint = joints
            .iter()
            .position(|j: &Joint| j.name == a.joint.value)
            .ok_or_else(|| {
                located(
                    &a.joint.loc,
                    &a.element,
                    Some("joint"),
                    format!("no joint named `{}`", a.joint.value),
                )
            })?;
        actuators.push(Actuator {
            name: a.name.clone(),
            joint,
            kind: match a.kind {
                Kind3::Motor => ActuatorKind::Motor,
                Kind3::Position { kp, kv } => ActuatorKind::Position { kp, kv },
                Kind3::Velocity { kv } => ActuatorKind::Velocity { kv },
            },
            gear: a.gear,
            ctrl_range: a.ctrl_range,
            force_range: a.force_range,
        });
    }

    let flag = |name: &str, default: bool| doc.options.flags.get(name).copied().unwrap_or(default);
    let constraints = flag("constraint", true);
    let gravity = if flag("gravity", true) {
        doc.options.gravity
    } else {
        V3::zeros()
    };
    let options = Options {
        timestep: doc.options.timestep,
        gravity: plane.project(&gravity),
        gravity_normal: gravity.dot(&n),
        contact: constraints && flag("contact", true),
        limits: constraints && flag("limit", true),
        frictionloss: constraints && flag("frictionloss", true),
        springs: flag("spring", true),
        dampers: flag("damper", true),
        actuation: flag("actuation", true),
        clamp_controls: flag("clampctrl", true),
        filter_parent: flag("filterparent", true),
    };
    let equalities = crate::equality::planar(
        &doc.equalities,
        &crate::equality::Frames {
            bodies3: &doc.bodies,
            xpos: &xpos,
            xquat: &xquat,
            owner: &owner,
            bodies: &bodies,
            plane: &plane,
        },
        constraints && flag("equality", true),
        ctx,
    )?;
    Ok(PlanarModel {
        name: doc.name,
        plane,
        options,
        bodies,
        world,
        joints,
        geoms,
        actuators,
        equalities,
        notices: std::mem::take(&mut ctx.notices),
    })
}

/// Bodies and joints are found by name (actuators, states): each name once, as in MuJoCo.
fn unique_names(doc: &Document) -> Result<()> {
    let mut bodies = std::collections::HashSet::new();
    let mut joints = std::collections::HashSet::new();
    for b in &doc.bodies {
        if !bodies.insert(b.name.as_str()) {
            return Err(located(
                &b.loc,
                "body",
                Some("name"),
                format!("a second body named `{}`", b.name),
            ));
        }
        for j in &b.joints {
            if !joints.insert(j.name.as_str()) {
                return Err(located(
                    &j.loc,
                    "joint",
                    Some("name"),
                    format!("a second joint named `{}`", j.name),
                ));
            }
        }
    }
    Ok(())
}

fn body_uses_geoms(body: &Body3, from_geom: Option<bool>) -> bool {
    from_geom.unwrap_or(body.inertial.is_none())
}

/// The body's mass, centre of mass and inertia from its parts (parallel-axis theorem).
fn compose(body: &mut Body) {
    let mass: f64 = body.parts.iter().map(|p| p.mass).sum();
    body.mass = mass;
    if mass <= 0.0 {
        return;
    }
    body.com = body.parts.iter().map(|p| p.com * p.mass).sum::<Vec2>() / mass;
    body.inertia = body
        .parts
        .iter()
        .map(|p| p.inertia + p.mass * (p.com - body.com).norm_squared())
        .sum();
}

fn joint(
    j: &Joint3,
    body: usize,
    qpos: usize,
    frame: &UnitQuaternion<f64>,
    plane: &Plane,
) -> Joint {
    let axis = frame * j.axis;
    Joint {
        name: j.name.clone(),
        kind: if j.hinge {
            JointKind::Hinge
        } else {
            let a = plane.project(&axis);
            JointKind::Slide { axis: a / a.norm() }
        },
        body,
        qpos,
        sign: if j.hinge {
            axis.dot(&plane.normal).signum()
        } else {
            1.0
        },
        anchor: plane.project(&(frame * j.pos)),
        reference: j.reference,
        spring_reference: j.spring_reference,
        stiffness: j.stiffness,
        damping: j.damping,
        armature: j.armature,
        frictionloss: j.frictionloss,
        range: j.range,
        actuator_force_range: j.actuator_force_range,
    }
}

fn fmt(v: &V3) -> String {
    let c = |x: f64| {
        let s = format!("{x:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    };
    format!("({} {} {})", c(v.x), c(v.y), c(v.z))
}

/// The plane of motion: the normal is the hinges' common axis (else the slides' common
/// normal); `e2` is the world's `z` in the plane (else `e1` is the world's `x`), and the
/// normal's sign puts `e1` along `+x` (else `+y`), so that `e1 × e2 = n`.
fn find_plane(bodies: &[Body3], xquat: &[UnitQuaternion<f64>]) -> Result<Plane> {
    let joints: Vec<(&Joint3, V3)> = bodies
        .iter()
        .zip(xquat)
        .flat_map(|(b, q)| b.joints.iter().map(move |j| (j, q * j.axis)))
        .collect();
    let hinges: Vec<&(&Joint3, V3)> = joints.iter().filter(|(j, _)| j.hinge).collect();
    let slides: Vec<&(&Joint3, V3)> = joints.iter().filter(|(j, _)| !j.hinge).collect();
    let normal = if let Some((first, a)) = hinges.first() {
        for (j, b) in &hinges[1..] {
            if a.cross(b).norm() > PLANE_TOLERANCE {
                return Err(located(&j.loc, "joint", Some("axis"), format!(
                    "joint `{}` leaves the plane: its hinge axis {} (in the world) is not parallel to the axis {} of the first hinge `{}`",
                    j.name, fmt(b), fmt(a), first.name
                )));
            }
        }
        *a
    } else {
        let first = slides.first().map(|(_, a)| *a);
        let other = slides
            .iter()
            .map(|(_, b)| first.unwrap_or_default().cross(b))
            .find(|c| c.norm() > 1e-6);
        match (first, other) {
            (_, Some(c)) => c / c.norm(),
            (Some(s), None) => [V3::y(), V3::z(), V3::x()]
                .into_iter()
                .find(|c| c.dot(&s).abs() < PLANE_TOLERANCE)
                .unwrap_or_else(|| {
                    let c = s.cross(&V3::z());
                    c / c.norm()
                }),
            (None, None) => V3::y(),
        }
    };
    for (j, s) in &slides {
        if s.dot(&normal).abs() > PLANE_TOLERANCE {
            return Err(located(&j.loc, "joint", Some("axis"), format!(
                "joint `{}` leaves the plane: its slide axis {} (in the world) is not perpendicular to the plane's normal {}",
                j.name, fmt(s), fmt(&normal)
            )));
        }
    }
    let up = V3::z() - normal * normal.dot(&V3::z());
    let (mut n, e1, e2);
    if up.norm() > 1e-6 {
        e2 = up / up.norm();
        n = normal;
        let mut x = e2.cross(&n);
        let forward = if x.x.abs() > 1e-9 { x.x } else { x.y };
        if forward < 0.0 {
            n = -n;
            x = -x;
        }
        e1 = x;
    } else {
        let x = V3::x() - normal * normal.dot(&V3::x());
        e1 = x / x.norm();
        n = normal;
        let mut y = n.cross(&e1);
        if y.y < 0.0 {
            n = -n;
            y = -y;
        }
        e2 = y;
    }
    Ok(Plane { normal: n, e1, e2 })
}

/// Where an axis lies with respect to the plane.
#[derive(PartialEq)]
enum Lies {
    InPlane,
    Normal,
    Tilted,
}

fn lies(axis: &V3, plane: &Plane) -> Lies {
    if axis.dot(&plane.normal).abs() < PLANE_TOLERANCE {
        Lies::InPlane
    } else if axis.cross(&plane.normal).norm() < PLANE_TOLERANCE {
        Lies::Normal
    } else {
        Lies::Tilted
    }
}

/// The planar shape of a geom centred at `c` (in its body's planar frame) with world axes
/// the columns of `axes`; `None` for a plane parallel to the plane of motion that touches
/// nothing.
fn shape(
    g: &Geom3,
    plane: &Plane,
    c: Vec2,
    axes: &nalgebra::Matrix3<f64>,
    moving: &[(u32, u32)],
    ctx: &mut Context,
) -> Result<Option<Shape>> {
    let name = g
        .name
        .as_deref()
        .map_or_else(|| "(unnamed)".to_string(), |n| format!("`{n}`"));
    let leaves = |what: &str| {
        located(
            &g.loc,
            "geom",
            None,
            format!(
                "geom {name} leaves the plane: {what} (the plane's normal is {})",
                fmt(&plane.normal)
            ),
        )
    };
    let col = |k: usize| V3::new(axes[(0, k)], axes[(1, k)], axes[(2, k)]);
    let [x, y, z] = [col(0), col(1), col(2)];
    let s = g.size;
    // The box-like shapes: the axis along the normal, and the other two in the plane.
    let flat = |kind: &str| -> Result<(Vec2, Vec2, f64, f64)> {
        match (lies(&x, plane), lies(&y, plane), lies(&z, plane)) {
            (Lies::Normal, _, _) => Ok((plane.project(&y), plane.project(&z), s[1], s[2])),
            (_, Lies::Normal, _) => Ok((plane.project(&x), plane.project(&z), s[0], s[2])),
            (_, _, Lies::Normal) => Ok((plane.project(&x), plane.project(&y), s[0], s[1])),
            _ => Err(leaves(&format!(
                "none of its {kind}'s axes {} {} {} is along the plane's normal",
                fmt(&x),
                fmt(&y),
                fmt(&z)
            ))),
        }
    };
    Ok(Some(match g.kind {
        GeomType::Sphere => Shape::Circle {
            center: c,
            radius: s[0],
        },
        GeomType::Capsule | GeomType::Cylinder => match lies(&z, plane) {
            Lies::Normal => Shape::Circle {
                center: c,
                radius: s[0],
            },
            Lies::InPlane => {
                let u = plane.project(&z);
                if g.kind == GeomType::Capsule {
                    Shape::Capsule {
                        a: c - u * s[1],
                        b: c + u * s[1],
                        radius: s[0],
                    }
                } else {
                    rectangle(c, u, Vec2::new(-u.y, u.x), s[1], s[0])
                }
            }
            Lies::Tilted => {
                return Err(leaves(&format!(
                    "its axis {} is neither in the plane nor along its normal",
                    fmt(&z)
                )))
            }
        },
        GeomType::Box => {
            let (u, v, a, b) = flat("box")?;
            rectangle(c, u, v, a, b)
        }
        GeomType::Ellipsoid => {
            let (u, _, a, b) = flat("ellipsoid")?;
            Shape::Ellipse {
                center: c,
                semi_axes: [a, b],
                angle: u.y.atan2(u.x),
            }
        }
        GeomType::Plane => match lies(&z, plane) {
            Lies::InPlane => Shape::Line {
                point: c,
                normal: plane.project(&z),
            },
            Lies::Normal => {
                if moving
                    .iter()
                    .any(|&(ct, ca)| ct & g.conaffinity != 0 || g.contype & ca != 0)
                {
                    return Err(leaves("it is parallel to the plane of motion and could touch the bodies out of the plane; give it contype=\"0\" conaffinity=\"0\" or remove it"));
                }
                ctx.notice(
                    NoticeKind::Ignored,
                    &g.loc,
                    "geom",
                    None,
                    "a plane parallel to the plane of motion that collides with no body",
                );
                return Ok(None);
            }
            Lies::Tilted => {
                return Err(leaves(&format!(
                    "its normal {} is neither in the plane nor along its normal",
                    fmt(&z)
                )))
            }
        },
    }))
}

/// The rectangle with centre `c`, half-extents `a` along the unit `u` and `b` along the unit
/// `v`, counter-clockwise.
fn rectangle(c: Vec2, u: Vec2, v: Vec2, a: f64, b: f64) -> Shape {
    let mut vertices = vec![
        c - u * a - v * b,
        c + u * a - v * b,
        c + u * a + v * b,
        c - u * a + v * b,
    ];
    if u.perp(&v) < 0.0 {
        vertices.reverse();
    }
    Shape::Polygon { vertices }
}
