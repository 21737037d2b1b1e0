//! Contact shapes fixed to bodies, in body-frame coordinates relative to the centre of mass.

use crate::Vec2;

/// A contact shape in its body's frame (origin at the body's centre of mass, m and rad).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A disc of `radius` centred at `center`; an eccentric disc has `center = (0, a)`
    /// so that its centre sits at `CoM + (-a sin φ, a cos φ)` (docs/physics.md §2).
    Circle { center: Vec2, radius: f64 },
    /// The circular arc of `radius` about `center` spanning the body-frame angles
    /// `start ..= end` (counter-clockwise, `end > start`): a curved foot (§5.4).
    Arc {
        center: Vec2,
        radius: f64,
        start: f64,
        end: f64,
    },
    /// An ellipse with semi-axes `semi_x`, `semi_y` along the body axes (§5.3 variants).
    Ellipse {
        center: Vec2,
        semi_x: f64,
        semi_y: f64,
    },
    /// A single contact point, e.g. a cane tip (§5.4).
    Point { position: Vec2 },
    /// A convex polygon, vertices counter-clockwise (the cube baseline of §5.3).
    Polygon { vertices: Vec<Vec2> },
    /// The points within `radius` of the segment `from`–`to` (a rod with round ends,
    /// MuJoCo's capsule in its plane). Its two end caps are its corners (discs of
    /// `radius` about `from` and `to`, [`Shape::vertex_radius`]); its segment meets
    /// terrain corners and other bodies (docs/physics.md §2, §7).
    Capsule { from: Vec2, to: Vec2, radius: f64 },
}

impl Shape {
    /// An axis-aligned rectangle (a polygon) centred at `center` in the body frame, with
    /// its vertices counter-clockwise from the lower left.
    pub fn rectangle(center: Vec2, half_width: f64, half_height: f64) -> Self {
        let (w, h) = (half_width, half_height);
        Shape::Polygon {
            vertices: [(-w, -h), (w, -h), (w, h), (-w, h)]
                .map(|(x, y)| center + Vec2::new(x, y))
                .to_vec(),
        }
    }

    /// Number of corner points that can touch the terrain on their own (polygon
    /// vertices, the two arc end points, the point itself, a capsule's two end centres).
    pub fn vertex_count(&self) -> usize {
        match self {
            Shape::Circle { .. } | Shape::Ellipse { .. } => 0,
            Shape::Arc { .. } | Shape::Capsule { .. } => 2,
            Shape::Point { .. } => 1,
            Shape::Polygon { vertices } => vertices.len(),
        }
    }

    /// The `k`-th corner point in the body frame (see [`Shape::vertex_count`]).
    pub fn vertex(&self, k: usize) -> Option<Vec2> {
        match self {
            Shape::Circle { .. } | Shape::Ellipse { .. } => None,
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => {
                let a = [*start, *end].get(k).copied()?;
                Some(center + *radius * Vec2::new(a.cos(), a.sin()))
            }
            Shape::Point { position } => (k == 0).then_some(*position),
            Shape::Polygon { vertices } => vertices.get(k).copied(),
            Shape::Capsule { from, to, .. } => [*from, *to].get(k).copied(),
        }
    }

    /// The radius of the disc about each corner point: a capsule's radius (its end caps),
    /// 0 for the sharp corners of the other shapes.
    #[inline]
    pub fn vertex_radius(&self) -> f64 {
        match self {
            Shape::Capsule { radius, .. } => *radius,
            _ => 0.0,
        }
    }

    /// Whether the shape has a smooth curved boundary (circle, arc, ellipse).
    pub fn is_smooth(&self) -> bool {
        matches!(
            self,
            Shape::Circle { .. } | Shape::Arc { .. } | Shape::Ellipse { .. }
        )
    }

    /// Whether the body-frame direction `dir` (from the shape's centre) falls on the
    /// shape's boundary: always for closed curves, inside `start ..= end` for an arc.
    #[inline]
    pub fn covers_direction(&self, dir: Vec2) -> bool {
        match self {
            Shape::Arc { start, end, .. } => {
                let two_pi = std::f64::consts::TAU;
                let angle = dir.y.atan2(dir.x);
                let offset = (angle - start).rem_euclid(two_pi);
                offset <= (end - start)
            }
            _ => true,
        }
    }
}

/// A shape attached to one body of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeInstance {
    /// Name used in records and viewers.
    pub name: String,
    /// Index of the body carrying the shape.
    pub body: usize,
    /// The geometry in the body frame.
    pub shape: Shape,
}
