//! The closest point on an ellipse to a given point, inside or outside.
//!
//! D. Eberly, "Distance from a point to an ellipse, an ellipsoid, or a hyperellipsoid"
//! (Geometric Tools, 2013): for semi-axes `e0 ≥ e1` and a point `y` in the first quadrant,
//! the closest point is `x_i = r_i y_i / (s + r_i)` (`r_0 = (e0/e1)²`, `r_1 = 1`) where `s`
//! is the unique root of the convex, decreasing
//!
//! ```text
//! F(s) = (r_0 z_0 / (s + r_0))² + (z_1 / (s + 1))² − 1,   z_i = y_i / e_i,
//! ```
//!
//! on `[z_1 − 1, |r_0 z_0, z_1| − 1]`. We find it by Newton's method from the left end
//! (monotone for a convex decreasing `F`) safeguarded by bisection, to round-off.
//! No closed form exists (the root of a quartic), and a support-map GJK query converges
//! only to a relative tolerance (~1e-7 in parry), so this is both exact and cheaper.

use crate::Vec2;

/// Where an ellipse's boundary is closest to a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EllipsePoint {
    /// The closest boundary point, in the ellipse's frame.
    pub point: Vec2,
    /// Unit outward normal of the ellipse at `point`.
    pub normal: Vec2,
    /// Distance to the boundary, negative inside the ellipse.
    pub signed_distance: f64,
}

/// The closest point on the ellipse `x²/a² + y²/b² = 1` to `y` (all in the ellipse's frame).
pub(crate) fn closest_point_on_ellipse(a: f64, b: f64, y: Vec2) -> EllipsePoint {
    // Reduce to e0 ≥ e1 and a point in the first quadrant, then map back.
    let swap = a < b;
    let (e0, e1, y0, y1) = if swap {
        (b, a, y.y, y.x)
    } else {
        (a, b, y.x, y.y)
    };
    let (x0, x1) = first_quadrant(e0, e1, y0.abs(), y1.abs());
    let (x0, x1) = (x0.copysign(y0), x1.copysign(y1));
    let (point, axes) = if swap {
        (Vec2::new(x1, x0), Vec2::new(e1, e0))
    } else {
        (Vec2::new(x0, x1), Vec2::new(e0, e1))
    };
    let gradient = Vec2::new(point.x / (axes.x * axes.x), point.y / (axes.y * axes.y));
    let normal = gradient.normalize();
    let inside = (y.x / axes.x).powi(2) + (y.y / axes.y).powi(2) < 1.0;
    let distance = (y - point).norm();
    EllipsePoint {
        point,
        normal,
        signed_distance: if inside { -distance } else { distance },
    }
}

/// Closest point for `e0 ≥ e1 > 0` and `y0, y1 ≥ 0` (Eberly's `DistancePointEllipse`).
fn first_quadrant(e0: f64, e1: f64, y0: f64, y1: f64) -> (f64, f64) {
    if y1 > 0.0 {
        if y0 > 0.0 {
            let (z0, z1) = (y0 / e0, y1 / e1);
            let g = z0 * z0 + z1 * z1 - 1.0;
            if g == 0.0 {
                return (y0, y1);
            }
            let r0 = (e0 / e1) * (e0 / e1);
            let s = root(r0, z0, z1, g);
            (r0 * y0 / (s + r0), y1 / (s + 1.0))
        } else {
            (0.0, e1)
        }
    } else {
        let (numer, denom) = (e0 * y0, e0 * e0 - e1 * e1);
        if numer < denom {
            let xde0 = numer / denom;
            (e0 * xde0, e1 * (1.0 - xde0 * xde0).max(0.0).sqrt())
        } else {
            (e0, 0.0)
        }
    }
}

/// The root `s` of `F` above (`g = F(0)`), to round-off.
fn root(r0: f64, z0: f64, z1: f64, g: f64) -> f64 {
    let n0 = r0 * z0;
    let f = |s: f64| {
        let (t0, t1) = (n0 / (s + r0), z1 / (s + 1.0));
        (
            t0 * t0 + t1 * t1 - 1.0,
            -2.0 * (t0 * t0 / (s + r0) + t1 * t1 / (s + 1.0)),
        )
    };
    // F(lo) ≥ 0 ≥ F(hi); s stays in [lo, hi].
    let mut lo = z1 - 1.0;
    let mut hi = if g < 0.0 { 0.0 } else { n0.hypot(z1) - 1.0 };
    let mut s = lo;
    for _ in 0..200 {
        let (value, slope) = f(s);
        if value == 0.0 {
            break;
        }
        if value > 0.0 {
            lo = s;
        } else {
            hi = s;
        }
        let newton = s - value / slope;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if next <= lo || next >= hi {
            // The bracket has shrunk to adjacent floating-point numbers.
            break;
        }
        s = next;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_gives_the_radial_point() {
        let p = closest_point_on_ellipse(2.0, 2.0, Vec2::new(3.0, 4.0));
        assert!((p.point - Vec2::new(1.2, 1.6)).norm() < 1e-14);
        assert!((p.signed_distance - 3.0).abs() < 1e-14);
        let p = closest_point_on_ellipse(2.0, 2.0, Vec2::new(0.3, -0.4));
        assert!((p.signed_distance + 1.5).abs() < 1e-14);
        assert!((p.normal - Vec2::new(0.6, -0.8)).norm() < 1e-14);
    }

    #[test]
    fn points_on_the_axes_and_at_the_centre() {
        let p = closest_point_on_ellipse(2.0, 1.0, Vec2::new(0.0, 3.0));
        assert_eq!((p.point, p.signed_distance), (Vec2::new(0.0, 1.0), 2.0));
        let p = closest_point_on_ellipse(2.0, 1.0, Vec2::new(0.0, 0.0));
        assert_eq!((p.point, p.signed_distance), (Vec2::new(0.0, 1.0), -1.0));
        let p = closest_point_on_ellipse(1.0, 2.0, Vec2::new(-5.0, 0.0));
        assert_eq!((p.point, p.signed_distance), (Vec2::new(-1.0, 0.0), 4.0));
    }

    /// Inside and outside, on the axes and off them, for both orientations: the point is
    /// on the ellipse, `y` lies on its normal line there, no point of a fine sampling of
    /// the ellipse is nearer, and the sign says inside.
    #[test]
    fn the_closest_point_is_the_nearest_of_the_ellipse() {
        let samples: usize = 20_000;
        for (a, b) in [(2.0_f64, 1.0_f64), (1.0, 2.0), (0.3, 0.25)] {
            let scale = a.max(b);
            for y in [
                (0.25, 0.0),
                (-0.4, 0.0),
                (0.0, 0.2),
                (0.0, -0.1),
                (0.3, 0.2),
                (-0.5, 0.1),
                (0.2, -0.6),
                (1.1, 0.9),
                (-2.0, 0.0),
                (0.0, 1.7),
                (1.5, -1.5),
            ] {
                let y = scale * Vec2::new(y.0, y.1);
                let p = closest_point_on_ellipse(a, b, y);
                let x = p.point;
                let on = (x.x / a).powi(2) + (x.y / b).powi(2);
                assert!(
                    (on - 1.0).abs() < 1e-12,
                    "{a}, {b}, {y:?}: {x:?} off the ellipse"
                );
                let d = y - x;
                assert!((d.norm() - p.signed_distance.abs()).abs() < 1e-14 * scale);
                let cross = d.x * p.normal.y - d.y * p.normal.x;
                assert!(
                    cross.abs() < 1e-12 * scale,
                    "{a}, {b}, {y:?}: not along the normal"
                );
                let nearest = (0..samples)
                    .map(|k| {
                        let t = k as f64 * std::f64::consts::TAU / samples as f64;
                        (Vec2::new(a * t.cos(), b * t.sin()) - y).norm()
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d.norm() <= nearest + 1e-12 * scale,
                    "{a}, {b}, {y:?}: {} farther than a sample at {nearest}",
                    d.norm()
                );
                let inside = (y.x / a).powi(2) + (y.y / b).powi(2) < 1.0;
                assert_eq!(p.signed_distance < 0.0, inside, "{a}, {b}, {y:?}");
            }
        }
    }
}
