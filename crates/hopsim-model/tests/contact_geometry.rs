//! Contact geometry against independent geometry (physics.md §1-§2): an ellipse and a
//! convex polygon against a terrain corner, checked by dense sampling with Newton
//! refinement, by point-segment distances and by parry2d's GJK/EPA queries; and the
//! clearance of every shape above a step, from all its candidates together.

use hopsim_model::{ContactMaterial, Model, Shape, Terrain, TerrainFeature, Vec2, Workspace};
use nalgebra::DVector;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::details::distance_support_map_support_map;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::{Ball, ConvexPolygon, SupportMap};
use proptest::prelude::*;

fn model(shape: Shape, terrain: Terrain) -> Model {
    Model::single_body(1.0, 0.01, shape, terrain, ContactMaterial::default()).unwrap()
}

fn workspace(model: &Model, pose: [f64; 3]) -> Workspace {
    let mut ws = Workspace::new(model);
    ws.update(model, &DVector::from_row_slice(&pose), &DVector::zeros(3));
    ws
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
            let ws = workspace(&probe, pose);
            (0..probe.contacts.len()).find_map(|i| probe.contact_geometry(&ws, i))
        })
        .map(|g| g.normal)
        .expect("some cone holds the normal");
    let m = model(shape.clone(), corner(axis, 0.2));
    let ws = workspace(&m, pose);
    let g = (0..m.contacts.len())
        .find_map(|i| m.contact_geometry(&ws, i))
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
    let ws = workspace(&excluded, pose);
    prop_assert!((0..excluded.contacts.len()).all(|i| excluded.contact_geometry(&ws, i).is_none()));
    Ok(())
}

/// A box sunk slightly into a step's top touches the top only: the step's face, whose
/// line extends behind the box's vertices, does not claim them (they are far deeper
/// behind the face than behind the top), while a vertex just behind the face near the
/// corner does belong to the face.
#[test]
fn a_step_face_does_not_claim_points_behind_the_top() {
    let square = Shape::rectangle(Vec2::zeros(), 0.05, 0.05);
    let m = model(square, Terrain::step(-0.3, 0.1));
    let touching = |pose: [f64; 3]| -> Vec<(usize, f64)> {
        let ws = workspace(&m, pose);
        (0..m.contacts.len())
            .filter_map(|i| {
                m.contact_geometry(&ws, i)
                    .map(|g| (m.contacts[i].terrain, g.gap))
            })
            .filter(|(_, gap)| *gap <= 0.0)
            .collect()
    };
    // Sunk 1e-6 into the top (terrain feature 2) at x = 0: two vertices, the top only.
    let contacts = touching([0.0, 0.15 - 1e-6, 0.0]);
    assert_eq!(contacts.len(), 2, "{contacts:?}");
    assert!(contacts
        .iter()
        .all(|&(t, gap)| t == 2 && (gap + 1e-6).abs() < 1e-12));
    // Pushed 1e-3 into the face (feature 1) from the left, reaching above the top: the
    // face holds the lower right vertex, the corner (feature 3) the right edge.
    let contacts = touching([-0.35 + 1e-3, 0.06, 0.0]);
    assert_eq!(contacts.len(), 2, "{contacts:?}");
    assert!(contacts
        .iter()
        .all(|&(t, gap)| (t == 1 || t == 3) && (gap + 1e-3).abs() < 1e-12));
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

    /// Above a step, the smallest gap over all of a shape's candidates (lines and corner)
    /// is its clearance to the terrain, sampled densely along the shape's boundary.
    #[test]
    fn clearance_above_a_step(
        which in 0..3usize,
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
        let ws = workspace(&m, [x, y, phi]);
        let gap = (0..m.contacts.len())
            .filter_map(|i| m.contact_geometry(&ws, i))
            .map(|g| g.gap)
            .fold(f64::INFINITY, f64::min);
        prop_assert!(gap <= clearance + 1e-12, "gap {gap} above clearance {clearance}");
        prop_assert!(clearance - gap < 2e-4, "gap {gap} vs sampled clearance {clearance}");
    }
}
