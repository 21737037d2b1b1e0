//! Kinematics, mass matrix and forces of a body tree against independent derivations:
//! finite differences of positions and energies, and Lagrange's equations (docs/physics.md §1).

use hopsim_model::{
    Body, ContactMaterial, Joint, JointCoordinate, JointKind, Kinematics, Model, Shape,
    ShapeInstance, Spring, Terrain, Vec2,
};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// A three-body tree: a base, a child on a relative joint and a grandchild on an absolute
/// joint, with offset pivots and centres of mass, joint damping and a damped spring.
fn tree(offsets: [f64; 6], damping: f64) -> Model {
    let joint = |parent, pivot: Vec2, com: Vec2, coordinate| Joint {
        coordinate,
        damping,
        ..Joint::revolute(Some(parent), pivot, com)
    };
    let [a, b, c, d, e, f] = offsets;
    let bodies = vec![
        Body::base("base", 1.3, 0.02),
        Body {
            name: "thigh".into(),
            mass: 0.7,
            inertia: 0.011,
            joint: Some(joint(
                0,
                Vec2::new(a, b),
                Vec2::new(c, -0.1),
                JointCoordinate::Relative,
            )),
        },
        Body {
            name: "wheel".into(),
            mass: 0.4,
            inertia: 0.005,
            joint: Some(joint(
                1,
                Vec2::new(d, e),
                Vec2::new(f, 0.02),
                JointCoordinate::Absolute,
            )),
        },
    ];
    let spring = Spring {
        name: "spring".into(),
        body_a: 0,
        point_a: Vec2::new(0.05, 0.1),
        body_b: 2,
        point_b: Vec2::new(-0.03, 0.01),
        stiffness: 40.0,
        rest_length: 0.05,
        damping,
        tension_only: false,
    };
    let shape = ShapeInstance {
        name: "foot".into(),
        body: 1,
        shape: Shape::Circle {
            center: Vec2::new(0.0, -0.2),
            radius: 0.05,
        },
    };
    Model::new(
        bodies,
        vec![shape],
        Terrain::flat(0.0),
        vec![spring],
        Vec2::new(0.0, -9.81),
        ContactMaterial::default(),
    )
    .unwrap()
}

/// Two trees and a fixed body (docs/physics.md §7): a floating hip with a leg on a sprung,
/// damped prismatic joint at an offset pivot and a tilted axis; a fixed frame; an arm
/// pinned to the world with a torsional joint spring, carrying a slider on a prismatic
/// joint. Offsets as in [`tree`].
fn forest(offsets: [f64; 6], damping: f64) -> Model {
    let [a, b, c, d, e, f] = offsets;
    let prismatic = |parent, pivot: Vec2, axis: Vec2, com: Vec2| Joint {
        kind: JointKind::Prismatic {
            axis: axis.normalize(),
        },
        damping,
        ..Joint::revolute(parent, pivot, com)
    };
    let body = |name: &str, mass, inertia, joint| Body {
        name: name.into(),
        mass,
        inertia,
        joint,
    };
    let bodies = vec![
        Body::base("hip", 1.3, 0.02),
        body(
            "leg",
            0.3,
            0.004,
            Some(Joint {
                stiffness: 50.0,
                rest_position: 0.1,
                ..prismatic(
                    Some(0),
                    Vec2::new(a, b),
                    Vec2::new(c, -1.0),
                    Vec2::new(d, 0.03),
                )
            }),
        ),
        body(
            "frame",
            2.0,
            0.1,
            Some(Joint {
                kind: JointKind::Fixed { angle: 0.3 },
                ..Joint::revolute(None, Vec2::new(1.0, 0.5), Vec2::zeros())
            }),
        ),
        body(
            "arm",
            0.5,
            0.01,
            Some(Joint {
                stiffness: 2.0,
                rest_position: 0.2,
                damping,
                ..Joint::revolute(None, Vec2::new(1.0, 0.8), Vec2::new(e, -0.2))
            }),
        ),
        body(
            "slider",
            0.2,
            0.001,
            Some(prismatic(
                Some(3),
                Vec2::new(0.0, -0.1),
                Vec2::new(1.0, f),
                Vec2::new(0.02, 0.01),
            )),
        ),
    ];
    let shapes = ["leg", "frame", "slider"]
        .iter()
        .enumerate()
        .map(|(i, name)| ShapeInstance {
            name: (*name).into(),
            body: [1, 2, 4][i],
            shape: Shape::Point {
                position: Vec2::new(0.01, -0.02),
            },
        })
        .collect();
    Model::new(
        bodies,
        shapes,
        Terrain::flat(0.0),
        vec![],
        Vec2::new(0.0, -9.81),
        ContactMaterial::default(),
    )
    .unwrap()
}

/// MuJoCo's floating base as a chain (docs/mjcf.md): on a fixed ground, two massless
/// links on prismatic joints along `x` and a tilted axis (the second with an armature),
/// a torso on a clockwise revolute joint with a spring, damping and an armature, a thigh
/// on another clockwise joint and a shin on a relative one, both with armatures. Offsets as
/// in [`tree`].
fn chain(offsets: [f64; 6], damping: f64) -> Model {
    let [a, b, c, d, e, f] = offsets;
    let body = |name: &str, mass, inertia, joint| Body {
        name: name.into(),
        mass,
        inertia,
        joint: Some(joint),
    };
    let slide = |parent, axis: Vec2, armature| Joint {
        kind: JointKind::Prismatic {
            axis: axis.normalize(),
        },
        armature,
        damping,
        ..Joint::revolute(Some(parent), Vec2::zeros(), Vec2::zeros())
    };
    let hinge = |parent, pivot, com, coordinate, armature| Joint {
        coordinate,
        armature,
        damping,
        stiffness: 3.0,
        rest_position: 0.1,
        ..Joint::revolute(Some(parent), pivot, com)
    };
    let bodies = vec![
        body(
            "ground",
            0.0,
            0.0,
            Joint {
                kind: JointKind::Fixed { angle: 0.0 },
                ..Joint::revolute(None, Vec2::new(a, b), Vec2::zeros())
            },
        ),
        body("rootx", 0.0, 0.0, slide(0, Vec2::new(1.0, 0.0), 0.0)),
        body("rootz", 0.0, 0.0, slide(1, Vec2::new(c, 1.0), 0.3)),
        body(
            "torso",
            3.0,
            0.05,
            hinge(
                2,
                Vec2::zeros(),
                Vec2::new(c, 0.1),
                JointCoordinate::Clockwise,
                0.2,
            ),
        ),
        body(
            "thigh",
            1.0,
            0.02,
            hinge(
                3,
                Vec2::new(d, e),
                Vec2::new(f, -0.2),
                JointCoordinate::Clockwise,
                0.1,
            ),
        ),
        body(
            "shin",
            0.5,
            0.01,
            hinge(
                4,
                Vec2::new(0.0, -0.4),
                Vec2::new(0.0, -0.2),
                JointCoordinate::Relative,
                0.05,
            ),
        ),
    ];
    let foot = ShapeInstance {
        name: "foot".into(),
        body: 5,
        shape: Shape::Capsule {
            from: Vec2::new(-0.1, -0.2),
            to: Vec2::new(0.1, -0.2),
            radius: 0.03,
        },
    };
    Model::new(
        bodies,
        vec![foot],
        Terrain::flat(0.0),
        vec![],
        Vec2::new(0.0, -9.81),
        ContactMaterial::default(),
    )
    .unwrap()
}

/// The tree of [`tree`] (0), the trees of [`forest`] (1) or the chain of [`chain`] (2).
fn model(which: usize, offsets: [f64; 6], damping: f64) -> Model {
    match which {
        0 => tree(offsets, damping),
        1 => forest(offsets, damping),
        _ => chain(offsets, damping),
    }
}

fn evaluate(model: &Model, q: &DVector<f64>, u: &DVector<f64>) -> Kinematics {
    let mut kinematics = Kinematics::new(model);
    kinematics.update(model, q, u);
    kinematics
}

/// Stacked body poses `(x_b, y_b, θ_b)`.
fn poses(model: &Model, q: &DVector<f64>) -> DVector<f64> {
    let kinematics = evaluate(model, q, &DVector::zeros(q.len()));
    DVector::from_iterator(
        3 * model.bodies().len(),
        (0..model.bodies().len()).flat_map(|b| {
            [
                kinematics.position(b).x,
                kinematics.position(b).y,
                kinematics.angle(b),
            ]
        }),
    )
}

fn jacobian(kinematics: &Kinematics, bodies: usize, n: usize) -> DMatrix<f64> {
    DMatrix::from_fn(3 * bodies, n, |r, j| {
        let (x, y, t) = kinematics.jacobian_rows(r / 3);
        [x, y, t][r % 3][j]
    })
}

fn kinetic(model: &Model, q: &DVector<f64>, u: &DVector<f64>) -> f64 {
    model.kinetic_energy(&evaluate(model, q, u))
}

fn potential(model: &Model, q: &DVector<f64>) -> f64 {
    let kinematics = evaluate(model, q, &DVector::zeros(q.len()));
    model.potential_energy(&kinematics) + model.spring_energy(&kinematics)
}

/// Central difference of `f` along `dir`.
fn along(f: impl Fn(&DVector<f64>) -> f64, x: &DVector<f64>, dir: &DVector<f64>, h: f64) -> f64 {
    (f(&(x + h * dir)) - f(&(x - h * dir))) / (2.0 * h)
}

fn unit(n: usize, j: usize) -> DVector<f64> {
    DVector::from_fn(n, |i, _| if i == j { 1.0 } else { 0.0 })
}

/// Offsets, `q`, `u` (the first `dof` entries are used) and which model.
fn state() -> impl Strategy<Value = ([f64; 6], Vec<f64>, Vec<f64>, usize)> {
    (
        prop::array::uniform6(-0.3..0.3f64),
        prop::collection::vec(-2.0..2.0f64, 6),
        prop::collection::vec(-3.0..3.0f64, 6),
        0..3usize,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Jacobian = ∂(poses)/∂q, velocities = J u, bias = J̇ u, also after other updates of
    /// the same workspace (buffers are reused, not cleared).
    #[test]
    fn jacobian_velocities_and_bias_match_finite_differences((offsets, q, u, which) in state()) {
        let model = model(which, offsets, 0.0);
        let n = model.dof();
        let (q, u) = (DVector::from_column_slice(&q[..n]), DVector::from_column_slice(&u[..n]));
        let mut kinematics = Kinematics::new(&model);
        kinematics.update(&model, &(&q * 0.5), &(&u * -2.0));
        kinematics.update(&model, &q, &u);
        let jac = jacobian(&kinematics, model.bodies().len(), n);
        let h = 1e-6;
        for j in 0..n {
            let e = unit(n, j);
            let column = (poses(&model, &(&q + h * &e)) - poses(&model, &(&q - h * &e))) / (2.0 * h);
            prop_assert!((jac.column(j) - column).amax() < 1e-8, "column {j}");
        }
        let v = &jac * &u;
        for b in 0..model.bodies().len() {
            prop_assert!((kinematics.velocity(b) - Vec2::new(v[3 * b], v[3 * b + 1])).norm() < 1e-12);
            prop_assert!((kinematics.angular_velocity(b) - v[3 * b + 2]).abs() < 1e-12);
            // J̇ u = d/ds [J(q + s u)] u at s = 0.
            let j_at = |s: f64| jacobian(&evaluate(&model, &(&q + s * &u), &u), model.bodies().len(), n);
            let jdot_u = (j_at(h) - j_at(-h)) / (2.0 * h) * &u;
            let bias = kinematics.bias(b);
            prop_assert!((bias - Vec2::new(jdot_u[3 * b], jdot_u[3 * b + 1])).norm() < 1e-6,
                "bias {bias} vs {}", jdot_u);
        }
    }

    /// `M` is symmetric with `½ uᵀ M u` = kinetic energy, and `h` (without damping) is
    /// Lagrange's right-hand side `-∂V/∂q - (Ṁ u - ∂T/∂q)`: gravity, springs (joint springs
    /// included) and the velocity-product terms of relative and prismatic joints all checked
    /// at once.
    #[test]
    fn mass_matrix_and_forces_follow_from_lagranges_equations((offsets, q, u, which) in state()) {
        let model = model(which, offsets, 0.0);
        let n = model.dof();
        let (q, u) = (DVector::from_column_slice(&q[..n]), DVector::from_column_slice(&u[..n]));
        let kinematics = evaluate(&model, &q, &u);
        let mut m = DMatrix::zeros(n, n);
        model.mass_matrix(&kinematics, &mut m);
        prop_assert!((&m - m.transpose()).amax() < 1e-15);
        prop_assert!((0.5 * u.dot(&(&m * &u)) - model.kinetic_energy(&kinematics)).abs() < 1e-12);
        let mut h = DVector::zeros(n);
        model.forces(&kinematics, &DVector::zeros(n), &mut h);
        let step = 1e-6;
        let m_at = |q: &DVector<f64>| {
            let mut m = DMatrix::zeros(n, n);
            model.mass_matrix(&evaluate(&model, q, &u), &mut m);
            m
        };
        let m_dot_u = (m_at(&(&q + step * &u)) - m_at(&(&q - step * &u))) / (2.0 * step) * &u;
        for j in 0..n {
            let e = unit(n, j);
            let dt_dq = along(|q| kinetic(&model, q, &u), &q, &e, step);
            let dv_dq = along(|q| potential(&model, q), &q, &e, step);
            let lagrange = -dv_dq - (m_dot_u[j] - dt_dq);
            prop_assert!((h[j] - lagrange).abs() < 1e-5 * (1.0 + lagrange.abs()),
                "h[{j}] = {} vs {lagrange}", h[j]);
        }
    }

    /// Joint and spring damping only dissipate: `uᵀ h_damping ≤ 0`, and equals
    /// `-Σ c θ̇_rel² - c_s L̇²`.
    #[test]
    fn damping_dissipates((offsets, q, u, _) in state(), c in 0.0..3.0f64) {
        let model = tree(offsets, c);
        let n = model.dof();
        let (q, u) = (DVector::from_column_slice(&q[..n]), DVector::from_column_slice(&u[..n]));
        let kinematics = evaluate(&model, &q, &u);
        let mut d = DVector::zeros(n);
        model.damping_forces(&kinematics, &mut d);
        let joints: f64 = (1..3)
            .map(|b| {
                let p = model.bodies()[b].joint.as_ref().unwrap().parent.unwrap();
                (kinematics.angular_velocity(b) - kinematics.angular_velocity(p)).powi(2)
            })
            .sum();
        let length = |q: &DVector<f64>| {
            let kinematics = evaluate(&model, q, &u);
            let (a, b) = model.spring_ends(&kinematics, 0);
            (a - b).norm()
        };
        let rate = along(length, &q, &u, 1e-6);
        let expected = -c * joints - c * rate * rate;
        prop_assert!((u.dot(&d) - expected).abs() < 1e-6 * (1.0 + expected.abs()));
        prop_assert!(u.dot(&d) <= 1e-12);
    }

    /// In the trees of [`forest`] and the chain of [`chain`], damping is `-c ṡ²` per damped
    /// joint, with `ṡ` the joint position's rate by finite differences (prismatic
    /// extensions, the pinned arm's angle, clockwise and relative angles).
    #[test]
    fn joint_damping_of_several_trees_dissipates((offsets, q, u, which) in state(), c in 0.0..3.0f64) {
        let chained = which == 2;
        let model = if chained { chain(offsets, c) } else { forest(offsets, c) };
        let n = model.dof();
        let (q, u) = (DVector::from_column_slice(&q[..n]), DVector::from_column_slice(&u[..n]));
        let kinematics = evaluate(&model, &q, &u);
        let mut d = DVector::zeros(n);
        model.damping_forces(&kinematics, &mut d);
        let damped: &[usize] = if chained { &[1, 2, 3, 4, 5] } else { &[1, 3, 4] };
        let expected: f64 = damped
            .iter()
            .map(|&b| {
                let position = |q: &DVector<f64>| evaluate(&model, q, &u).joint_position(b);
                -c * along(position, &q, &u, 1e-6).powi(2)
            })
            .sum();
        prop_assert!((u.dot(&d) - expected).abs() < 1e-6 * (1.0 + expected.abs()));
    }
}

/// A clockwise joint is a relative one turned the other way: the same poses at `−q`, its
/// column of the Jacobian and its spring's force negated, `M` congruent by the sign; an
/// armature adds to `M`'s diagonal and to the kinetic energy alone.
#[test]
fn clockwise_joints_and_armatures() {
    let offsets = [0.05, -0.1, 0.02, 0.1, -0.03, 0.04];
    let with = chain(offsets, 0.0);
    let plain = {
        let mut bodies = with.bodies().to_vec();
        for body in &mut bodies {
            let joint = body.joint.as_mut().unwrap();
            joint.armature = 0.0;
            if joint.coordinate == JointCoordinate::Clockwise {
                joint.coordinate = JointCoordinate::Relative;
                joint.rest_position = -joint.rest_position;
            }
        }
        Model::new(
            bodies,
            with.shapes().to_vec(),
            with.terrain().clone(),
            vec![],
            with.gravity(),
            ContactMaterial::default(),
        )
        .unwrap()
    };
    // Coordinates 2 and 3 are the clockwise angles.
    let sign = DVector::from_row_slice(&[1.0, 1.0, -1.0, -1.0, 1.0]);
    let q = DVector::from_row_slice(&[0.3, -0.2, 0.7, -1.1, 0.4]);
    let u = DVector::from_row_slice(&[1.0, 0.5, -2.0, 3.0, -1.5]);
    let (qs, us) = (q.component_mul(&sign), u.component_mul(&sign));
    let (k, ks) = (evaluate(&with, &q, &u), evaluate(&plain, &qs, &us));
    for b in 0..with.bodies().len() {
        assert!((k.position(b) - ks.position(b)).norm() < 1e-15);
        assert!((k.angle(b) - ks.angle(b)).abs() < 1e-15);
        assert!((k.velocity(b) - ks.velocity(b)).norm() < 1e-14);
    }
    let mass = |model: &Model, k: &Kinematics| {
        let mut m = DMatrix::zeros(5, 5);
        model.mass_matrix(k, &mut m);
        m
    };
    let s = DMatrix::from_diagonal(&sign);
    let armature = DMatrix::from_diagonal(&DVector::from_row_slice(&[0.0, 0.3, 0.2, 0.1, 0.05]));
    let difference = mass(&with, &k) - (&s * mass(&plain, &ks) * &s + &armature);
    assert!(difference.amax() < 1e-14, "{difference}");
    let extra = 0.5 * u.dot(&(&armature * &u));
    let kinetic = with.kinetic_energy(&k) - plain.kinetic_energy(&ks);
    assert!((kinetic - extra).abs() < 1e-13, "{kinetic} vs {extra}");
    let forces = |model: &Model, k: &Kinematics| {
        let mut h = DVector::zeros(5);
        model.forces(k, &DVector::zeros(5), &mut h);
        h
    };
    let difference = forces(&with, &k) - &s * forces(&plain, &ks);
    assert!(difference.amax() < 1e-12, "{difference}");
    // The joint positions are the coordinates themselves.
    assert_eq!(k.joint_position(3), q[2]);
    assert_eq!(k.joint_position(4), q[3]);
}

/// A massless body needs a child to carry its coordinate; an armature needs a joint
/// position as its coordinate.
#[test]
fn massless_links_need_children_and_armatures_joint_positions() {
    let slide = Joint {
        kind: JointKind::Prismatic {
            axis: Vec2::new(1.0, 0.0),
        },
        ..Joint::revolute(None, Vec2::zeros(), Vec2::zeros())
    };
    let body = |name: &str, mass, joint| Body {
        name: name.into(),
        mass,
        inertia: mass,
        joint: Some(joint),
    };
    let build = |bodies| {
        Model::new(
            bodies,
            vec![],
            Terrain::flat(0.0),
            vec![],
            Vec2::zeros(),
            ContactMaterial::default(),
        )
    };
    let child = Joint {
        parent: Some(0),
        ..Joint::revolute(Some(0), Vec2::zeros(), Vec2::new(0.1, 0.0))
    };
    assert!(build(vec![
        body("link", 0.0, slide.clone()),
        body("arm", 1.0, child.clone())
    ])
    .is_ok());
    let error = build(vec![body("link", 0.0, slide.clone())]).unwrap_err();
    assert!(
        error.to_string().contains("mass must be positive"),
        "{error}"
    );
    let absolute = Joint {
        coordinate: JointCoordinate::Absolute,
        armature: 0.1,
        ..child
    };
    let error = build(vec![body("link", 1.0, slide), body("arm", 1.0, absolute)]).unwrap_err();
    assert!(error.to_string().contains("armature"), "{error}");
}

/// Coordinates are numbered in body order: 3 per floating base, 1 per joint, none for a
/// fixed body; a fixed body's shapes have no terrain contacts, and it does not count in
/// the mass or centre of mass of what moves.
#[test]
fn coordinates_of_several_trees() {
    let model = forest([0.0; 6], 0.0);
    assert_eq!(model.dof(), 6);
    let coordinates: Vec<Option<usize>> = (0..5).map(|b| model.coordinate(b)).collect();
    assert_eq!(coordinates, [Some(0), Some(3), None, Some(4), Some(5)]);
    assert_eq!(
        (0..5).map(|b| model.root(b)).collect::<Vec<_>>(),
        [0, 0, 2, 3, 3]
    );
    assert!(model
        .contacts()
        .iter()
        .all(|c| model.shapes()[c.shape].body != 2));
    assert!((model.total_mass() - (1.3 + 0.3 + 0.5 + 0.2)).abs() < 1e-15);
    let k = evaluate(&model, &DVector::zeros(6), &DVector::zeros(6));
    assert_eq!((k.position(2), k.angle(2)), (Vec2::new(1.0, 0.5), 0.3));
}

#[test]
fn polygons_must_be_convex_and_counter_clockwise() {
    let build = |vertices: Vec<Vec2>| {
        Model::single_body(
            1.0,
            0.1,
            Shape::Polygon { vertices },
            Terrain::flat(0.0),
            ContactMaterial::default(),
        )
    };
    let square = vec![
        Vec2::new(-1.0, -1.0),
        Vec2::new(1.0, -1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(-1.0, 1.0),
    ];
    assert!(build(square.clone()).is_ok());
    let clockwise: Vec<Vec2> = square.iter().rev().copied().collect();
    assert!(build(clockwise).is_err());
    let dart = vec![
        Vec2::new(-1.0, -1.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, -1.0),
        Vec2::new(0.0, 1.0),
    ];
    assert!(build(dart).is_err());
    let star: Vec<Vec2> = (0..5)
        .map(|k| {
            let a = k as f64 * 4.0 * std::f64::consts::PI / 5.0;
            Vec2::new(a.cos(), a.sin())
        })
        .collect();
    assert!(
        build(star).is_err(),
        "a pentagram turns left at every vertex but winds twice"
    );
}

/// A model's parts, to change one and build again.
#[derive(Clone)]
struct Parts {
    bodies: Vec<Body>,
    shapes: Vec<ShapeInstance>,
    terrain: Terrain,
    springs: Vec<Spring>,
    gravity: Vec2,
}

impl Parts {
    fn of(model: &Model) -> Self {
        Self {
            bodies: model.bodies().to_vec(),
            shapes: model.shapes().to_vec(),
            terrain: model.terrain().clone(),
            springs: model.springs().to_vec(),
            gravity: model.gravity(),
        }
    }

    fn build(&self) -> Result<Model, hopsim_model::ModelError> {
        Model::new(
            self.bodies.clone(),
            self.shapes.clone(),
            self.terrain.clone(),
            self.springs.clone(),
            self.gravity,
            ContactMaterial::default(),
        )
    }
}

/// Non-finite or negative parameters are build errors, never NaN in a run.
#[test]
fn non_finite_parameters_are_build_errors() {
    let base = Parts::of(&tree([0.0; 6], 0.0));
    assert!(base.build().is_ok());
    let mut m = base.clone();
    m.shapes[0].shape = Shape::Circle {
        center: Vec2::zeros(),
        radius: f64::NAN,
    };
    assert!(m.build().is_err());
    let mut m = base.clone();
    m.shapes[0].shape = Shape::Ellipse {
        center: Vec2::new(f64::INFINITY, 0.0),
        semi_x: 1.0,
        semi_y: 1.0,
    };
    assert!(m.build().is_err());
    let mut m = base.clone();
    m.springs[0].stiffness = f64::NAN;
    assert!(m.build().is_err());
    let mut m = base.clone();
    m.bodies[1].joint.as_mut().unwrap().damping = -1.0;
    assert!(m.build().unwrap_err().to_string().contains("damping"));
    let mut m = base;
    m.bodies[2].joint.as_mut().unwrap().pivot_in_parent = Vec2::new(f64::NAN, 0.0);
    assert!(m.build().is_err());
    // Joints of several trees: limits, axes, welds and what only revolute joints have.
    let forest = Parts::of(&forest([0.0; 6], 0.0));
    let joint_error = |b: usize, change: &dyn Fn(&mut Joint)| {
        let mut m = forest.clone();
        change(m.bodies[b].joint.as_mut().unwrap());
        m.build().unwrap_err().to_string()
    };
    let limits = |lower, upper, restitution| {
        Some(hopsim_model::JointLimits {
            lower,
            upper,
            restitution,
        })
    };
    assert!(joint_error(1, &|j| j.limits = limits(0.2, 0.1, 0.0)).contains("lower < upper"));
    assert!(joint_error(1, &|j| j.limits = limits(0.0, 0.1, 1.5)).contains("restitution"));
    assert!(joint_error(1, &|j| {
        j.kind = JointKind::Prismatic {
            axis: Vec2::new(2.0, 0.0),
        }
    })
    .contains("unit vector"));
    assert!(joint_error(1, &|j| j.coordinate = JointCoordinate::Absolute).contains("absolute"));
    assert!(joint_error(1, &|j| j.kind = JointKind::Fixed { angle: 0.0 }).contains("root"));
    assert!(joint_error(3, &|j| j.stiffness = -1.0).contains("stiffness"));
    assert!(joint_error(4, &|j| j.parent = Some(4)).contains("earlier body"));
}

/// `M(q)` of `model` at `q`.
fn mass_at(model: &Model, q: &DVector<f64>) -> DMatrix<f64> {
    let n = model.dof();
    let kinematics = evaluate(model, q, &DVector::zeros(n));
    let mut m = vec![0.0; n * n];
    model.mass_matrix_to(&kinematics, &mut m);
    DMatrix::from_row_slice(n, n, &m)
}

/// `Model::jacobian_is_constant` says exactly when the bodies' Jacobians are the same
/// at every `q`, and then `M(q)` is too (the stepper builds and factors it once): a base
/// with a flywheel pivoting at its centre of mass and a slider on the world's axis with a
/// wheel at its centre are constant; a pendulum, a flywheel off the centre and a leg
/// sliding along a turning base are not.
#[test]
fn a_constant_jacobian_is_a_constant_mass_matrix() {
    let flat = Terrain::flat(0.0);
    let build = |bodies: Vec<Body>| {
        let material = ContactMaterial::default();
        Model::new(
            bodies,
            vec![],
            flat.clone(),
            vec![],
            Vec2::new(0.0, -9.81),
            material,
        )
        .unwrap()
    };
    let slider = |parent| Body {
        name: "slider".into(),
        mass: 0.5,
        inertia: 0.01,
        joint: Some(Joint {
            kind: JointKind::Prismatic {
                axis: Vec2::new(0.6, 0.8),
            },
            ..Joint::revolute(parent, Vec2::new(0.1, 0.2), Vec2::zeros())
        }),
    };
    let pinned = |parent, pivot, com| Body {
        name: "link".into(),
        mass: 0.3,
        inertia: 0.02,
        joint: Some(Joint::revolute(parent, pivot, com)),
    };
    let cases = [
        (
            "base with a centred flywheel",
            vec![
                Body::base("disc", 2.0, 0.1),
                Body::flywheel("wheel", 0.5, 0.01, 0),
            ],
            true,
        ),
        (
            "slider on the world carrying a centred wheel",
            vec![slider(None), pinned(Some(0), Vec2::zeros(), Vec2::zeros())],
            true,
        ),
        (
            "pendulum pinned to the world",
            vec![pinned(None, Vec2::new(0.0, 1.0), Vec2::new(0.0, -0.5))],
            false,
        ),
        (
            "flywheel pivoting off the base's centre of mass",
            vec![
                Body::base("disc", 2.0, 0.1),
                pinned(Some(0), Vec2::new(0.1, 0.0), Vec2::zeros()),
            ],
            false,
        ),
        (
            "leg sliding along a turning base",
            vec![Body::base("body", 2.0, 0.1), slider(Some(0))],
            false,
        ),
    ];
    for (name, bodies, constant) in cases {
        let model = build(bodies);
        let _ = Kinematics::new(&model);
        assert_eq!(model.jacobian_is_constant(), constant, "{name}");
        let n = model.dof();
        // One `Kinematics` reused over many `q` (a constant Jacobian is written once) gives
        // what a fresh one gives at each.
        let mut reused = Kinematics::new(&model);
        for i in 0..3 {
            let q = DVector::from_fn(n, |j, _| 1.1 * i as f64 - 0.4 * j as f64);
            let u = DVector::from_fn(n, |j, _| 0.3 + 0.2 * (i + j) as f64);
            reused.update(&model, &q, &u);
            let fresh = evaluate(&model, &q, &u);
            let bodies = model.bodies().len();
            assert_eq!(
                jacobian(&reused, bodies, n),
                jacobian(&fresh, bodies, n),
                "{name}"
            );
            let of = |k: &Kinematics| {
                (0..bodies)
                    .map(|b| (k.velocity(b), k.bias(b)))
                    .collect::<Vec<_>>()
            };
            assert_eq!(of(&reused), of(&fresh), "{name}");
        }
        let zero = DVector::zeros(n);
        let (m0, j0) = (
            mass_at(&model, &zero),
            jacobian(&evaluate(&model, &zero, &zero), model.bodies().len(), n),
        );
        let (mut mass_change, mut jacobian_change) = (0.0f64, 0.0f64);
        for i in 0..5 {
            let q = DVector::from_fn(n, |j, _| 0.7 * (i as f64 + 1.0) + 0.3 * j as f64);
            let j = jacobian(&evaluate(&model, &q, &zero), model.bodies().len(), n);
            mass_change = mass_change.max((mass_at(&model, &q) - &m0).amax());
            jacobian_change = jacobian_change.max((j - &j0).amax());
        }
        if constant {
            assert!(
                jacobian_change < 1e-15,
                "{name}: J changes by {jacobian_change:e}"
            );
            assert!(mass_change < 1e-15, "{name}: M changes by {mass_change:e}");
        } else {
            assert!(
                jacobian_change > 1e-3,
                "{name}: J changes by only {jacobian_change:e}"
            );
        }
    }
}

/// With a constant Jacobian `J̇ = 0`, so `h(q, u)` is the bodies' weight alone, the same at
/// every state (docs/physics.md §1): for a floating disc with a centred flywheel the whole
/// weight on `y`, no torque; for a slider on a fixed axis `a` carrying a centred wheel the
/// weight's component `m g · a` along it. The kinematics are updated once at a state with
/// spin and then at others (the weight is written with the Jacobian, at the first).
#[test]
fn a_constant_jacobian_has_the_bodies_weight_as_its_forces() {
    let g = 9.81;
    let model_of = |bodies: Vec<Body>| {
        Model::new(
            bodies,
            vec![],
            Terrain::flat(0.0),
            vec![],
            Vec2::new(0.0, -g),
            ContactMaterial::default(),
        )
        .unwrap()
    };
    let axis = Vec2::new(0.6, 0.8);
    let slider = Body {
        name: "slider".into(),
        mass: 0.5,
        inertia: 0.01,
        joint: Some(Joint {
            kind: JointKind::Prismatic { axis },
            ..Joint::revolute(None, Vec2::new(0.1, 0.2), Vec2::zeros())
        }),
    };
    let wheel = Body {
        name: "wheel".into(),
        mass: 0.3,
        inertia: 0.02,
        joint: Some(Joint::revolute(Some(0), Vec2::zeros(), Vec2::zeros())),
    };
    let cases = [
        (
            model_of(vec![
                Body::base("disc", 2.0, 0.1),
                Body::flywheel("flywheel", 0.5, 0.01, 0),
            ]),
            vec![0.0, -2.5 * g, 0.0, 0.0],
        ),
        (model_of(vec![slider, wheel]), vec![-0.8 * g * axis.y, 0.0]),
    ];
    for (model, weight) in cases {
        let n = model.dof();
        let mut kinematics = Kinematics::new(&model);
        let zero = DVector::zeros(n);
        for i in 0..4 {
            let q = DVector::from_fn(n, |j, _| 0.9 * i as f64 - 0.35 * j as f64);
            let u = DVector::from_fn(n, |j, _| 3.0 * (i as f64 + 1.0) - 1.7 * j as f64);
            kinematics.update(&model, &q, &u);
            assert!(model.jacobian_is_constant());
            let mut h = DVector::zeros(n);
            model.forces(&kinematics, &zero, &mut h);
            for (k, (h, w)) in h.iter().zip(&weight).enumerate() {
                assert!((h - w).abs() < 1e-12, "state {i}, h[{k}] = {h} against {w}");
            }
        }
    }
}
