//! Body–body contact geometry (docs/physics.md §7) against parry2d's contact query, an
//! independent implementation: disc–disc, disc–polygon and polygon–polygon (separated),
//! each pair on two floating bodies at random poses; and the generalised directions
//! `w_N`, `w_T` against finite differences of the gap and of the contact points.

use hopsim_model::{
    Body, ContactMaterial, Kinematics, Model, ModelBuilder, Shape, ShapeInstance, Terrain, Vec2,
};
use nalgebra::DVector;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::contact;
use parry2d_f64::shape::{Ball, ConvexPolygon};
use proptest::prelude::*;

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

fn parry_shape(shape: &Shape) -> Box<dyn parry2d_f64::shape::Shape> {
    match shape {
        Shape::Circle { radius, .. } => Box::new(Ball::new(*radius)),
        Shape::Polygon { vertices } => Box::new(
            ConvexPolygon::from_convex_polyline(
                vertices.iter().map(|v| Vector::new(v.x, v.y)).collect(),
            )
            .unwrap(),
        ),
        _ => unreachable!(),
    }
}

/// parry's signed distance and normal (first → second) of the two shapes at `q`.
fn parry_gap(a: &Shape, b: &Shape, q: &[f64; 6]) -> (f64, Vec2) {
    let pose = |i: usize| Pose::new(Vector::new(q[3 * i], q[3 * i + 1]), q[3 * i + 2]);
    let c = contact(&pose(0), &*parry_shape(a), &pose(1), &*parry_shape(b), 10.0)
        .unwrap()
        .unwrap();
    (c.dist, Vec2::new(c.normal1.x, c.normal1.y))
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
