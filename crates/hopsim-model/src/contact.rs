//! Contact kinematics: the gap `g_N` and the contact frame of every potential contact
//! between a body's shape and a terrain feature (physics.md §1, §2).

use crate::{perp, rotate, Shape, TerrainFeature, Vec2};

/// Friction and restitution of one contact (physics.md §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactMaterial {
    /// Coulomb friction coefficient `μ` (≥ 0).
    pub friction: f64,
    /// Normal restitution `ε_N` (0 inelastic … 1 elastic).
    pub restitution_normal: f64,
    /// Tangential restitution `ε_T`.
    pub restitution_tangent: f64,
}

impl Default for ContactMaterial {
    fn default() -> Self {
        Self {
            friction: 1.0,
            restitution_normal: 0.0,
            restitution_tangent: 0.0,
        }
    }
}

/// Which part of a shape a contact candidate uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeFeature {
    /// The smooth boundary of a circle, arc or ellipse.
    Smooth,
    /// The shape's `k`-th vertex (see [`Shape::vertices`]).
    Vertex(usize),
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

/// Gap and contact frame of `feature` of `shape` (on a body at `position`, `angle`)
/// against `terrain`, or `None` when the pair cannot touch there (the closest point lies
/// beyond the end of a line, outside a corner's normal cone, or off an arc).
pub fn contact_geometry(
    shape: &Shape,
    feature: ShapeFeature,
    position: Vec2,
    angle: f64,
    terrain: &TerrainFeature,
) -> Option<ContactGeometry> {
    let to_world = |p: Vec2| position + rotate(angle, p);
    match (feature, terrain) {
        (ShapeFeature::Vertex(k), TerrainFeature::Line { .. }) => {
            let vertex = shape.vertex(k)?;
            point_against_line(to_world(vertex), terrain)
        }
        (ShapeFeature::Vertex(_), TerrainFeature::Corner { .. }) => None,
        (ShapeFeature::Smooth, _) => smooth_geometry(shape, position, angle, terrain),
    }
}

fn smooth_geometry(
    shape: &Shape,
    position: Vec2,
    angle: f64,
    terrain: &TerrainFeature,
) -> Option<ContactGeometry> {
    match (shape, terrain) {
        (Shape::Circle { center, radius } | Shape::Arc { center, radius, .. }, _) => {
            let c = position + rotate(angle, *center);
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
            if !shape.covers_direction(rotate(-angle, -normal)) {
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
            let d = rotate(-angle, -normal);
            let scaled = Vec2::new(semi_x * semi_x * d.x, semi_y * semi_y * d.y);
            let support = scaled / (d.x * scaled.x + d.y * scaled.y).sqrt();
            point_against_line(position + rotate(angle, center + support), terrain)
        }
        _ => None,
    }
}

/// A world point against a line feature; `None` beyond the line's ends.
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

/// The velocity direction of the body's material point at world offset `r` from the
/// centre of mass, for a unit rotation rate: `ω × r`.
pub(crate) fn lever(r: Vec2) -> Vec2 {
    perp(r)
}
