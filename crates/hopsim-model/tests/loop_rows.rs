//! Loop joints (docs/physics.md §8.1): every row is the gradient of its residual (checked
//! against central differences at random states, for each kind, with a floating base, a
//! prismatic joint and the world), and the builder refuses bad loop joints.

use hopsim_model::{
    Body, ContactMaterial, Joint, JointKind, Kinematics, LoopJoint, LoopKind, Model, ModelBuilder,
    ModelError, Terrain, Vec2,
};

/// A floating base with a revolute child and a prismatic child, and a pinned bar.
fn builder() -> ModelBuilder {
    let mut arm = Body::base("arm", 0.5, 0.01);
    arm.joint = Some(Joint::revolute(
        Some(0),
        Vec2::new(0.1, 0.05),
        Vec2::new(0.2, -0.03),
    ));
    let mut slide = Body::base("slide", 0.3, 0.002);
    let mut prismatic = Joint::revolute(Some(0), Vec2::new(-0.1, 0.0), Vec2::new(0.02, 0.01));
    prismatic.kind = JointKind::Prismatic {
        axis: Vec2::new(0.6, 0.8),
    };
    slide.joint = Some(prismatic);
    let mut bar = Body::base("bar", 0.4, 0.003);
    bar.joint = Some(Joint::revolute(
        None,
        Vec2::new(0.5, 0.2),
        Vec2::new(0.15, 0.0),
    ));
    ModelBuilder::new(
        vec![Body::base("base", 2.0, 0.05), arm, slide, bar],
        vec![],
        Terrain::flat(-10.0),
        vec![],
        Vec2::new(0.0, -9.81),
        ContactMaterial::inelastic(0.0),
    )
    .unwrap()
}

fn joint(name: &str, a: usize, b: Option<usize>, kind: LoopKind) -> LoopJoint {
    LoopJoint {
        name: name.into(),
        body_a: a,
        point_a: Vec2::new(0.07, -0.04),
        body_b: b,
        point_b: Vec2::new(-0.05, 0.09),
        kind,
    }
}

fn model() -> Model {
    let mut b = builder();
    for j in [
        joint("pin", 1, Some(3), LoopKind::Revolute),
        joint("rod", 2, Some(1), LoopKind::Distance { length: 0.3 }),
        joint("weld", 3, None, LoopKind::Weld { angle: 0.4 }),
        joint(
            "slot",
            1,
            Some(2),
            LoopKind::Slot {
                axis: Vec2::new(2.0, 1.0),
            },
        ),
        joint(
            "world slot",
            2,
            None,
            LoopKind::Slot {
                axis: Vec2::new(0.0, 3.0),
            },
        ),
    ] {
        b.add_loop(j).unwrap();
    }
    b.build()
}

#[test]
fn every_loop_row_is_the_gradient_of_its_residual() {
    let model = model();
    let (n, m) = (model.dof(), model.loop_row_count());
    assert_eq!(m, 2 + 1 + 3 + 1 + 1);
    let mut k = Kinematics::new(&model);
    let mut seed: u64 = 7;
    let mut uniform = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let u = vec![0.0; n];
    for _ in 0..20 {
        let q: Vec<f64> = (0..n).map(|_| 2.0 * uniform()).collect();
        k.update_slices(&model, &q, &u);
        let mut rows = vec![0.0; m * n];
        model.loop_rows_to(&k, &mut rows);
        let h = 1e-6;
        for i in 0..n {
            let mut at = |d: f64| {
                let mut qd = q.clone();
                qd[i] += d;
                k.update_slices(&model, &qd, &u);
                let mut phi = vec![0.0; m];
                model.loop_residuals_to(&k, &mut phi);
                phi
            };
            let (plus, minus) = (at(h), at(-h));
            for r in 0..m {
                let numeric = (plus[r] - minus[r]) / (2.0 * h);
                let analytic = rows[r * n + i];
                assert!(
                    (numeric - analytic).abs() < 1e-7,
                    "row {r} ({}) column {i}: {analytic} vs {numeric}",
                    model.loops()[model.loop_of_row(r)].name
                );
            }
        }
    }
}

#[test]
fn bad_loop_joints_are_refused() {
    let refused = |j: LoopJoint| builder().add_loop(j).unwrap_err();
    assert!(matches!(
        refused(joint("far", 1, Some(9), LoopKind::Revolute)),
        ModelError::UnknownBody {
            owner: "loop",
            body: 9,
            ..
        }
    ));
    let same = refused(joint("same", 1, Some(1), LoopKind::Revolute));
    assert!(same.to_string().contains("loop 'same'"), "{same}");
    for kind in [
        LoopKind::Distance { length: 0.0 },
        LoopKind::Distance { length: f64::NAN },
        LoopKind::Slot {
            axis: Vec2::zeros(),
        },
        LoopKind::Weld {
            angle: f64::INFINITY,
        },
    ] {
        assert!(matches!(
            refused(joint("bad", 1, Some(2), kind)),
            ModelError::BadLoop { .. }
        ));
    }
}
