//! Contacts between shapes of two bodies (docs/physics.md §7): the candidates of a shape pair,
//! their gap and contact frame in closed form, and their generalised directions.
//!
//! Every candidate is a *probe* of one shape (a circle's or arc's centre with its radius,
//! a capsule's end centre with its radius, or a corner point with radius zero) against the whole *target* shape of the other body:
//! the gap is the signed distance from the probe's centre to the target minus the probe's
//! radius, which is exact for a disc, a point and any convex target. The normal `n` is the
//! target's outward normal at its closest point, so it points from the target (side A of
//! §7) to the probe (side B), and a target fixed to the world reproduces the terrain
//! contacts of §1.

use crate::contact::{sided_signed_distance, ContactGeometry, ContactMaterial, ShapeFeature};
use crate::ellipse::closest_point_on_ellipse;
use crate::kinematics::Rotation;
use crate::{Kinematics, Shape, ShapeInstance, Vec2};

/// A potential contact between shapes of two different bodies.
#[derive(Clone, Debug, PartialEq)]
pub struct PairCandidate {
    /// Name used in records: `<probe>[#k]/<target>`, e.g. `"ball2/ball1"`.
    pub name: String,
    /// Index into [`crate::Model::shapes`] of the shape whose feature probes (side B).
    pub probe: usize,
    /// The probing feature: [`ShapeFeature::Smooth`] for a circle's or arc's round
    /// boundary, [`ShapeFeature::Vertex`] for a corner point.
    pub feature: ShapeFeature,
    /// Index into [`crate::Model::shapes`] of the shape probed (side A, the normal's origin).
    pub target: usize,
    /// Friction and restitution of the pair.
    pub material: ContactMaterial,
}

/// The geometry of a body–body contact at a configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairGeometry {
    /// Signed gap `g_N` (> 0 open, ≤ 0 closed), m.
    pub gap: f64,
    /// The probe's material point `p_B`, world frame, m.
    pub point: Vec2,
    /// The target's material point `p_A` (its closest boundary point), world frame, m.
    pub target_point: Vec2,
    /// Unit normal from the target (A) towards the probe (B).
    pub normal: Vec2,
}

impl PairGeometry {
    /// As a [`ContactGeometry`] seen from the probe's body (point `p_B`, normal A → B).
    pub fn as_contact(&self) -> ContactGeometry {
        ContactGeometry {
            gap: self.gap,
            point: self.point,
            normal: self.normal,
        }
    }
}

/// The probing features of a pair of shapes, as `(probe is the first shape, feature)`, or
/// why hopsim has no exact contact between them.
///
/// - round (circle, arc) against round: one round–round candidate, plus each arc end
///   against the other shape;
/// - round against a polygon, an ellipse or a point: the round boundary against the
///   polygon or ellipse (a polygon's corners are on its boundary, so they are covered) or
///   the point against the round shape; plus the arc ends;
/// - polygon or capsule against polygon or capsule: every corner of each (a capsule's
///   corners are its end caps) against the other; two convex shapes apart are nearest at
///   a corner of one of them, so this is exact;
/// - a point against a polygon, an ellipse or a capsule.
///
/// An ellipse against a polygon, a capsule or another ellipse has no closed-form closest
/// points, and two points never touch: these are errors.
pub fn pair_features(
    first: &Shape,
    second: &Shape,
) -> Result<Vec<(bool, ShapeFeature)>, &'static str> {
    use Shape::*;
    let round = |s: &Shape| matches!(s, Circle { .. } | Arc { .. });
    let corners = |s: &Shape, first: bool| {
        (0..s.vertex_count()).map(move |k| (first, ShapeFeature::Vertex(k)))
    };
    let mut out = Vec::new();
    match (first, second) {
        (Ellipse { .. }, Ellipse { .. }) => {
            return Err("two ellipses have no closed-form closest points")
        }
        (Ellipse { .. }, Polygon { .. }) | (Polygon { .. }, Ellipse { .. }) => {
            return Err("an ellipse and a polygon have no closed-form closest points")
        }
        (Ellipse { .. }, Capsule { .. }) | (Capsule { .. }, Ellipse { .. }) => {
            return Err("an ellipse and a capsule have no closed-form closest points")
        }
        (Point { .. }, Point { .. }) => return Err("two points never touch"),
        // The point is the probe (a polygon's or an ellipse's corners are its own).
        (Point { .. }, _) => out.push((true, ShapeFeature::Vertex(0))),
        (_, Point { .. }) => out.push((false, ShapeFeature::Vertex(0))),
        (Polygon { .. } | Capsule { .. }, Polygon { .. } | Capsule { .. }) => {
            out.extend(corners(first, true));
            out.extend(corners(second, false));
        }
        (a, b) if round(a) => {
            out.push((true, ShapeFeature::Smooth));
            out.extend(corners(a, true));
            if round(b) {
                out.extend(corners(b, false));
            }
        }
        // `second` is round, `first` a polygon, an ellipse or a capsule.
        (_, b) => {
            out.push((false, ShapeFeature::Smooth));
            out.extend(corners(b, false));
        }
    }
    Ok(out)
}

/// The probe of `feature` of `shape`: its centre in the body frame and its radius.
fn probe_of(shape: &Shape, feature: ShapeFeature) -> Option<(Vec2, f64)> {
    match (feature, shape) {
        (ShapeFeature::Smooth, Shape::Circle { center, radius })
        | (ShapeFeature::Smooth, Shape::Arc { center, radius, .. }) => Some((*center, *radius)),
        (ShapeFeature::Vertex(k), _) => Some((shape.vertex(k)?, shape.vertex_radius())),
        _ => None,
    }
}

/// The pose of a body: position of its centre of mass and rotation.
#[derive(Clone, Copy)]
pub(crate) struct Pose {
    pub position: Vec2,
    pub rotation: Rotation,
}

impl Pose {
    fn to_world(self, p: Vec2) -> Vec2 {
        self.position + self.rotation.apply(p)
    }
}

/// Gap and contact frame of the probe `feature` of `probe` (a body at `probe_pose`)
/// against `target` (at `target_pose`), or `None` when they cannot touch there (the
/// closest point lies off an arc, or the probe's centre sits on a round target's centre or
/// a capsule's segment).
pub(crate) fn pair_geometry(
    probe: &Shape,
    feature: ShapeFeature,
    probe_pose: Pose,
    target: &Shape,
    target_pose: Pose,
) -> Option<PairGeometry> {
    let (local_center, radius) = probe_of(probe, feature)?;
    let center = probe_pose.to_world(local_center);
    // The target's closest boundary point and outward normal (world), and the signed
    // distance of the probe's centre from the target.
    let (distance, closest, normal) = match target {
        Shape::Circle {
            center: c,
            radius: r,
        }
        | Shape::Arc {
            center: c,
            radius: r,
            ..
        } => {
            let c = target_pose.to_world(*c);
            let d = center - c;
            let length = d.norm();
            let n = d.try_normalize(1e-12 * (1.0 + length))?;
            if !target.covers_direction(target_pose.rotation.inverse(n)) {
                return None;
            }
            (length - r, c + *r * n, n)
        }
        Shape::Point { position } => {
            let p = target_pose.to_world(*position);
            let d = center - p;
            let length = d.norm();
            (length, p, d.try_normalize(1e-12 * (1.0 + length))?)
        }
        Shape::Polygon { .. } | Shape::Capsule { .. } => {
            let local = target_pose.rotation.inverse(center - target_pose.position);
            let (s, closest, outward) = sided_signed_distance(target, local)?;
            (
                s,
                target_pose.to_world(closest),
                target_pose.rotation.apply(outward),
            )
        }
        Shape::Ellipse {
            center: c,
            semi_x,
            semi_y,
        } => {
            let local = target_pose.rotation.inverse(center - target_pose.position) - c;
            let p = closest_point_on_ellipse(*semi_x, *semi_y, local);
            (
                p.signed_distance,
                target_pose.to_world(c + p.point),
                target_pose.rotation.apply(p.normal),
            )
        }
    };
    // An arc probes only in the directions it spans.
    if feature == ShapeFeature::Smooth
        && !probe.covers_direction(probe_pose.rotation.inverse(-normal))
    {
        return None;
    }
    Some(PairGeometry {
        gap: distance - radius,
        point: center - radius * normal,
        target_point: closest,
        normal,
    })
}

/// Writes `w_N = (J_B(p) − J_A(p))ᵀ n` and `w_T = (J_B(p) − J_A(p))ᵀ t` (docs/physics.md
/// §7.3) for the probe on body `probe` and the target on body `target`: the relative
/// velocity of the two bodies' material points at one point, the probe's contact point
/// `p = p_B` (as a terrain contact's, so a target on a fixed body gives the terrain's
/// rows). Its normal part is `∂g_N/∂q` exactly (`p_A` and `p_B` differ along `n`, which a
/// rotation does not change to first order); the tangential part is the slip at one place,
/// so that a contact whose bodies can only move along one direction relative to each
/// other has `w_T ∥ w_N` exactly (§4.8).
pub(crate) fn pair_directions_to(
    kinematics: &Kinematics,
    probe: usize,
    target: usize,
    geometry: &PairGeometry,
    w_n: &mut [f64],
    w_t: &mut [f64],
) {
    let tangent = geometry.as_contact().tangent();
    let r_b = geometry.point - kinematics.position(probe);
    let r_a = geometry.point - kinematics.position(target);
    kinematics.frame_directions_to(probe, r_b, (geometry.normal, tangent), w_n, w_t);
    kinematics.add_point_force_to(target, r_a, -geometry.normal, w_n);
    kinematics.add_point_force_to(target, r_a, -tangent, w_t);
}

/// The candidates between shapes `a` and `b` (indices into `shapes`) with `material`.
pub(crate) fn pair_candidates(
    shapes: &[ShapeInstance],
    a: usize,
    b: usize,
    material: ContactMaterial,
) -> Result<Vec<PairCandidate>, &'static str> {
    let features = pair_features(&shapes[a].shape, &shapes[b].shape)?;
    Ok(features
        .into_iter()
        .map(|(first_probes, feature)| {
            let (probe, target) = if first_probes { (a, b) } else { (b, a) };
            let corner = match feature {
                ShapeFeature::Vertex(k) if shapes[probe].shape.vertex_count() > 1 => {
                    format!("#{k}")
                }
                _ => String::new(),
            };
            PairCandidate {
                name: format!("{}{corner}/{}", shapes[probe].name, shapes[target].name),
                probe,
                feature,
                target,
                material,
            }
        })
        .collect())
}
