//! Drawing geometry shared by the recorders: shape outlines, terrain pieces, units of the
//! generalised coordinates.

use crate::BodyPose;
use hopsim_model::{Shape, Terrain, TerrainFeature};
use std::f64::consts::TAU;

/// A planar point, m.
pub(crate) type Point = [f64; 2];

/// Unit of a generalised coordinate. `q = (x, y, φ, θ_1, …)` (docs/architecture.md): the
/// base's centre of mass in metres, then angles in radians (docs/physics.md §1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CoordinateUnit {
    Metre,
    Radian,
}

impl CoordinateUnit {
    /// The unit of coordinate `index`.
    pub(crate) fn of(index: usize) -> Self {
        if index < 2 {
            Self::Metre
        } else {
            Self::Radian
        }
    }

    /// Unit suffix of the coordinate, e.g. `m`.
    pub(crate) fn position(self) -> &'static str {
        match self {
            Self::Metre => "m",
            Self::Radian => "rad",
        }
    }

    /// Unit suffix of its velocity, e.g. `m_s` for m/s.
    pub(crate) fn velocity(self) -> &'static str {
        match self {
            Self::Metre => "m_s",
            Self::Radian => "rad_s",
        }
    }
}

/// How a shape is drawn, in its body's frame.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Outline {
    /// A polyline (closed for circles, ellipses and polygons).
    Strip(Vec<Point>),
    /// A single point (a cane tip).
    Marker(Point),
}

/// Segments of a full circle or ellipse outline.
const SEGMENTS_PER_TURN: usize = 64;

impl Outline {
    /// The outline of `shape` (body frame, relative to the body's centre of mass).
    pub(crate) fn of(shape: &Shape) -> Self {
        let around = |center: Point, rx: f64, ry: f64, start: f64, end: f64| -> Vec<Point> {
            let n = ((SEGMENTS_PER_TURN as f64 * (end - start).abs() / TAU).ceil() as usize)
                .clamp(8, SEGMENTS_PER_TURN);
            (0..=n)
                .map(|k| {
                    let a = start + (end - start) * k as f64 / n as f64;
                    [center[0] + rx * a.cos(), center[1] + ry * a.sin()]
                })
                .collect()
        };
        match shape {
            Shape::Circle { center, radius } => {
                Self::Strip(around([center.x, center.y], *radius, *radius, 0.0, TAU))
            }
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => Self::Strip(around([center.x, center.y], *radius, *radius, *start, *end)),
            Shape::Ellipse {
                center,
                semi_x,
                semi_y,
            } => Self::Strip(around([center.x, center.y], *semi_x, *semi_y, 0.0, TAU)),
            Shape::Point { position } => Self::Marker([position.x, position.y]),
            Shape::Polygon { vertices } => Self::Strip(
                vertices
                    .iter()
                    .chain(vertices.first())
                    .map(|v| [v.x, v.y])
                    .collect(),
            ),
        }
    }

    /// Largest distance of the outline from the body's centre of mass, m.
    pub(crate) fn reach(&self) -> f64 {
        let norm = |p: &Point| p[0].hypot(p[1]);
        match self {
            Self::Strip(points) => points.iter().map(norm).fold(0.0, f64::max),
            Self::Marker(p) => norm(p),
        }
    }
}

/// `p` (body frame) in world coordinates for a body at `pose`.
pub(crate) fn to_world(pose: &BodyPose, p: Point) -> Point {
    let (s, c) = pose.angle.sin_cos();
    [
        pose.position[0] + c * p[0] - s * p[1],
        pose.position[1] + s * p[0] + c * p[1],
    ]
}

/// The terrain between abscissae `x_lo` and `x_hi`: line pieces as segments (infinite
/// pieces cut to the range) and corner points. A piece not crossing the range in `x`
/// (a vertical step face) is kept when its ends lie within it.
pub(crate) fn terrain_pieces(
    terrain: &Terrain,
    x_lo: f64,
    x_hi: f64,
) -> (Vec<[Point; 2]>, Vec<Point>) {
    let mut segments = Vec::new();
    let mut corners = Vec::new();
    for feature in &terrain.features {
        match feature {
            TerrainFeature::Line {
                origin,
                normal,
                from,
                to,
            } => {
                let t = TerrainFeature::tangent(*normal);
                // Parameter range of the piece whose points have x in [x_lo, x_hi].
                let (s_lo, s_hi) = if t.x.abs() > 1e-12 {
                    let (a, b) = ((x_lo - origin.x) / t.x, (x_hi - origin.x) / t.x);
                    (a.min(b), a.max(b))
                } else if (x_lo..=x_hi).contains(&origin.x) {
                    let span = x_hi - x_lo;
                    (-span, span)
                } else {
                    continue;
                };
                let (s0, s1) = (from.max(s_lo), to.min(s_hi));
                if s0 < s1 {
                    let at = |s: f64| [origin.x + s * t.x, origin.y + s * t.y];
                    segments.push([at(s0), at(s1)]);
                }
            }
            TerrainFeature::Corner { point, .. } => {
                if (x_lo..=x_hi).contains(&point.x) {
                    corners.push([point.x, point.y]);
                }
            }
        }
    }
    (segments, corners)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopsim_model::Vec2;

    fn close(a: Point, b: Point) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn circle_outline_is_closed_and_on_the_circle() {
        let shape = Shape::Circle {
            center: Vec2::new(0.0, 0.1),
            radius: 0.2,
        };
        let Outline::Strip(points) = Outline::of(&shape) else {
            panic!("a circle is a strip")
        };
        assert!(close(points[0], *points.last().unwrap()));
        for p in &points {
            assert!(((p[0]).hypot(p[1] - 0.1) - 0.2).abs() < 1e-12);
        }
        assert!((Outline::of(&shape).reach() - 0.3).abs() < 1e-3);
    }

    #[test]
    fn arc_outline_spans_its_angles_and_points_are_markers() {
        let shape = Shape::Arc {
            center: Vec2::zeros(),
            radius: 1.0,
            start: -std::f64::consts::FRAC_PI_2,
            end: 0.0,
        };
        let Outline::Strip(points) = Outline::of(&shape) else {
            panic!("an arc is a strip")
        };
        assert!(close(points[0], [0.0, -1.0]));
        assert!(close(*points.last().unwrap(), [1.0, 0.0]));
        let point = Shape::Point {
            position: Vec2::new(0.1, -0.2),
        };
        assert_eq!(Outline::of(&point), Outline::Marker([0.1, -0.2]));
    }

    #[test]
    fn body_points_rotate_with_the_body() {
        let pose = BodyPose {
            position: [1.0, 2.0],
            angle: std::f64::consts::FRAC_PI_2,
        };
        assert!(close(to_world(&pose, [0.5, 0.0]), [1.0, 2.5]));
    }

    #[test]
    fn terrain_is_cut_to_the_range_and_a_step_keeps_its_face_and_edge() {
        let (segments, corners) = terrain_pieces(&Terrain::step(1.0, 0.1), -2.0, 3.0);
        assert_eq!(segments.len(), 3);
        assert!(close(segments[0][0], [-2.0, 0.0]) && close(segments[0][1], [1.0, 0.0]));
        let face = segments[1];
        assert!((face[0][0] - 1.0).abs() < 1e-12 && (face[1][0] - 1.0).abs() < 1e-12);
        assert!(close(segments[2][1], [3.0, 0.1]));
        assert_eq!(corners, vec![[1.0, 0.1]]);
        let (flat, _) = terrain_pieces(&Terrain::flat(0.0), 5.0, 6.0);
        assert!(close(flat[0][0], [5.0, 0.0]) && close(flat[0][1], [6.0, 0.0]));
    }
}
