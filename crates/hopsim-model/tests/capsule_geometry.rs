//! The capsule's contact geometry (docs/physics.md §2, §7): against flat ground (its
//! lowest point in closed form), against a terrain corner (the distance to its segment,
//! and parry2d's capsule projection as an independent reference), its clearance above a
//! step sampled densely, and against circles, points, boxes and capsules on another body
//! with parry2d's contact query as the oracle; `w_N` is the gap's gradient.

use hopsim_model::{
    Body, ContactMaterial, Kinematics, Model, ModelBuilder, Shape, ShapeFeature, ShapeInstance,
    Terrain, TerrainFeature, Vec2,
};
use nalgebra::DVector;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::{contact, PointQuery};
use parry2d_f64::shape::{Ball, Capsule, ConvexPolygon};
use proptest::prelude::*;

fn rotate(theta: f64, v: Vec2) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

fn capsule(from: Vec2, to: Vec2, radius: f64) -> Shape {
    Shape::Capsule { from, to, radius }
}

/// One floating body carrying `shape` on `terrain`, evaluated at `pose`.
fn on_terrain(shape: Shape, terrain: Terrain, pose: [f64; 3]) -> (Model, Kinematics) {
    let m = Model::single_body(1.0, 0.01, shape, terrain, ContactMaterial::default()).unwrap();
    let mut k = Kinematics::new(&m);
    k.update(&m, &DVector::from_row_slice(&pose), &DVector::zeros(3));
    (m, k)
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

/// Distance of `p` from the segment `a`–`b`, by the segment's parameter.
fn segment_distance(a: Vec2, b: Vec2, p: Vec2) -> (f64, Vec2) {
    let e = b - a;
    let t = ((p - a).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
    let foot = a + t * e;
    ((p - foot).norm(), foot)
}

fn end_points() -> impl Strategy<Value = (Vec2, Vec2, f64)> {
    (
        -0.2..0.2f64,
        -0.2..0.2f64,
        0.02..0.3f64,
        -4.0..4.0f64,
        0.01..0.15f64,
    )
        .prop_map(|(cx, cy, half, angle, radius)| {
            let d = half * Vec2::new(angle.cos(), angle.sin());
            let c = Vec2::new(cx, cy);
            (c - d, c + d, radius)
        })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 400,
        max_global_rejects: 1_000_000,
        ..ProptestConfig::default()
    })]

    /// On flat ground each end cap is a candidate whose gap is its centre's height less
    /// the radius; the lowest is the capsule's lowest point.
    #[test]
    fn capsule_on_flat_ground(
        (a, b, r) in end_points(), x in -1.0..1.0f64, y in -0.5..0.5f64, phi in -4.0..4.0f64,
        height in -0.3..0.3f64,
    ) {
        let (m, k) = on_terrain(capsule(a, b, r), Terrain::flat(height), [x, y, phi]);
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
        let (m, k) = on_terrain(capsule(a, b, r), corner(normal, 0.3), [x, y, phi]);
        let edges = (0..m.contacts().len())
            .find(|&i| m.contacts()[i].feature == ShapeFeature::Edges)
            .unwrap();
        let g = m.contact_geometry(&k, edges).unwrap();
        prop_assert!((g.gap - reference).abs() < 1e-12, "gap {} vs {reference}", g.gap);
        prop_assert!((g.normal - normal).norm() < 1e-12);
        prop_assert!((g.point - g.gap * g.normal).norm() < 1e-12);
        let (m, k) = on_terrain(capsule(a, b, r), corner(-normal, 0.3), [x, y, phi]);
        prop_assert!(m.contact_geometry(&k, edges).is_none());
    }

    /// Above a step, the smallest gap over the capsule's candidates (its caps on the lines,
    /// its boundary at the corner) is its clearance, sampled densely over discs along the
    /// segment.
    #[test]
    fn capsule_clearance_above_a_step(
        (a, b, r) in end_points(), x in -0.4..0.4f64, y in 0.0..0.6f64, phi in -3.2..3.2f64,
    ) {
        let (face, height) = (0.0, 0.1);
        let region_distance = |p: Vec2| {
            let low = p.y.max(0.0);
            let high = ((face - p.x).max(0.0).powi(2) + (p.y - height).max(0.0).powi(2)).sqrt();
            low.min(high)
        };
        let inside = |p: Vec2| p.y < 0.0 || (p.x > face && p.y < height);
        let samples: Vec<Vec2> = (0..=200)
            .flat_map(|i| {
                let centre = a + (b - a) * (i as f64 / 200.0);
                (0..400).map(move |k| {
                    let t = k as f64 * std::f64::consts::TAU / 400.0;
                    centre + r * Vec2::new(t.cos(), t.sin())
                })
            })
            .map(|p| Vec2::new(x, y) + rotate(phi, p))
            .collect();
        prop_assume!(!samples.iter().any(|p| inside(*p)));
        let clearance = samples.iter().map(|p| region_distance(*p)).fold(f64::INFINITY, f64::min);
        prop_assume!(clearance > 1e-3);
        let (m, k) = on_terrain(capsule(a, b, r), Terrain::step(face, height), [x, y, phi]);
        let gap = (0..m.contacts().len())
            .filter_map(|i| m.contact_geometry(&k, i))
            .map(|g| g.gap)
            .fold(f64::INFINITY, f64::min);
        prop_assert!(gap <= clearance + 1e-12, "gap {gap} above clearance {clearance}");
        prop_assert!(clearance - gap < 2e-3 * r.max(0.01), "gap {gap} vs sampled clearance {clearance}");
    }
}

/// Two floating bodies, shape `a` on the first and `b` on the second, paired.
fn pair_model(a: Shape, b: Shape) -> Model {
    let shape = |name: &str, body: usize, shape: Shape| ShapeInstance {
        name: name.into(),
        body,
        shape,
    };
    let mut builder = ModelBuilder::new(
        vec![Body::base("a", 1.0, 0.01), Body::base("b", 2.0, 0.03)],
        vec![shape("sa", 0, a), shape("sb", 1, b)],
        Terrain::flat(-100.0),
        vec![],
        Vec2::zeros(),
        ContactMaterial::default(),
    )
    .unwrap();
    builder
        .add_body_contacts(0, 1, ContactMaterial::inelastic(0.5))
        .unwrap();
    builder.build()
}

fn kinematics(model: &Model, q: &[f64; 6]) -> Kinematics {
    let mut k = Kinematics::new(model);
    k.update(model, &DVector::from_row_slice(q), &DVector::zeros(6));
    k
}

/// The smallest gap over the pair's candidates, with its normal from the first body to
/// the second.
fn min_gap(model: &Model, q: &[f64; 6]) -> Option<(f64, Vec2)> {
    let k = kinematics(model, q);
    (0..model.pairs().len())
        .filter_map(|p| {
            let g = model.pair_geometry(&k, p)?;
            let sign = if model.shapes()[model.pairs()[p].probe].body == 1 {
                1.0
            } else {
                -1.0
            };
            Some((g.gap, sign * g.normal))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
}

fn parry_shape(shape: &Shape) -> (Vec2, Box<dyn parry2d_f64::shape::Shape>) {
    let v = |p: &Vec2| Vector::new(p.x, p.y);
    match shape {
        Shape::Circle { center, radius } => (*center, Box::new(Ball::new(*radius))),
        Shape::Point { position } => (*position, Box::new(Ball::new(0.0))),
        Shape::Capsule { from, to, radius } => (
            Vec2::zeros(),
            Box::new(Capsule::new(v(from), v(to), *radius)),
        ),
        Shape::Polygon { vertices } => (
            Vec2::zeros(),
            Box::new(
                ConvexPolygon::from_convex_polyline(vertices.iter().map(v).collect()).unwrap(),
            ),
        ),
        _ => unreachable!("not used here"),
    }
}

/// parry's signed distance and normal (first → second) of the two shapes at `q`.
fn parry_gap(a: &Shape, b: &Shape, q: &[f64; 6]) -> (f64, Vec2) {
    let (sa, pa) = parry_shape(a);
    let (sb, pb) = parry_shape(b);
    let pose = |i: usize, offset: Vec2| {
        let at = Vec2::new(q[3 * i], q[3 * i + 1]) + rotate(q[3 * i + 2], offset);
        Pose::new(Vector::new(at.x, at.y), q[3 * i + 2])
    };
    let c = contact(&pose(0, sa), &*pa, &pose(1, sb), &*pb, 10.0)
        .unwrap()
        .unwrap();
    (c.dist, Vec2::new(c.normal1.x, c.normal1.y))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        max_global_rejects: 1_000_000,
        ..ProptestConfig::default()
    })]

    /// A capsule against a disc, a point, a box or a capsule on another body at random
    /// poses: the smallest gap is parry2d's distance (apart), and a disc's or a point's
    /// gap and normal are parry's also when they overlap.
    #[test]
    fn capsule_against_other_shapes(
        which in 0..4usize, (a, b, r) in end_points(), size in 0.02..0.2f64,
        x in -0.8..0.8f64, y in -0.8..0.8f64, p1 in -4.0..4.0f64, p2 in -4.0..4.0f64,
    ) {
        let other = match which {
            0 => Shape::Circle { center: Vec2::new(0.03, -0.02), radius: size },
            1 => Shape::Point { position: Vec2::new(size, 0.01) },
            2 => Shape::rectangle(Vec2::new(0.01, 0.02), size, 0.7 * size),
            _ => capsule(Vec2::new(-size, 0.02), Vec2::new(size, -0.01), 0.5 * size),
        };
        let first = capsule(a, b, r);
        let model = pair_model(first.clone(), other.clone());
        let expected = [1, 1, 2 + 4, 2 + 2][which];
        prop_assert_eq!(model.pairs().len(), expected);
        let q = [0.0, 0.0, p1, x, y, p2];
        let (reference, parry_normal) = parry_gap(&first, &other, &q);
        let round = which < 2;
        prop_assume!(round || reference > 1e-3);
        let Some((gap, normal)) = min_gap(&model, &q) else {
            return Err(TestCaseError::reject("a probe centred on the segment has no direction"));
        };
        // parry's GJK between polygons and capsules converges to about 1e-8.
        let tolerance = if round { 1e-12 } else { 1e-7 };
        prop_assert!((gap - reference).abs() < tolerance, "gap {gap} vs parry {reference}");
        if round && reference.abs() > 1e-6 {
            prop_assert!((normal - parry_normal).norm() < 1e-6, "{normal} vs {parry_normal}");
        }
    }

    /// `w_N = ∂g_N/∂q` by central differences of the gap, for every candidate of two
    /// capsules and of a capsule and a box.
    #[test]
    fn capsule_normal_direction_is_the_gap_gradient(
        boxed in any::<bool>(), x in -0.3..0.3f64, y in 0.3..0.5f64,
        p1 in -1.0..1.0f64, p2 in -4.0..4.0f64,
    ) {
        let first = capsule(Vec2::new(-0.2, 0.01), Vec2::new(0.15, -0.02), 0.05);
        let other = if boxed {
            Shape::rectangle(Vec2::zeros(), 0.1, 0.05)
        } else {
            capsule(Vec2::new(-0.1, 0.0), Vec2::new(0.1, 0.03), 0.04)
        };
        let model = pair_model(first, other);
        let q = [0.0, 0.0, p1, x, y, p2];
        let k = kinematics(&model, &q);
        for p in 0..model.pairs().len() {
            let geometry = model.pair_geometry(&k, p).unwrap();
            let (mut w_n, mut w_t) = (vec![0.0; 6], vec![0.0; 6]);
            model.pair_directions_to(&k, p, &geometry, &mut w_n, &mut w_t);
            let h = 1e-6;
            let gap = |q: &[f64; 6]| model.pair_geometry(&kinematics(&model, q), p).unwrap().gap;
            for i in 0..6 {
                let (mut plus, mut minus) = (q, q);
                plus[i] += h;
                minus[i] -= h;
                let fd = (gap(&plus) - gap(&minus)) / (2.0 * h);
                prop_assert!((fd - w_n[i]).abs() < 1e-6, "pair {p}: w_N[{i}] = {} vs {fd}", w_n[i]);
            }
        }
    }
}

/// Two capsules lying parallel on each other touch at both ends (two rows, as a box on a
/// box), each with the gap between the surfaces.
#[test]
fn parallel_capsules_touch_at_both_ends() {
    let rod = capsule(Vec2::new(-0.2, 0.0), Vec2::new(0.2, 0.0), 0.05);
    let model = pair_model(rod.clone(), rod);
    let q = [0.0, 0.0, 0.0, 0.05, 0.1 + 1e-3, 0.0];
    let k = kinematics(&model, &q);
    let gaps: Vec<f64> = (0..model.pairs().len())
        .filter_map(|p| model.pair_geometry(&k, p).map(|g| g.gap))
        .filter(|g| *g < 0.01)
        .collect();
    assert_eq!(gaps.len(), 2, "{gaps:?}");
    assert!(gaps.iter().all(|g| (g - 1e-3).abs() < 1e-12), "{gaps:?}");
}

/// An ellipse against a capsule has no closed form: refused with the reason.
#[test]
fn ellipse_against_capsule_is_refused() {
    let ellipse = Shape::Ellipse {
        center: Vec2::zeros(),
        semi_x: 0.1,
        semi_y: 0.05,
    };
    let rod = capsule(Vec2::new(-0.1, 0.0), Vec2::new(0.1, 0.0), 0.02);
    let shape = |name: &str, body: usize, shape: Shape| ShapeInstance {
        name: name.into(),
        body,
        shape,
    };
    let mut builder = ModelBuilder::new(
        vec![Body::base("a", 1.0, 0.01), Body::base("b", 2.0, 0.03)],
        vec![shape("sa", 0, ellipse), shape("sb", 1, rod)],
        Terrain::flat(-100.0),
        vec![],
        Vec2::zeros(),
        ContactMaterial::default(),
    )
    .unwrap();
    let error = builder
        .add_body_contacts(0, 1, ContactMaterial::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("ellipse and a capsule"), "{error}");
}
