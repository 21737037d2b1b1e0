//! Whether two planar shapes overlap: each is a convex core (a point, a segment, a convex
//! polygon; an ellipse as an inscribed 64-gon) swollen by a radius, and two overlap when
//! their cores are closer than the sum of the radii.

use crate::model::{Shape, Vec2};

/// Overlaps shallower than this are contact, not overlap, m.
const TOUCH: f64 = 1e-9;

/// Whether the shapes' interiors overlap (lines overlap nothing).
pub(crate) fn overlap(a: &Shape, b: &Shape) -> bool {
    let (Some((ca, ra)), Some((cb, rb))) = (core(a), core(b)) else {
        return false;
    };
    distance(&ca, &cb) < ra + rb - TOUCH
}

/// The convex core's corners (counter-clockwise) and the radius about it.
fn core(shape: &Shape) -> Option<(Vec<Vec2>, f64)> {
    match shape {
        Shape::Circle { center, radius } => Some((vec![*center], *radius)),
        Shape::Capsule { a, b, radius } => Some((vec![*a, *b], *radius)),
        Shape::Polygon { vertices } => Some((vertices.clone(), 0.0)),
        Shape::Ellipse {
            center,
            semi_axes,
            angle,
        } => {
            let (s, c) = angle.sin_cos();
            let corners = (0..64)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / 64.0;
                    let (x, y) = (semi_axes[0] * t.cos(), semi_axes[1] * t.sin());
                    center + Vec2::new(c * x - s * y, s * x + c * y)
                })
                .collect();
            Some((corners, 0.0))
        }
        Shape::Line { .. } => None,
    }
}

/// The distance between two convex cores (0 when they meet).
fn distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    let edges = |p: &[Vec2]| -> Vec<(Vec2, Vec2)> {
        match p.len() {
            1 => vec![(p[0], p[0])],
            2 => vec![(p[0], p[1])],
            n => (0..n).map(|i| (p[i], p[(i + 1) % n])).collect(),
        }
    };
    let (ea, eb) = (edges(a), edges(b));
    let crossing = ea
        .iter()
        .any(|&(p, q)| eb.iter().any(|&(r, s)| segments_cross(p, q, r, s)));
    if crossing || a.iter().any(|p| inside(b, *p)) || b.iter().any(|p| inside(a, *p)) {
        return 0.0;
    }
    let to_edges = |points: &[Vec2], edges: &[(Vec2, Vec2)]| {
        points
            .iter()
            .flat_map(|p| edges.iter().map(move |&(r, s)| point_segment(*p, r, s)))
            .fold(f64::INFINITY, f64::min)
    };
    to_edges(a, &eb).min(to_edges(b, &ea))
}

fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Whether the segments `p`–`q` and `r`–`s` share a point (touching included).
fn segments_cross(p: Vec2, q: Vec2, r: Vec2, s: Vec2) -> bool {
    let d1 = cross(s - r, p - r);
    let d2 = cross(s - r, q - r);
    let d3 = cross(q - p, r - p);
    let d4 = cross(q - p, s - p);
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    let on = |a: Vec2, b: Vec2, c: Vec2, d: f64| d == 0.0 && point_segment(c, a, b) == 0.0;
    on(r, s, p, d1) || on(r, s, q, d2) || on(p, q, r, d3) || on(p, q, s, d4)
}

/// Whether `p` lies inside the convex counter-clockwise polygon (three corners or more).
fn inside(polygon: &[Vec2], p: Vec2) -> bool {
    let n = polygon.len();
    n >= 3 && (0..n).all(|i| cross(polygon[(i + 1) % n] - polygon[i], p - polygon[i]) >= 0.0)
}

fn point_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let e = b - a;
    let length_sq = e.norm_squared();
    let t = if length_sq == 0.0 {
        0.0
    } else {
        ((p - a).dot(&e) / length_sq).clamp(0.0, 1.0)
    };
    (p - (a + t * e)).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn capsule(a: [f64; 2], b: [f64; 2], radius: f64) -> Shape {
        Shape::Capsule {
            a: Vec2::new(a[0], a[1]),
            b: Vec2::new(b[0], b[1]),
            radius,
        }
    }

    /// Closed forms: parallel capsules overlap when their axes are closer than the radii;
    /// crossing capsules always; a disc beside a square by its distance to the face; a
    /// disc inside a square.
    #[test]
    fn overlaps_by_the_distance_of_the_cores() {
        let rod = capsule([-1.0, 0.0], [1.0, 0.0], 0.1);
        assert!(overlap(&rod, &capsule([-1.0, 0.19], [1.0, 0.19], 0.1)));
        assert!(!overlap(&rod, &capsule([-1.0, 0.21], [1.0, 0.21], 0.1)));
        assert!(overlap(&rod, &capsule([0.0, -1.0], [0.0, 1.0], 0.01)));
        let square = Shape::Polygon {
            vertices: [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| Vec2::new(x, y))
                .to_vec(),
        };
        let disc = |x: f64, r: f64| Shape::Circle {
            center: Vec2::new(x, 0.3),
            radius: r,
        };
        assert!(overlap(&square, &disc(1.4, 0.41)));
        assert!(!overlap(&square, &disc(1.4, 0.39)));
        assert!(overlap(&square, &disc(0.0, 0.01)));
        // Touching is contact, not overlap.
        assert!(!overlap(&square, &disc(1.5, 0.5)));
    }
}
