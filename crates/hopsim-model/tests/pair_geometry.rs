//! Body–body contact geometry (docs/physics.md §7) against parry2d's contact query, an
//! independent implementation: disc–disc, disc–polygon, polygon–polygon (separated) and a
//! capsule against a disc, a point, a box and a capsule, each pair on two floating bodies
//! at random poses; and the generalised directions `w_N`, `w_T` against finite differences
//! of the gap and of the contact points.

use hopsim_model::{
    Body, ContactMaterial, Kinematics, Model, ModelBuilder, Shape, ShapeInstance, Terrain, Vec2,
};
use nalgebra::DVector;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::contact;
use parry2d_f64::shape::{Ball, Capsule, ConvexPolygon};
use proptest::prelude::*;

mod common;
use common::{capsule, end_points};

/// Two floating bodies, shape `a` on the first and `b` on the second, paired with
/// `Model::add_body_contacts`; no gravity, the terrain far below.
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

/// The smallest gap over the pair's candidates, with its normal (from A to B, reoriented
/// from the first body to the second).
fn min_gap(model: &Model, q: &[f64; 6]) -> Option<(f64, Vec2)> {
    let k = kinematics(model, q);
    (0..model.pairs().len())
        .filter_map(|p| {
            let g = model.pair_geometry(&k, p)?;
            // The normal points from the target to the probe; make it first → second.
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

fn rotate(theta: f64, v: Vec2) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

fn box_shape(w: f64, h: f64) -> Shape {
    Shape::rectangle(Vec2::zeros(), w, h)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Two discs, separated or overlapping: gap and normal as parry's (closed form both).
    #[test]
    fn disc_against_disc(
        r1 in 0.05..0.3f64, r2 in 0.05..0.3f64,
        x in -0.6..0.6f64, y in -0.6..0.6f64, p1 in -4.0..4.0f64, p2 in -4.0..4.0f64,
    ) {
        prop_assume!((x * x + y * y).sqrt() > 1e-3);
        let (a, b) = (Shape::Circle { center: Vec2::zeros(), radius: r1 }, Shape::Circle { center: Vec2::zeros(), radius: r2 });
        let model = pair_model(a.clone(), b.clone());
        prop_assert_eq!(model.pairs().len(), 1);
        let q = [0.0, 0.0, p1, x, y, p2];
        let (gap, normal) = min_gap(&model, &q).unwrap();
        let (reference, parry_normal) = parry_gap(&a, &b, &q);
        prop_assert!((gap - reference).abs() < 1e-12, "gap {gap} vs parry {reference}");
        prop_assert!((normal - parry_normal).norm() < 1e-9);
    }

    /// A disc against a box on another body, the disc's centre outside or inside the box.
    #[test]
    fn disc_against_box(
        r in 0.02..0.2f64, w in 0.05..0.3f64, h in 0.05..0.3f64,
        x in -0.6..0.6f64, y in -0.6..0.6f64, p1 in -4.0..4.0f64, p2 in -4.0..4.0f64,
    ) {
        let (a, b) = (box_shape(w, h), Shape::Circle { center: Vec2::zeros(), radius: r });
        let model = pair_model(a.clone(), b.clone());
        let q = [0.0, 0.0, p1, x, y, p2];
        let (gap, normal) = min_gap(&model, &q).unwrap();
        let (reference, parry_normal) = parry_gap(&a, &b, &q);
        // parry's EPA converges to ~1e-7 when the disc's centre is inside the box.
        prop_assert!((gap - reference).abs() < 1e-7, "gap {gap} vs parry {reference}");
        if reference > 1e-6 {
            prop_assert!((normal - parry_normal).norm() < 1e-6);
        }
    }

    /// Two separated boxes: the smallest corner-against-polygon gap is the distance.
    #[test]
    fn separated_boxes(
        w1 in 0.05..0.3f64, h1 in 0.05..0.3f64, w2 in 0.05..0.3f64, h2 in 0.05..0.3f64,
        x in -1.5..1.5f64, y in -1.5..1.5f64, p1 in -4.0..4.0f64, p2 in -4.0..4.0f64,
    ) {
        let (a, b) = (box_shape(w1, h1), box_shape(w2, h2));
        let model = pair_model(a.clone(), b.clone());
        prop_assert_eq!(model.pairs().len(), 8);
        let q = [0.0, 0.0, p1, x, y, p2];
        let (reference, _) = parry_gap(&a, &b, &q);
        prop_assume!(reference > 1e-3);
        let (gap, _) = min_gap(&model, &q).unwrap();
        prop_assert!((gap - reference).abs() < 1e-7, "gap {gap} vs parry {reference}");
    }

    /// `w_N = ∂g_N/∂q` (docs/physics.md §7: `J_Bᵀ n − J_Aᵀ n`) by central differences of the
    /// gap, for a disc against a box and a disc against a disc.
    #[test]
    fn normal_direction_is_the_gap_gradient(
        which in 0..2usize,
        x in -0.4..0.4f64, y in 0.25..0.5f64, p1 in -1.0..1.0f64, p2 in -4.0..4.0f64,
    ) {
        let a = if which == 0 { box_shape(0.2, 0.1) } else { Shape::Circle { center: Vec2::new(0.05, 0.0), radius: 0.1 } };
        let b = Shape::Circle { center: Vec2::new(0.0, 0.03), radius: 0.1 };
        let model = pair_model(a, b);
        let q = [0.0, 0.0, p1, x, y, p2];
        let k = kinematics(&model, &q);
        let geometry = model.pair_geometry(&k, 0).unwrap();
        let (mut w_n, mut w_t) = (vec![0.0; 6], vec![0.0; 6]);
        model.pair_directions_to(&k, 0, &geometry, &mut w_n, &mut w_t);
        let h = 1e-6;
        for i in 0..6 {
            let (mut plus, mut minus) = (q, q);
            plus[i] += h;
            minus[i] -= h;
            let gap = |q: &[f64; 6]| model.pair_geometry(&kinematics(&model, q), 0).unwrap().gap;
            let fd = (gap(&plus) - gap(&minus)) / (2.0 * h);
            prop_assert!((fd - w_n[i]).abs() < 1e-6, "w_N[{i}] = {} vs {fd}", w_n[i]);
        }
    }
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

/// Pairs hopsim cannot compute exactly are refused, with the reason.
#[test]
fn inexact_pairs_are_refused() {
    let ellipse = Shape::Ellipse {
        center: Vec2::zeros(),
        semi_x: 0.1,
        semi_y: 0.05,
    };
    let point = Shape::Point {
        position: Vec2::zeros(),
    };
    for (a, b, reason) in [
        (ellipse.clone(), box_shape(0.1, 0.1), "no closed-form"),
        (ellipse.clone(), ellipse.clone(), "no closed-form"),
        (
            ellipse.clone(),
            Shape::Capsule {
                from: Vec2::new(-0.1, 0.0),
                to: Vec2::new(0.1, 0.0),
                radius: 0.02,
            },
            "an ellipse and a capsule",
        ),
        (point.clone(), point.clone(), "never touch"),
    ] {
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
        let error = builder
            .add_body_contacts(0, 1, ContactMaterial::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains(reason), "{error}");
    }
}
