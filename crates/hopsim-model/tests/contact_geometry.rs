//! Contact geometry against independent geometry (docs/physics.md §1-§2): an ellipse and a
//! convex polygon against a terrain corner, checked by dense sampling with Newton
//! refinement, by point-segment distances and by parry2d's GJK/EPA queries; and the
//! clearance of every shape above a step, from all its candidates together. The capsule:
//! against flat ground (its lowest point in closed form), against a corner (the distance
//! to its segment, and parry2d's capsule projection), its clearance above a step.

use hopsim_model::{ContactMaterial, Kinematics, Model, Shape, Terrain, TerrainFeature, Vec2};
use nalgebra::DVector;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::details::distance_support_map_support_map;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::{Ball, Capsule, ConvexPolygon, SupportMap};
use proptest::prelude::*;

mod common;
use common::{capsule, end_points};

fn model(shape: Shape, terrain: Terrain) -> Model {
    Model::single_body(1.0, 0.01, shape, terrain, ContactMaterial::default()).unwrap()
}

fn workspace(model: &Model, pose: [f64; 3]) -> Kinematics {
    let mut kinematics = Kinematics::new(model);
    kinematics.update(model, &DVector::from_row_slice(&pose), &DVector::zeros(3));
    kinematics
}

fn rotate(theta: f64, v: Vec2) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// A corner at the origin whose normal cone is `±half` around `axis`.
fn corner(axis: Vec2, half: f64) -> Terrain {
    Terrain {
        features: vec![TerrainFeature::Corner {
            point: Vec2::zeros(),
            normal_first: rotate(-half, axis),
            normal_last: rotate(half, axis),
        }],
    }
}

/// Signed distance from `p` to the ellipse boundary by dense sampling of the parameter
/// and Newton refinement of `|e(t) - p|²`; negative inside.
fn ellipse_reference(a: f64, b: f64, p: Vec2) -> f64 {
    let dist_sq = |t: f64| (a * t.cos() - p.x).powi(2) + (b * t.sin() - p.y).powi(2);
    let samples = 4096;
    let mut t = (0..samples)
        .map(|k| k as f64 * std::f64::consts::TAU / samples as f64)
        .min_by(|x, y| dist_sq(*x).total_cmp(&dist_sq(*y)))
        .unwrap();
    for _ in 0..30 {
        // f = ½ d/dt |e - p|², f' its derivative.
        let (s, c) = t.sin_cos();
        let (ex, ey) = (a * c - p.x, b * s - p.y);
        let f = -ex * a * s + ey * b * c;
        let df = a * a * s * s - ex * a * c + b * b * c * c - ey * b * s;
        if df <= 0.0 {
            break;
        }
        t -= f / df;
    }
    let d = dist_sq(t).sqrt();
    if (p.x / a).powi(2) + (p.y / b).powi(2) < 1.0 {
        -d
    } else {
        d
    }
}

/// An ellipse as a parry support map (the independent GJK reference).
struct EllipseSupport {
    a: f64,
    b: f64,
}

impl SupportMap for EllipseSupport {
    fn local_support_point(&self, dir: Vector) -> Vector {
        let scaled = Vector::new(self.a * self.a * dir.x, self.b * self.b * dir.y);
        scaled / (dir.x * scaled.x + dir.y * scaled.y).sqrt()
    }
}

fn convex_polygon() -> impl Strategy<Value = Vec<Vec2>> {
    // Points on an ellipse at sorted angles: convex and counter-clockwise.
    (
        prop::collection::vec(0.0..1.0f64, 3..8),
        0.05..0.3f64,
        0.05..0.3f64,
    )
        .prop_filter_map("well-spread vertices", |(mut fractions, a, b)| {
            fractions.sort_by(f64::total_cmp);
            let angles: Vec<f64> = fractions
                .iter()
                .map(|f| f * std::f64::consts::TAU)
                .collect();
            let gaps_ok = angles
                .windows(2)
                .map(|w| w[1] - w[0])
                .chain([angles[0] + std::f64::consts::TAU - angles[angles.len() - 1]])
                .all(|g| g > 0.2 && g < std::f64::consts::PI - 0.2);
            gaps_ok.then(|| {
                angles
                    .iter()
                    .map(|t| Vec2::new(a * t.cos(), b * t.sin()))
                    .collect()
            })
        })
}

/// Signed distance of `p` to a convex CCW polygon from point-segment distances.
fn polygon_reference(vertices: &[Vec2], p: Vec2) -> f64 {
    let n = vertices.len();
    let mut inside = true;
    let mut d = f64::INFINITY;
    for i in 0..n {
        let (v0, v1) = (vertices[i], vertices[(i + 1) % n]);
        let e = v1 - v0;
        inside &= e.x * (p - v0).y - e.y * (p - v0).x >= 0.0;
        let t = ((p - v0).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
        d = d.min((v0 + t * e - p).norm());
    }
    if inside {
        -d
    } else {
        d
    }
}

/// Checks the corner contact of `shape` at `pose` against the reference signed distance
/// `reference` (of the corner point to the shape, in the body frame): the gap, and that
/// the contact point lies `|gap|` from the corner along the normal.
fn check_corner(shape: Shape, pose: [f64; 3], reference: f64) -> Result<(), TestCaseError> {
    // Find the normal with eight cones covering every direction, then check the contact
    // in a cone around it and its absence in the opposite cone.
    let axis = (0..8)
        .find_map(|k| {
            let probe = model(
                shape.clone(),
                corner(
                    rotate(k as f64 * 0.25 * std::f64::consts::PI, Vec2::new(1.0, 0.0)),
                    0.4,
                ),
            );
            let kinematics = workspace(&probe, pose);
            (0..probe.contacts().len()).find_map(|i| probe.contact_geometry(&kinematics, i))
        })
        .map(|g| g.normal)
        .expect("some cone holds the normal");
    let m = model(shape.clone(), corner(axis, 0.2));
    let kinematics = workspace(&m, pose);
    let g = (0..m.contacts().len())
        .find_map(|i| m.contact_geometry(&kinematics, i))
        .expect("a corner contact inside the cone");
    prop_assert!(
        (g.gap - reference).abs() < 1e-9,
        "gap {} vs reference {reference}",
        g.gap
    );
    prop_assert!((g.normal.norm() - 1.0).abs() < 1e-12);
    // point = corner + gap · normal (the corner is the origin).
    prop_assert!(
        (g.point - g.gap * g.normal).norm() < 1e-9,
        "point {} gap {} normal {}",
        g.point,
        g.gap,
        g.normal
    );
    let excluded = model(shape, corner(-axis, 0.2));
    let kinematics = workspace(&excluded, pose);
    prop_assert!(
        (0..excluded.contacts().len()).all(|i| excluded.contact_geometry(&kinematics, i).is_none())
    );
    Ok(())
}

/// A box sunk slightly into a step's top touches the top only: the step's face, whose
/// line extends behind the box's vertices, does not claim them (they are far deeper
/// behind the face than behind the top), while a vertex just behind the face near the
/// corner does belong to the face.
#[test]
fn a_step_face_does_not_claim_points_behind_the_top() {
    step_face_ownership(Terrain::step(-0.3, 0.1), 1e-12);
    // The corner that ends the face is found within 1e-9 of the face's end (relative to
    // its distance from the origin): terrain built from rounded numbers still closes.
    step_face_ownership(step_with_corner_moved(Vec2::new(0.9e-9, -0.9e-9)), 2e-9);
}

/// Without a corner at its end the face is a line like any other: it claims the points
/// behind it, also those under the top.
#[test]
fn a_face_without_its_corner_claims_points_behind_it() {
    let square = Shape::rectangle(Vec2::zeros(), 0.05, 0.05);
    let m = model(square, step_with_corner_moved(Vec2::new(1e-4, 0.0)));
    let kinematics = workspace(&m, [0.0, 0.15 - 1e-6, 0.0]);
    let face = (0..m.contacts().len())
        .filter(|&i| m.contacts()[i].terrain == 1)
        .filter_map(|i| m.contact_geometry(&kinematics, i))
        .filter(|g| g.gap < -0.2)
        .count();
    assert_eq!(
        face, 2,
        "the face claims the lower vertices, 0.25 and 0.35 m behind it"
    );
}

/// `Terrain::step(-0.3, 0.1)` with its corner moved by `offset`.
fn step_with_corner_moved(offset: Vec2) -> Terrain {
    let mut terrain = Terrain::step(-0.3, 0.1);
    for feature in &mut terrain.features {
        if let TerrainFeature::Corner { point, .. } = feature {
            *point += offset;
        }
    }
    terrain
}

/// The two poses of [`a_step_face_does_not_claim_points_behind_the_top`] on `terrain`,
/// gaps to `tolerance`.
fn step_face_ownership(terrain: Terrain, tolerance: f64) {
    let square = Shape::rectangle(Vec2::zeros(), 0.05, 0.05);
    let m = model(square, terrain);
    let touching = |pose: [f64; 3]| -> Vec<(usize, f64)> {
        let kinematics = workspace(&m, pose);
        (0..m.contacts().len())
            .filter_map(|i| {
                m.contact_geometry(&kinematics, i)
                    .map(|g| (m.contacts()[i].terrain, g.gap))
            })
            .filter(|(_, gap)| *gap <= 0.0)
            .collect()
    };
    // Sunk 1e-6 into the top (terrain feature 2) at x = 0: two vertices, the top only.
    let contacts = touching([0.0, 0.15 - 1e-6, 0.0]);
    assert_eq!(contacts.len(), 2, "{contacts:?}");
    assert!(contacts
        .iter()
        .all(|&(t, gap)| t == 2 && (gap + 1e-6).abs() < tolerance));
    // Pushed 1e-3 into the face (feature 1) from the left, reaching above the top: the
    // face holds the lower right vertex, the corner (feature 3) the right edge.
    let contacts = touching([-0.35 + 1e-3, 0.06, 0.0]);
    assert_eq!(contacts.len(), 2, "{contacts:?}");
    assert!(contacts
        .iter()
        .all(|&(t, gap)| (t == 1 || t == 3) && (gap + 1e-3).abs() < tolerance));
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 400,
        // The clearance test rejects overlapping poses.
        max_global_rejects: 1_000_000,
        ..ProptestConfig::default()
    })]

    /// Ellipse (offset centre, any pose) against a corner inside or outside it.
    #[test]
    fn ellipse_against_a_corner(
        a in 0.03..0.3f64, ratio in 0.2..5.0f64,
        cx in -0.1..0.1f64, cy in -0.1..0.1f64,
        x in -0.5..0.5f64, y in -0.5..0.5f64, phi in -4.0..4.0f64,
    ) {
        let b = a * ratio;
        let center = Vec2::new(cx, cy);
        let shape = Shape::Ellipse { center, semi_x: a, semi_y: b };
        // The corner (origin) in the ellipse's frame.
        let local = rotate(-phi, -Vec2::new(x, y)) - center;
        let reference = ellipse_reference(a, b, local);
        check_corner(shape, [x, y, phi], reference)?;
        if reference > 1e-3 {
            // parry's GJK between the ellipse support map and a point.
            let pos12 = Pose::new(Vector::new(local.x, local.y), 0.0);
            let gjk = distance_support_map_support_map(&pos12, &EllipseSupport { a, b }, &Ball::new(0.0));
            prop_assert!((gjk - reference).abs() < 1e-6 * (1.0 + reference), "GJK {gjk} vs {reference}");
        }
    }

    /// Convex polygon against a corner inside or outside it.
    #[test]
    fn polygon_against_a_corner(
        vertices in convex_polygon(),
        x in -0.5..0.5f64, y in -0.5..0.5f64, phi in -4.0..4.0f64,
    ) {
        let local = rotate(-phi, -Vec2::new(x, y));
        let reference = polygon_reference(&vertices, local);
        // parry's projection (GJK outside, EPA inside) as a second reference.
        let points: Vec<Vector> = vertices.iter().map(|v| Vector::new(v.x, v.y)).collect();
        let poly = ConvexPolygon::from_convex_polyline(points).unwrap();
        let proj = poly.project_local_point(Vector::new(local.x, local.y), false);
        let d = (proj.point - Vector::new(local.x, local.y)).length();
        let parry = if proj.is_inside { -d } else { d };
        prop_assert!((parry - reference).abs() < 1e-7, "parry {parry} vs {reference}");
        check_corner(Shape::Polygon { vertices }, [x, y, phi], reference)?;
    }

    /// Above a step, the smallest gap over all of a shape's candidates (lines and corner;
    /// a capsule's caps and boundary) is its clearance to the terrain, sampled densely
    /// along the shape's boundary.
    #[test]
    fn clearance_above_a_step(
        which in 0..4usize,
        size in 0.05..0.2f64, ratio in 0.3..1.0f64,
        x in -0.4..0.4f64, y in 0.0..0.5f64, phi in -3.2..3.2f64,
    ) {
        let (a, b) = (size, size * ratio);
        let (shape, boundary): (Shape, Vec<Vec2>) = match which {
            0 => (
                Shape::Ellipse { center: Vec2::zeros(), semi_x: a, semi_y: b },
                (0..20_000).map(|k| {
                    let t = k as f64 * std::f64::consts::TAU / 20_000.0;
                    Vec2::new(a * t.cos(), b * t.sin())
                }).collect(),
            ),
            1 => {
                let v = vec![Vec2::new(-a, -b), Vec2::new(a, -b), Vec2::new(a, b), Vec2::new(-a, b)];
                let samples = (0..4).flat_map(|i| {
                    let (v0, v1) = (v[i], v[(i + 1) % 4]);
                    (0..5000).map(move |k| v0 + (v1 - v0) * (k as f64 / 5000.0))
                }).collect();
                (Shape::Polygon { vertices: v }, samples)
            }
            3 => (
                // A capsule: its two end circles and its two sides.
                Shape::Capsule { from: Vec2::new(-a, 0.0), to: Vec2::new(a, 0.0), radius: b },
                (0..20_000).flat_map(|k| {
                    let t = k as f64 * std::f64::consts::TAU / 20_000.0;
                    let s = -a + 2.0 * a * k as f64 / 20_000.0;
                    [
                        Vec2::new(-a, 0.0) + b * Vec2::new(t.cos(), t.sin()),
                        Vec2::new(a, 0.0) + b * Vec2::new(t.cos(), t.sin()),
                        Vec2::new(s, b),
                        Vec2::new(s, -b),
                    ]
                }).collect(),
            ),
            _ => (
                Shape::Circle { center: Vec2::new(0.0, b - a), radius: a },
                (0..20_000).map(|k| {
                    let t = k as f64 * std::f64::consts::TAU / 20_000.0;
                    Vec2::new(0.0, b - a) + a * Vec2::new(t.cos(), t.sin())
                }).collect(),
            ),
        };
        let (face, height) = (0.0, 0.1);
        let region_distance = |p: Vec2| {
            let low = p.y.max(0.0);
            let high = ((face - p.x).max(0.0).powi(2) + (p.y - height).max(0.0).powi(2)).sqrt();
            low.min(high)
        };
        let inside = |p: Vec2| p.y < 0.0 || (p.x > face && p.y < height);
        let world: Vec<Vec2> = boundary.iter().map(|p| Vec2::new(x, y) + rotate(phi, *p)).collect();
        prop_assume!(!world.iter().any(|p| inside(*p)));
        let clearance = world.iter().map(|p| region_distance(*p)).fold(f64::INFINITY, f64::min);
        prop_assume!(clearance > 1e-3);
        let m = model(shape, Terrain::step(face, height));
        let kinematics = workspace(&m, [x, y, phi]);
        let gap = (0..m.contacts().len())
            .filter_map(|i| m.contact_geometry(&kinematics, i))
            .map(|g| g.gap)
            .fold(f64::INFINITY, f64::min);
        prop_assert!(gap <= clearance + 1e-12, "gap {gap} above clearance {clearance}");
        prop_assert!(clearance - gap < 2e-4, "gap {gap} vs sampled clearance {clearance}");
    }


    /// On flat ground each end cap is a candidate whose gap is its centre's height less
    /// the radius; the lowest is the capsule's lowest point.
    #[test]
    fn capsule_on_flat_ground(
        (a, b, r) in end_points(), x in -1.0..1.0f64, y in -0.5..0.5f64, phi in -4.0..4.0f64,
        height in -0.3..0.3f64,
    ) {
        let m = model(capsule(a, b, r), Terrain::flat(height));
        let k = workspace(&m, [x, y, phi]);
        prop_assert_eq!(m.contacts().len(), 2);
        for (i, end) in [a, b].into_iter().enumerate() {
            prop_assert_eq!(m.contacts()[i].feature, ShapeFeature::Vertex(i));
            let centre = Vec2::new(x, y) + rotate(phi, end);
            let g = m.contact_geometry(&k, i).unwrap();
            prop_assert!((g.gap - (centre.y - r - height)).abs() < 1e-12);
            prop_assert!((g.point - (centre - Vec2::new(0.0, r))).norm() < 1e-12);
            prop_assert_eq!(g.normal, Vec2::new(0.0, 1.0));
        }
    }

    /// Against a corner: the gap is the corner's distance from the segment less the radius
    /// (also parry2d's signed distance to its capsule), the normal points from the corner
    /// to the segment, and the contact point lies on the capsule's boundary; a cone facing
    /// away has no contact.
    #[test]
    fn capsule_against_a_corner(
        (a, b, r) in end_points(), x in -0.5..0.5f64, y in -0.5..0.5f64, phi in -4.0..4.0f64,
    ) {
        let local = rotate(-phi, -Vec2::new(x, y));
        let (distance, foot) = segment_distance(a, b, local);
        prop_assume!(distance > 1e-6);
        let reference = distance - r;
        let parry = Capsule::new(Vector::new(a.x, a.y), Vector::new(b.x, b.y), r);
        let projection = parry.project_local_point(Vector::new(local.x, local.y), false);
        let d = (projection.point - Vector::new(local.x, local.y)).length();
        let signed = if projection.is_inside { -d } else { d };
        prop_assert!((signed - reference).abs() < 1e-12, "parry {signed} vs {reference}");
        let normal = rotate(phi, (foot - local) / distance);
        let m = model(capsule(a, b, r), corner(normal, 0.3));
        let k = workspace(&m, [x, y, phi]);
        let edges = (0..m.contacts().len())
            .find(|&i| m.contacts()[i].feature == ShapeFeature::Edges)
            .unwrap();
        let g = m.contact_geometry(&k, edges).unwrap();
        prop_assert!((g.gap - reference).abs() < 1e-12, "gap {} vs {reference}", g.gap);
        prop_assert!((g.normal - normal).norm() < 1e-12);
        prop_assert!((g.point - g.gap * g.normal).norm() < 1e-12);
        let m = model(capsule(a, b, r), corner(-normal, 0.3));
        let k = workspace(&m, [x, y, phi]);
        prop_assert!(m.contact_geometry(&k, edges).is_none());
    }
}

/// World point of the arc `center + radius (cos t, sin t)` (body frame) at `pose`, and its
/// derivative in `t`, transformed by hand.
fn arc_point(center: Vec2, radius: f64, pose: [f64; 3], t: f64) -> (Vec2, Vec2) {
    let local = center + radius * Vec2::new(t.cos(), t.sin());
    let d_local = radius * Vec2::new(-t.sin(), t.cos());
    (
        Vec2::new(pose[0], pose[1]) + rotate(pose[2], local),
        rotate(pose[2], d_local),
    )
}

/// Minimum of `f` over the arc parameter `[start, end]` by dense sampling, refined by
/// bisection on the sign of `df` in the bracket around the best sample; `(t, interior)`
/// where `interior` says the minimum is not at an end of the arc.
fn arc_minimum(
    start: f64,
    end: f64,
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
) -> (f64, bool) {
    let samples = 20_000;
    let ts: Vec<f64> = (0..=samples)
        .map(|k| start + (end - start) * k as f64 / samples as f64)
        .collect();
    let best = (0..=samples)
        .min_by(|&a, &b| f(ts[a]).total_cmp(&f(ts[b])))
        .unwrap();
    if best == 0 || best == samples {
        return (ts[best], false);
    }
    let (mut lo, mut hi) = (ts[best - 1], ts[best + 1]);
    if df(lo) > 0.0 || df(hi) < 0.0 {
        // No sign change of the derivative in the bracket: a sampled end effect.
        return (ts[best], false);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if df(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi), true)
}

/// The geometry of `m`'s candidates at `pose` by feature: `(terrain index, shape feature,
/// geometry)` of every reported contact.
fn reported(m: &Model, pose: [f64; 3]) -> Vec<(usize, ShapeFeature, ContactGeometry)> {
    let kinematics = workspace(m, pose);
    (0..m.contacts().len())
        .filter_map(|i| {
            m.contact_geometry(&kinematics, i)
                .map(|g| (m.contacts()[i].terrain, m.contacts()[i].feature, g))
        })
        .collect()
}

use hopsim_model::{ContactGeometry, ShapeFeature};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// A circular arc above flat ground: where the body-frame direction `−n` falls inside
    /// the arc, its smooth contact's gap and point are the lowest point of the densely
    /// sampled arc (refined by bisection on `dy/dt`); where it falls outside, there is no
    /// smooth contact, and the arc's ends (vertices) give the lowest points, transformed
    /// by hand.
    #[test]
    fn arc_above_flat_ground(
        cx in -0.1..0.1f64, cy in -0.1..0.1f64, radius in 0.05..0.3f64,
        start in -4.0..2.0f64, span in 0.2..3.0f64,
        x in -1.0..1.0f64, y in 0.35..0.6f64, phi in -4.0..4.0f64,
    ) {
        let center = Vec2::new(cx, cy);
        let end = start + span;
        let pose = [x, y, phi];
        let shape = Shape::Arc { center, radius, start, end };
        let m = model(shape, Terrain::flat(0.0));
        let got = reported(&m, pose);
        let (t, interior) = arc_minimum(
            start, end,
            |t| arc_point(center, radius, pose, t).0.y,
            |t| arc_point(center, radius, pose, t).1.y,
        );
        // The full circle's lowest point at the body-frame angle −π/2 − φ, as an arc offset.
        let offset = (-std::f64::consts::FRAC_PI_2 - phi - start).rem_euclid(std::f64::consts::TAU);
        let margin = 1e-6;
        let smooth: Vec<_> = got.iter().filter(|c| c.1 == ShapeFeature::Smooth).collect();
        if interior && offset > margin && offset < span - margin {
            prop_assert_eq!(smooth.len(), 1, "{:?}", got);
            let (p, _) = arc_point(center, radius, pose, t);
            let g = smooth[0].2;
            prop_assert!((g.gap - p.y).abs() < 1e-12, "gap {} vs sampled {}", g.gap, p.y);
            prop_assert!((g.point - p).norm() < 1e-9, "point {} vs sampled {}", g.point, p);
            prop_assert_eq!(g.normal, Vec2::new(0.0, 1.0));
        } else if offset > span + margin && offset < std::f64::consts::TAU - margin {
            // Beyond the arc's range: the smooth boundary must not touch.
            prop_assert!(smooth.is_empty(), "smooth contact outside the arc: {:?}", got);
        }
        // The vertices: the arc's ends transformed by hand.
        for (k, a) in [start, end].into_iter().enumerate() {
            let (p, _) = arc_point(center, radius, pose, a);
            let v: Vec<_> = got.iter().filter(|c| c.1 == ShapeFeature::Vertex(k)).collect();
            prop_assert_eq!(v.len(), 1);
            prop_assert!((v[0].2.gap - p.y).abs() < 1e-12);
            prop_assert!((v[0].2.point - p).norm() < 1e-12);
        }
        // Together: the smallest gap is the clearance of the sampled arc.
        let clearance = arc_point(center, radius, pose, t).0.y;
        let gap = got.iter().map(|c| c.2.gap).fold(f64::INFINITY, f64::min);
        prop_assert!((gap - clearance).abs() < 1e-12, "gap {} vs clearance {}", gap, clearance);
    }

    /// A circular arc near a step's corner: where the point of the arc closest to the
    /// corner (dense sampling of the distance, bisection on its derivative) is interior to
    /// the arc and its normal lies in the corner's cone (up to left), the corner contact's
    /// gap is that distance (negative when the corner is inside the circle) and its point
    /// that arc point; where the circle's closest point lies beyond the arc's range, no
    /// corner contact is reported.
    #[test]
    fn arc_near_a_step_corner(
        cx in -0.05..0.05f64, cy in -0.05..0.05f64, radius in 0.05..0.2f64,
        start in -4.0..2.0f64, span in 0.2..3.0f64,
        dx in -0.3..0.1f64, dy in -0.1..0.3f64, phi in -4.0..4.0f64,
    ) {
        let (face, height) = (0.2, 0.1);
        let corner = Vec2::new(face, height);
        let center = Vec2::new(cx, cy);
        let end = start + span;
        let pose = [face + dx, height + dy, phi];
        let m = model(Shape::Arc { center, radius, start, end }, Terrain::step(face, height));
        let got = reported(&m, pose);
        let at_corner: Vec<_> = got.iter().filter(|c| c.0 == 3).collect();
        let c_world = Vec2::new(pose[0], pose[1]) + rotate(phi, center);
        let dist = (c_world - corner).norm();
        prop_assume!(dist > 1e-3 && (dist - radius).abs() > 1e-6);
        let inside = dist < radius;
        // The arc point nearest the corner (also when the corner is inside the circle).
        let (t, interior) = arc_minimum(
            start, end,
            |t| (arc_point(center, radius, pose, t).0 - corner).norm(),
            |t| {
                let (p, dp) = arc_point(center, radius, pose, t);
                (p - corner).dot(&dp)
            },
        );
        // Terrain-to-body normal: (centre − corner)/|centre − corner| (the contact point
        // c − R n is the circle point nearest the corner, inside or outside).
        let n = (c_world - corner) / dist;
        let in_cone = n.x <= -1e-6 && n.y >= 1e-6;
        // Body-frame angle of the circle point closest to the corner, as an arc offset.
        let local = rotate(-phi, -n);
        let offset = (local.y.atan2(local.x) - start).rem_euclid(std::f64::consts::TAU);
        let margin = 1e-6;
        if in_cone && offset > margin && offset < span - margin {
            prop_assert!(interior);
            prop_assert_eq!(at_corner.len(), 1, "{:?}", got);
            let (p, _) = arc_point(center, radius, pose, t);
            let d = (p - corner).norm();
            let reference = if inside { -d } else { d };
            let g = at_corner[0].2;
            prop_assert!((g.gap - reference).abs() < 1e-12, "gap {} vs sampled {}", g.gap, reference);
            prop_assert!((g.point - p).norm() < 1e-9, "point {} vs sampled {}", g.point, p);
            prop_assert!((g.normal - n).norm() < 1e-12);
        } else if offset > span + margin && offset < std::f64::consts::TAU - margin {
            prop_assert!(at_corner.is_empty(), "corner contact off the arc: {:?}", got);
        } else if !in_cone && (n.x > 1e-6 || n.y < -1e-6) {
            prop_assert!(at_corner.is_empty(), "corner contact outside the cone: {:?}", got);
        }
    }

    /// A point shape at random poses above flat ground and around a step: its world
    /// position, transformed by hand, is the contact point, and the gaps are its heights
    /// above the ground and the step's top and its distance from the face, each reported
    /// only where the point lies over that line's extent (the ground's and the face's reach
    /// on past the face's foot, under the step: docs/physics.md §2.1).
    #[test]
    fn point_above_flat_ground_and_a_step(
        px in -0.2..0.2f64, py in -0.2..0.2f64,
        x in -0.5..0.5f64, y in 0.25..0.6f64, phi in -4.0..4.0f64,
    ) {
        let position = Vec2::new(px, py);
        let pose = [x, y, phi];
        let p = Vec2::new(x, y) + rotate(phi, position);
        let m = model(Shape::Point { position }, Terrain::flat(0.0));
        let got = reported(&m, pose);
        prop_assert_eq!(got.len(), 1);
        prop_assert_eq!(got[0].1, ShapeFeature::Vertex(0));
        prop_assert!((got[0].2.gap - p.y).abs() < 1e-15);
        prop_assert!((got[0].2.point - p).norm() < 1e-15);
        prop_assert_eq!(got[0].2.normal, Vec2::new(0.0, 1.0));

        // Step: face at x = 0, top at y = 0.2 (the point lies in the open region).
        let (face, height) = (0.0, 0.2);
        prop_assume!(p.x < face || p.y > height);
        prop_assume!((p.x - face).abs() > 1e-9 && (p.y - height).abs() > 1e-9);
        let m = model(Shape::Point { position }, Terrain::step(face, height));
        let got = reported(&m, pose);
        let mut expected: Vec<(usize, f64)> = vec![(0, p.y)];
        // The face spans every height up to `height`.
        if p.y <= height {
            expected.push((1, face - p.x));
        }
        if p.x > face {
            expected.push((2, p.y - height));
        }
        let mut seen: Vec<(usize, f64)> = got.iter().map(|c| (c.0, c.2.gap)).collect();
        seen.sort_by_key(|c| c.0);
        prop_assert_eq!(seen.len(), expected.len(), "{:?} vs {:?}", seen, expected);
        for ((t, gap), (te, ge)) in seen.iter().zip(&expected) {
            prop_assert_eq!(t, te);
            prop_assert!((gap - ge).abs() < 1e-15, "terrain {}: gap {} vs {}", t, gap, ge);
        }
        prop_assert!(got.iter().all(|c| (c.2.point - p).norm() < 1e-15));
    }
}

/// A line through `origin` with unit normal `normal` and ends at `from`, `to`.
fn line(origin: Vec2, normal: Vec2, from: f64, to: f64) -> Terrain {
    Terrain {
        features: vec![TerrainFeature::Line {
            origin,
            normal,
            from,
            to,
        }],
    }
}

proptest! {
    /// An eccentric disc (centre `(0, a)` in the body frame, docs/physics.md §2) on a line
    /// without ends: the contact is the disc's lowest point along the normal, the gap the
    /// centre's height above the line less `R`, the centre at `(x − a sin φ, y + a cos φ)`
    /// (on flat ground `g_N = y + a cos φ − R`). The same disc on the same line with ends far away
    /// (which the general contact search handles) gives the same geometry, bit for bit.
    #[test]
    fn eccentric_disc_on_a_line_without_ends(
        x in -3.0..3.0f64,
        y in -0.3..0.6f64,
        phi in -20.0..20.0f64,
        a in 0.0..0.15f64,
        slope in -0.5..0.5f64,
    ) {
        let radius = 0.2;
        let disc = Shape::Circle { center: Vec2::new(0.0, a), radius };
        let (origin, normal) = (Vec2::new(0.1, -0.05), rotate(slope, Vec2::new(0.0, 1.0)));
        let endless = line(origin, normal, f64::NEG_INFINITY, f64::INFINITY);
        let ended = line(origin, normal, -1e6, 1e6);
        let pose = [x, y, phi];
        let (m_endless, m_ended) = (model(disc.clone(), endless), model(disc, ended));
        let g = m_endless.contact_geometry(&workspace(&m_endless, pose), 0).unwrap();
        let reference = m_ended.contact_geometry(&workspace(&m_ended, pose), 0).unwrap();
        prop_assert_eq!(g, reference);
        let centre = Vec2::new(x - a * phi.sin(), y + a * phi.cos());
        prop_assert!((g.gap - ((centre - origin).dot(&normal) - radius)).abs() < 1e-12);
        prop_assert!((g.point - (centre - radius * normal)).norm() < 1e-12);
        prop_assert_eq!(g.normal, normal);
        // The tangent: the normal turned by −90°, `+x` on flat ground (docs/physics.md §2).
        let t = g.tangent();
        prop_assert_eq!(t, Vec2::new(normal.y, -normal.x));
        prop_assert!(slope != 0.0 || t == Vec2::new(1.0, 0.0));
    }
}

/// Distance of `p` from the segment `a`–`b`, by the segment's parameter.
fn segment_distance(a: Vec2, b: Vec2, p: Vec2) -> (f64, Vec2) {
    let e = b - a;
    let t = ((p - a).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
    let foot = a + t * e;
    ((p - foot).norm(), foot)
}
