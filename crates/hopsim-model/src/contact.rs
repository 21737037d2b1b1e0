//! Contact kinematics: the gap `g_N` and the contact frame of every potential contact
//! between a body's shape and a terrain feature (docs/physics.md §1, §2).

use crate::capsule::capsule_signed_distance;
use crate::ellipse::closest_point_on_ellipse;
use crate::kinematics::Rotation;
use crate::{Model, Shape, TerrainFeature, Vec2};

/// Friction and restitution of one contact (docs/physics.md §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactMaterial {
    /// Coulomb friction coefficient `μ` (≥ 0).
    pub friction: f64,
    /// Normal restitution `ε_N` (0 inelastic … 1 elastic).
    pub restitution_normal: f64,
    /// Tangential restitution `ε_T`.
    pub restitution_tangent: f64,
}

impl ContactMaterial {
    /// A perfectly inelastic contact (`ε_N = ε_T = 0`) with friction coefficient `friction`.
    pub fn inelastic(friction: f64) -> Self {
        Self {
            friction,
            restitution_normal: 0.0,
            restitution_tangent: 0.0,
        }
    }
}

impl Default for ContactMaterial {
    /// Inelastic, `μ = 1`.
    fn default() -> Self {
        Self::inelastic(1.0)
    }
}

/// Which part of a shape a contact candidate uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeFeature {
    /// The smooth boundary of a circle, arc or ellipse.
    Smooth,
    /// The shape's `k`-th vertex (see [`Shape::vertex`]).
    Vertex(usize),
    /// A convex polygon's edges or a capsule's whole boundary, as one boundary, against a
    /// terrain corner.
    Edges,
}

/// A potential contact: one feature of one shape against one terrain feature.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactCandidate {
    /// Name used in records, e.g. `"disc/ground"`.
    pub name: String,
    /// Index into [`crate::Model::shapes`].
    pub shape: usize,
    /// The part of the shape that touches.
    pub feature: ShapeFeature,
    /// Index into the terrain's features.
    pub terrain: usize,
    /// Friction and restitution.
    pub material: ContactMaterial,
}

/// The geometry of one potential contact at a configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactGeometry {
    /// Signed gap `g_N` (> 0 open, ≤ 0 closed), m.
    pub gap: f64,
    /// The body's material point that touches, world frame, m.
    pub point: Vec2,
    /// Unit normal pointing from the terrain towards the body.
    pub normal: Vec2,
}

impl ContactGeometry {
    /// The unit tangent `t = (n_y, -n_x)`: `+x` on flat ground, so `w_T` matches §2.
    pub fn tangent(&self) -> Vec2 {
        TerrainFeature::tangent(self.normal)
    }
}

/// Gap and contact frame of `feature` of `shape` (on a body at `position`, rotated by
/// `rotation`) against `terrain`, or `None` when the pair cannot touch there (the closest
/// point lies beyond the end of a line, outside a corner's normal cone, or off an arc).
///
/// Closed forms where they exist: circles, arcs, ellipses and vertices against lines
/// (support points; a capsule's vertices are its end caps), circles and arcs against
/// corners, a corner against a convex polygon's edges (signed point-polygon distance) or a
/// capsule (distance to its segment). A corner against an ellipse uses the
/// closest point on the ellipse by Eberly's monotone root, exact to round-off (see
/// `ellipse.rs`). A point behind a line is that line's only if [`owned_by_line`].
#[inline]
pub(crate) fn contact_geometry(
    shape: &Shape,
    feature: ShapeFeature,
    position: Vec2,
    rotation: Rotation,
    features: &[TerrainFeature],
    index: usize,
) -> Option<ContactGeometry> {
    let terrain = &features[index];
    let geometry = feature_geometry(shape, feature, position, rotation, terrain)?;
    if geometry.gap < 0.0 && !owned_by_line(&geometry, terrain, features) {
        return None;
    }
    Some(geometry)
}

/// A circle's boundary against a line without ends (a wheel or a disc on flat ground, the
/// commonest contact), resolved once per model so that its geometry skips the general
/// dispatch of [`contact_geometry`]. It gives the same geometry bit for bit: the same
/// operations in the same order, and a line without ends owns every point behind it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DiscOnLine {
    /// The body carrying the circle.
    pub body: usize,
    center: Vec2,
    radius: f64,
    normal: Vec2,
    line: TerrainFeature,
}

impl DiscOnLine {
    /// The shortcut for potential contact `i` of `model`, if it is a circle's boundary
    /// against a line without ends.
    pub(crate) fn new(model: &Model, i: usize) -> Option<Self> {
        let contact = &model.contacts()[i];
        let instance = &model.shapes()[contact.shape];
        let (Shape::Circle { center, radius }, ShapeFeature::Smooth) =
            (&instance.shape, contact.feature)
        else {
            return None;
        };
        let line = *model.terrain().features.get(contact.terrain)?;
        match line {
            TerrainFeature::Line {
                normal, from, to, ..
            } if !(from.is_finite() || to.is_finite()) => Some(Self {
                body: instance.body,
                center: *center,
                radius: *radius,
                normal,
                line,
            }),
            _ => None,
        }
    }

    /// The contact's geometry with the body at `position`, turned by `rotation`.
    #[inline]
    pub(crate) fn geometry(&self, position: Vec2, rotation: Rotation) -> Option<ContactGeometry> {
        let c = position + rotation.apply(self.center);
        point_against_line(c - self.radius * self.normal, &self.line)
    }
}

/// Whether a point behind a line feature (`g_N < 0`) is that line's contact. The solid
/// behind a convex corner is split by the corner's bisector: a point deeper behind this
/// line than behind the corner's other face belongs to that face. Without this test a
/// vertex resting on a step's top would also touch the step's face, whose line extends
/// behind it (and hold the vertex from sliding across). Corners and points in front of
/// the line are always kept.
#[inline]
fn owned_by_line(
    geometry: &ContactGeometry,
    terrain: &TerrainFeature,
    features: &[TerrainFeature],
) -> bool {
    let TerrainFeature::Line {
        origin,
        normal,
        from,
        to,
    } = terrain
    else {
        return true;
    };
    if !(from.is_finite() || to.is_finite()) {
        // A line without ends meets no corner.
        return true;
    }
    let tangent = TerrainFeature::tangent(*normal);
    for end in [*from, *to].into_iter().filter(|s| s.is_finite()) {
        let end = origin + end * tangent;
        for corner in features {
            let TerrainFeature::Corner {
                point,
                normal_first,
                normal_last,
            } = corner
            else {
                continue;
            };
            if (point - end).norm() > 1e-9 * (1.0 + end.norm()) {
                continue;
            }
            // The corner's other face: the normal of the cone further from this line's.
            let other = if normal_first.dot(normal) < normal_last.dot(normal) {
                normal_first
            } else {
                normal_last
            };
            if geometry.gap < (geometry.point - point).dot(other) {
                return false;
            }
        }
    }
    true
}

/// The geometry of `feature` against one terrain feature, without the ownership test.
#[inline]
fn feature_geometry(
    shape: &Shape,
    feature: ShapeFeature,
    position: Vec2,
    rotation: Rotation,
    terrain: &TerrainFeature,
) -> Option<ContactGeometry> {
    let to_world = |p: Vec2| position + rotation.apply(p);
    match (feature, terrain) {
        (ShapeFeature::Vertex(k), TerrainFeature::Line { normal, .. }) => {
            // A capsule's corner is the disc of its end cap: its lowest point touches.
            let vertex = to_world(shape.vertex(k)?);
            point_against_line(vertex - shape.vertex_radius() * normal, terrain)
        }
        (ShapeFeature::Vertex(_), TerrainFeature::Corner { .. }) => None,
        (ShapeFeature::Smooth, _) => smooth_geometry(shape, position, rotation, terrain),
        (
            ShapeFeature::Edges,
            TerrainFeature::Corner {
                point,
                normal_first,
                normal_last,
            },
        ) => {
            let local = rotation.inverse(point - position);
            let (gap, closest, outward) = sided_signed_distance(shape, local)?;
            corner_contact(
                gap,
                to_world(closest),
                -rotation.apply(outward),
                *normal_first,
                *normal_last,
            )
        }
        (ShapeFeature::Edges, TerrainFeature::Line { .. }) => None,
    }
}

/// A corner contact with the body's `normal` (terrain towards body) if that normal lies in
/// the corner's normal cone; outside it the corner's lines carry the contact.
fn corner_contact(
    gap: f64,
    point: Vec2,
    normal: Vec2,
    first: Vec2,
    last: Vec2,
) -> Option<ContactGeometry> {
    in_cone(normal, first, last).then_some(ContactGeometry { gap, point, normal })
}

#[inline]
fn smooth_geometry(
    shape: &Shape,
    position: Vec2,
    rotation: Rotation,
    terrain: &TerrainFeature,
) -> Option<ContactGeometry> {
    match (shape, terrain) {
        (Shape::Circle { center, radius } | Shape::Arc { center, radius, .. }, _) => {
            let c = position + rotation.apply(*center);
            let normal = match terrain {
                TerrainFeature::Line { normal, .. } => *normal,
                TerrainFeature::Corner {
                    point,
                    normal_first,
                    normal_last,
                } => {
                    let d = c - point;
                    let n = d.try_normalize(1e-15)?;
                    in_cone(n, *normal_first, *normal_last).then_some(n)?
                }
            };
            if !shape.covers_direction(rotation.inverse(-normal)) {
                return None;
            }
            let point = c - *radius * normal;
            match terrain {
                TerrainFeature::Line { .. } => point_against_line(point, terrain),
                TerrainFeature::Corner { point: corner, .. } => Some(ContactGeometry {
                    gap: (c - corner).norm() - radius,
                    point,
                    normal,
                }),
            }
        }
        (
            Shape::Ellipse {
                center,
                semi_x,
                semi_y,
            },
            TerrainFeature::Line { normal, .. },
        ) => {
            // Support point of the ellipse in the direction -n (body frame).
            let d = rotation.inverse(-normal);
            let scaled = Vec2::new(semi_x * semi_x * d.x, semi_y * semi_y * d.y);
            let support = scaled / (d.x * scaled.x + d.y * scaled.y).sqrt();
            point_against_line(position + rotation.apply(center + support), terrain)
        }
        (
            Shape::Ellipse {
                center,
                semi_x,
                semi_y,
            },
            TerrainFeature::Corner {
                point,
                normal_first,
                normal_last,
            },
        ) => {
            let local = rotation.inverse(point - position) - center;
            let p = closest_point_on_ellipse(*semi_x, *semi_y, local);
            corner_contact(
                p.signed_distance,
                position + rotation.apply(center + p.point),
                -rotation.apply(p.normal),
                *normal_first,
                *normal_last,
            )
        }
        _ => None,
    }
}

/// Signed distance of the body-frame point `c` from a polygon or a capsule (`< 0`
/// inside), the closest boundary point and the unit outward normal there; `None` for the
/// other shapes and where the distance has no direction (see
/// [`polygon_signed_distance`], [`capsule_signed_distance`]).
#[inline]
pub(crate) fn sided_signed_distance(shape: &Shape, c: Vec2) -> Option<(f64, Vec2, Vec2)> {
    match shape {
        Shape::Polygon { vertices } => polygon_signed_distance(vertices, c),
        Shape::Capsule { from, to, radius } => capsule_signed_distance(*from, *to, *radius, c),
        _ => None,
    }
}

/// Signed distance of point `c` to the convex counter-clockwise polygon `vertices` (`< 0`
/// inside), the closest boundary point and the unit outward normal there. `None` for a
/// degenerate polygon.
pub(crate) fn polygon_signed_distance(vertices: &[Vec2], c: Vec2) -> Option<(f64, Vec2, Vec2)> {
    let count = vertices.len();
    // Deepest-inside edge (largest signed distance to its line) and nearest boundary point.
    let mut best_edge: Option<(f64, Vec2, Vec2)> = None;
    let mut nearest: Option<(f64, Vec2)> = None;
    for (i, &v0) in vertices.iter().enumerate() {
        let v1 = vertices[(i + 1) % count];
        let e = v1 - v0;
        let length_sq = e.norm_squared();
        if length_sq == 0.0 {
            continue;
        }
        let outward = Vec2::new(e.y, -e.x) / length_sq.sqrt();
        let rel = c - v0;
        let s = outward.dot(&rel);
        if best_edge.is_none_or(|(best, _, _)| s > best) {
            best_edge = Some((s, c - s * outward, outward));
        }
        let t = (rel.dot(&e) / length_sq).clamp(0.0, 1.0);
        let p = v0 + t * e;
        let d_sq = (c - p).norm_squared();
        if nearest.is_none_or(|(best, _)| d_sq < best) {
            nearest = Some((d_sq, p));
        }
    }
    let (s, foot, outward) = best_edge?;
    if s <= 0.0 {
        // Inside (or on the boundary): the nearest edge line's foot lies on that edge.
        return Some((s, foot, outward));
    }
    let (d_sq, p) = nearest?;
    let d = d_sq.sqrt();
    // Outside: the normal points from the boundary to c; at d → 0 take the edge's normal.
    let normal = (c - p)
        .try_normalize(1e-12 * (1.0 + p.norm()))
        .unwrap_or(outward);
    Some((d, p, normal))
}

/// A world point against a line feature; `None` beyond the line's ends.
#[inline]
fn point_against_line(point: Vec2, terrain: &TerrainFeature) -> Option<ContactGeometry> {
    let TerrainFeature::Line {
        origin,
        normal,
        from,
        to,
    } = terrain
    else {
        return None;
    };
    let rel = point - origin;
    let s = rel.dot(&TerrainFeature::tangent(*normal));
    (s >= *from && s <= *to).then(|| ContactGeometry {
        gap: rel.dot(normal),
        point,
        normal: *normal,
    })
}

/// Whether unit `n` lies in the cone from `first` counter-clockwise to `last`.
fn in_cone(n: Vec2, first: Vec2, last: Vec2) -> bool {
    let cross = |a: Vec2, b: Vec2| a.x * b.y - a.y * b.x;
    cross(first, n) >= 0.0 && cross(n, last) >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Just outside a corner of a square, nearer than round-off of its coordinates, the
    /// direction from the corner means nothing: the normal is the nearest edge's; a little
    /// farther it is the direction from the corner.
    #[test]
    fn the_normal_at_a_polygon_corner_falls_back_to_an_edge() {
        let square = [
            Vec2::new(-0.5, -0.5),
            Vec2::new(0.5, -0.5),
            Vec2::new(0.5, 0.5),
            Vec2::new(-0.5, 0.5),
        ];
        let diagonal = Vec2::new(1.0, 1.0).normalize();
        let corner = Vec2::new(0.5, 0.5);
        let (d, p, normal) = polygon_signed_distance(&square, corner + 1e-12 * diagonal).unwrap();
        assert!(d > 0.0 && d < 2e-12);
        assert_eq!(p, corner);
        assert!(
            normal == Vec2::new(1.0, 0.0) || normal == Vec2::new(0.0, 1.0),
            "{normal:?}"
        );
        let (_, _, normal) = polygon_signed_distance(&square, corner + 1e-6 * diagonal).unwrap();
        assert!((normal - diagonal).norm() < 1e-9, "{normal:?}");
    }
}
