//! Drawing geometry shared by the recorders: shape outlines, terrain pieces and how far
//! they are drawn, series colours, units of the generalised coordinates.

use crate::RecordingInfo;
use hopsim_model::{Shape, Terrain, TerrainFeature, Vec2};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// A planar point, m.
pub(crate) type Point = [f64; 2];

/// Unit of a generalised coordinate (docs/physics.md §7.1): metres for a floating base's
/// `x`, `y` and a prismatic joint's extension, radians for every angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordinateUnit {
    Metre,
    Radian,
}

impl CoordinateUnit {
    /// Unit suffix of the coordinate, e.g. `m`.
    pub fn position(self) -> &'static str {
        match self {
            Self::Metre => "m",
            Self::Radian => "rad",
        }
    }

    /// Unit suffix of its velocity, e.g. `m_s` for m/s.
    pub fn velocity(self) -> &'static str {
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
            Shape::Capsule { from, to, radius } => {
                // Half a turn about each end, joined by the two straight sides.
                let turn = (to - from).y.atan2((to - from).x) - FRAC_PI_2;
                let mut points = around([to.x, to.y], *radius, *radius, turn, turn + PI);
                points.extend(around(
                    [from.x, from.y],
                    *radius,
                    *radius,
                    turn + PI,
                    turn + TAU,
                ));
                points.push(points[0]);
                Self::Strip(points)
            }
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

/// What is drawn of each body (in its frame) and the size of the robot.
pub(crate) struct RobotShapes {
    /// Per body (order of `RecordingInfo::bodies`): its shapes' outlines.
    pub(crate) outlines: Vec<Vec<Outline>>,
    /// Per body: length of a body-fixed spoke along its x axis that shows its rotation, m
    /// (the body's reach, or half the robot's size for a body without shapes).
    pub(crate) spokes_m: Vec<f64>,
    /// Size of the robot: the largest reach of a shape from its body's centre of mass, m
    /// (0.1 m for a robot without shapes).
    pub(crate) size_m: f64,
}

impl RobotShapes {
    pub(crate) fn of(info: &RecordingInfo) -> Self {
        let outlines: Vec<Vec<Outline>> = info
            .bodies
            .iter()
            .map(|b| b.shapes.iter().map(|(_, s)| Outline::of(s)).collect())
            .collect();
        let reach: Vec<f64> = outlines
            .iter()
            .map(|o| o.iter().map(Outline::reach).fold(0.0, f64::max))
            .collect();
        let largest = reach.iter().copied().fold(0.0, f64::max);
        let size_m = if largest > 0.0 { largest } else { 0.1 };
        let spokes_m = reach
            .into_iter()
            .map(|r| if r > 0.0 { r } else { 0.5 * size_m })
            .collect();
        Self {
            outlines,
            spokes_m,
            size_m,
        }
    }
}

/// The stretch of terrain drawn so far: it grows ahead of the robot, geometrically, so
/// that it is drawn again rarely however far the robot goes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TerrainCover {
    /// Abscissae covered, m (empty before the first [`TerrainCover::cover`]).
    pub(crate) range: (f64, f64),
    /// How far beyond the robot the terrain reaches at least, m.
    margin: f64,
}

impl TerrainCover {
    /// Nothing covered yet, for a robot of size `robot_size_m`: a few robot sizes around it
    /// (a viewer fits what it shows, so a long terrain line would shrink the robot to a dot).
    pub(crate) fn new(robot_size_m: f64) -> Self {
        Self {
            range: (f64::INFINITY, f64::NEG_INFINITY),
            margin: (3.0 * robot_size_m).max(0.5),
        }
    }

    /// Widens the range so that it reaches well beyond `x` on both sides; true if it
    /// changed (and must be drawn again).
    pub(crate) fn cover(&mut self, x: f64) -> bool {
        if !x.is_finite() {
            return false;
        }
        let margin = self.margin;
        let (lo, hi) = self.range;
        if lo.is_finite() && x - lo >= 0.5 * margin && hi - x >= 0.5 * margin {
            return false;
        }
        let width = if lo.is_finite() { hi - lo } else { 0.0 };
        self.range = if !lo.is_finite() {
            (x - margin, x + margin)
        } else if x - lo < 0.5 * margin {
            (x - margin.max(width), hi)
        } else {
            (lo, x + margin.max(width))
        };
        true
    }
}

/// Colours of bodies and of the series of one plot, by index (cycled): the Tableau 10
/// palette, whose neighbours differ clearly in hue.
pub(crate) const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// Colour `index` of [`PALETTE`] (cycled).
pub(crate) fn palette(index: usize) -> [u8; 3] {
    PALETTE[index % PALETTE.len()]
}

/// Colour of inactive shapes (a retracted cane).
pub(crate) const INACTIVE_COLOR: [u8; 3] = [170, 170, 170];

/// Colour of the terrain.
pub(crate) const TERRAIN_COLOR: [u8; 3] = [90, 90, 90];
/// A prismatic joint's rail (the extensions it may take), drawn in its parent's frame.
pub(crate) const RAIL_COLOR: [u8; 3] = [150, 150, 150];

/// `angle` wrapped to (−π, π], rad (the Rerun recorder's panels).
#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
pub(crate) fn wrap_angle(angle: f64) -> f64 {
    use std::f64::consts::PI;
    let wrapped = angle - TAU * (angle / TAU).round();
    if wrapped <= -PI {
        wrapped + TAU
    } else {
        wrapped
    }
}

/// The terrain between abscissae `x_lo` and `x_hi`: line pieces as segments (infinite
/// pieces cut to the range) and corner points. A piece not crossing the range in `x`
/// (a vertical step face) is kept when its ends lie within it.
/// The parameters in `(s0, s1)` where the line `origin + s t` crosses the terrain's other
/// lines.
fn crossings(terrain: &Terrain, origin: Vec2, t: Vec2, s0: f64, s1: f64) -> Vec<f64> {
    terrain
        .features
        .iter()
        .filter_map(|f| match f {
            TerrainFeature::Line {
                origin: o, normal, ..
            } => {
                // (origin + s t − o) · n = 0.
                let rate = t.dot(normal);
                (rate.abs() > 1e-12).then(|| (o - origin).dot(normal) / rate)
            }
            TerrainFeature::Corner { .. } => None,
        })
        .filter(|s| *s > s0 && *s < s1)
        .collect()
}

pub(crate) fn terrain_pieces(
    terrain: &Terrain,
    x_lo: f64,
    x_hi: f64,
) -> (Vec<[Point; 2]>, Vec<Point>) {
    let mut segments = Vec::new();
    let mut corners = Vec::new();
    for (index, feature) in terrain.features.iter().enumerate() {
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
                    // Split where other lines cross it; draw the pieces on the surface.
                    let mut cuts = vec![s0, s1];
                    cuts.extend(crossings(terrain, *origin, t, s0, s1));
                    cuts.sort_by(f64::total_cmp);
                    for piece in cuts.windows(2).filter(|w| w[1] > w[0]) {
                        let middle = *origin + 0.5 * (piece[0] + piece[1]) * t;
                        if !terrain.hides(middle, index) {
                            segments.push([at(piece[0]), at(piece[1])]);
                        }
                    }
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

    /// A capsule's outline is closed, every point lies at its radius from the segment,
    /// and it reaches the far end of a cap.
    #[test]
    fn capsule_outline_is_closed_and_at_its_radius_from_the_segment() {
        let (from, to, radius) = (Vec2::new(-0.1, 0.05), Vec2::new(0.3, -0.1), 0.04);
        let Outline::Strip(points) = Outline::of(&Shape::Capsule { from, to, radius }) else {
            panic!("a capsule is a strip")
        };
        assert!(close(points[0], *points.last().unwrap()));
        let e = to - from;
        for p in &points {
            let p = Vec2::new(p[0], p[1]);
            let t = ((p - from).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
            assert!(((p - (from + t * e)).norm() - radius).abs() < 1e-12);
        }
        let reach = to.norm() + radius;
        let drawn = Outline::of(&Shape::Capsule { from, to, radius }).reach();
        assert!(
            drawn <= reach + 1e-12 && reach - drawn < 1e-3,
            "{drawn} vs {reach}"
        );
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
    fn wrapped_angles_lie_in_the_half_open_interval_and_keep_sin_and_cos() {
        use std::f64::consts::PI;
        assert_eq!(wrap_angle(PI), PI);
        assert_eq!(wrap_angle(-PI), PI);
        for k in -2000_i32..2000 {
            let a = 0.0137 * f64::from(k * k.abs());
            let w = wrap_angle(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
            // Round-off of a - 2πn grows with |a|: a few ulps of |a|.
            let tol = 8.0 * f64::EPSILON * a.abs().max(1.0);
            assert!((w.sin() - a.sin()).abs() < tol && (w.cos() - a.cos()).abs() < tol);
        }
    }

    #[test]
    fn terrain_coverage_grows_ahead_of_the_robot_and_rarely() {
        let mut cover = TerrainCover::new(0.1);
        assert!(cover.cover(0.0));
        let (lo, hi) = cover.range;
        assert!(lo <= -0.5 && hi >= 0.5);
        assert!(!cover.cover(0.1), "well inside: no redraw");
        assert!(!cover.cover(f64::NAN));
        let redraws = (0..10_000)
            .filter(|&k| cover.cover(k as f64 * 1e-2))
            .count();
        assert!(redraws <= 10, "{redraws} redraws over 100 m");
        assert!(cover.range.1 >= 100.0 && cover.range.0 <= -0.5);
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
